// The reference the floor is measured by: a hand-unrolled scalar
// implementation of one step of W1 and W2, on the same structs as the
// library (W2's two models written in, as the library does for its
// built-in ones), with no checks, no Joseph form, no NIS and no constant
// terms (zero in both workloads). Used only by gf_bench, to show
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
    // W2's motion written in (a hand implementation of W2 knows its model):
    // x + d cos, y + d sin, theta + phi; G = I + a e0 e2^T + b e1 e2^T.
    const gf_real d = u[0], th = ekf->mu.v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    const gf_real a = -d * s, b = d * c;
    const gf_mat3 *S = &ekf->sigma, *R = &motion->R;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    const gf_real t02 = s02 + a * s22, t12 = s12 + b * s22;
    ekf->mu.v[0] += d * c;
    ekf->mu.v[1] += d * s;
    ekf->mu.v[2] = wrap(th + u[1]);
    gf_real(*o)[3] = ekf->sigma.m;
    o[0][0] = s00 + a * s02 + a * t02 + R->m[0][0];
    o[0][1] = o[1][0] = s01 + a * s12 + b * t02 + R->m[0][1];
    o[0][2] = o[2][0] = t02 + R->m[0][2];
    o[1][1] = s11 + b * s12 + b * t12 + R->m[1][1];
    o[1][2] = o[2][1] = t12 + R->m[1][2];
    o[2][2] = s22 + R->m[2][2];
}

void ref_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                     const gf_vec3 *z)
{
    // W2's measurement written in: z_hat = x, H = (1 0 0), so p = Sigma's
    // first column.
    const gf_mat3 *S = &ekf->sigma;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    const gf_real si = GF_R(1.0) / (s00 + meas->Q.m[0][0]);
    const gf_real y = z->v[0] - ekf->mu.v[0];
    const gf_real k0 = s00 * si, k1 = s01 * si, k2 = s02 * si;
    ekf->mu.v[0] += k0 * y;
    ekf->mu.v[1] += k1 * y;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + k2 * y);
    gf_real(*o)[3] = ekf->sigma.m;
    o[0][0] = s00 - k0 * s00;
    o[0][1] = o[1][0] = s01 - k0 * s01;
    o[0][2] = o[2][0] = s02 - k0 * s02;
    o[1][1] = s11 - k1 * s01;
    o[1][2] = o[2][1] = s12 - k1 * s02;
    o[2][2] = s22 - k2 * s02;
}
