// SPDX-License-Identifier: MIT
// The loop floor (bench only): the least code that keeps KF2's promises in
// the core's loop style, to measure what a step and its flash cost at the
// least. floor_core.c has the steps for any n (out of line, n at run time,
// as src/udu.c's), floor.c KF2 on them. What it keeps and what it leaves
// out: floor_core.c's header.
#ifndef GF_BENCH_FLOOR_H
#define GF_BENCH_FLOOR_H

#include "gaussfilt/gaussfilt.h"

// Packed U D U^T, as src/udu.h: U_ij (i < j) at FL_UD(i, j), d_j at
// FL_UD(j, j).
#define FL_UD(i, j) ((j) * ((j) + 1u) / 2u + (i))

typedef struct floor_kf2 {
    gf_vec2 mu;
    gf_real ud[3];
} floor_kf2;

typedef struct floor_ekf3 {
    gf_vec3 mu;
    gf_real ud[6];
} floor_ekf3;

// The steps for any n.
int fl_finite(const gf_real *x, unsigned n);
gf_status fl_factor(const gf_real *s, unsigned n, gf_real *ud);
int fl_belief_finite(const gf_real *mu, const gf_real *ud, unsigned n);
void fl_predict(unsigned n, const gf_real *ud, const gf_real *A,
                const gf_real *rud, gf_real *out, gf_real *w);
gf_status fl_correct(unsigned n, gf_real *ud, gf_real *mu, const gf_real *h,
                     gf_real r, gf_real y, gf_real *nis, gf_real *b);
void fl_to_cov(const gf_real *ud, unsigned n, gf_real *s);

// KF2 on them (W1: no control, m = 1).
gf_status floor_kf2_init(floor_kf2 *kf, const gf_vec2 *mu,
                         const gf_mat2 *sigma);
gf_status floor_kf2_predict(floor_kf2 *kf, const gf_kf2_model *model);
gf_status floor_kf2_update(floor_kf2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_real *nis);
void floor_kf2_cov(const floor_kf2 *kf, gf_mat2 *sigma);

// EKF3 on them (W2: m = 1).
gf_status floor_ekf3_init(floor_ekf3 *ekf, const gf_vec3 *mu,
                          const gf_mat3 *sigma);
gf_status floor_ekf3_predict(floor_ekf3 *ekf, const gf_ekf3_motion *motion,
                             const gf_real *u);
gf_status floor_ekf3_update(floor_ekf3 *ekf, const gf_ekf3_meas *meas,
                            const gf_vec3 *z, gf_real *nis);
void floor_ekf3_cov(const floor_ekf3 *ekf, gf_mat3 *sigma);

#endif
