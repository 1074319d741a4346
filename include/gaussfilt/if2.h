// SPDX-License-Identifier: MIT
// gaussfilt: IF2, the information filter (Table 3.6 of Probabilistic
// Robotics) on KF2's state x = (position, velocity) and KF2's models.
//
// The belief is held in canonical form: the information matrix
// Omega = Sigma^-1 and the information vector xi = Sigma^-1 mu. That form
// cannot hold a covariance that is singular (a state known exactly, as
// Sigma_0 = 0 in exercise 1, or Sigma_1 = R of rank one): converting from
// one returns GF_ERR_SINGULAR. It can hold what the moments form cannot:
// Omega = 0, "nothing known at all". Updates are additions; predictions
// invert. See the README, "Beyond the EKF".
#ifndef GAUSSFILT_IF2_H
#define GAUSSFILT_IF2_H

#include "gaussfilt/kf2.h"

#ifdef __cplusplus
extern "C" {
#endif

// The belief in canonical form.
typedef struct gf_if2 {
    gf_mat2 omega; // information matrix Omega = Sigma^-1, symmetric PSD
    gf_vec2 xi;    // information vector xi = Sigma^-1 mu
} gf_if2;

// Sets the belief to (Omega, xi) directly. omega must be symmetric PSD;
// zero is fine (no information). GF_ERR_ARG on NULL, GF_ERR_NONFINITE,
// GF_ERR_NOT_PSD; inf is untouched on failure.
gf_status gf_if2_init(gf_if2 *inf, const gf_mat2 *omega, const gf_vec2 *xi);

// Sets the belief from the moments: Omega = Sigma^-1, xi = Sigma^-1 mu.
// GF_ERR_ARG on NULL, GF_ERR_NONFINITE, GF_ERR_NOT_PSD when sigma is not a
// covariance, GF_ERR_SINGULAR when it is one but singular (the information
// form has no finite Omega for it); inf is untouched on failure.
gf_status gf_if2_from_moments(gf_if2 *inf, const gf_vec2 *mu,
                              const gf_mat2 *sigma);

// The moments of the belief: Sigma = Omega^-1, mu = Sigma xi. Either output
// may be NULL. GF_ERR_SINGULAR when Omega is not positive definite (some
// direction has no information, the covariance is unbounded); GF_ERR_ARG
// when inf or both outputs are NULL. Outputs are written only on GF_OK.
gf_status gf_if2_to_moments(const gf_if2 *inf, gf_vec2 *mu, gf_mat2 *sigma);

// Prediction (Table 3.6, lines 2-3, with exercise 5's constant c):
//   Omega_bar = (A Omega^-1 A^T + R)^-1,
//   xi_bar = Omega_bar (A Omega^-1 xi + B u + c).
// Two 2x2 inversions: the expensive step of this form. u may be NULL.
// GF_ERR_ARG (NULL), GF_ERR_NONFINITE, GF_ERR_NOT_PSD (R), GF_ERR_SINGULAR
// (Omega not positive definite, or A Omega^-1 A^T + R singular); the
// belief is untouched on failure.
gf_status gf_if2_predict(gf_if2 *inf, const gf_kf2_model *model,
                         const gf_vec2 *u);

// Correction (Table 3.6, lines 4-5, with exercise 5's constant c):
//   Omega = Omega_bar + C^T Q^-1 C,  xi = xi_bar + C^T Q^-1 (z - c).
// Additions only (Q^-1 is the measurement's own, and constant in most
// programs): the cheap step, and independent measurements commute.
// meas->Q must be positive definite (GF_ERR_SINGULAR otherwise: a
// noiseless measurement has infinite information).
// The innovation is not needed for the update itself; only when info is
// non-NULL or meas->gate > 0 is it computed, from the moments
// (y = z - c - C mu_bar, S = C Sigma_bar C^T + Q, NIS = y^T S^-1 y), which
// costs an inversion and needs Omega_bar positive definite
// (GF_ERR_SINGULAR otherwise). Gate and info rules as gf_kf2_update.
gf_status gf_if2_update(gf_if2 *inf, const gf_kf2_meas *meas, const gf_vec2 *z,
                        gf_innovation *info);

#ifdef __cplusplus
}
#endif

#endif
