// SPDX-License-Identifier: MIT
// gaussfilt: EKF3, the extended Kalman filter of exercise 4 of Probabilistic
// Robotics chapter 3, on the state x = (x, y, theta). Motion g and
// measurement h are caller-supplied callbacks that also give their
// Jacobians G and H; the exercise's models are built in. The heading and
// any angle residual are kept in (-pi, pi]. Book names as in kf2.h:
// R is process noise, Q measurement noise.
#ifndef GAUSSFILT_EKF3_H
#define GAUSSFILT_EKF3_H

#include "gaussfilt/kf2.h"

#ifdef __cplusplus
extern "C" {
#endif

// The belief N(mu, Sigma), mu = (x, y, theta), Sigma carried as its
// factors as in gf_kf2; read it with gf_ekf3_cov. Write a belief with
// gf_ekf3_init only. 40 bytes in float, 80 in double.
typedef struct gf_ekf3 {
    gf_vec3 mu;
    gf_real ud[3 * 4 / 2]; // U and D, packed (src/udu.h)
    // P: the state of each index of the factors (entries beyond the
    // third zero: as many bytes as a gf_real, so there is no padding)
    unsigned char perm[sizeof(gf_real)];
} gf_ekf3;

// Motion callback: mu_bar = g(u, mu) and G = dg/dx at mu. u is whatever the
// callback defines (the built-in takes two entries). Returns GF_OK or any
// error, which the filter passes on (GF_ERR_MODEL if unsure; a status the
// enum lacks, and GF_ERR_GATED, which only the gate reports, arrive as
// GF_ERR_MODEL). mu_bar arrives as a copy of mu, G as the identity.
typedef gf_status (*gf_ekf3_motion_fn)(void *ctx, const gf_vec3 *mu,
                                       const gf_real *u, gf_vec3 *mu_bar,
                                       gf_mat3 *G);

// Measurement callback: z_hat = h(mu_bar) (first m entries) and H = dh/dx
// (first m rows).
typedef gf_status (*gf_ekf3_meas_fn)(void *ctx, const gf_vec3 *mu_bar,
                                     gf_vec3 *z_hat, gf_mat3 *H);

typedef struct gf_ekf3_motion {
    gf_ekf3_motion_fn g;
    void *ctx; // handed to g untouched; may be NULL
    gf_mat3 R; // process noise covariance, symmetric PSD
} gf_ekf3_motion;

typedef struct gf_ekf3_meas {
    unsigned m; // 1..3 measured quantities
    gf_ekf3_meas_fn h;
    void *ctx;           // handed to h untouched; may be NULL
    gf_mat3 Q;           // m x m measurement noise covariance, symmetric PSD
    unsigned angle_mask; // bit i set: residual i is an angle, wrapped
    gf_real gate;        // chi-square gate on the NIS; 0 disables the gate
} gf_ekf3_meas;

// Built-in motion of exercise 4: move u[0] forward along the heading, then
// turn by u[1]:  x' = x + d cos(theta), y' = y + d sin(theta),
// theta' = theta + phi, with the Jacobian of equation 4.1. ctx unused.
gf_status gf_ekf3_motion_forward_turn(void *ctx, const gf_vec3 *mu,
                                      const gf_real *u, gf_vec3 *mu_bar,
                                      gf_mat3 *G);

// Built-in measurement of x alone (m = 1). ctx unused.
gf_status gf_ekf3_meas_x(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                         gf_mat3 *H);

// Built-in measurement of (x, y) (m = 2). ctx unused.
gf_status gf_ekf3_meas_xy(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                          gf_mat3 *H);

// Sets the belief to N(mu, sigma) with mu's heading wrapped. As
// gf_kf2_init.
gf_status gf_ekf3_init(gf_ekf3 *ekf, const gf_vec3 *mu, const gf_mat3 *sigma);

// *sigma = the belief's covariance, as gf_kf2_cov.
gf_status gf_ekf3_cov(const gf_ekf3 *ekf, gf_mat3 *sigma);

// Prediction (Table 3.3, lines 2-3):
//   mu_bar = g(u, mu),  Sigma_bar = G Sigma G^T + R,
// on the factors, as gf_kf2_predict.
// u is passed to the callback as is (may be NULL if it accepts that).
// GF_ERR_ARG (NULL), GF_ERR_NOT_PSD (R), GF_ERR_NONFINITE (R, or what g
// returned), or the callback's own error; the belief is untouched then.
gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u);

// Correction (Table 3.3, lines 4-6, Joseph form):
//   S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T S^-1,
//   mu = mu_bar + K (z - h(mu_bar)),
//   Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T,
// computed as gf_kf2_update computes it (Bierman's scalar update on each
// quantity whitened by Q's factors), H evaluated once at mu_bar.
// Status, gate and info rules as gf_kf2_update, with m = 1..3 and h's own
// error passed on as in gf_ekf3_predict.
gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info);

// ---- Prepared models, as gf_kf2's -----------------------------------
//
// gf_ekf3_prepare_motion checks R once and keeps its factors;
// gf_ekf3_prepare_meas checks m, the gate and Q once and keeps Q's
// factors. The prepared steps then check what changes from step to step
// (the callbacks' results, z, the innovation variances, the result) and
// equal gf_ekf3_predict/update bit for bit, statuses included.

// A checked motion model. Fill with gf_ekf3_prepare_motion only.
typedef struct gf_ekf3_pmotion {
    gf_ekf3_motion motion; // the model as given, checked
    gf_real Rf[9];         // R = F diag(Rd) F^T: F, rows of 3 (src/udu.h)
    gf_real Rd[3];
} gf_ekf3_pmotion;

// What an update needs of a checked Q: its factors, as gf_kf2_qfactors'.
typedef struct gf_ekf3_qfactors {
    gf_real Qf[9];      // Q = F diag(Qe) F^T: F, m x m, rows of m
    gf_real Qe[3];      // the noises of the whitened quantities
    unsigned Qorder[3]; // F's pivot order (F is unit lower triangular in it)
} gf_ekf3_qfactors;

// A checked measurement model. Fill with gf_ekf3_prepare_meas only.
typedef struct gf_ekf3_pmeas {
    gf_ekf3_meas meas;  // the model as given, checked
    gf_ekf3_qfactors q; // Q factored
} gf_ekf3_pmeas;

// Checks motion as gf_ekf3_predict does before its callback (g not NULL;
// R finite, symmetric PSD) and stores it with R's factors. GF_ERR_ARG,
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD; *pm is untouched on failure.
gf_status gf_ekf3_prepare_motion(gf_ekf3_pmotion *pm,
                                 const gf_ekf3_motion *motion);

// Checks meas as gf_ekf3_update does before its callback (h not NULL, m
// 1..3, gate finite and >= 0, Q symmetric PSD) and stores it with Q's
// factors. GF_ERR_ARG, GF_ERR_NONFINITE, GF_ERR_NOT_PSD; *pq is untouched
// on failure.
gf_status gf_ekf3_prepare_meas(gf_ekf3_pmeas *pq, const gf_ekf3_meas *meas);

// gf_ekf3_predict with a prepared motion model.
gf_status gf_ekf3_predict_prepared(gf_ekf3 *ekf, const gf_ekf3_pmotion *pm,
                                   const gf_real *u);

// gf_ekf3_update with a prepared measurement model: checks z, the
// callback's results, S, the NIS, the gate and the result.
gf_status gf_ekf3_update_prepared(gf_ekf3 *ekf, const gf_ekf3_pmeas *pq,
                                  const gf_vec3 *z, gf_innovation *info);

#ifdef __cplusplus
}
#endif

#endif
