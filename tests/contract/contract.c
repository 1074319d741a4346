// SPDX-License-Identifier: MIT
// The numbers of a fixed run of KF2, EKF3 and gf_kf (n = 4, m = 2), every
// one printed exactly (%a): scripts/test.d/12-contract.sh builds the core
// with and without the compiler's licence to fuse products and sums and
// compares the outputs byte for byte. Inputs from a fixed seed (gf_rng).
#include <stdio.h>

#include "gaussfilt/gaussfilt.h"

static void put(const char *what, const gf_real *x, unsigned n, int st)
{
    printf("%s %d", what, st);
    for (unsigned i = 0; i < n; i++) {
        printf(" %a", (double)x[i]);
    }
    printf("\n");
}

static gf_real draw(gf_rng *rng)
{
    return (gf_real)(gf_rng_u32(rng) % 2001u) / GF_R(1000.0) - GF_R(1.0);
}

int main(void)
{
    gf_rng rng;
    gf_rng_seed(&rng, 20261205u);

    const gf_kf2_model car = {{{{1, 1}, {0, 1}}},
                              {{{0.5, 0}, {1, 0}}},
                              {{{0.25, 0.5}, {0.5, 1}}},
                              {{0, 0}}};
    const gf_kf2_meas gps = {
        2, {{{1, 0}, {0, 1}}}, {{{10, 2}, {2, 3}}}, {{0, 0}}, 0};
    const gf_vec2 mu0 = {{0, 0}};
    const gf_mat2 s0 = {{{1, 0.3}, {0.3, 2}}};
    gf_kf2 kf;
    int st = (int)gf_kf2_init(&kf, &mu0, &s0);
    for (unsigned t = 0; t < 50; t++) {
        const gf_vec2 u = {{draw(&rng), 0}};
        st |= (int)gf_kf2_predict(&kf, &car, &u);
        const gf_vec2 z = {{kf.mu.v[0] + 3 * draw(&rng), draw(&rng)}};
        gf_innovation in;
        st |= (int)gf_kf2_update(&kf, &gps, &z, &in);
        gf_mat2 s;
        st |= (int)gf_kf2_cov(&kf, &s);
        put("kf2 mu", kf.mu.v, 2, st);
        put("kf2 sigma", s.m[0], 4, st);
        put("kf2 nis", &in.nis, 1, st);
    }

    const gf_ekf3_motion move = {
        gf_ekf3_motion_forward_turn,
        NULL,
        {{{0.01, 0.002, 0}, {0.002, 0.01, 0}, {0, 0, 0.001}}}};
    const gf_ekf3_meas xy = {
        2,    gf_ekf3_meas_xy,
        NULL, {{{0.04, 0.01, 0}, {0.01, 0.05, 0}, {0, 0, 0}}},
        0,    0};
    const gf_vec3 m0 = {{0, 0, 0.3}};
    const gf_mat3 p0 = {{{1, 0.1, 0}, {0.1, 1, 0}, {0, 0, 0.1}}};
    gf_ekf3 ekf;
    st = (int)gf_ekf3_init(&ekf, &m0, &p0);
    for (unsigned t = 0; t < 50; t++) {
        const gf_real u[2] = {1 + draw(&rng), GF_R(0.1) * draw(&rng)};
        st |= (int)gf_ekf3_predict(&ekf, &move, u);
        const gf_vec3 z = {{ekf.mu.v[0] + GF_R(0.2) * draw(&rng),
                            ekf.mu.v[1] + GF_R(0.2) * draw(&rng), 0}};
        st |= (int)gf_ekf3_update(&ekf, &xy, &z, NULL);
        gf_mat3 p;
        st |= (int)gf_ekf3_cov(&ekf, &p);
        put("ekf3 mu", ekf.mu.v, 3, st);
        put("ekf3 sigma", p.m[0], 9, st);
    }

    static gf_kf_work work;
    const gf_real A[16] = {1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1};
    const gf_real R[16] = {0.25, 0.5, 0,    0,   0.5, 1, 0,   0,
                           0,    0,   0.25, 0.5, 0,   0, 0.5, 1};
    const gf_real C[8] = {1, 0, 0, 0, 0, 0, 1, 0};
    const gf_real Q[4] = {4, 1, 1, 5};
    const gf_real mu4[4] = {0, 1, 0, -1};
    const gf_real S4[16] = {2, 0.5, 0, 0,   0.5, 1, 0,   0,
                            0, 0,   2, 0.5, 0,   0, 0.5, 1};
    const gf_kf_model model = {0, A, NULL, R, NULL};
    const gf_kf_meas meas = {2, C, Q, NULL, 0};
    gf_kf k4;
    st = (int)gf_kf_init(&k4, 4, mu4, S4, &work);
    for (unsigned t = 0; t < 50; t++) {
        st |= (int)gf_kf_predict(&k4, &model, NULL, &work);
        const gf_real z[2] = {k4.mu[0] + 2 * draw(&rng),
                              k4.mu[2] + 2 * draw(&rng)};
        st |= (int)gf_kf_update(&k4, &meas, z, NULL, &work);
        gf_real s[16];
        st |= (int)gf_kf_cov(&k4, s);
        put("kf4 mu", k4.mu, 4, st);
        put("kf4 sigma", s, 16, st);
    }
    return 0;
}
