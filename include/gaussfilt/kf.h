// SPDX-License-Identifier: MIT
// gaussfilt: gf_kf, the linear Kalman filter for n states (1 <= n <=
// GF_KF_NMAX), on the factored core of KF2 and EKF3 (docs/numerics.md).
// Names follow the book as in kf2.h: R is process noise, Q measurement
// noise. Matrices are row-major arrays of gf_real, read through const
// pointers, so a model can live in flash.
//
// Storage is the caller's and sized at compile time by GF_KF_NMAX: a belief
// (gf_kf), a workspace for the steps' scratch (gf_kf_work: everything that
// grows with n^2; one may serve many filters, one call at a time), the
// prepared models. Nothing is allocated, nothing is global, no scratch that
// grows with n lives on the stack. docs/api.md gives the RAM per size.
#ifndef GAUSSFILT_KF_H
#define GAUSSFILT_KF_H

#include "gaussfilt/config.h"
#include "gaussfilt/status.h"

#ifdef __cplusplus
extern "C" {
#endif

// The largest number of states (and of measured quantities). Raise it
// (-DGF_KF_NMAX=16) for larger filters; RAM grows with its square.
#ifndef GF_KF_NMAX
#define GF_KF_NMAX 12
#endif

// n (n + 1) / 2: the numbers of a factored n x n covariance.
#define GF_KF_TRI(n) ((n) * ((n) + 1) / 2)

// The permutation's bytes, rounded up to whole gf_reals (no padding).
#define GF_KF_PERM_BYTES                                                       \
    (((GF_KF_NMAX) + sizeof(gf_real) - 1) / sizeof(gf_real) * sizeof(gf_real))

// The belief N(mu, Sigma) of n states, Sigma carried as its factors
// P U D U^T P^T (as gf_kf2's); read it with gf_kf_cov, set it with
// gf_kf_init or gf_ekf_init only. angles: bit i set keeps state i in
// (-pi, pi] (an EKF's heading, wrapped by gf_ekf's steps); zero for a
// linear filter (gf_kf's steps wrap nothing).
typedef struct gf_kf {
    unsigned n;
    unsigned angles;
    gf_real mu[GF_KF_NMAX];
    gf_real ud[GF_KF_TRI(GF_KF_NMAX)];
    unsigned char perm[GF_KF_PERM_BYTES];
} gf_kf;

// A noise covariance's factors F diag(d) F^T, as a step finds them.
typedef struct gf_kf_factors {
    gf_real F[GF_KF_NMAX * GF_KF_NMAX]; // unit lower triangular in order
    gf_real d[GF_KF_NMAX];
    unsigned order[GF_KF_NMAX]; // F's pivot order
} gf_kf_factors;

// What an update saw: the innovation y = z - c - C mu_bar (m entries) and
// its NIS = y^T S^-1 y.
typedef struct gf_kf_innovation {
    unsigned m;
    gf_real y[GF_KF_NMAX];
    gf_real nis;
} gf_kf_innovation;

// The steps' scratch: caller-owned, contents meaningless between calls.
// It holds everything a step would otherwise keep on the stack beyond a
// few scalars (the n^2 arrays and the vectors of n alike), so that a
// step's stack depth does not grow with GF_KF_NMAX (docs/api.md gives its
// size per GF_KF_NMAX).
typedef struct gf_kf_work {
    gf_kf belief; // the new belief, until it is whole
    // the factored steps' own: Thornton's rows and weights, Bierman's
    // vectors, the factorisation's low parts
    gf_real steps[2 * GF_KF_NMAX * GF_KF_NMAX + 6 * GF_KF_NMAX];
    gf_real rows[GF_KF_NMAX * GF_KF_NMAX]; // G, or the whitened C or H
    gf_real mean[GF_KF_NMAX];              // mu_bar, or z_hat
    gf_real yw[GF_KF_NMAX];                // the whitened innovation
    gf_kf_factors noise;                   // R's or Q's factors
    gf_kf_innovation in;                   // an update's innovation, until kept
} gf_kf_work;

// The motion model x_t = A x_{t-1} + B u_t + c + eps, eps ~ N(0, R).
typedef struct gf_kf_model {
    unsigned nu;      // entries of u (0: no control; B and u unread)
    const gf_real *A; // n x n state transition
    const gf_real *B; // n x nu control matrix
    const gf_real *R; // n x n process noise covariance, symmetric PSD
    const gf_real *c; // n constant term, or NULL for none
} gf_kf_model;

// The measurement model z = C x + c + delta, delta ~ N(0, Q), of m
// measured quantities (1 <= m <= n).
typedef struct gf_kf_meas {
    unsigned m;
    const gf_real *C; // m x n measurement matrix
    const gf_real *Q; // m x m measurement noise covariance, symmetric PSD
    const gf_real *c; // m constant term, or NULL for none
    gf_real gate;     // chi-square gate on the NIS; 0 disables it
} gf_kf_meas;

// Sets kf to N(mu, sigma) of n states (sigma n x n, symmetric PSD: zero is
// fine), factoring sigma once. GF_ERR_ARG (NULL, n out of 1..GF_KF_NMAX),
// GF_ERR_NONFINITE (as gf_kf2_init's), GF_ERR_NOT_PSD; kf is untouched on
// failure.
gf_status gf_kf_init(gf_kf *kf, unsigned n, const gf_real *mu,
                     const gf_real *sigma, gf_kf_work *work);

// sigma (n x n) = the belief's covariance, exactly symmetric.
// GF_ERR_ARG on NULL.
gf_status gf_kf_cov(const gf_kf *kf, gf_real *sigma);

// Prediction: mu_bar = A mu + B u + c, Sigma_bar = A Sigma A^T + R (on the
// factors, as gf_kf2_predict). u (model->nu entries) may be NULL for no
// control. GF_ERR_ARG (NULL, n out of range), GF_ERR_NONFINITE,
// GF_ERR_NOT_PSD (R); the belief is untouched on failure.
gf_status gf_kf_predict(gf_kf *kf, const gf_kf_model *model, const gf_real *u,
                        gf_kf_work *work);

// Correction with m measured quantities, as gf_kf2_update: z holds m
// values; info (may be NULL) receives the innovation and NIS on GF_OK and
// GF_ERR_GATED. GF_ERR_ARG (NULL, m out of 1..n, gate < 0),
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (Q), GF_ERR_SINGULAR, GF_ERR_GATED; the
// belief and info are untouched on failure.
gf_status gf_kf_update(gf_kf *kf, const gf_kf_meas *meas, const gf_real *z,
                       gf_kf_innovation *info, gf_kf_work *work);

// ---- Prepared models, as kf2.h's: checked and factored once -----------

typedef struct gf_kf_pmodel {
    gf_kf_model model;                   // as given, checked
    unsigned n;                          // the states it was prepared for
    gf_real Rf[GF_KF_NMAX * GF_KF_NMAX]; // R = F diag(Rd) F^T (rows of n)
    gf_real Rd[GF_KF_NMAX];
} gf_kf_pmodel;

typedef struct gf_kf_pmeas {
    gf_kf_meas meas;                     // as given, checked
    unsigned n;                          // the states it was prepared for
    gf_real Qf[GF_KF_NMAX * GF_KF_NMAX]; // Q = F diag(Qe) F^T (rows of m)
    gf_real Qe[GF_KF_NMAX];
    unsigned Qorder[GF_KF_NMAX];         // F's pivot order
    gf_real Cw[GF_KF_NMAX * GF_KF_NMAX]; // F^-1 C (m x n)
} gf_kf_pmeas;

// Checks model for n states as gf_kf_predict does and keeps R's factors.
// GF_ERR_ARG, GF_ERR_NONFINITE, GF_ERR_NOT_PSD; *pm untouched on failure.
gf_status gf_kf_prepare_model(gf_kf_pmodel *pm, unsigned n,
                              const gf_kf_model *model, gf_kf_work *work);

// Checks meas for n states as gf_kf_update does and keeps Q's factors and
// the whitened C. Statuses as gf_kf_prepare_model.
gf_status gf_kf_prepare_meas(gf_kf_pmeas *pq, unsigned n,
                             const gf_kf_meas *meas, gf_kf_work *work);

// The steps with prepared models: bit for bit gf_kf_predict / update's
// results and statuses; GF_ERR_ARG if prepared for another n.
gf_status gf_kf_predict_prepared(gf_kf *kf, const gf_kf_pmodel *pm,
                                 const gf_real *u, gf_kf_work *work);
gf_status gf_kf_update_prepared(gf_kf *kf, const gf_kf_pmeas *pq,
                                const gf_real *z, gf_kf_innovation *info,
                                gf_kf_work *work);

#ifdef __cplusplus
}
#endif

#endif
