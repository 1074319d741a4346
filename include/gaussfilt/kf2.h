// SPDX-License-Identifier: MIT
// gaussfilt: KF2, the linear Kalman filter of exercises 1, 2 and 5 of
// Probabilistic Robotics chapter 3, on the state x = (position, velocity).
//
// Names follow the book (Table 3.1), not most software:
//
//   book      here                   FilterPy / PX4 name
//   mu, Sigma gf_kf2.mu, gf_kf2_cov() x, P
//   A, B      model.A, .B            F, B
//   R         model.R                Q   (process noise)
//   C         meas.C                 H
//   Q         meas.Q                 R   (measurement noise)
//
// The caller owns every struct; nothing is allocated and nothing is global.
#ifndef GAUSSFILT_KF2_H
#define GAUSSFILT_KF2_H

#include "gaussfilt/mat.h"

#ifdef __cplusplus
extern "C" {
#endif

// The belief N(mu, Sigma). Sigma is carried as its factors
// P U D U^T P^T (U unit upper triangular, D >= 0 diagonal, P a permutation
// of the states), which every step updates in place, so that no rounding
// can make it indefinite; read it with gf_kf2_cov. Write a belief with
// gf_kf2_init only. 24 bytes in float, 48 in double.
typedef struct gf_kf2 {
    gf_vec2 mu;
    gf_real ud[2 * 3 / 2]; // U and D, packed (src/udu.h)
    // P: the state of each index of the factors (entries beyond the
    // second zero: as many bytes as a gf_real, so there is no padding)
    unsigned char perm[sizeof(gf_real)];
} gf_kf2;

// The motion model x_t = A x_{t-1} + B u_t + c + eps, eps ~ N(0, R).
// Never changes in most programs, so it can live in flash as const.
typedef struct gf_kf2_model {
    gf_mat2 A; // state transition
    gf_mat2 B; // control matrix (u has two entries)
    gf_mat2 R; // process noise covariance, symmetric PSD
    gf_vec2 c; // constant additive motion term (exercise 5), usually zero
} gf_kf2_model;

// The measurement model z = C x + c + delta, delta ~ N(0, Q), of m = 1 or 2
// measured quantities. Only rows (and columns of Q) 0..m-1 are read.
typedef struct gf_kf2_meas {
    unsigned m;   // 1 or 2
    gf_mat2 C;    // m x 2 measurement matrix
    gf_mat2 Q;    // m x m measurement noise covariance, symmetric PSD
    gf_vec2 c;    // constant additive measurement term (exercise 5)
    gf_real gate; // chi-square gate on the NIS; 0 disables the gate
} gf_kf2_meas;

// What an update saw: the innovation y = z - c - C mu_bar (first m entries)
// and its normalised innovation squared NIS = y^T S^-1 y.
typedef struct gf_innovation {
    unsigned m;
    gf_real y[3];
    gf_real nis;
} gf_innovation;

// Sets the belief to N(mu, sigma), factoring sigma once. sigma must be
// symmetric PSD (zero is fine: a state known exactly). GF_ERR_ARG on NULL,
// GF_ERR_NONFINITE (also for a variance so near the largest gf_real that
// its factors, multiplied out, pass it), GF_ERR_NOT_PSD
// (gf_mat2_check_psd's verdict); kf is untouched on failure.
gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma);

// *sigma = the belief's covariance U D U^T, exactly symmetric, each
// variance a sum of non-negative terms. GF_ERR_ARG on NULL.
gf_status gf_kf2_cov(const gf_kf2 *kf, gf_mat2 *sigma);

// Prediction (Table 3.1, lines 2-3, with exercise 5's constant):
//   mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R,
// on the factors (Thornton's time update, src/udu.h, docs/numerics.md).
// u may be NULL for no control. Checks the model (finite, R PSD) and u;
// on any failure the belief is untouched.
gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u);

