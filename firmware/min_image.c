// SPDX-License-Identifier: MIT
// The minimal firmware images of the footprint report, built from this file
// with the filters their macros name (firmware/CMakeLists.txt):
//   gf_fw_base      none: the same inputs and outputs, no filter;
//   gf_fw_kf2       GF_FW_KF2: one KF2 init, predict, update and cov;
//   gf_fw_ekf3      GF_FW_EKF3: the same for EKF3 with the built-in models
//                   (gf_ekf3_motion_forward_turn, gf_ekf3_meas_x);
//   gf_fw_kf4       GF_FW_KF: the same for gf_kf at n = 4, m = 2 (a 2-D
//                   constant-velocity target, its position measured);
//   gf_fw_kf2_ekf3  GF_FW_KF2 and GF_FW_EKF3;
//   gf_fw_floor_*   the same four with GF_FW_FLOOR: the loop floor's
//                   filters (bench/floor.h) in place of the library's, on
//                   the same models and inputs.
// An image's flash minus the base image's is what its filters cost. Inputs
// and outputs are volatile so that nothing is folded away at compile time.
#include "gaussfilt/gaussfilt.h"
#ifdef GF_FW_FLOOR
#include "floor.h"
#endif

volatile gf_real gf_fw_in[4] = {GF_R(1.0), GF_R(0.0), GF_R(5.0), GF_R(-0.7)};
volatile gf_real gf_fw_out[8];
volatile int gf_fw_status;

// The models never change: const, so they live in flash.
#ifdef GF_FW_KF2
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

// KF2: one predict and one update (Table 2.1's measurement).
#ifdef GF_FW_FLOOR
static int run_kf2(void)
{
    floor_kf2 kf;
    gf_real nis;
    const gf_vec2 mu0 = {{GF_R(0.0), GF_R(0.0)}};
    const gf_mat2 s0 = {{{GF_R(0.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}};
    int st = (int)floor_kf2_init(&kf, &mu0, &s0);
    const gf_vec2 u = {{gf_fw_in[1], GF_R(0.0)}};
    st |= (int)floor_kf2_predict(&kf, &kf2_model, &u);
    const gf_vec2 z = {{gf_fw_in[2], GF_R(0.0)}};
    st |= (int)floor_kf2_update(&kf, &kf2_meas, &z, &nis);
    gf_mat2 s1;
    floor_kf2_cov(&kf, &s1);
    gf_fw_out[0] = kf.mu.v[0];
    gf_fw_out[1] = s1.m[0][0];
    return st;
}
#else
static int run_kf2(void)
{
    gf_kf2 kf;
    const gf_vec2 mu0 = {{GF_R(0.0), GF_R(0.0)}};
    const gf_mat2 s0 = {{{GF_R(0.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}};
    int st = (int)gf_kf2_init(&kf, &mu0, &s0);
    const gf_vec2 u = {{gf_fw_in[1], GF_R(0.0)}};
    st |= (int)gf_kf2_predict(&kf, &kf2_model, &u);
    const gf_vec2 z = {{gf_fw_in[2], GF_R(0.0)}};
    st |= (int)gf_kf2_update(&kf, &kf2_meas, &z, 0);
    gf_mat2 s1;
    st |= (int)gf_kf2_cov(&kf, &s1);
    gf_fw_out[0] = kf.mu.v[0];
    gf_fw_out[1] = s1.m[0][0];
    return st;
}
#endif
#endif

#ifdef GF_FW_EKF3
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

// EKF3: Tables 4.1 and 4.2, move forward then observe x.
#ifdef GF_FW_FLOOR
static int run_ekf3(void)
{
    floor_ekf3 ekf;
    gf_real nis;
    const gf_vec3 m0 = {{GF_R(0.0), GF_R(0.0), GF_R(0.0)}};
    const gf_mat3 p0 = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.01), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.0), GF_R(10000.0)}}};
    int st = (int)floor_ekf3_init(&ekf, &m0, &p0);
    const gf_real du[2] = {gf_fw_in[0], GF_R(0.0)};
    st |= (int)floor_ekf3_predict(&ekf, &ekf3_motion, du);
    const gf_vec3 zx = {{gf_fw_in[3], GF_R(0.0), GF_R(0.0)}};
    st |= (int)floor_ekf3_update(&ekf, &ekf3_meas, &zx, &nis);
    gf_fw_out[2] = ekf.mu.v[0];
    gf_fw_out[3] = ekf.mu.v[1];
    gf_mat3 p1;
    floor_ekf3_cov(&ekf, &p1);
    gf_fw_out[4] = p1.m[0][0];
    gf_fw_out[5] = p1.m[1][1];
    return st;
}
#else
static int run_ekf3(void)
{
    gf_ekf3 ekf;
    const gf_vec3 m0 = {{GF_R(0.0), GF_R(0.0), GF_R(0.0)}};
    const gf_mat3 p0 = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.01), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.0), GF_R(10000.0)}}};
    int st = (int)gf_ekf3_init(&ekf, &m0, &p0);
    const gf_real du[2] = {gf_fw_in[0], GF_R(0.0)};
    st |= (int)gf_ekf3_predict(&ekf, &ekf3_motion, du);
    const gf_vec3 zx = {{gf_fw_in[3], GF_R(0.0), GF_R(0.0)}};
    st |= (int)gf_ekf3_update(&ekf, &ekf3_meas, &zx, 0);
    gf_fw_out[2] = ekf.mu.v[0];
    gf_fw_out[3] = ekf.mu.v[1];
    gf_mat3 p1;
    st |= (int)gf_ekf3_cov(&ekf, &p1);
    gf_fw_out[4] = p1.m[0][0];
    gf_fw_out[5] = p1.m[1][1];
    return st;
}
#endif
#endif

