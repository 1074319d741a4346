// The reference the floor is measured by: a hand-unrolled scalar
// implementation of one step of W1 and W2, on the same structs and model
// callbacks as the library, with no checks, no Joseph form, no NIS and no
// constant terms (zero in both workloads). Used only by gf_bench, to show
// what the library's checks and Joseph form cost on this machine. Not
// library code: it trusts its inputs and returns nothing.
#include "ref.h"

void ref_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model)
{
    const gf_mat2 *A = &model->A;
    const gf_real a00 = A->m[0][0], a01 = A->m[0][1];
    const gf_real a10 = A->m[1][0], a11 = A->m[1][1];
    const gf_real s00 = kf->sigma.m[0][0], s01 = kf->sigma.m[0][1];
    const gf_real s11 = kf->sigma.m[1][1];
    const gf_real m0 = kf->mu.v[0], m1 = kf->mu.v[1];
    // mu = A mu; Sigma = A Sigma A^T + R (upper triangle)
    kf->mu.v[0] = a00 * m0 + a01 * m1;
    kf->mu.v[1] = a10 * m0 + a11 * m1;
    const gf_real t00 = a00 * s00 + a01 * s01, t01 = a00 * s01 + a01 * s11;
    const gf_real t10 = a10 * s00 + a11 * s01, t11 = a10 * s01 + a11 * s11;
    const gf_real n01 = t00 * a10 + t01 * a11 + model->R.m[0][1];
    kf->sigma.m[0][0] = t00 * a00 + t01 * a01 + model->R.m[0][0];
    kf->sigma.m[0][1] = n01;
    kf->sigma.m[1][0] = n01;
    kf->sigma.m[1][1] = t10 * a10 + t11 * a11 + model->R.m[1][1];
}

void ref_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z)
{
    const gf_real c0 = meas->C.m[0][0], c1 = meas->C.m[0][1];
    const gf_real s00 = kf->sigma.m[0][0], s01 = kf->sigma.m[0][1];
    const gf_real s11 = kf->sigma.m[1][1];
    const gf_real m0 = kf->mu.v[0], m1 = kf->mu.v[1];
    const gf_real p0 = s00 * c0 + s01 * c1, p1 = s01 * c0 + s11 * c1;
    const gf_real si = GF_R(1.0) / (c0 * p0 + c1 * p1 + meas->Q.m[0][0]);
    const gf_real y = z->v[0] - (c0 * m0 + c1 * m1);
    const gf_real k0 = p0 * si, k1 = p1 * si;
    kf->mu.v[0] = m0 + k0 * y;
    kf->mu.v[1] = m1 + k1 * y;
    const gf_real n01 = s01 - k0 * p1;
    kf->sigma.m[0][0] = s00 - k0 * p0;
    kf->sigma.m[0][1] = n01;
    kf->sigma.m[1][0] = n01;
    kf->sigma.m[1][1] = s11 - k1 * p1;
}

static gf_real wrap(gf_real a)
{
    return (a > -GF_PI && a <= GF_PI) ? a : gf_angle_wrap(a);
}

void ref_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                      const gf_real *u)
{
    gf_vec3 mu;
    gf_mat3 G;
    (void)motion->g(motion->ctx, &ekf->mu, u, &mu, &G);
    const gf_mat3 *S = &ekf->sigma;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    gf_real t[3][3];
    for (int i = 0; i < 3; i++) { // T = G Sigma
        const gf_real g0 = G.m[i][0], g1 = G.m[i][1], g2 = G.m[i][2];
        t[i][0] = g0 * s00 + g1 * s01 + g2 * s02;
        t[i][1] = g0 * s01 + g1 * s11 + g2 * s12;
        t[i][2] = g0 * s02 + g1 * s12 + g2 * s22;
    }
    gf_mat3 n;
    for (int i = 0; i < 3; i++) { // Sigma = T G^T + R, upper triangle
        for (int j = i; j < 3; j++) {
            n.m[i][j] = t[i][0] * G.m[j][0] + t[i][1] * G.m[j][1] +
                        t[i][2] * G.m[j][2] + motion->R.m[i][j];
            n.m[j][i] = n.m[i][j];
        }
    }
    mu.v[2] = wrap(mu.v[2]);
    ekf->mu = mu;
    ekf->sigma = n;
}

void ref_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                     const gf_vec3 *z)
{
    gf_vec3 zh;
    gf_mat3 H;
    (void)meas->h(meas->ctx, &ekf->mu, &zh, &H);
    const gf_mat3 *S = &ekf->sigma;
    const gf_real h0 = H.m[0][0], h1 = H.m[0][1], h2 = H.m[0][2];
    gf_real p[3];
    for (int i = 0; i < 3; i++) {
        p[i] = S->m[i][0] * h0 + S->m[i][1] * h1 + S->m[i][2] * h2;
    }
    const gf_real si =
        GF_R(1.0) / (h0 * p[0] + h1 * p[1] + h2 * p[2] + meas->Q.m[0][0]);
    const gf_real y = z->v[0] - zh.v[0];
    gf_real k[3];
    for (int i = 0; i < 3; i++) {
        k[i] = p[i] * si;
        ekf->mu.v[i] += k[i] * y;
    }
    ekf->mu.v[2] = wrap(ekf->mu.v[2]);
    for (int i = 0; i < 3; i++) {
        for (int j = i; j < 3; j++) {
            ekf->sigma.m[i][j] -= k[i] * p[j];
            ekf->sigma.m[j][i] = ekf->sigma.m[i][j];
        }
    }
}
