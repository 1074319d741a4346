// SPDX-License-Identifier: MIT
// The benchmarks' workloads (workloads.h): models, simulated truth, and the
// tables the measured loops replay.
#include "workloads.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// A deterministic xorshift64* generator and Box-Muller normals, for the
// simulated truth only.
static unsigned long long rng_state;

double wl_uniform(unsigned long long *state)
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    unsigned long long r = *state * 2685821657736338717ull;
    return ((double)(r >> 11) + 0.5) / 9007199254740992.0;
}

double wl_normal(unsigned long long *state)
{
    const double u1 = wl_uniform(state);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * wl_uniform(state));
}

static double uniform01(void)
{
    return wl_uniform(&rng_state);
}

static double normal01(void)
{
    return wl_normal(&rng_state);
}

const gf_kf2_model wl_w1_model = {
    {{{1, 1}, {0, 1}}},
    {{{0, 0}, {0, 0}}},
    {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), 1}}},
    {{0, 0}},
};

const gf_kf2_meas wl_w1_meas = {
    1, {{{1, 0}, {0, 0}}}, {{{10, 0}, {0, 0}}}, {{0, 0}}, 0,
};

gf_kf2_pmodel wl_w1_pmodel;
gf_kf2_pmeas wl_w1_pmeas;
gf_kf2 wl_w1_init;
gf_vec2 wl_w1_z[WL_TAB];
gf_kf2 wl_w1_post[WL_TAB];
gf_kf2 wl_w1_prior[WL_TAB];

gf_ekf3_motion wl_w2_motion;
gf_ekf3_meas wl_w2_meas;
gf_ekf3_pmotion wl_w2_pmotion;
gf_ekf3_pmeas wl_w2_pmeas;
gf_ekf3 wl_w2_init;
gf_real wl_w2_u[WL_TAB][2];
gf_vec3 wl_w2_z[WL_TAB];
gf_ekf3 wl_w2_post[WL_TAB];
gf_ekf3 wl_w2_prior[WL_TAB];

void wl_die(const char *what, int i, gf_status st)
{
    printf("gf_bench: %s failed at step %d: %s\n", what, i, gf_status_str(st));
    exit(1);
}

void wl_setup_w1(void)
{
    // Truth: x += v + 0.5 a, v += a, a ~ N(0, 1) (so R = G G^T), z = x +
    // N(0, 10).
    double x = 0, v = 0;
    gf_vec2 mu = {{0, 0}};
    gf_mat2 sig = {{{0, 0}, {0, 0}}};
    gf_kf2 kf;
    rng_state = 0x9E3779B97F4A7C15ull;
    if (gf_kf2_init(&wl_w1_init, &mu, &sig) != GF_OK) {
        wl_die("w1 init", 0, GF_ERR_ARG);
    }
    kf = wl_w1_init;
    if (gf_kf2_prepare_model(&wl_w1_pmodel, &wl_w1_model) != GF_OK ||
        gf_kf2_prepare_meas(&wl_w1_pmeas, &wl_w1_meas) != GF_OK) {
        wl_die("w1 prepare", 0, GF_ERR_ARG);
    }
    for (unsigned i = 0; i < WL_TAB; i++) {
        double a = normal01();
        x += v + 0.5 * a;
        v += a;
        wl_w1_z[i].v[0] = (gf_real)(x + sqrt(10.0) * normal01());
        wl_w1_z[i].v[1] = 0;
        wl_w1_post[i] = kf;
        gf_status st = gf_kf2_predict(&kf, &wl_w1_model, NULL);
        if (st != GF_OK) {
            wl_die("w1 predict", (int)i, st);
        }
        wl_w1_prior[i] = kf;
        st = gf_kf2_update(&kf, &wl_w1_meas, &wl_w1_z[i], NULL);
        if (st != GF_OK) {
            wl_die("w1 update", (int)i, st);
        }
    }
}

