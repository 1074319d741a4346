// SPDX-License-Identifier: MIT
// The conventional (unsafe) floor for the filters of n states (bench
// only): the textbook Kalman filter step for a generic n, in loops, with
// no checks and no library call. bench/ref_n.c.
#ifndef GF_BENCH_REF_N_H
#define GF_BENCH_REF_N_H

#include "gaussfilt/ekf.h"
#include "gaussfilt/kf.h"

// The textbook belief, mu and Sigma itself (n x n, row-major), and the
// step's scratch.
typedef struct ref_n {
    unsigned n;
    gf_real mu[GF_KF_NMAX];
    gf_real P[GF_KF_NMAX * GF_KF_NMAX];
    gf_real T[GF_KF_NMAX * GF_KF_NMAX]; // A P; P C^T (n x m)
    gf_real J[GF_KF_NMAX * GF_KF_NMAX]; // G, H (the EKF's Jacobians)
    gf_real S[GF_KF_NMAX * GF_KF_NMAX]; // C P C^T + Q, then its LDL^T
    gf_real K[GF_KF_NMAX * GF_KF_NMAX]; // the gain (n x m)
    gf_real y[GF_KF_NMAX];              // the innovation
    gf_real v[GF_KF_NMAX];              // g(mu), h(mu_bar)
} ref_n;

void ref_n_from(ref_n *r, unsigned n, const gf_real *mu, const gf_real *sigma);

// gf_kf's model and measurement (A, R; C, Q; no control, no constant
// terms, no gate).
void ref_kf_predict(ref_n *r, const gf_kf_model *model);
void ref_kf_update(ref_n *r, const gf_kf_meas *meas, const gf_real *z);

// gf_ekf's: the same callbacks (mu_bar preset to mu, G to I; z_hat and H
// to zeros), no angle wrapping.
void ref_ekf_predict(ref_n *r, const gf_ekf_motion *motion, const gf_real *u);
void ref_ekf_update(ref_n *r, const gf_ekf_meas *meas, const gf_real *z);

#endif
