// SPDX-License-Identifier: MIT
// The loop floor (bench only): the least code that keeps KF2's, EKF3's and
// gf_kf's promises in the core's loop style, to measure what a step and its
// flash cost at the least. floor_core.c has the steps for any n (out of
// line, n at run time, as src/udu.c's), floor.c the filters on them. What
// it keeps and what it leaves out: floor_core.c's header.
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

typedef struct floor_kf {
    unsigned n;
    gf_real mu[GF_KF_NMAX];
    gf_real ud[GF_KF_TRI(GF_KF_NMAX)];
} floor_kf;

// gf_kf's floor's scratch: the new belief, R's factors, the steps' own.
typedef struct floor_kf_work {
    floor_kf belief;
    gf_real rud[GF_KF_TRI(GF_KF_NMAX)];
    gf_real steps[2 * GF_KF_NMAX * GF_KF_NMAX + 4 * GF_KF_NMAX];
} floor_kf_work;

// The steps for any n.
int fl_finite(const gf_real *x, unsigned n);
gf_status fl_factor(const gf_real *s, unsigned n, gf_real *ud);
int fl_belief_finite(const gf_real *mu, const gf_real *ud, unsigned n);
void fl_predict(unsigned n, const gf_real *ud, const gf_real *A,
                const gf_real *rud, gf_real *out, gf_real *w);
gf_status fl_correct(unsigned n, gf_real *ud, gf_real *mu, const gf_real *h,
                     gf_real r, gf_real y, gf_real *nis, gf_real *b);
void fl_to_cov(const gf_real *ud, unsigned n, gf_real *s);
void fl_whiten(const gf_real *qud, unsigned m, gf_real *x, unsigned cols);
// h Sigma h^T = f^T D f, f = U^T h.
gf_real fl_hsh(unsigned n, const gf_real *ud, const gf_real *h);
gf_status fl_correct_exact(unsigned n, gf_real *ud, gf_real *mu,
                           const gf_real *h, gf_real sii, gf_real y,
                           gf_real *nis, gf_real *x);
// q = the variances of an m x m Q (rows of stride) that is diagonal with
// variances >= 0, else GF_ERR_NOT_PSD.
gf_status fl_noise_diag(const gf_real *Q, unsigned stride, unsigned m,
                        gf_real *q);
// m quantities of independent noises q (H m rows of n, y their innovations
// at the prior mean), one after another, each innovation taken at the mean
// the earlier ones gave; *nis their sum. b: scratch of 2n.
gf_status fl_correct_m(unsigned n, unsigned m, gf_real *ud, gf_real *mu,
                       const gf_real *H, const gf_real *q, const gf_real *y,
                       gf_real *nis, gf_real *b);

// KF2 on them (u may be NULL).
gf_status floor_kf2_init(floor_kf2 *kf, const gf_vec2 *mu,
                         const gf_mat2 *sigma);
gf_status floor_kf2_predict(floor_kf2 *kf, const gf_kf2_model *model,
                            const gf_vec2 *u);
gf_status floor_kf2_update(floor_kf2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_real *nis);
void floor_kf2_cov(const floor_kf2 *kf, gf_mat2 *sigma);
// The update with what gf_kf2_update must also hold (the stack's floor):
// a full Q, factored and whitened (U_Q^-1 C, U_Q^-1 y), one scalar update
// per quantity at the mean the earlier ones gave, exact quantities (e = 0)
// in the Joseph form, the innovation returned.
gf_status floor_kf2_update_api(floor_kf2 *kf, const gf_kf2_meas *meas,
                               const gf_vec2 *z, gf_innovation *info);

// EKF3 on them.
gf_status floor_ekf3_init(floor_ekf3 *ekf, const gf_vec3 *mu,
                          const gf_mat3 *sigma);
gf_status floor_ekf3_predict(floor_ekf3 *ekf, const gf_ekf3_motion *motion,
                             const gf_real *u);
gf_status floor_ekf3_update(floor_ekf3 *ekf, const gf_ekf3_meas *meas,
                            const gf_vec3 *z, gf_real *nis);
void floor_ekf3_cov(const floor_ekf3 *ekf, gf_mat3 *sigma);
// As floor_kf2_update_api, for m = 1..3 and the callback's H.
gf_status floor_ekf3_update_api(floor_ekf3 *ekf, const gf_ekf3_meas *meas,
                                const gf_vec3 *z, gf_innovation *info);

// gf_kf on them, n states (1..GF_KF_NMAX), m quantities of independent
// noises (Q diagonal), the scratch in work.
gf_status floor_kf_init(floor_kf *kf, unsigned n, const gf_real *mu,
                        const gf_real *sigma, floor_kf_work *work);
gf_status floor_kf_predict(floor_kf *kf, const gf_kf_model *model,
                           const gf_real *u, floor_kf_work *work);
gf_status floor_kf_update(floor_kf *kf, const gf_kf_meas *meas,
                          const gf_real *z, gf_real *nis, floor_kf_work *work);
void floor_kf_cov(const floor_kf *kf, gf_real *sigma);

#endif
