// SPDX-License-Identifier: MIT
// The filter half of the endurance test, in whatever precision gf_real is
// (see endurance.h). ENDURANCE_SUFFIX is d or f.
#include <math.h>
#include <string.h>

#include "endurance.h"
#include "gaussfilt/gaussfilt.h"

#define ENDURANCE_CAT2(a, b) a##_##b
#define ENDURANCE_CAT(a, b) ENDURANCE_CAT2(a, b)
#define ENDURANCE_NAME(name) ENDURANCE_CAT(name, ENDURANCE_SUFFIX)

// One program runs one copy of each filter: file-scope state is fine in
// this test code (the core itself has none).
static gf_kf2 kf;
static gf_ekf3 ekf;

static const gf_kf2_model kf2_model = {
    .A = {{{1, 1}, {0, 1}}},
    .B = {{{GF_R(0.5), 0}, {1, 0}}},
    .R = {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), 1}}},
    .c = {{0, 0}},
};
static const gf_kf2_meas kf2_meas = {
    .m = 1,
    .C = {{{1, 0}, {0, 0}}},
    .Q = {{{(gf_real)ENDURANCE_KF2_Q, 0}, {0, 0}}},
    .c = {{0, 0}},
    .gate = 0,
};

static const gf_ekf3_motion ekf3_motion = {
    .g = gf_ekf3_motion_forward_turn,
    .ctx = NULL,
    .R = {{{(gf_real)ENDURANCE_EKF3_R_XY, 0, 0},
           {0, (gf_real)ENDURANCE_EKF3_R_XY, 0},
           {0, 0, (gf_real)ENDURANCE_EKF3_R_TH}}},
};
static const gf_ekf3_meas ekf3_meas = {
    .m = 2,
    .h = gf_ekf3_meas_xy,
    .ctx = NULL,
    .Q = {{{(gf_real)ENDURANCE_EKF3_Q, 0, 0},
           {0, (gf_real)ENDURANCE_EKF3_Q, 0},
           {0, 0, 0}}},
    .angle_mask = 0,
    .gate = 0,
};

// The belief widened to double, Sigma read through its accessor (NaN,
// which the driver reports, if that fails).
static void widen2(const gf_kf2 *f, endurance_belief *out)
{
    memset(out->mu, 0, sizeof out->mu);
    memset(out->sigma, 0, sizeof out->sigma);
    gf_mat2 sigma;
    const int ok = gf_kf2_cov(f, &sigma) == GF_OK;
    for (int i = 0; i < 2; i++) {
        out->mu[i] = (double)f->mu.v[i];
        for (int j = 0; j < 2; j++) {
            out->sigma[i][j] = ok ? (double)sigma.m[i][j] : (double)NAN;
        }
    }
}

static void widen3(const gf_ekf3 *f, endurance_belief *out)
{
    gf_mat3 sigma;
    const int ok = gf_ekf3_cov(f, &sigma) == GF_OK;
    for (int i = 0; i < 3; i++) {
        out->mu[i] = (double)f->mu.v[i];
        for (int j = 0; j < 3; j++) {
            out->sigma[i][j] = ok ? (double)sigma.m[i][j] : (double)NAN;
        }
    }
}

int ENDURANCE_NAME(endurance_kf2_start)(void)
{
    const gf_vec2 mu = {{0, 0}};
    const gf_mat2 sigma = {{{100, 0}, {0, 100}}};
    return gf_kf2_init(&kf, &mu, &sigma);
}

void ENDURANCE_NAME(endurance_kf2_step)(double u, const double *z,
                                        endurance_belief *out)
{
    const gf_vec2 uu = {{(gf_real)u, 0}};
    out->predict_status = gf_kf2_predict(&kf, &kf2_model, &uu);
    out->update_status = 1;
    if (z) {
        const gf_vec2 zz = {{(gf_real)z[0], 0}};
        out->update_status = gf_kf2_update(&kf, &kf2_meas, &zz, NULL);
    }
    widen2(&kf, out);
}

int ENDURANCE_NAME(endurance_ekf3_start)(void)
{
    const gf_vec3 mu = {{20, 0, GF_PI / 2}};
    const gf_mat3 sigma = {{{1, 0, 0}, {0, 1, 0}, {0, 0, GF_R(0.1)}}};
    return gf_ekf3_init(&ekf, &mu, &sigma);
}

void ENDURANCE_NAME(endurance_ekf3_step)(const double u[2], const double *z,
                                         endurance_belief *out)
{
    const gf_real uu[2] = {(gf_real)u[0], (gf_real)u[1]};
    out->predict_status = gf_ekf3_predict(&ekf, &ekf3_motion, uu);
    out->update_status = 1;
    if (z) {
        const gf_vec3 zz = {{(gf_real)z[0], (gf_real)z[1], 0}};
        out->update_status = gf_ekf3_update(&ekf, &ekf3_meas, &zz, NULL);
    }
    widen3(&ekf, out);
}