#ifdef GF_FW_KF
// A 2-D constant-velocity target, states (x, y, vx, vy), a step of 1 s,
// its position measured. The matrices are laid out a row a line.
// clang-format off
static const gf_real kf_A[16] = {
    GF_R(1.0), GF_R(0.0), GF_R(1.0), GF_R(0.0),
    GF_R(0.0), GF_R(1.0), GF_R(0.0), GF_R(1.0),
    GF_R(0.0), GF_R(0.0), GF_R(1.0), GF_R(0.0),
    GF_R(0.0), GF_R(0.0), GF_R(0.0), GF_R(1.0),
};
// White acceleration of unit density: [1/3 1/2; 1/2 1] per axis.
static const gf_real kf_R[16] = {
    GF_R(0.333333), GF_R(0.0), GF_R(0.5), GF_R(0.0),
    GF_R(0.0), GF_R(0.333333), GF_R(0.0), GF_R(0.5),
    GF_R(0.5), GF_R(0.0), GF_R(1.0), GF_R(0.0),
    GF_R(0.0), GF_R(0.5), GF_R(0.0), GF_R(1.0),
};
static const gf_real kf_C[8] = {
    GF_R(1.0), GF_R(0.0), GF_R(0.0), GF_R(0.0),
    GF_R(0.0), GF_R(1.0), GF_R(0.0), GF_R(0.0),
};
static const gf_real kf_Q[4] = {GF_R(4.0), GF_R(0.0), GF_R(0.0), GF_R(4.0)};
// clang-format on
static const gf_kf_model kf_model = {
    .nu = 0, .A = kf_A, .B = 0, .R = kf_R, .c = 0};
static const gf_kf_meas kf_meas = {
    .m = 2, .C = kf_C, .Q = kf_Q, .c = 0, .gate = GF_R(0.0)};
// The prior, for the library and the floor alike.
static const gf_real kf_mu0[4] = {GF_R(0.0), GF_R(0.0), GF_R(0.0), GF_R(0.0)};
// clang-format off
static const gf_real kf_s0[16] = {
    GF_R(100.0), GF_R(0.0), GF_R(0.0), GF_R(0.0),
    GF_R(0.0), GF_R(100.0), GF_R(0.0), GF_R(0.0),
    GF_R(0.0), GF_R(0.0), GF_R(10.0), GF_R(0.0),
    GF_R(0.0), GF_R(0.0), GF_R(0.0), GF_R(10.0),
};
// clang-format on
#ifdef GF_FW_FLOOR
// The steps' scratch: static, as firmware keeps it.
static floor_kf_work kf_work;

static int run_kf(void)
{
    floor_kf kf;
    gf_real nis;
    int st = (int)floor_kf_init(&kf, 4, kf_mu0, kf_s0, &kf_work);
    st |= (int)floor_kf_predict(&kf, &kf_model, 0, &kf_work);
    const gf_real z[2] = {gf_fw_in[2], gf_fw_in[3]};
    st |= (int)floor_kf_update(&kf, &kf_meas, z, &nis, &kf_work);
    gf_real s1[16];
    floor_kf_cov(&kf, s1);
    gf_fw_out[6] = kf.mu[0];
    gf_fw_out[7] = s1[0];
    return st;
}
#else
// The steps' scratch: static, as firmware keeps it.
static gf_kf_work kf_work;

static int run_kf(void)
{
    gf_kf kf;
    int st = (int)gf_kf_init(&kf, 4, kf_mu0, kf_s0, &kf_work);
    st |= (int)gf_kf_predict(&kf, &kf_model, 0, &kf_work);
    const gf_real z[2] = {gf_fw_in[2], gf_fw_in[3]};
    st |= (int)gf_kf_update(&kf, &kf_meas, z, 0, &kf_work);
    gf_real s1[16];
    st |= (int)gf_kf_cov(&kf, s1);
    gf_fw_out[6] = kf.mu[0];
    gf_fw_out[7] = s1[0];
    return st;
}
#endif
#endif

int main(void)
{
    int st = 0;
#ifdef GF_FW_KF2
    st |= run_kf2();
#endif
#ifdef GF_FW_EKF3
    st |= run_ekf3();
#endif
#ifdef GF_FW_KF
    st |= run_kf();
#endif
#if !defined(GF_FW_KF2) && !defined(GF_FW_EKF3) && !defined(GF_FW_KF)
    for (int i = 0; i < 4; i++) {
        gf_fw_out[i] = gf_fw_in[i];
    }
#endif
    gf_fw_status = st;
    return 0;
}