// Correction (Table 3.1, lines 4-6, Joseph form):
//   S = C Sigma_bar C^T + Q,  K = Sigma_bar C^T S^-1,
//   mu = mu_bar + K (z - c - C mu_bar),
//   Sigma = (I - K C) Sigma_bar (I - K C)^T + K Q K^T,
// computed on the factors of Sigma_bar, one whitened measured quantity at
// a time (Bierman's scalar update, src/udu.h, docs/numerics.md): the
// posterior is positive semidefinite; NIS = the sum of the scalar NIS.
// A quantity with zero noise is taken exactly; it is GF_ERR_SINGULAR only
// if its predicted variance is zero too (so is a second one along the
// direction an earlier zero-noise quantity of the same update fixed).
// z holds meas->m values. info (may be NULL) receives the innovation and
// its NIS on GF_OK and on GF_ERR_GATED (NIS above meas->gate, belief
// untouched). Other failures: GF_ERR_ARG (NULL, m not 1 or 2, gate < 0),
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (Q), GF_ERR_SINGULAR (S); the belief and
// info are untouched.
gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z,
                        gf_innovation *info);

// ---- Prepared models: checked once, trusted every step ----------------
//
// A firmware loop predicts with the same motion model and updates with the
// same measurement model at every step, so checking them at every step
// (finite, R and Q PSD, gate >= 0) is repeated work. As CMSIS-DSP's *_init
// functions do, gf_kf2_prepare_model and gf_kf2_prepare_meas check a model
// once and keep what the step needs; gf_kf2_predict_prepared and
// gf_kf2_update_prepared then test only what changes from step to step: u
// and z, S > 0, the NIS and its gate, and that the new belief is finite.
// Results equal gf_kf2_predict/update's bit for bit; a failing step leaves
// the belief (and info) untouched and returns the status gf_kf2_predict/
// update return for the same inputs. The step trusts the prepared struct:
// to change a model, prepare it again (a prepared struct written any other
// way may pass a model the checks would refuse, though never a non-finite
// belief: the result's finiteness is tested at every step).

// A checked motion model. Fill with gf_kf2_prepare_model only.
typedef struct gf_kf2_pmodel {
    gf_kf2_model model; // the model as given, checked
    gf_real Rf[4];      // R = F diag(Rd) F^T: F, rows of 2 (src/udu.h)
    gf_real Rd[2];
} gf_kf2_pmodel;

// What an update needs of a checked Q: its factors and the whitened rows.
typedef struct gf_kf2_qfactors {
    gf_real Qf[4];      // Q = F diag(Qe) F^T: F, m x m, rows of m
    gf_real Qe[2];      // the noises of the whitened quantities
    unsigned Qorder[2]; // F's pivot order (src/udu.h)
    gf_mat2 Cw;         // F^-1 C: the rows of independent noises Qe
} gf_kf2_qfactors;

// A checked measurement model. Fill with gf_kf2_prepare_meas only.
typedef struct gf_kf2_pmeas {
    gf_kf2_meas meas;  // the model as given, checked
    gf_kf2_qfactors q; // Q factored, C whitened
} gf_kf2_pmeas;

// Checks model as gf_kf2_predict does (A, B, c finite; R symmetric PSD)
// and stores it with R's factors in *pm. GF_ERR_ARG on NULL,
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD; *pm is untouched on failure.
gf_status gf_kf2_prepare_model(gf_kf2_pmodel *pm, const gf_kf2_model *model);

// Checks meas as gf_kf2_update does (m 1 or 2; C, c, gate finite; gate >=
// 0; Q symmetric PSD) and stores it, Q factored and C whitened, in *pq.
// GF_ERR_ARG on NULL, on m not 1 or 2 and on gate < 0, GF_ERR_NONFINITE,
// GF_ERR_NOT_PSD; *pq is untouched on failure.
gf_status gf_kf2_prepare_meas(gf_kf2_pmeas *pq, const gf_kf2_meas *meas);

// gf_kf2_predict with a prepared model: checks u (may be NULL) and the
// result. GF_ERR_ARG on NULL, GF_ERR_NONFINITE; belief untouched on failure.
gf_status gf_kf2_predict_prepared(gf_kf2 *kf, const gf_kf2_pmodel *pm,
                                  const gf_vec2 *u);

// gf_kf2_update with a prepared measurement model: checks z, S, the NIS,
// the gate and the result. Statuses and info as gf_kf2_update.
gf_status gf_kf2_update_prepared(gf_kf2 *kf, const gf_kf2_pmeas *pq,
                                 const gf_vec2 *z, gf_innovation *info);

#ifdef __cplusplus
}
#endif

#endif
