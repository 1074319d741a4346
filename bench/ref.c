// SPDX-License-Identifier: MIT
// The reference the floor is measured by: a hand-unrolled scalar
// implementation of one step of W1 and W2 (W2's update with m = 1, 2 or
// 3), on the same structs as the library (W2's models written in, as a
// hand implementation of the workload knows them), the textbook covariance
// update (Sigma - K H Sigma), with no checks, no NIS and no constant terms
// (zero in every workload). Used only by the benchmarks, to show what the
// library spends over it. Not library code: it trusts its inputs and
// returns nothing.
#include <stddef.h>

#include "ref.h"

ref_kf2 ref_kf2_from(const gf_kf2 *kf)
{
    ref_kf2 r;
    r.mu = kf->mu;
    (void)gf_kf2_cov(kf, &r.sigma);
    return r;
}

ref_ekf3 ref_ekf3_from(const gf_ekf3 *ekf)
{
    ref_ekf3 r;
    r.mu = ekf->mu;
    (void)gf_ekf3_cov(ekf, &r.sigma);
    return r;
}

void ref_kf2_predict(ref_kf2 *kf, const gf_kf2_model *model)
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

void ref_kf2_update(ref_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z)
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

void ref_ekf3_predict(ref_ekf3 *ekf, const gf_ekf3_motion *motion,
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

void ref_ekf3_update(ref_ekf3 *ekf, const gf_ekf3_meas *meas, const gf_vec3 *z)
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

void ref_ekf3_update_xy(ref_ekf3 *ekf, const gf_ekf3_meas *meas,
                        const gf_vec3 *z)
{
    // W2's m = 2 measurement written in: z_hat = (x, y), H = (I 0), so
    // S = Sigma's upper-left 2x2 + Q and P = Sigma H^T its first two
    // columns; K = P S^-1 by the closed-form 2x2 inverse.
    const gf_mat3 *S = &ekf->sigma, *Q = &meas->Q;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    const gf_real a = s00 + Q->m[0][0], b = s01 + Q->m[0][1];
    const gf_real c = s11 + Q->m[1][1];
    const gf_real idet = GF_R(1.0) / (a * c - b * b);
    const gf_real i00 = c * idet, i01 = -b * idet, i11 = a * idet;
    // K rows: (P_r0, P_r1) S^-1, P = ((s00 s01) (s01 s11) (s02 s12)).
    const gf_real k00 = s00 * i00 + s01 * i01, k01 = s00 * i01 + s01 * i11;
    const gf_real k10 = s01 * i00 + s11 * i01, k11 = s01 * i01 + s11 * i11;
    const gf_real k20 = s02 * i00 + s12 * i01, k21 = s02 * i01 + s12 * i11;
    const gf_real y0 = z->v[0] - ekf->mu.v[0], y1 = z->v[1] - ekf->mu.v[1];
    ekf->mu.v[0] += k00 * y0 + k01 * y1;
    ekf->mu.v[1] += k10 * y0 + k11 * y1;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + k20 * y0 + k21 * y1);
    // Sigma - K P^T, upper triangle.
    gf_real(*o)[3] = ekf->sigma.m;
    o[0][0] = s00 - (k00 * s00 + k01 * s01);
    o[0][1] = o[1][0] = s01 - (k00 * s01 + k01 * s11);
    o[0][2] = o[2][0] = s02 - (k00 * s02 + k01 * s12);
    o[1][1] = s11 - (k10 * s01 + k11 * s11);
    o[1][2] = o[2][1] = s12 - (k10 * s02 + k11 * s12);
    o[2][2] = s22 - (k20 * s02 + k21 * s12);
}

void ref_ekf3_update_xyt(ref_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z)
{
    // W2's m = 3 measurement written in: z_hat = mu, H = I, so S = Sigma + Q
    // and K = Sigma S^-1, S^-1 by the adjugate of the symmetric S.
    const gf_mat3 *S = &ekf->sigma, *Q = &meas->Q;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    const gf_real a00 = s00 + Q->m[0][0], a01 = s01 + Q->m[0][1];
    const gf_real a02 = s02 + Q->m[0][2], a11 = s11 + Q->m[1][1];
    const gf_real a12 = s12 + Q->m[1][2], a22 = s22 + Q->m[2][2];
    const gf_real c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22;
    const gf_real c02 = a01 * a12 - a02 * a11, c11 = a00 * a22 - a02 * a02;
    const gf_real c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
    const gf_real idet = GF_R(1.0) / (a00 * c00 + a01 * c01 + a02 * c02);
    const gf_real i00 = c00 * idet, i01 = c01 * idet, i02 = c02 * idet;
    const gf_real i11 = c11 * idet, i12 = c12 * idet, i22 = c22 * idet;
    // K = Sigma S^-1 (both symmetric, K general).
    const gf_real k00 = s00 * i00 + s01 * i01 + s02 * i02;
    const gf_real k01 = s00 * i01 + s01 * i11 + s02 * i12;
    const gf_real k02 = s00 * i02 + s01 * i12 + s02 * i22;
    const gf_real k10 = s01 * i00 + s11 * i01 + s12 * i02;
    const gf_real k11 = s01 * i01 + s11 * i11 + s12 * i12;
    const gf_real k12 = s01 * i02 + s11 * i12 + s12 * i22;
    const gf_real k20 = s02 * i00 + s12 * i01 + s22 * i02;
    const gf_real k21 = s02 * i01 + s12 * i11 + s22 * i12;
    const gf_real k22 = s02 * i02 + s12 * i12 + s22 * i22;
    const gf_real y0 = z->v[0] - ekf->mu.v[0], y1 = z->v[1] - ekf->mu.v[1];
    const gf_real y2 = wrap(z->v[2] - ekf->mu.v[2]);
    ekf->mu.v[0] += k00 * y0 + k01 * y1 + k02 * y2;
    ekf->mu.v[1] += k10 * y0 + k11 * y1 + k12 * y2;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + k20 * y0 + k21 * y1 + k22 * y2);
    // Sigma - K Sigma, upper triangle.
    gf_real(*o)[3] = ekf->sigma.m;
    o[0][0] = s00 - (k00 * s00 + k01 * s01 + k02 * s02);
    o[0][1] = o[1][0] = s01 - (k00 * s01 + k01 * s11 + k02 * s12);
    o[0][2] = o[2][0] = s02 - (k00 * s02 + k01 * s12 + k02 * s22);
    o[1][1] = s11 - (k10 * s01 + k11 * s11 + k12 * s12);
    o[1][2] = o[2][1] = s12 - (k10 * s02 + k11 * s12 + k12 * s22);
    o[2][2] = s22 - (k20 * s02 + k21 * s12 + k22 * s22);
}
