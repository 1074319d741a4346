// SPDX-License-Identifier: MIT
// The reference implementations of one W1 / W2 step (bench only), W2's
// update with m = 1 (x), 2 (x, y) or 3 (x, y, heading): the textbook step
// on Sigma, which the benchmarks' ratios are taken against.
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

#endif
