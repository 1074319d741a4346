// SPDX-License-Identifier: MIT
// The minimal firmware image of the footprint report. Built three times
// from this file: gf_fw_min (GF_FW_WITH_FILTERS: one KF2 step and one EKF3
// step with the built-in models, the exercises' numbers), gf_fw_base (the
// same inputs and outputs, no filter) and gf_fw_floor (GF_FW_FLOOR too: the
// same calls to the hand-written checked sound floor of bench/ref.c, U D
// U^T with the plain API's checks, in the library's place; the built-in
// models still the library's). The difference of an image and the base is
// what its filters cost. Inputs and outputs are volatile so that nothing
// is folded away at compile time.
#include "gaussfilt/gaussfilt.h"

#ifdef GF_FW_WITH_FILTERS
#ifdef GF_FW_FLOOR
#include "ref.h"
typedef ref_udu2 fw_kf2;
typedef ref_udu3 fw_ekf3;
#define fw_kf2_init ref_uduc2_init
#define fw_kf2_predict ref_uduc2_predict
#define fw_kf2_update ref_uduc2_update
#define fw_kf2_cov ref_udu2_cov
#define fw_ekf3_init ref_uduc3_init
#define fw_ekf3_predict ref_uduc3_predict
#define fw_ekf3_update ref_uduc3_update
#define fw_ekf3_cov ref_udu3_cov
#else
typedef gf_kf2 fw_kf2;
typedef gf_ekf3 fw_ekf3;
#define fw_kf2_init gf_kf2_init
#define fw_kf2_predict gf_kf2_predict
#define fw_kf2_update gf_kf2_update
#define fw_kf2_cov gf_kf2_cov
#define fw_ekf3_init gf_ekf3_init
#define fw_ekf3_predict gf_ekf3_predict
#define fw_ekf3_update gf_ekf3_update
#define fw_ekf3_cov gf_ekf3_cov
#endif
#endif

volatile gf_real gf_fw_in[4] = {GF_R(1.0), GF_R(0.0), GF_R(5.0), GF_R(-0.7)};
volatile gf_real gf_fw_out[6];
volatile int gf_fw_status;

#ifdef GF_FW_WITH_FILTERS
// The models never change: const, so they live in flash.
static const gf_kf2_model kf2_model = {
    .A = {{{GF_R(1.0), GF_R(1.0)}, {GF_R(0.0), GF_R(1.0)}}},
    .B = {{{GF_R(0.5), GF_R(0.0)}, {GF_R(1.0), GF_R(0.0)}}},
    .R = {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), GF_R(1.0)}}},
    .c = {{GF_R(0.0), GF_R(0.0)}},
};
static const gf_kf2_meas kf2_meas = {
    .m = 1,
    .C = {{{GF_R(1.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}},
    .Q = {{{GF_R(10.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}},
    .c = {{GF_R(0.0), GF_R(0.0)}},
    .gate = GF_R(0.0),
};
static const gf_ekf3_motion ekf3_motion = {
    .g = gf_ekf3_motion_forward_turn,
    .ctx = 0,
    .R = {{{GF_R(0.0), GF_R(0.0), GF_R(0.0)},
           {GF_R(0.0), GF_R(0.0), GF_R(0.0)},
           {GF_R(0.0), GF_R(0.0), GF_R(0.0)}}},
};
static const gf_ekf3_meas ekf3_meas = {
    .m = 1,
    .h = gf_ekf3_meas_x,
    .ctx = 0,
    .Q = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
           {GF_R(0.0), GF_R(0.0), GF_R(0.0)},
           {GF_R(0.0), GF_R(0.0), GF_R(0.0)}}},
    .angle_mask = 0,
    .gate = GF_R(0.0),
};
#endif

int main(void)
{
#ifdef GF_FW_WITH_FILTERS
    // KF2: one predict and one update (Table 2.1's measurement).
    fw_kf2 kf;
    const gf_vec2 mu0 = {{GF_R(0.0), GF_R(0.0)}};
    const gf_mat2 s0 = {{{GF_R(0.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}};
    int st = (int)fw_kf2_init(&kf, &mu0, &s0);
    const gf_vec2 u = {{gf_fw_in[1], GF_R(0.0)}};
    st |= (int)fw_kf2_predict(&kf, &kf2_model, &u);
    const gf_vec2 z = {{gf_fw_in[2], GF_R(0.0)}};
    st |= (int)fw_kf2_update(&kf, &kf2_meas, &z, 0);
    gf_mat2 s1;
    st |= (int)fw_kf2_cov(&kf, &s1);
    gf_fw_out[0] = kf.mu.v[0];
    gf_fw_out[1] = s1.m[0][0];

    // EKF3: Tables 4.1 and 4.2, move forward then observe x.
    fw_ekf3 ekf;
    const gf_vec3 m0 = {{GF_R(0.0), GF_R(0.0), GF_R(0.0)}};
    const gf_mat3 p0 = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.01), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.0), GF_R(10000.0)}}};
    st |= (int)fw_ekf3_init(&ekf, &m0, &p0);
    const gf_real du[2] = {gf_fw_in[0], GF_R(0.0)};
    st |= (int)fw_ekf3_predict(&ekf, &ekf3_motion, du);
    const gf_vec3 zx = {{gf_fw_in[3], GF_R(0.0), GF_R(0.0)}};
    st |= (int)fw_ekf3_update(&ekf, &ekf3_meas, &zx, 0);
    gf_fw_out[2] = ekf.mu.v[0];
    gf_fw_out[3] = ekf.mu.v[1];
    gf_mat3 p1;
    st |= (int)fw_ekf3_cov(&ekf, &p1);
    gf_fw_out[4] = p1.m[0][0];
    gf_fw_out[5] = p1.m[1][1];
    gf_fw_status = st;
#else
    for (int i = 0; i < 4; i++) {
        gf_fw_out[i] = gf_fw_in[i];
    }
    gf_fw_status = 0;
#endif
    return 0;
}
