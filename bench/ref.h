// SPDX-License-Identifier: MIT
// The reference implementations of one W1 / W2 step (bench only), W2's
// update with m = 1 (x), 2 (x, y) or 3 (x, y, heading): the textbook step
// on Sigma, and the factored step on U D U^T, unchecked and checked.
#ifndef GF_BENCH_REF_H
#define GF_BENCH_REF_H

#include "gaussfilt/gaussfilt.h"

// The textbook beliefs the floor works on: mu and Sigma itself.
typedef struct ref_kf2 {
    gf_vec2 mu;
    gf_mat2 sigma;
} ref_kf2;

typedef struct ref_ekf3 {
    gf_vec3 mu;
    gf_mat3 sigma;
} ref_ekf3;

// The library's belief as a textbook one (Sigma through the accessor).
ref_kf2 ref_kf2_from(const gf_kf2 *kf);
ref_ekf3 ref_ekf3_from(const gf_ekf3 *ekf);

void ref_kf2_predict(ref_kf2 *kf, const gf_kf2_model *model);
void ref_kf2_update(ref_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z);
void ref_ekf3_predict(ref_ekf3 *ekf, const gf_ekf3_motion *motion,
                      const gf_real *u);
void ref_ekf3_update(ref_ekf3 *ekf, const gf_ekf3_meas *meas, const gf_vec3 *z);
void ref_ekf3_update_xy(ref_ekf3 *ekf, const gf_ekf3_meas *meas,
                        const gf_vec3 *z);
void ref_ekf3_update_xyt(ref_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z);

// ---- The sound floor: Sigma carried as U D U^T between steps -----------
//
// The same steps on the factors Sigma = P U D U^T P^T (U unit upper
// triangular, D >= 0 diagonal, packed as the library's: U_ij (i < j) at
// j (j + 1) / 2 + i, d_j at j (j + 1) / 2 + j; P a permutation of the
// states, perm[k] the state of the factors' index k, as the library's):
// Thornton's modified weighted Gram-Schmidt for the prediction, Bierman's
// scalar update for the correction. The fewest instructions a filter that
// stays positive semidefinite by construction can spend on W1 and W2.
// "udu": no checks, the states in their own order (perm the identity,
// not read), R given as its factors (ref_noise2/3_from, once); "uduc": the
// checks gf_kf2/gf_ekf3's plain API promises, R taken as a matrix and
// judged and factored at every call, and the library's order of the
// factors: the prior's states reversed, and a quantity that tells much
// made the root first (bench/ref.c says which, and how).
typedef struct ref_udu2 {
    gf_vec2 mu;
    gf_real ud[3];
    unsigned char perm[sizeof(gf_real)];
} ref_udu2;

typedef struct ref_udu3 {
    gf_vec3 mu;
    gf_real ud[6];
    unsigned char perm[sizeof(gf_real)];
} ref_udu3;

// R = F diag(e) F^T, F unit upper triangular, packed as a belief's factors
// (F's entries where U's are, e where D is).
typedef struct ref_noise2 {
    gf_real ud[3];
} ref_noise2;

typedef struct ref_noise3 {
    gf_real ud[6];
} ref_noise3;

// The library's belief as the checked floors carry it (its mean, factors
// and permutation, copied); the same belief factored again in the states'
// own order (Sigma through the accessor, perm the identity), for udu; a
// noise matrix factored in the states' order (not measured).
ref_udu2 ref_udu2_from(const gf_kf2 *kf);
ref_udu3 ref_udu3_from(const gf_ekf3 *ekf);
ref_udu2 ref_udu2_inorder(const gf_kf2 *kf);
ref_udu3 ref_udu3_inorder(const gf_ekf3 *ekf);
ref_noise2 ref_noise2_from(const gf_mat2 *R);
ref_noise3 ref_noise3_from(const gf_mat3 *R);

// How far a floor's belief is from the library's: the largest
// |Sigma_ij - Sigma'_ij| / sqrt(Sigma'_ii Sigma'_jj) (Sigma' the
// library's), and in *mu_dev the largest |mu_i - mu'_i| / sqrt(Sigma'_ii)
// (the heading's difference wrapped).
gf_real ref_udu2_dev(const ref_udu2 *r, const gf_kf2 *kf, gf_real *mu_dev);
gf_real ref_udu3_dev(const ref_udu3 *r, const gf_ekf3 *ekf, gf_real *mu_dev);

