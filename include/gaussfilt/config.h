// gaussfilt: the scalar type and the few math hooks the core uses.
//
// The scalar type is chosen here, once. Double by default; define
// GF_SINGLE_PRECISION (CMake: -DGAUSSFILT_SINGLE_PRECISION=ON) for MCUs whose
// FPU only does single precision. Every literal in the core goes through
// GF_R() so that the float build never silently promotes to double.
#ifndef GAUSSFILT_CONFIG_H
#define GAUSSFILT_CONFIG_H

#include <float.h>
#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#ifdef GF_SINGLE_PRECISION
typedef float gf_real;
#define GF_R(x) x##f
#define GF_REAL_EPSILON FLT_EPSILON
#define GF_SQRT sqrtf
#define GF_ATAN2 atan2f
#define GF_LOG logf
#define GF_FABS fabsf
#else
typedef double gf_real;
#define GF_R(x) x
#define GF_REAL_EPSILON DBL_EPSILON
#define GF_SQRT sqrt
#define GF_ATAN2 atan2
#define GF_LOG log
#define GF_FABS fabs
#endif

// The link names carry the precision (gf_kf2_update_f32 or _f64): a program
// built for the other gf_real than its library does not link.
#include "gaussfilt/names.h"

// True when x is neither infinite nor NaN. Overridable, e.g. for compilers
// whose isfinite() is a library call.
#ifndef GF_ISFINITE
#define GF_ISFINITE(x) isfinite(x)
#endif

// Relative tolerance of the positive-definiteness tests: a Cholesky pivot
// smaller than GF_PD_RTOL times its diagonal entry counts as singular, and a
// principal minor below -GF_PD_RTOL times the product of its diagonal entries
// counts as indefinite. Scale-free: multiplying a matrix by any positive
// number never changes the verdict.
#ifndef GF_PD_RTOL
#define GF_PD_RTOL (GF_R(64.0) * GF_REAL_EPSILON)
#endif

// Relative tolerance of the symmetry test on covariances the caller passes
// in: |a_ij - a_ji| <= GF_SYM_RTOL * (|a_ij| + |a_ji|).
#ifndef GF_SYM_RTOL
#define GF_SYM_RTOL (GF_R(1024.0) * GF_REAL_EPSILON)
#endif

// GF_SMALL selects how KF2's and EKF3's steps are built. 1: for size
// (src/small.c: one shared generic prediction and correction, no fast
// paths, models always called through their pointers; less flash and
// stack on an MCU, more time per step). 0: the fast paths of kf2.c and
// ekf3.c. Same API, statuses and results within rounding either way.
// Default: 1 when the compiler optimises for size (gcc and clang define
// __OPTIMIZE_SIZE__ at -Os and -Oz, the usual firmware setting), else 0.
// Force either with -DGF_SMALL=1 or -DGF_SMALL=0 (CMake: GAUSSFILT_SMALL
// AUTO, the default, ON or OFF; ON and OFF are PUBLIC definitions of the
// gaussfilt target). Code tests it with #if GF_SMALL. A program that
// includes gaussfilt's headers need not be built like the library: the
// choice is made where the library is compiled.
#ifndef GF_SMALL
#if defined(__OPTIMIZE_SIZE__)
#define GF_SMALL 1
#else
#define GF_SMALL 0
#endif
#endif

#define GF_PI GF_R(3.14159265358979323846)

#ifdef __cplusplus
}
#endif

#endif
