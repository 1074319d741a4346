// SPDX-License-Identifier: MIT
// gaussfilt: fixed-size 2x2 and 3x3 matrix math, only what the filters need.
//
// Matrices are row-major structs (m[row][col]) so they copy by assignment.
// Sources are const and come first, the destination comes last; every
// function works through locals, so the destination may alias a source.
// Every function returns GF_ERR_ARG for a NULL pointer (and writes
// nothing), GF_OK on success; the _is_finite tests return 0 for NULL.
#ifndef GAUSSFILT_MAT_H
#define GAUSSFILT_MAT_H

#include "gaussfilt/config.h"
#include "gaussfilt/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gf_vec2 {
    gf_real v[2];
} gf_vec2;
typedef struct gf_vec3 {
    gf_real v[3];
} gf_vec3;
typedef struct gf_mat2 {
    gf_real m[2][2];
} gf_mat2;
typedef struct gf_mat3 {
    gf_real m[3][3];
} gf_mat3;

// ---- 2x2 -----------------------------------------------------------------

// out = a b
gf_status gf_mat2_mul(const gf_mat2 *a, const gf_mat2 *b, gf_mat2 *out);

// out = a x
gf_status gf_mat2_mulv(const gf_mat2 *a, const gf_vec2 *x, gf_vec2 *out);

// out = a s a^T for a symmetric s; out is exactly symmetric.
gf_status gf_mat2_sandwich(const gf_mat2 *a, const gf_mat2 *s, gf_mat2 *out);

// s = (s + s^T) / 2
gf_status gf_mat2_symmetrize(gf_mat2 *s);

// 1 if every entry is finite, else 0.
int gf_mat2_is_finite(const gf_mat2 *a);

// Checks that s is a covariance: finite (else GF_ERR_NONFINITE), symmetric
// within GF_SYM_RTOL and positive semidefinite within GF_PD_RTOL in the
// correlation form (else GF_ERR_NOT_PSD; config.h). The verdict is the
// same for s and any power of two times s that keeps the entries normal.
gf_status gf_mat2_check_psd(const gf_mat2 *s);

// inv = s^-1 for a symmetric positive-definite s, in closed form.
// GF_ERR_SINGULAR if s is not positive definite relative to its scale,
// GF_ERR_NONFINITE on NaN or inf; inv is untouched then.
gf_status gf_mat2_spd_inv(const gf_mat2 *s, gf_mat2 *inv);

// Closed-form eigen-decomposition of a symmetric s: eigenvalues with
// lambda->v[0] >= lambda->v[1], and *angle in (-pi/2, pi/2], the direction
// of the first eigenvector (cos angle, sin angle) from the first axis.
// GF_ERR_NONFINITE on NaN or inf, or an eigenvalue too large for gf_real;
// the outputs are untouched then.
gf_status gf_mat2_eig_sym(const gf_mat2 *s, gf_vec2 *lambda, gf_real *angle);

// ---- 3x3 -----------------------------------------------------------------

// out = a b
gf_status gf_mat3_mul(const gf_mat3 *a, const gf_mat3 *b, gf_mat3 *out);

// out = a x
gf_status gf_mat3_mulv(const gf_mat3 *a, const gf_vec3 *x, gf_vec3 *out);

// out = a s a^T for a symmetric s; out is exactly symmetric.
gf_status gf_mat3_sandwich(const gf_mat3 *a, const gf_mat3 *s, gf_mat3 *out);

// s = (s + s^T) / 2
gf_status gf_mat3_symmetrize(gf_mat3 *s);

// 1 if every entry is finite, else 0.
int gf_mat3_is_finite(const gf_mat3 *a);

// Like gf_mat2_check_psd, on the leading n x n block of s (n = 1..3; other
// n give GF_ERR_ARG). All principal minors are tested, so a semidefinite
// matrix with a zero leading entry is judged right.
gf_status gf_mat3_check_psd(const gf_mat3 *s, unsigned n);

// Cholesky factor s = l l^T of the leading n x n block of a symmetric
// positive-definite s (n = 1..3), l lower triangular, the rest of l zeroed.
// A pivot below GF_PD_RTOL times its diagonal entry (or NaN) gives
// GF_ERR_SINGULAR; n out of range gives GF_ERR_ARG; l is untouched then.
gf_status gf_mat3_chol(const gf_mat3 *s, unsigned n, gf_mat3 *l);

// Solves l l^T x = b on the leading n entries, l from gf_mat3_chol.
gf_status gf_mat3_chol_solve(const gf_mat3 *l, unsigned n, const gf_vec3 *b,
                             gf_vec3 *x);

// Lower-triangular square root l (s = l l^T) of the leading n x n block of
// a symmetric positive SEMIdefinite s (n = 1..3), for drawing sigma points
// and samples: a pivot within GF_PD_RTOL of zero (relative to its diagonal
// entry) gives a zero column instead of a failure, so a variance of zero
// (a state known exactly, no process noise) is fine. The rest of l is
// zeroed. GF_ERR_ARG (NULL, n), GF_ERR_NONFINITE, GF_ERR_NOT_PSD (as
// gf_mat3_check_psd); l is untouched then.
gf_status gf_mat3_sqrt_psd(const gf_mat3 *s, unsigned n, gf_mat3 *l);

// ---- angles --------------------------------------------------------------

// The angle a wrapped to (-pi, pi]. NaN and inf give NaN. Beyond 2^22
// turns in float, 2^51 in double (|a| / 2 pi; TURNS_MAX in src/angle.c) a
// number no longer holds a direction at its own precision, and wraps to 0.
gf_real gf_angle_wrap(gf_real a);

// *s = sin(a), *c = cos(a). On (-GF_PI, GF_PI], what gf_angle_wrap returns
// (every heading the filters keep), within 2 ulp of the true values, near the
// zeros of sin and cos too (docs/accuracy.md has the figures). Any other a is
// wrapped first, and the wrap's rounding bounds the error absolutely: within
// 1e-15 in double and 6e-7 in float up to 1000 turns (tests/test_angle.c), many
// ulps where sin or cos is near zero (-GF_PI included: it wraps to GF_PI). Does
// nothing if s or c is NULL. The core's own, with no libm call
// (docs/firmware.md says why).
void gf_sincos(gf_real a, gf_real *s, gf_real *c);

// ---- exp, log, atan2 -----------------------------------------------------

// The core's own exp, log and atan2 (src/elem.c), with no libm call: the
// same bits on every IEEE-754 target, where libms round differently
// (docs/firmware.md). gf_exp and gf_log within 1 ulp of the true value,
// gf_atan2 within 1.5 (the rounding of y / x included), in both precisions
// (tests/test_elem.c measures them). As C99's: a NaN gives NaN;
// gf_exp(-inf) = 0 and gf_exp of a large a is inf; gf_log(+-0) = -inf,
// gf_log(a < 0) is NaN, gf_log(inf) = inf; gf_atan2(y, x) is in [-pi, pi]
// and follows the signs of zeros and infinities as C99 Annex F says.
gf_real gf_exp(gf_real a);
gf_real gf_log(gf_real a);
gf_real gf_atan2(gf_real y, gf_real x);

#ifdef __cplusplus
}
#endif

#endif