// No checks: KF2 with a general A (no B u, no c), an update of m = 1 with
// a general row C; EKF3 through the model callbacks, G and H general, an
// update of m = 1, 2 (x, y) or 3 (x, y, heading, its residual wrapped), Q
// diagonal, one scalar update per quantity.
void ref_udu2_predict(ref_udu2 *kf, const gf_kf2_model *model,
                      const ref_noise2 *rn);
void ref_udu2_update(ref_udu2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z);
void ref_udu3_predict(ref_udu3 *ekf, const gf_ekf3_motion *motion,
                      const ref_noise3 *rn, const gf_real *u);
void ref_udu3_update(ref_udu3 *ekf, const gf_ekf3_meas *meas, const gf_vec3 *z);
void ref_udu3_update_xy(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                        const gf_vec3 *z);
void ref_udu3_update_xyt(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z);

// Checked: gf_kf2_predict, gf_kf2_update, gf_ekf3_predict and
// gf_ekf3_update's statuses for the same inputs, the belief untouched on
// any failure, info as theirs; the updates take m = 1 or 2 (KF2) and 1 to
// 3 (EKF3) quantities, whitened by Q's factors and taken one at a time in
// their own order, each made the root of the factors first if it tells
// much (bench/ref.c).
gf_status ref_uduc2_predict(ref_udu2 *kf, const gf_kf2_model *model,
                            const gf_vec2 *u);
gf_status ref_uduc2_update(ref_udu2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_innovation *info);
gf_status ref_uduc3_predict(ref_udu3 *ekf, const gf_ekf3_motion *motion,
                            const gf_real *u);
gf_status ref_uduc3_update(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                           const gf_vec3 *z, gf_innovation *info);

// The checked floor's gf_kf2_init / gf_ekf3_init (the prior judged and
// factored by hand, as uduc judges R) and gf_kf2_cov / gf_ekf3_cov (in
// closed form): statuses as the library's, the belief untouched on
// failure.
gf_status ref_uduc2_init(ref_udu2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma);
gf_status ref_uduc3_init(ref_udu3 *ekf, const gf_vec3 *mu,
                         const gf_mat3 *sigma);
gf_status ref_udu2_cov(const ref_udu2 *kf, gf_mat2 *sigma);
gf_status ref_udu3_cov(const ref_udu3 *ekf, gf_mat3 *sigma);

// ---- The checked prepared floor ("uducp") -------------------------------
//
// The models checked once, R's factors made once (the prepare functions,
// with the statuses of uduc's checks); each step tests only what the
// library's prepared steps test per step (u, z, the callbacks' results, s,
// the NIS, the gate, the result) and is otherwise uduc's step, statuses
// and info included; m as uduc's.
typedef struct ref_kf2_pmodel {
    gf_kf2_model model;
    ref_noise2 rn[2]; // P^T R P's factors for each order (by perm[0])
} ref_kf2_pmodel;

typedef struct ref_kf2_pmeas {
    gf_kf2_meas meas;
    gf_real qn[3]; // Q's factors, packed as a belief's (m = 1: Q itself)
} ref_kf2_pmeas;

typedef struct ref_ekf3_pmotion {
    gf_ekf3_motion motion;
    ref_noise3 rn[9]; // the same, by perm[0] * 3 + perm[1] (6 used)
} ref_ekf3_pmotion;

typedef struct ref_ekf3_pmeas {
    gf_ekf3_meas meas;
    gf_real qn[6]; // as ref_kf2_pmeas's
} ref_ekf3_pmeas;

gf_status ref_uducp2_prepare_model(ref_kf2_pmodel *pm,
                                   const gf_kf2_model *model);
gf_status ref_uducp2_prepare_meas(ref_kf2_pmeas *pq, const gf_kf2_meas *meas);
gf_status ref_uducp2_predict(ref_udu2 *kf, const ref_kf2_pmodel *pm,
                             const gf_vec2 *u);
gf_status ref_uducp2_update(ref_udu2 *kf, const ref_kf2_pmeas *pq,
                            const gf_vec2 *z, gf_innovation *info);
gf_status ref_uducp3_prepare_motion(ref_ekf3_pmotion *pm,
                                    const gf_ekf3_motion *motion);
gf_status ref_uducp3_prepare_meas(ref_ekf3_pmeas *pq, const gf_ekf3_meas *meas);
gf_status ref_uducp3_predict(ref_udu3 *ekf, const ref_ekf3_pmotion *pm,
                             const gf_real *u);
gf_status ref_uducp3_update(ref_udu3 *ekf, const ref_ekf3_pmeas *pq,
                            const gf_vec3 *z, gf_innovation *info);

#endif
