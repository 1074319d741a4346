// SPDX-License-Identifier: MIT
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
#define GF_REAL_MIN FLT_MIN
#define GF_SQRT sqrtf
#define GF_FABS fabsf
#else
typedef double gf_real;
#define GF_R(x) x
#define GF_REAL_EPSILON DBL_EPSILON
#define GF_REAL_MIN DBL_MIN
#define GF_SQRT sqrt
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

// The tolerances of the verdicts. Every test of definiteness and
// singularity looks at the correlation form D^-1/2 M D^-1/2 (D = diag(M)),
// through the pivots of M = U D U^T taken relative to M's own diagonal
// (src/udu.h), so multiplying M by any power of two that keeps its entries
// normal never changes a verdict, and units never do.
//
// GF_PD_RTOL: a pivot below GF_PD_RTOL times its diagonal entry is zero
// (semidefinite in that direction; singular for an inverse or a Cholesky
// factor), one below -GF_PD_RTOL times it is indefinite, and an entry
// coupled to a zero pivot must be below GF_PD_RTOL in the correlation
// form. Derived for both precisions from the factorisation's error: a
// computed pivot of a correlation matrix of order n <= 3 is off by at most
// about gamma_(n+1) * n <= 12 u = 6 eps (Higham, Accuracy and Stability of
// Numerical Algorithms, 2nd ed., theorem 10.5, u = eps / 2), and a
// covariance the filter computed carries a few eps of its own; 64 eps
// leaves a margin of five over both. Float: 7.6e-6; double: 1.4e-14.
#ifndef GF_PD_RTOL
#define GF_PD_RTOL (GF_R(64.0) * GF_REAL_EPSILON)
#endif

// Relative tolerance of the symmetry test on covariances the caller passes
// in: |a_ij - a_ji| <= GF_SYM_RTOL * (|a_ij| + |a_ji|).
#ifndef GF_SYM_RTOL
#define GF_SYM_RTOL (GF_R(1024.0) * GF_REAL_EPSILON)
#endif

#define GF_PI GF_R(3.14159265358979323846)

#ifdef __cplusplus
}
#endif

#endif
