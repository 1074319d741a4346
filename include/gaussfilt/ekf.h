// SPDX-License-Identifier: MIT
// gaussfilt: gf_ekf, the extended Kalman filter for n states, on the
// belief, workspace and factored steps of gf_kf (kf.h). Motion g and
// measurement h are the caller's callbacks, which also give their
// Jacobians G and H. States whose bit is set in the belief's `angles` are
// kept in (-pi, pi], and residuals whose bit is set in the measurement's
// angle_mask are wrapped. Book names: R process noise, Q measurement
// noise. At n = 3 with the heading an angle, gf_ekf runs EKF3's arithmetic.
#ifndef GAUSSFILT_EKF_H
#define GAUSSFILT_EKF_H

#include "gaussfilt/kf.h"

#ifdef __cplusplus
extern "C" {
#endif

// Motion callback: mu_bar = g(u, mu) (n entries) and G = dg/dx at mu (n x n,
// row-major). mu_bar arrives as a copy of mu, G as the identity. Returns
// GF_OK or any error, passed on as gf_ekf3's callbacks' are.
typedef gf_status (*gf_ekf_motion_fn)(void *ctx, unsigned n, const gf_real *mu,
                                      const gf_real *u, gf_real *mu_bar,
                                      gf_real *G);

// Measurement callback: z_hat = h(mu_bar) (m entries) and H = dh/dx (m x n,
// row-major). Both arrive as zeros.
typedef gf_status (*gf_ekf_meas_fn)(void *ctx, unsigned n, unsigned m,
                                    const gf_real *mu_bar, gf_real *z_hat,
                                    gf_real *H);

typedef struct gf_ekf_motion {
    gf_ekf_motion_fn g;
    void *ctx;        // handed to g untouched; may be NULL
    const gf_real *R; // n x n process noise covariance, symmetric PSD
} gf_ekf_motion;

typedef struct gf_ekf_meas {
    unsigned m; // 1..n measured quantities
    gf_ekf_meas_fn h;
    void *ctx;           // handed to h untouched; may be NULL
    const gf_real *Q;    // m x m measurement noise covariance, symmetric PSD
    unsigned angle_mask; // bit i set: residual i is an angle, wrapped
    gf_real gate;        // chi-square gate on the NIS; 0 disables it
} gf_ekf_meas;

// Sets ekf to N(mu, sigma) of n states, the states in `angles` wrapped.
// As gf_kf_init.
gf_status gf_ekf_init(gf_kf *ekf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work);

// Prediction (Table 3.3, lines 2-3): mu_bar = g(u, mu), Sigma_bar =
// G Sigma G^T + R, on the factors. u is handed to g as is. GF_ERR_ARG,
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (R), or the callback's error; the
// belief is untouched on failure.
gf_status gf_ekf_predict(gf_kf *ekf, const gf_ekf_motion *motion,
                         const gf_real *u, gf_kf_work *work);

// Correction (Table 3.3, lines 4-6), H evaluated once at mu_bar, as
// gf_kf_update; statuses as gf_kf_update and the callback's error.
gf_status gf_ekf_update(gf_kf *ekf, const gf_ekf_meas *meas, const gf_real *z,
                        gf_kf_innovation *info, gf_kf_work *work);

// ---- Prepared models ---------------------------------------------------

typedef struct gf_ekf_pmotion {
    gf_ekf_motion motion;
    unsigned n;
    gf_real Rf[GF_KF_NMAX * GF_KF_NMAX];
    gf_real Rd[GF_KF_NMAX];
} gf_ekf_pmotion;

typedef struct gf_ekf_pmeas {
    gf_ekf_meas meas;
    unsigned n;
    gf_real Qf[GF_KF_NMAX * GF_KF_NMAX];
    gf_real Qe[GF_KF_NMAX];
    unsigned Qorder[GF_KF_NMAX];
} gf_ekf_pmeas;

gf_status gf_ekf_prepare_motion(gf_ekf_pmotion *pm, unsigned n,
                                const gf_ekf_motion *motion, gf_kf_work *work);
gf_status gf_ekf_prepare_meas(gf_ekf_pmeas *pq, unsigned n,
                              const gf_ekf_meas *meas, gf_kf_work *work);
gf_status gf_ekf_predict_prepared(gf_kf *ekf, const gf_ekf_pmotion *pm,
                                  const gf_real *u, gf_kf_work *work);
gf_status gf_ekf_update_prepared(gf_kf *ekf, const gf_ekf_pmeas *pq,
                                 const gf_real *z, gf_kf_innovation *info,
                                 gf_kf_work *work);

// ---- Checking a model's Jacobians -------------------------------------

// Where a model's Jacobian (G of g, H of h) and the central differences of
// its function disagree most (gf_ekf_check_model).
typedef struct gf_ekf_check {
    gf_real worst;     // the largest relative difference, 0 if none
    unsigned jacobian; // 0: the motion's G, 1: the measurement's H
    unsigned row, col; // its entry
    gf_real given;     // J_ij, as the callback gave it at mu
    gf_real numeric;   // D_ij, the central difference there
} gf_ekf_check;

// Compares the Jacobians the callbacks give at mu with central differences
// of their functions there: G of motion->g (with u; skipped if motion is
// NULL) and H of meas->h (skipped if meas is NULL). For each state j,
//   D_ij = (f_i(mu + h_j e_j) - f_i(mu - h_j e_j)) / (2 h_j),
//   h_j = 2^-17 max(|mu_j|, 1) in double, 2^-8 max(|mu_j|, 1) in float
// (about eps^(1/3)), the difference wrapped to (-pi, pi] for the outputs
// that are angles (g's states in `angles`, h's residuals in
// meas->angle_mask). The difference of entry ij is
//   |J_ij - D_ij| / max(|J_ij|, |D_ij|, 1000 eps (|f_i(mu + h_j e_j)| +
//                                                |f_i(mu - h_j e_j)|) / 2h_j)
// (the last term: a thousand times what rounding alone can put in D_ij,
// so that a true zero reads as one). *out gets the largest. A correct,
// smooth model reads below about 1e-8 in double and 1e-2 in float; a
// wrong entry about 1 (a sign: 2). GF_ERR_ARG (out or mu NULL, both
// models NULL, a callback NULL, n out of 1..GF_KF_NMAX, meas->m out of
// 1..n), GF_ERR_NONFINITE (mu, or a callback's answer), or a callback's
// error. Calls g and h 2n + 1 times each; work is scratch.
gf_status gf_ekf_check_model(const gf_ekf_motion *motion,
                             const gf_ekf_meas *meas, unsigned n,
                             const gf_real *mu, const gf_real *u,
                             unsigned angles, gf_ekf_check *out,
                             gf_kf_work *work);

#ifdef __cplusplus
}
#endif

#endif
