// SPDX-License-Identifier: MIT
// Exercise 4 (docs/exercises.md) three ways, as data for a figure
// (scripts/ex4-figure): EKF3, UKF3 and PF3 from the same prior, one move of 1,
// one observation x = -0.7. Prints one record a line:
//   ellipse NAME mx my a b angle     68% ellipse of the (x, y) marginal
//   particle STAGE x y w             PF3 particles (STAGE: pred, post)
#include <stdio.h>

#include "book.h"
#include "gaussfilt/gaussfilt.h"

#define N_PARTICLES 2000
static gf_pf3_particle particles[N_PARTICLES];

static void ellipse(const char *name, const gf_vec3 *mu, const gf_mat3 *s)
{
    gf_mat2 m;
    gf_ellipse e;
    if (gf_cov2_marginal(s, 0, 1, &m) != GF_OK ||
        gf_cov2_ellipse(&m, GF_R(0.68), &e) != GF_OK) {
        fprintf(stderr, "%s: no ellipse\n", name);
        return;
    }
    printf("ellipse %s %.6f %.6f %.6f %.6f %.6f\n", name, (double)mu->v[0],
           (double)mu->v[1], (double)e.a, (double)e.b, (double)e.angle);
}

// The EKF's ellipse: its belief carries Sigma as factors, read back here.
static void ellipse_ekf(const char *name, const gf_ekf3 *ekf)
{
    gf_mat3 s;
    if (gf_ekf3_cov(ekf, &s) != GF_OK) {
        fprintf(stderr, "%s: no covariance\n", name);
        return;
    }
    ellipse(name, &ekf->mu, &s);
}

static void dump(const char *stage)
{
    for (unsigned k = 0; k < N_PARTICLES; k++) {
        printf("particle %s %.5f %.5f %.6g\n", stage,
               (double)particles[k].x.v[0], (double)particles[k].x.v[1],
               (double)particles[k].w);
    }
}

int main(void)
{
    const gf_vec3 mu0 = {{0, 0, 0}};
    // exercise 4's numbers (book.h)
    const gf_real xy = (gf_real)GF_BOOK_EX4_XY_VAR;
    const gf_mat3 s0 = {
        {{xy, 0, 0}, {0, xy, 0}, {0, 0, (gf_real)GF_BOOK_EX4_HEADING_VAR}}};
    const gf_ekf3_motion move = {
        gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
    const gf_ekf3_meas obs = {
        1,    gf_ekf3_meas_x,
        NULL, {{{(gf_real)GF_BOOK_EX4_Q, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
        0,    0};
    const gf_real u[2] = {(gf_real)GF_BOOK_EX4_D, (gf_real)GF_BOOK_EX4_PHI};
    const gf_vec3 z = {{(gf_real)GF_BOOK_EX4_Z, 0, 0}};
    const gf_ukf3_params p = {1, 2, 0};
    gf_ekf3 ekf;
    gf_ukf3 ukf;
    gf_pf3 pf;
    if (gf_ekf3_init(&ekf, &mu0, &s0) || gf_ukf3_init(&ukf, &mu0, &s0, &p) ||
        gf_pf3_init(&pf, particles, N_PARTICLES, 4, &mu0, &s0)) {
        return 1;
    }
    ellipse("prior", &mu0, &s0);
    if (gf_ekf3_predict(&ekf, &move, u) || gf_ukf3_predict(&ukf, &move, u) ||
        gf_pf3_predict(&pf, &move, u)) {
        return 1;
    }
    ellipse_ekf("ekf_pred", &ekf);
    ellipse("ukf_pred", &ukf.mu, &ukf.sigma);
    dump("pred");
    if (gf_ekf3_update(&ekf, &obs, &z, NULL) ||
        gf_ukf3_update(&ukf, &obs, &z, NULL) || gf_pf3_update(&pf, &obs, &z) ||
        gf_pf3_resample(&pf)) {
        return 1;
    }
    ellipse_ekf("ekf_post", &ekf);
    ellipse("ukf_post", &ukf.mu, &ukf.sigma);
    dump("post");
    return 0;
}
