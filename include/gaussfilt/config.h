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

// Define GF_SMALL (CMake: -DGAUSSFILT_SMALL=ON) to build KF2's and EKF3's
// predict and update for size instead of speed: one shared generic
// correction and prediction (src/small.c), no fast paths, models always
// called through their pointers. Same API, statuses and results within
// rounding; less flash and stack on an MCU, more time per step. Define it
// for the whole build (it is a PUBLIC definition of the CMake target).

#define GF_PI GF_R(3.14159265358979323846)

#ifdef __cplusplus
}
#endif

#endif
