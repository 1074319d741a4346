// SPDX-License-Identifier: MIT
// gaussfilt: what a 2-D covariance says: correlation and uncertainty ellipse.
#ifndef GAUSSFILT_COV2_H
#define GAUSSFILT_COV2_H

#include "gaussfilt/mat.h"

#ifdef __cplusplus
extern "C" {
#endif

// An ellipse centred on the mean: semi-axes a >= b >= 0, and the direction
// of the a axis, in radians from the first axis, in (-pi/2, pi/2].
typedef struct gf_ellipse {
    gf_real a;
    gf_real b;
    gf_real angle;
} gf_ellipse;

// rho = s01 / sqrt(s00 s11), clamped to [-1, 1]. GF_ERR_UNDEFINED when a
// variance is zero (or negative), never a division by zero;
// GF_ERR_NONFINITE on NaN or inf; GF_ERR_ARG on NULL. *rho untouched then.
gf_status gf_cov2_correlation(const gf_mat2 *s, gf_real *rho);

// The ellipse holding probability mass p (0 < p < 1) of N(0, s):
// k^2 = -2 ln(1 - p), semi-axes k sqrt(lambda_i) along s's eigenvectors.
// p = 0.68 gives the ellipses of docs/exercises.md's figures. GF_ERR_ARG on
// NULL or p out of range, GF_ERR_NONFINITE, GF_ERR_NOT_PSD; *e untouched
// then.
gf_status gf_cov2_ellipse(const gf_mat2 *s, gf_real p, gf_ellipse *e);

// The 2-D marginal of entries (i, j) of a 3-D covariance, e.g. (0, 1) for
// the (x, y) position of an EKF3 belief. GF_ERR_ARG if i or j > 2 or NULL.
gf_status gf_cov2_marginal(const gf_mat3 *s, unsigned i, unsigned j,
                           gf_mat2 *out);

#ifdef __cplusplus
}
#endif

#endif
