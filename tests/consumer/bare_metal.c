// SPDX-License-Identifier: MIT
// A bare-metal application for the vendoring tests: KF2 with a two-value
// measurement, the 68% ellipse of its covariance and one EKF3 step, so
// that the image calls the core's log and atan2 (gf_log, gf_atan2) and
// needs only sqrtf from libm. Inputs and
// outputs are volatile so that nothing is folded away. The caller's start-up
// code calls main().
#include "gaussfilt/gaussfilt.h"

volatile gf_real bm_in[3] = {GF_R(5.0), GF_R(1.0), GF_R(-0.7)};
volatile gf_real bm_out[4];
volatile int bm_status;

int main(void)
{
    gf_kf2_model car;
    gf_kf2_meas gps;
    gf_kf2 kf;
    gf_ekf3_motion move;
    gf_ekf3_meas see_x;
    gf_ekf3 ekf;
    gf_ellipse e;
    gf_mat2 s1;
    gf_mat3 p1;
    const gf_vec2 mu0 = {{GF_R(0.0), GF_R(0.0)}};
    const gf_mat2 s0 = {{{GF_R(1.0), GF_R(0.0)}, {GF_R(0.0), GF_R(1.0)}}};
    const gf_vec3 m0 = {{GF_R(0.0), GF_R(0.0), GF_R(0.0)}};
    const gf_mat3 p0 = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.01), GF_R(0.0)},
                         {GF_R(0.0), GF_R(0.0), GF_R(1.0)}}};
    gf_vec2 z;
    gf_vec3 zx;
    gf_real u[2];
    int st;

    car.A = (gf_mat2){{{GF_R(1.0), GF_R(1.0)}, {GF_R(0.0), GF_R(1.0)}}};
    car.B = (gf_mat2){{{GF_R(0.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}};
    car.R = (gf_mat2){{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), GF_R(1.0)}}};
    car.c = mu0;
    gps.m = 2;
    gps.C = (gf_mat2){{{GF_R(1.0), GF_R(0.0)}, {GF_R(0.0), GF_R(1.0)}}};
    gps.Q = (gf_mat2){{{GF_R(10.0), GF_R(0.0)}, {GF_R(0.0), GF_R(1.0)}}};
    gps.c = mu0;
    gps.gate = GF_R(0.0);
    z.v[0] = bm_in[0];
    z.v[1] = bm_in[1];
    st = (int)gf_kf2_init(&kf, &mu0, &s0);
    st |= (int)gf_kf2_predict(&kf, &car, 0);
    st |= (int)gf_kf2_update(&kf, &gps, &z, 0);
    st |= (int)gf_kf2_cov(&kf, &s1);
    st |= (int)gf_cov2_ellipse(&s1, GF_R(0.68), &e);
    bm_out[0] = kf.mu.v[0];
    bm_out[1] = e.angle;

    move.g = gf_ekf3_motion_forward_turn;
    move.ctx = 0;
    move.R = p0;
    see_x.m = 1;
    see_x.h = gf_ekf3_meas_x;
    see_x.ctx = 0;
    see_x.Q = p0;
    see_x.angle_mask = 0;
    see_x.gate = GF_R(0.0);
    u[0] = bm_in[1];
    u[1] = GF_R(0.0);
    zx.v[0] = bm_in[2];
    zx.v[1] = GF_R(0.0);
    zx.v[2] = GF_R(0.0);
    st |= (int)gf_ekf3_init(&ekf, &m0, &p0);
    st |= (int)gf_ekf3_predict(&ekf, &move, u);
    st |= (int)gf_ekf3_update(&ekf, &see_x, &zx, 0);
    bm_out[2] = ekf.mu.v[0];
    st |= (int)gf_ekf3_cov(&ekf, &p1);
    bm_out[3] = p1.m[0][0];
    bm_status = st;
    return st;
}