// The same models as the built-ins, written here, so the core cannot
// recognise them.
gf_status wl_forward_turn(void *ctx, const gf_vec3 *mu, const gf_real *u,
                          gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)ctx;
    const gf_real d = u[0], th = mu->v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    mu_bar->v[0] = mu->v[0] + d * c;
    mu_bar->v[1] = mu->v[1] + d * s;
    mu_bar->v[2] = th + u[1];
    G->m[0][2] = -d * s; // the rest of G: identity, preset by the core
    G->m[1][2] = d * c;
    return GF_OK;
}

gf_status wl_meas_x(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                    gf_mat3 *H)
{
    (void)ctx;
    z_hat->v[0] = mu_bar->v[0];
    H->m[0][0] = 1;
    H->m[0][1] = 0;
    H->m[0][2] = 0;
    return GF_OK;
}

// z = (x, y, theta): the whole state, H = I.
gf_status wl_meas_xyt(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                      gf_mat3 *H)
{
    (void)ctx;
    *z_hat = *mu_bar;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            H->m[i][j] = (gf_real)(i == j);
        }
    }
    return GF_OK;
}

void wl_setup_w2(unsigned m, int user)
{
    memset(&wl_w2_motion, 0, sizeof wl_w2_motion);
    wl_w2_motion.g = user ? wl_forward_turn : gf_ekf3_motion_forward_turn;
    // Process noise: 5 cm along each axis, 0.02 rad of heading per step.
    wl_w2_motion.R.m[0][0] = GF_R(0.0025);
    wl_w2_motion.R.m[1][1] = GF_R(0.0025);
    wl_w2_motion.R.m[2][2] = GF_R(0.0004);
    memset(&wl_w2_meas, 0, sizeof wl_w2_meas);
    wl_w2_meas.m = m;
    wl_w2_meas.h = m == 1   ? (user ? wl_meas_x : gf_ekf3_meas_x)
                   : m == 2 ? gf_ekf3_meas_xy
                            : wl_meas_xyt;
    wl_w2_meas.Q.m[0][0] = GF_R(0.01);
    wl_w2_meas.Q.m[1][1] = m >= 2 ? GF_R(0.01) : 0;
    wl_w2_meas.Q.m[2][2] = m >= 3 ? GF_R(0.0025) : 0;
    wl_w2_meas.angle_mask = m >= 3 ? 4u : 0u;

    if (gf_ekf3_prepare_motion(&wl_w2_pmotion, &wl_w2_motion) != GF_OK ||
        gf_ekf3_prepare_meas(&wl_w2_pmeas, &wl_w2_meas) != GF_OK) {
        wl_die("w2 prepare", 0, GF_ERR_ARG);
    }

    gf_vec3 mu = {{0, 0, 0}};
    gf_mat3 sig = {
        {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, GF_R(0.01)}}};
    if (gf_ekf3_init(&wl_w2_init, &mu, &sig) != GF_OK) {
        wl_die("w2 init", 0, GF_ERR_ARG);
    }
    gf_ekf3 ekf = wl_w2_init;
    double x = 0, y = 0, th = 0;
    rng_state = 0x9E3779B97F4A7C15ull;
    for (unsigned i = 0; i < WL_TAB; i++) {
        double phi = 1.2 * uniform01() - 0.6;
        x += cos(th) + 0.05 * normal01();
        y += sin(th) + 0.05 * normal01();
        th += phi + 0.02 * normal01();
        wl_w2_u[i][0] = 1;
        wl_w2_u[i][1] = (gf_real)phi;
        wl_w2_z[i].v[0] = (gf_real)(x + 0.1 * normal01());
        wl_w2_z[i].v[1] = (gf_real)(y + 0.1 * normal01());
        double zt = th + 0.05 * normal01();
        wl_w2_z[i].v[2] = (gf_real)atan2(sin(zt), cos(zt));
        wl_w2_post[i] = ekf;
        gf_status st = gf_ekf3_predict(&ekf, &wl_w2_motion, wl_w2_u[i]);
        if (st != GF_OK) {
            wl_die("w2 predict", (int)i, st);
        }
        wl_w2_prior[i] = ekf;
        st = gf_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[i], NULL);
        if (st != GF_OK) {
            wl_die("w2 update", (int)i, st);
        }
    }
}
