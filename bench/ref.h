// The no-checks reference implementation of one W1 / W2 step (bench only),
// W2's update with m = 1 (x), 2 (x, y) or 3 (x, y, heading).
#ifndef GF_BENCH_REF_H
#define GF_BENCH_REF_H

#include "gaussfilt/gaussfilt.h"

void ref_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model);
void ref_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z);
void ref_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                      const gf_real *u);
void ref_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                     const gf_vec3 *z);
void ref_ekf3_update_xy(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                        const gf_vec3 *z);
void ref_ekf3_update_xyt(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z);

#endif
