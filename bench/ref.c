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

// ---- The sound floor: U D U^T carried between steps -----------------------
//
// One step of W1 and W2 on the factors Sigma = P U D U^T P^T (ref.h),
// written out for n = 2 and 3: Thornton's modified weighted Gram-Schmidt
// for the prediction, Bierman's scalar update for each measured quantity.
// The arithmetic is written once (the REF_INLINE helpers below) and
// inlined into two variants:
//   udu   no checks, the states in their own order (P = I): R arrives as
//         its factors (ref_noise2/3_from, once), a d_j of the prediction
//         is divided by as it is (R's last variance is positive in both
//         workloads), no NIS, no constant terms;
//   uduc  the checks the plain API promises (kf2.h, ekf3.h), each as cheap
//         as a hand-written step can make it: every input finite (a sum of
//         x * 0, NaN if one x is not), R judged and factored in closed
//         form at every call, Q's m x m block judged and factored the same
//         way (m = 1: q >= 0), the gate >= 0, s > 0 (or the exact-quantity
//         rule), the NIS finite, the gate, the result finite (mu, U, D and
//         the variances they give); the work done on locals and written to
//         the belief only on success. The m quantities of an update are
//         whitened by Q's factors and taken one Bierman update each, in
//         their own order (as the library's), each made the root first
//         if it tells much; and the
//         library's order of the factors and precision of the prior
//         ("The factors' order", "The checked floor's init" below), which
//         the float accuracy target needs.
// The library's own guards (src/udu.h) come with uduc: a d_j or an
// alpha_j below GF_REAL_MIN is zero, not divided by.

#if defined(__GNUC__)
#define REF_INLINE static inline __attribute__((always_inline))
#define REF_NOINLINE __attribute__((noinline))
#else
#define REF_INLINE static inline
#define REF_NOINLINE
#endif
// A loop of constant count written out (gcc would make a zeroing loop a
// memset call, far slower on newlib-nano than its stores).
#if defined(__GNUC__) && !defined(__clang__)
#define REF_UNROLL _Pragma("GCC unroll 3")
#else
#define REF_UNROLL
#endif

// Packed factors: U_ij (i < j) and d_j, as src/udu.h packs them.
#define UD(i, j) ((j) * ((j) + 1u) / 2u + (i))

// 0 for a finite x, NaN for an infinite or NaN one; a sum of them stays
// NaN and cannot overflow, so (sum < 1) tells that every x was finite.
#define Z(x) ((x)*GF_R(0.0))

// The factors of a symmetric PSD s (n x n, rows of n, upper triangle
// read), column j from the last: d_j = s_jj - sum_(k>j) U_jk^2 d_k,
// U_ij = (s_ij - sum_(k>j) U_ik d_k U_jk) / d_j; a d_j not above zero is
// zero, with a zero column of U. Set-up only.
static void udu_factor(const gf_real *s, unsigned n, gf_real *ud)
{
    for (unsigned j = n; j-- > 0u;) {
        gf_real dj = s[j * n + j];
        for (unsigned k = j + 1u; k < n; k++) {
            dj -= ud[UD(j, k)] * ud[UD(k, k)] * ud[UD(j, k)];
        }
        for (unsigned i = 0; i < j; i++) {
            gf_real r = s[i * n + j];
            for (unsigned k = j + 1u; k < n; k++) {
                r -= ud[UD(i, k)] * ud[UD(k, k)] * ud[UD(j, k)];
            }
            ud[UD(i, j)] = dj > 0 ? r / dj : GF_R(0.0);
        }
        ud[UD(j, j)] = dj > 0 ? dj : GF_R(0.0);
    }
}

// Sigma_(perm i)(perm j) = sum_(k >= max(i, j)) U_ik d_k U_jk, U_kk = 1,
// into s (n x n).
static void udu_cov(const gf_real *ud, const unsigned char *perm, unsigned n,
                    gf_real *s)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            for (unsigned k = j; k < n; k++) {
                const gf_real uik = (k == i) ? GF_R(1.0) : ud[UD(i, k)];
                const gf_real ujk = (k == j) ? GF_R(1.0) : ud[UD(j, k)];
                acc += uik * ud[UD(k, k)] * ujk;
            }
            s[perm[i] * n + perm[j]] = acc;
            s[perm[j] * n + perm[i]] = acc;
        }
    }
}

// ref_udu2_dev and ref_udu3_dev for n states (lib: the library's Sigma,
// n x n; angle: the index of a heading, n if none).
static gf_real udu_dev(const gf_real *ud, const unsigned char *perm,
                       const gf_real *mu, const gf_real *lib,
                       const gf_real *lib_mu, unsigned n, unsigned angle,
                       gf_real *mu_dev)
{
    gf_real s[9], sd[3], worst = 0, worst_mu = 0;
    udu_cov(ud, perm, n, s);
    for (unsigned i = 0; i < n; i++) {
        sd[i] = GF_SQRT(lib[i * n + i]);
        gf_real dm = mu[i] - lib_mu[i];
        if (i == angle) {
            dm = gf_angle_wrap(dm);
        }
        dm = GF_FABS(dm);
        worst_mu = (sd[i] > 0 && dm / sd[i] > worst_mu) ? dm / sd[i]
                   : (sd[i] > 0)                        ? worst_mu
                   : (dm > worst_mu)                    ? dm
                                                        : worst_mu;
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            const gf_real den = sd[i] * sd[j];
            gf_real e = GF_FABS(s[i * n + j] - lib[i * n + j]);
            e = den > 0 ? e / den : e;
            worst = e > worst ? e : worst;
        }
    }
    *mu_dev = worst_mu;
    return worst;
}

ref_udu2 ref_udu2_from(const gf_kf2 *kf)
{
    ref_udu2 r;
    r.mu = kf->mu;
    for (unsigned k = 0; k < 3u; k++) {
        r.ud[k] = kf->ud[k];
    }
    for (unsigned k = 0; k < sizeof r.perm; k++) {
        r.perm[k] = kf->perm[k];
    }
    return r;
}

ref_udu3 ref_udu3_from(const gf_ekf3 *ekf)
{
    ref_udu3 r;
    r.mu = ekf->mu;
    for (unsigned k = 0; k < 6u; k++) {
        r.ud[k] = ekf->ud[k];
    }
    for (unsigned k = 0; k < sizeof r.perm; k++) {
        r.perm[k] = ekf->perm[k];
    }
    return r;
}

ref_udu2 ref_udu2_inorder(const gf_kf2 *kf)
{
    ref_udu2 r = {kf->mu, {0}, {0, 1}};
    gf_mat2 s;
    (void)gf_kf2_cov(kf, &s);
    udu_factor(s.m[0], 2, r.ud);
    return r;
}

ref_udu3 ref_udu3_inorder(const gf_ekf3 *ekf)
{
    ref_udu3 r = {ekf->mu, {0}, {0, 1, 2}};
    gf_mat3 s;
    (void)gf_ekf3_cov(ekf, &s);
    udu_factor(s.m[0], 3, r.ud);
    return r;
}

ref_noise2 ref_noise2_from(const gf_mat2 *R)
{
    ref_noise2 r;
    udu_factor(R->m[0], 2, r.ud);
    return r;
}

ref_noise3 ref_noise3_from(const gf_mat3 *R)
{
    ref_noise3 r;
    udu_factor(R->m[0], 3, r.ud);
    return r;
}

gf_real ref_udu2_dev(const ref_udu2 *r, const gf_kf2 *kf, gf_real *mu_dev)
{
    gf_mat2 s;
    (void)gf_kf2_cov(kf, &s);
    return udu_dev(r->ud, r->perm, r->mu.v, s.m[0], kf->mu.v, 2, 2, mu_dev);
}

gf_real ref_udu3_dev(const ref_udu3 *r, const gf_ekf3 *ekf, gf_real *mu_dev)
{
    gf_mat3 s;
    (void)gf_ekf3_cov(ekf, &s);
    return udu_dev(r->ud, r->perm, r->mu.v, s.m[0], ekf->mu.v, 3, 2, mu_dev);
}

// Thornton's time update of 2 states, in place on ud:
//   Sigma_bar = W diag(D, e) W^T,  W = [A U | F]  (R = F diag(e) F^T, rn),
// then the weighted Gram-Schmidt from the last row of W up:
//   c = diag(D, e) w_j,  d_j = w_j . c,  U_ij = (w_i . c) / d_j,
//   w_i -= U_ij w_j  (i < j).
// F is unit upper triangular: its zeros and ones are written in.
// checked: a d_j below GF_REAL_MIN is zero, with a zero column of U.
REF_INLINE void thornton2(gf_real ud[3], const gf_mat2 *A, const gf_real rn[3],
                          int checked)
{
    const gf_real d0 = ud[0], u01 = ud[1], d1 = ud[2];
    const gf_real e0 = rn[0], f01 = rn[1], e1 = rn[2];
    // W = ((x00 x01 1 f01) (x10 x11 0 1)), (A U)_i1 = a_i0 U_01 + a_i1
    gf_real x00 = A->m[0][0], x01 = A->m[0][0] * u01 + A->m[0][1];
    const gf_real x10 = A->m[1][0], x11 = A->m[1][0] * u01 + A->m[1][1];
    // j = 1: c = (d0 x10, d1 x11, 0, e1)
    const gf_real c0 = d0 * x10, c1 = d1 * x11;
    gf_real n1 = x10 * c0 + x11 * c1 + e1, i1 = 0;
    if (!checked || n1 >= GF_REAL_MIN) {
        i1 = GF_R(1.0) / n1;
    } else {
        n1 = 0;
    }
    const gf_real n01 = (x00 * c0 + x01 * c1 + f01 * e1) * i1;
    x00 -= n01 * x10;
    x01 -= n01 * x11;
    const gf_real w03 = f01 - n01;
    // j = 0: row 0 is (x00 x01 1 w03)
    gf_real n0 = x00 * (d0 * x00) + x01 * (d1 * x01) + e0 + w03 * (e1 * w03);
    if (checked && !(n0 >= GF_REAL_MIN)) {
        n0 = 0;
    }
    ud[0] = n0;
    ud[1] = n01;
    ud[2] = n1;
}

// Thornton's time update of 3 states, as thornton2: W = [G U | F], rows
// (x_i0 x_i1 x_i2 | F's row i), F = ((1 f01 f02) (0 1 f12) (0 0 1)).
REF_INLINE void thornton3(gf_real ud[6], const gf_mat3 *G, const gf_real rn[6],
                          int checked)
{
    const gf_real d0 = ud[0], u01 = ud[1], d1 = ud[2];
    const gf_real u02 = ud[3], u12 = ud[4], d2 = ud[5];
    const gf_real e0 = rn[0], f01 = rn[1], e1 = rn[2];
    const gf_real f02 = rn[3], f12 = rn[4], e2 = rn[5];
    // (G U)_i0 = g_i0, (G U)_i1 = g_i0 U_01 + g_i1,
    // (G U)_i2 = g_i0 U_02 + g_i1 U_12 + g_i2
    const gf_real(*g)[3] = G->m;
    gf_real x00 = g[0][0], x01 = g[0][0] * u01 + g[0][1];
    gf_real x02 = g[0][0] * u02 + g[0][1] * u12 + g[0][2];
    gf_real x10 = g[1][0], x11 = g[1][0] * u01 + g[1][1];
    gf_real x12 = g[1][0] * u02 + g[1][1] * u12 + g[1][2];
    const gf_real x20 = g[2][0], x21 = g[2][0] * u01 + g[2][1];
    const gf_real x22 = g[2][0] * u02 + g[2][1] * u12 + g[2][2];
    // j = 2: c = (d0 x20, d1 x21, d2 x22, 0, 0, e2)
    gf_real c0 = d0 * x20, c1 = d1 * x21, c2 = d2 * x22;
    gf_real n2 = x20 * c0 + x21 * c1 + x22 * c2 + e2, i2 = 0;
    if (!checked || n2 >= GF_REAL_MIN) {
        i2 = GF_R(1.0) / n2;
    } else {
        n2 = 0;
    }
    const gf_real n12 = (x10 * c0 + x11 * c1 + x12 * c2 + f12 * e2) * i2;
    const gf_real n02 = (x00 * c0 + x01 * c1 + x02 * c2 + f02 * e2) * i2;
    x10 -= n12 * x20;
    x11 -= n12 * x21;
    x12 -= n12 * x22;
    const gf_real w15 = f12 - n12; // row 1: (x10 x11 x12 0 1 w15)
    x00 -= n02 * x20;
    x01 -= n02 * x21;
    x02 -= n02 * x22;
    gf_real w05 = f02 - n02; // row 0: (x00 x01 x02 1 f01 w05)
    // j = 1: c = (d0 x10, d1 x11, d2 x12, 0, e1, e2 w15)
    c0 = d0 * x10;
    c1 = d1 * x11;
    c2 = d2 * x12;
    const gf_real c5 = e2 * w15;
    gf_real n1 = x10 * c0 + x11 * c1 + x12 * c2 + e1 + w15 * c5, i1 = 0;
    if (!checked || n1 >= GF_REAL_MIN) {
        i1 = GF_R(1.0) / n1;
    } else {
        n1 = 0;
    }
    const gf_real n01 =
        (x00 * c0 + x01 * c1 + x02 * c2 + f01 * e1 + w05 * c5) * i1;
    x00 -= n01 * x10;
    x01 -= n01 * x11;
    x02 -= n01 * x12;
    const gf_real w04 = f01 - n01;
    w05 -= n01 * w15;
    // j = 0: row 0 is (x00 x01 x02 1 w04 w05)
    gf_real n0 = x00 * (d0 * x00) + x01 * (d1 * x01) + x02 * (d2 * x02) + e0 +
                 w04 * (e1 * w04) + w05 * (e2 * w05);
    if (checked && !(n0 >= GF_REAL_MIN)) {
        n0 = 0;
    }
    ud[0] = n0;
    ud[1] = n01;
    ud[2] = n1;
    ud[3] = n02;
    ud[4] = n12;
    ud[5] = n2;
}

// Bierman's update of 2 states, in place on ud, for the scalar z = h x +
// v, v ~ N(0, r): with f = U^T h, g = D f, alpha_(-1) = r,
//   alpha_j = alpha_(j-1) + f_j g_j,  d_j <- d_j alpha_(j-1) / alpha_j,
//   U_ij <- U_ij - b_i f_j / alpha_(j-1),  b_i <- b_i + U_ij g_j (i < j),
//   b_j = g_j;
// the gain is b / s, s = alpha_1 = h Sigma h^T + r (returned); b into b.
// checked: an alpha_j below GF_REAL_MIN is not divided by (d_j kept, and
// 1 / alpha_j taken as 0), a d_j below GF_REAL_MIN becomes zero with its
// column of U, as in src/udu.h. *inv receives 1 / s (0 if not taken).
REF_INLINE gf_real bierman2(gf_real ud[3], gf_real h0, gf_real h1, gf_real r,
                            gf_real b[2], gf_real *inv, int checked)
{
    const gf_real d0 = ud[0], u01 = ud[1], d1 = ud[2];
    const gf_real f0 = h0, f1 = h1 + u01 * h0;
    const gf_real g0 = d0 * f0, g1 = d1 * f1;
    const gf_real a0 = r + f0 * g0;
    gf_real i0 = 0, n0 = d0;
    if (!checked || a0 >= GF_REAL_MIN) {
        i0 = GF_R(1.0) / a0;
        n0 = d0 * (r * i0);
    }
    const gf_real a1 = a0 + f1 * g1;
    gf_real i1 = 0, n1 = d1;
    if (!checked || a1 >= GF_REAL_MIN) {
        i1 = GF_R(1.0) / a1;
        n1 = d1 * (a0 * i1);
    }
    gf_real n01 = u01 + g0 * (-f1 * i0);
    b[0] = g0 + u01 * g1;
    b[1] = g1;
    if (checked && !(n0 >= GF_REAL_MIN)) {
        n0 = 0;
    }
    if (checked && !(n1 >= GF_REAL_MIN)) {
        n1 = 0;
        n01 = 0;
    }
    ud[0] = n0;
    ud[1] = n01;
    ud[2] = n1;
    *inv = i1;
    return a1;
}

// Bierman's update of 3 states, as bierman2; h: the row (3 entries).
REF_INLINE gf_real bierman3(gf_real ud[6], const gf_real h[3], gf_real r,
                            gf_real b[3], gf_real *inv, int checked)
{
    const gf_real d0 = ud[0], u01 = ud[1], d1 = ud[2];
    const gf_real u02 = ud[3], u12 = ud[4], d2 = ud[5];
    const gf_real f0 = h[0], f1 = h[1] + u01 * h[0];
    const gf_real f2 = h[2] + u02 * h[0] + u12 * h[1];
    const gf_real g0 = d0 * f0, g1 = d1 * f1, g2 = d2 * f2;
    const gf_real a0 = r + f0 * g0;
    gf_real i0 = 0, n0 = d0;
    if (!checked || a0 >= GF_REAL_MIN) {
        i0 = GF_R(1.0) / a0;
        n0 = d0 * (r * i0);
    }
    const gf_real a1 = a0 + f1 * g1;
    gf_real i1 = 0, n1 = d1;
    if (!checked || a1 >= GF_REAL_MIN) {
        i1 = GF_R(1.0) / a1;
        n1 = d1 * (a0 * i1);
    }
    gf_real n01 = u01 + g0 * (-f1 * i0);
    gf_real b0 = g0 + u01 * g1;
    const gf_real a2 = a1 + f2 * g2;
    gf_real i2 = 0, n2 = d2;
    if (!checked || a2 >= GF_REAL_MIN) {
        i2 = GF_R(1.0) / a2;
        n2 = d2 * (a1 * i2);
    }
    const gf_real p2 = -f2 * i1;
    gf_real n02 = u02 + b0 * p2;
    gf_real n12 = u12 + g1 * p2;
    b[0] = b0 + u02 * g2;
    b[1] = g1 + u12 * g2;
    b[2] = g2;
    if (checked && !(n0 >= GF_REAL_MIN)) {
        n0 = 0;
    }
    if (checked && !(n1 >= GF_REAL_MIN)) {
        n1 = 0;
        n01 = 0;
    }
    if (checked && !(n2 >= GF_REAL_MIN)) {
        n2 = 0;
        n02 = 0;
        n12 = 0;
    }
    ud[0] = n0;
    ud[1] = n01;
    ud[2] = n1;
    ud[3] = n02;
    ud[4] = n12;
    ud[5] = n2;
    *inv = i2;
    return a2;
}

// ---- udu: no checks ----

void ref_udu2_predict(ref_udu2 *kf, const gf_kf2_model *model,
                      const ref_noise2 *rn)
{
    const gf_mat2 *A = &model->A;
    const gf_real m0 = kf->mu.v[0], m1 = kf->mu.v[1];
    // mu = A mu; Sigma = A Sigma A^T + R on the factors
    kf->mu.v[0] = A->m[0][0] * m0 + A->m[0][1] * m1;
    kf->mu.v[1] = A->m[1][0] * m0 + A->m[1][1] * m1;
    thornton2(kf->ud, A, rn->ud, 0);
}

void ref_udu2_update(ref_udu2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z)
{
    const gf_real c0 = meas->C.m[0][0], c1 = meas->C.m[0][1];
    // y = z - C mu; mu += K y, K = b / s
    const gf_real y = z->v[0] - (c0 * kf->mu.v[0] + c1 * kf->mu.v[1]);
    gf_real b[2], inv;
    (void)bierman2(kf->ud, c0, c1, meas->Q.m[0][0], b, &inv, 0);
    const gf_real k = y * inv;
    kf->mu.v[0] += b[0] * k;
    kf->mu.v[1] += b[1] * k;
}

void ref_udu3_predict(ref_udu3 *ekf, const gf_ekf3_motion *motion,
                      const ref_noise3 *rn, const gf_real *u)
{
    // mu_bar = g(u, mu) and G by the callback (mu_bar preset to mu, G to
    // the identity, as the library hands them over); Sigma = G Sigma G^T
    // + R on the factors, G taken as general
    gf_vec3 mb = ekf->mu;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    (void)motion->g(motion->ctx, &ekf->mu, u, &mb, &G);
    ekf->mu.v[0] = mb.v[0];
    ekf->mu.v[1] = mb.v[1];
    ekf->mu.v[2] = wrap(mb.v[2]);
    thornton3(ekf->ud, &G, rn->ud, 0);
}

// z_hat and H by the callback, its first m rows preset to zero.
REF_INLINE void meas3(const gf_ekf3_meas *meas, const gf_vec3 *mu, unsigned m,
                      gf_vec3 *zh, gf_mat3 *H)
{
    for (unsigned i = 0; i < m; i++) {
        zh->v[i] = 0;
        H->m[i][0] = 0;
        H->m[i][1] = 0;
        H->m[i][2] = 0;
    }
    (void)meas->h(meas->ctx, mu, zh, H);
}

void ref_udu3_update(ref_udu3 *ekf, const gf_ekf3_meas *meas, const gf_vec3 *z)
{
    gf_vec3 zh;
    gf_mat3 H;
    meas3(meas, &ekf->mu, 1, &zh, &H);
    // y = z - h(mu_bar); mu += K y, K = b / s
    const gf_real y = z->v[0] - zh.v[0];
    gf_real b[3], inv;
    (void)bierman3(ekf->ud, H.m[0], meas->Q.m[0][0], b, &inv, 0);
    const gf_real k = y * inv;
    ekf->mu.v[0] += b[0] * k;
    ekf->mu.v[1] += b[1] * k;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + b[2] * k);
}

void ref_udu3_update_xy(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                        const gf_vec3 *z)
{
    gf_vec3 zh;
    gf_mat3 H;
    meas3(meas, &ekf->mu, 2, &zh, &H);
    // Q diagonal: two scalar updates, the second's innovation at the mean
    // the first gave, y_1 = z_1 - h_1(mu_bar) - H_1 dx
    gf_real b[3], inv, dx[3];
    (void)bierman3(ekf->ud, H.m[0], meas->Q.m[0][0], b, &inv, 0);
    gf_real k = (z->v[0] - zh.v[0]) * inv;
    dx[0] = b[0] * k;
    dx[1] = b[1] * k;
    dx[2] = b[2] * k;
    const gf_real y1 =
        z->v[1] - zh.v[1] -
        (H.m[1][0] * dx[0] + H.m[1][1] * dx[1] + H.m[1][2] * dx[2]);
    (void)bierman3(ekf->ud, H.m[1], meas->Q.m[1][1], b, &inv, 0);
    k = y1 * inv;
    ekf->mu.v[0] += dx[0] + b[0] * k;
    ekf->mu.v[1] += dx[1] + b[1] * k;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + (dx[2] + b[2] * k));
}

void ref_udu3_update_xyt(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z)
{
    gf_vec3 zh;
    gf_mat3 H;
    meas3(meas, &ekf->mu, 3, &zh, &H);
    // Q diagonal: three scalar updates as in ref_udu3_update_xy, the
    // heading's residual wrapped
    gf_real b[3], inv, dx[3];
    (void)bierman3(ekf->ud, H.m[0], meas->Q.m[0][0], b, &inv, 0);
    gf_real k = (z->v[0] - zh.v[0]) * inv;
    dx[0] = b[0] * k;
    dx[1] = b[1] * k;
    dx[2] = b[2] * k;
    const gf_real y1 =
        z->v[1] - zh.v[1] -
        (H.m[1][0] * dx[0] + H.m[1][1] * dx[1] + H.m[1][2] * dx[2]);
    (void)bierman3(ekf->ud, H.m[1], meas->Q.m[1][1], b, &inv, 0);
    k = y1 * inv;
    dx[0] += b[0] * k;
    dx[1] += b[1] * k;
    dx[2] += b[2] * k;
    const gf_real y2 =
        wrap(z->v[2] - zh.v[2]) -
        (H.m[2][0] * dx[0] + H.m[2][1] * dx[1] + H.m[2][2] * dx[2]);
    (void)bierman3(ekf->ud, H.m[2], meas->Q.m[2][2], b, &inv, 0);
    k = y2 * inv;
    ekf->mu.v[0] += dx[0] + b[0] * k;
    ekf->mu.v[1] += dx[1] + b[1] * k;
    ekf->mu.v[2] = wrap(ekf->mu.v[2] + (dx[2] + b[2] * k));
}

// ---- uduc: the plain API's checks ----

// |x - y| <= GF_SYM_RTOL (|x| + |y|): symmetric as gf_cov_factor judges.
REF_INLINE int sym_ok(gf_real x, gf_real y)
{
    return GF_FABS(x - y) <= GF_SYM_RTOL * (GF_FABS(x) + GF_FABS(y));
}

// The verdict on R (2 x 2) and its factors in rn, as gf_kf2_predict gives
// it: GF_ERR_NONFINITE, GF_ERR_NOT_PSD (not symmetric, a negative
// variance, indefinite), else GF_OK. In closed form, pivot on the last
// state: e1 = r11, f = r01 / r11, e0 = r00 - f r01 = r00 (1 - rho^2),
// indefinite below -GF_PD_RTOL r00, zero up to GF_PD_RTOL r00 (the
// library's pair rule: the same quantity in the correlation form,
// whichever state is the pivot); r11 = 0 needs r01 = 0. R: rows of
// `stride` (2, or 3 for the leading block of a 3 x 3 Q); z: 0 times the
// caller's other numbers, tested with R's.
REF_INLINE gf_status noise2(const gf_real *R, unsigned stride, gf_real z,
                            gf_real rn[3])
{
    const gf_real r00 = R[0], r01 = R[1];
    const gf_real r10 = R[stride], r11 = R[stride + 1u];
    if (!(z + Z(r00) + Z(r01) + Z(r10) + Z(r11) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    if (!sym_ok(r01, r10) || r00 < 0 || r11 < 0) {
        return GF_ERR_NOT_PSD;
    }
    rn[0] = r00;
    rn[1] = 0;
    rn[2] = r11;
    if (r11 > 0) {
        const gf_real f = r01 / r11;
        gf_real e0 = r00 - f * r01;
        if (!(e0 >= -GF_PD_RTOL * r00)) {
            return GF_ERR_NOT_PSD;
        }
        if (!(e0 > GF_PD_RTOL * r00)) {
            e0 = 0;
        }
        rn[0] = e0;
        rn[1] = f;
    } else if (GF_FABS(r01) > 0) {
        return GF_ERR_NOT_PSD;
    }
    return GF_OK;
}

// The same for a 3 x 3 R (gf_ekf3_predict's verdict): a diagonal R (the
// usual noise) is its own factorisation; any other is factored from the
// last state up, each pivot judged against its own variance as above (a
// zero one's couplings within the 2 x 2 bound a_ik^2 <= a_ii a_kk, both
// sides widened by GF_PD_RTOL times their variance, as gf_ldl's).
// Mathematically the library's verdict; its pivot order can tip a case
// within the tolerance the other way.
// R: rows of 3.
REF_INLINE gf_status noise3(const gf_real *R, gf_real rn[6])
{
    const gf_real r00 = R[0], r01 = R[1], r02 = R[2];
    const gf_real r11 = R[4], r12 = R[5], r22 = R[8];
    const gf_real z = Z(r00) + Z(r01) + Z(r02) + Z(R[3]) + Z(r11) + Z(r12) +
                      Z(R[6]) + Z(R[7]) + Z(r22);
    if (!(z < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    if (!sym_ok(r01, R[3]) || !sym_ok(r02, R[6]) || !sym_ok(r12, R[7]) ||
        r00 < 0 || r11 < 0 || r22 < 0) {
        return GF_ERR_NOT_PSD;
    }
    rn[0] = r00;
    rn[1] = 0;
    rn[2] = r11;
    rn[3] = 0;
    rn[4] = 0;
    rn[5] = r22;
    if (!(GF_FABS(r01) + GF_FABS(r02) + GF_FABS(r12) > 0)) {
        return GF_OK; // diagonal
    }
    const gf_real tol = GF_PD_RTOL;
    gf_real a00 = r00, a01 = r01, a11 = r11;
    if (r22 > 0) {
        const gf_real inv = GF_R(1.0) / r22;
        rn[3] = r02 * inv;
        rn[4] = r12 * inv;
        a00 -= rn[3] * r02;
        a01 -= rn[3] * r12;
        a11 -= rn[4] * r12;
    } else if (GF_FABS(r02) + GF_FABS(r12) > 0) {
        return GF_ERR_NOT_PSD;
    }
    if (!(a11 >= -tol * r11)) {
        return GF_ERR_NOT_PSD;
    }
    if (a11 > tol * r11) {
        rn[1] = a01 / a11;
        rn[2] = a11;
        a00 -= rn[1] * a01;
    } else {
        const gf_real p1 = (a11 > 0 ? a11 : GF_R(0.0)) + tol * r11;
        const gf_real p0 = (a00 > 0 ? a00 : GF_R(0.0)) + tol * r00;
        if (!(a01 * a01 <= p1 * p0)) {
            return GF_ERR_NOT_PSD;
        }
        rn[2] = 0;
    }
    if (!(a00 >= -tol * r00)) {
        return GF_ERR_NOT_PSD;
    }
    rn[0] = a00 > tol * r00 ? a00 : GF_R(0.0);
    return GF_OK;
}

// P^T M P of an n x n M (rows of n) into o: o_ij = M_(perm i)(perm j),
// perm's entries read once.
REF_INLINE void gather(const gf_real *M, unsigned n, const unsigned char *perm,
                       gf_real *o)
{
    unsigned p[3];
    REF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        p[i] = perm[i];
    }
    REF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        const gf_real *mi = &M[p[i] * n];
        REF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            o[i * n + j] = mi[p[j]];
        }
    }
}

// noise2 and noise3 out of line, one copy each for the checked floor's
// plain calls: R in every prediction, a prior (init) and the Q of m > 1
// quantities (the updates). Only the prepared path's prepare functions
// inline their own.
static REF_NOINLINE gf_status noise2_at(const gf_real *R, unsigned stride,
                                        gf_real rn[3])
{
    return noise2(R, stride, GF_R(0.0), rn);
}

static REF_NOINLINE gf_status noise3_at(const gf_real *R, gf_real rn[6])
{
    return noise3(R, rn);
}

// The same for a prediction's P^T R P (perm: the belief's order), gathered
// in a frame of its own, not the prediction's (whose callback comes later).
static REF_NOINLINE gf_status noise2_p(const gf_real *R,
                                       const unsigned char *perm, gf_real rn[3])
{
    gf_real rp[4];
    gather(R, 2u, perm, rp);
    return noise2_at(rp, 2u, rn);
}

static REF_NOINLINE gf_status noise3_p(const gf_real *R,
                                       const unsigned char *perm, gf_real rn[6])
{
    gf_real rp[9];
    gather(R, 3u, perm, rp);
    return noise3_at(rp, rn);
}

// A model callback's status, as the library passes it on: an unknown one,
// or GF_ERR_GATED, is GF_ERR_MODEL.
static gf_status callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
               ? GF_ERR_MODEL
               : st;
}

// *info = *in field by field (if info is not NULL), as the library
// stores it.
REF_INLINE void info_store(gf_innovation *info, const gf_innovation *in)
{
    if (info) {
        info->m = in->m;
        info->y[0] = in->y[0];
        info->y[1] = in->y[1];
        info->y[2] = in->y[2];
        info->nis = in->nis;
    }
}

// Whitening, one step of x <- U_Q^-1 x (Q = U_Q D_Q U_Q^T, qn): the
// quantity i of an EKF3 update, its row of H and its y, less u = U_ik
// times quantity k's.
REF_INLINE void qsub(gf_mat3 *H, gf_real yw[3], unsigned i, gf_real u,
                     unsigned k)
{
    for (unsigned c = 0; c < 3u; c++) {
        H->m[i][c] -= u * H->m[k][c];
    }
    yw[i] -= u * yw[k];
}

// ---- The factors' order (uduc, uducp) ----
//
// The checked floor keeps the library's order of the factors: Sigma =
// P U D U^T P^T, perm[k] the state at the factors' index k. The prior is
// factored with the states reversed (state 0, the measured position of
// both workloads, at the root, the last index, whose d is its whole
// variance and whose row of U Bierman's update leaves alone); a quantity
// that tells more than ROOT_TELL (v = sum_s h_s^2 Sigma_ss above
// ROOT_TELL times its whitened noise) has its main state (the largest
// h_s^2 Sigma_ss) moved to the root first, by adjacent swaps, unless it
// measures the root's state alone; the prediction works through P.

#define ROOT_TELL GF_R(16.0)

// Swaps the factors' indices k and k + 1 (n = 2 or 3), the same Sigma
// with the state perm[k + 1] at k, and dp's entries with their states:
// with a = U_k(k+1), d'_(k+1) = d_k + a^2 d_(k+1), r = d_(k+1) / d'_(k+1),
//   U'_k(k+1) = a r,  d'_k = d_k r,
//   U'_ik = U_i(k+1) - a U_ik,  U'_i(k+1) = (d_k / d'_(k+1)) U_ik
//   + a r U_i(k+1)  (i < k),
// the later columns' rows k and k + 1 swapped; a d' below GF_REAL_MIN is
// zero, with its column (as src/udu.h's gf_udu_swap).
REF_INLINE void udu_swap(gf_real *ud, unsigned char *perm, gf_real *dp,
                         unsigned n, unsigned k)
{
    const unsigned ok = UD(0u, k), ol = UD(0u, k + 1u);
    const gf_real a = ud[ol + k], dk = ud[ok + k], dl = ud[ol + k + 1u];
    const gf_real dq = dk + a * a * dl;
    gf_real r = 0, sk = 0, dn = dl;
    if (dq >= GF_REAL_MIN) {
        const gf_real inv = GF_R(1.0) / dq;
        r = dl * inv;
        sk = dk * inv;
        dn = dk * r;
    }
    const gf_real beta = a * r;
    const int zk = !(dn >= GF_REAL_MIN);
    for (unsigned i = 0; i < k; i++) {
        const gf_real uk = ud[ok + i], ul = ud[ol + i];
        ud[ok + i] = zk ? GF_R(0.0) : ul - a * uk;
        ud[ol + i] = sk * uk + beta * ul;
    }
    ud[ok + k] = zk ? GF_R(0.0) : dn;
    ud[ol + k] = beta;
    ud[ol + k + 1u] = (dq >= GF_REAL_MIN) ? dq : GF_R(0.0);
    if (k + 2u < n) { // n = 3, k = 0: column 2's rows 0 and 1
        const gf_real t = ud[3];
        ud[3] = ud[4];
        ud[4] = t;
    }
    const unsigned char t = perm[k];
    perm[k] = perm[k + 1u];
    perm[k + 1u] = t;
    const gf_real x = dp[k];
    dp[k] = dp[k + 1u];
    dp[k + 1u] = x;
}

// Before a scalar update of the row h (by state) with noise q: its main
// state made the root if it tells more than ROOT_TELL (n = 2). Sigma's
// variances in the factors' order: sd0 = d0 + U01^2 d1, sd1 = d1.
// The one swap, udu_swap's k = 0, is written in (the belief then stays in
// registers); perm is (0 1) or (1 0), and h in the factors' order a
// selection by perm[0].
REF_INLINE void root2(ref_udu2 *b, const gf_real h[2], gf_real q, gf_real dp[2])
{
    gf_real *ud = b->ud;
    const int sw = b->perm[0] != 0;
    const gf_real h0 = sw ? h[1] : h[0], h1 = sw ? h[0] : h[1];
    if (!(GF_FABS(h0) > 0)) {
        return; // the root's state alone
    }
    const gf_real d0 = ud[0], a = ud[1], d1 = ud[2];
    const gf_real p0 = h0 * h0 * (d0 + a * a * d1);
    const gf_real p1 = h1 * h1 * d1;
    if (!(p1 > p0) && p0 + p1 > ROOT_TELL * q) {
        const gf_real dq = d0 + a * a * d1;
        gf_real r = 0, dn = d1;
        if (dq >= GF_REAL_MIN) {
            r = d1 * (GF_R(1.0) / dq);
            dn = d0 * r;
        }
        ud[0] = dn >= GF_REAL_MIN ? dn : GF_R(0.0);
        ud[1] = a * r;
        ud[2] = dq >= GF_REAL_MIN ? dq : GF_R(0.0);
        b->perm[0] = (unsigned char)!sw;
        b->perm[1] = (unsigned char)sw;
        const gf_real x = dp[0];
        dp[0] = dp[1];
        dp[1] = x;
    }
}

// The same for n = 3: sd0 = d0 + U01^2 d1 + U02^2 d2, sd1 = d1 + U12^2
// d2, sd2 = d2; the main state the first of the largest share.
REF_INLINE void root3(ref_udu3 *b, const gf_real h[3], gf_real q, gf_real dp[3])
{
    const gf_real *ud = b->ud;
    const gf_real h0 = h[b->perm[0]], h1 = h[b->perm[1]];
    const gf_real h2 = h[b->perm[2]];
    if (!(GF_FABS(h0) + GF_FABS(h1) > 0)) {
        return;
    }
    const gf_real p0 =
        h0 * h0 * (ud[0] + ud[1] * ud[1] * ud[2] + ud[3] * ud[3] * ud[5]);
    const gf_real p1 = h1 * h1 * (ud[2] + ud[4] * ud[4] * ud[5]);
    const gf_real p2 = h2 * h2 * ud[5];
    if (p2 > p0 && p2 > p1) {
        return; // the root's state is the main one
    }
    if (!(p0 + p1 + p2 > ROOT_TELL * q)) {
        return;
    }
    if (!(p1 > p0)) {
        udu_swap(b->ud, b->perm, dp, 3u, 0u);
    }
    udu_swap(b->ud, b->perm, dp, 3u, 1u);
}

// 0 (finite) or NaN: every number of a 2-state belief and the variance
// d0 + U01^2 d1 its factors give (d1 is one of them).
REF_INLINE gf_real belief2_z(const gf_real mu[2], const gf_real ud[3])
{
    return Z(mu[0]) + Z(mu[1]) + Z(ud[0]) + Z(ud[1]) + Z(ud[2]) +
           Z(ud[0] + ud[1] * ud[2] * ud[1]);
}

// 0 (finite) or NaN: A, B and c of a KF2 motion model.
REF_INLINE gf_real model2_z(const gf_kf2_model *model)
{
    const gf_mat2 *A = &model->A, *B = &model->B;
    return Z(A->m[0][0]) + Z(A->m[0][1]) + Z(A->m[1][0]) + Z(A->m[1][1]) +
           Z(B->m[0][0]) + Z(B->m[0][1]) + Z(B->m[1][0]) + Z(B->m[1][1]) +
           Z(model->c.v[0]) + Z(model->c.v[1]);
}

// The prediction once the model and u are checked and R factored (rn):
// mu_bar = A mu + B u + c, Sigma_bar on the factors, into a copy written
// back only if all of it is finite. Through P: thornton2 on P^T A P with
// P^T R P's factors (rn: the belief's order).
REF_INLINE gf_status uduc2_predict_step(ref_udu2 *kf, const gf_kf2_model *model,
                                        const gf_real rn[3], const gf_vec2 *u)
{
    const gf_mat2 *A = &model->A, *B = &model->B;
    ref_udu2 nb = *kf;
    const gf_real m0 = kf->mu.v[0], m1 = kf->mu.v[1];
    // each state's own term last, as the library
    gf_real a0 = model->c.v[0] + A->m[0][1] * m1;
    gf_real a1 = model->c.v[1] + A->m[1][0] * m0;
    if (u) {
        a0 += B->m[0][0] * u->v[0] + B->m[0][1] * u->v[1];
        a1 += B->m[1][0] * u->v[0] + B->m[1][1] * u->v[1];
    }
    nb.mu.v[0] = a0 + A->m[0][0] * m0;
    nb.mu.v[1] = a1 + A->m[1][1] * m1;
    gf_mat2 Ap;
    gather(A->m[0], 2u, kf->perm, Ap.m[0]);
    thornton2(nb.ud, &Ap, rn, 1);
    if (!(belief2_z(nb.mu.v, nb.ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    *kf = nb;
    return GF_OK;
}

gf_status ref_uduc2_predict(ref_udu2 *kf, const gf_kf2_model *model,
                            const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    // A, B, c, u finite, then R's finiteness and verdict (one status for
    // any non-finite number)
    gf_real z = model2_z(model);
    if (u) {
        z += Z(u->v[0]) + Z(u->v[1]);
    }
    if (!(z < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    // P^T R P judged and factored
    gf_real rn[3];
    const gf_status st = noise2_p(model->R.m[0], kf->perm, rn);
    return st != GF_OK ? st : uduc2_predict_step(kf, model, rn, u);
}

// The end of a measurement model's checks, once f holds 0 times every
// number checked before: those finite, gate >= 0, then (m = 1) Q's one
// entry q finite and >= 0, in the order of the status rules. qn[0] = q:
// one quantity's Q is its own factorisation. For m > 1 Q's verdict is the
// caller's (noise2_at, noise3_at), after GF_OK here.
REF_INLINE gf_status meas_tail(gf_real f, gf_real gate, gf_real q, unsigned m,
                               gf_real *qn)
{
    if (!(f < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    if (gate < 0) {
        return GF_ERR_ARG;
    }
    qn[0] = q;
    if (m > 1u) {
        return GF_OK;
    }
    if (!(Z(q) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    return q < 0 ? GF_ERR_NOT_PSD : GF_OK;
}

// The checks of a KF2 measurement model of m = 1 or 2 (z too, if not
// NULL), in the order of gf_kf2_update's statuses: C's m rows, c, z and
// the gate finite; gate >= 0; Q's verdict (m x m), its factors into qn.
REF_INLINE gf_status meas2_check(const gf_kf2_meas *meas, const gf_vec2 *z,
                                 gf_real qn[3])
{
    const unsigned m = meas->m;
    const gf_real gate = meas->gate;
    gf_real f = Z(gate);
    for (unsigned i = 0; i < m; i++) {
        f += Z(meas->C.m[i][0]) + Z(meas->C.m[i][1]) + Z(meas->c.v[i]);
        if (z) {
            f += Z(z->v[i]);
        }
    }
    const gf_status st = meas_tail(f, gate, meas->Q.m[0][0], m, qn);
    return (st != GF_OK || m == 1u) ? st : noise2_at(meas->Q.m[0], 2u, qn);
}

// The correction once the model and z are checked and Q factored (qn):
//   y = z - c - C mu_bar,  [C_w | y_w] = U_Q^-1 [C | y],
// then Bierman's update on a copy for each whitened quantity i (noise
// d_i), its innovation at the mean the earlier ones gave,
// y_i = y_w,i - C_w,i dx; each with the exact-quantity rule and s finite;
// the NIS (their sum) finite, the gate on it, the result finite, then the
// copy written back.
REF_INLINE gf_status uduc2_update_step(ref_udu2 *kf, const gf_kf2_meas *meas,
                                       const gf_real qn[3], const gf_vec2 *z,
                                       gf_innovation *info)
{
    const unsigned m = meas->m;
    const gf_real gate = meas->gate;
    const gf_real m0 = kf->mu.v[0], m1 = kf->mu.v[1];
    const gf_real(*C)[2] = meas->C.m;
    gf_innovation in;
    gf_real w[2][3]; // per quantity: C's row, y
    // y = z - c - C mu_bar
    in.m = m;
    in.y[0] = z->v[0] - meas->c.v[0] - (C[0][0] * m0 + C[0][1] * m1);
    in.y[1] = 0;
    in.y[2] = 0;
    w[0][0] = C[0][0];
    w[0][1] = C[0][1];
    w[0][2] = in.y[0];
    if (m > 1u) {
        in.y[1] = z->v[1] - meas->c.v[1] - (C[1][0] * m0 + C[1][1] * m1);
        w[1][0] = C[1][0];
        w[1][1] = C[1][1];
        w[1][2] = in.y[1];
        // [C_w | y_w] = U_Q^-1 [C | y]: row 0 -= U_01 row 1
        w[0][0] -= qn[1] * C[1][0];
        w[0][1] -= qn[1] * C[1][1];
        w[0][2] -= qn[1] * in.y[1];
    }
    ref_udu2 nb = *kf;
    gf_real *ud = nb.ud;
    gf_real dp[2] = {0, 0}; // mu - mu_bar in the factors' order
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        const gf_real q = qn[2u * i]; // d_i
        root2(&nb, w[i], q, dp);
        // the row in the factors' order
        const int sw = nb.perm[0] != 0;
        const gf_real c0 = sw ? w[i][1] : w[i][0];
        const gf_real c1 = sw ? w[i][0] : w[i][1];
        const gf_real y = w[i][2] - (c0 * dp[0] + c1 * dp[1]);
        // An exact quantity (q = 0): s must be positive relative to its
        // terms before cancellation, sum_j d_j (|h_j| + sum_(i<j) |U_ij
        // h_i|)^2
        gf_real scale = 0;
        if (!(q > 0)) {
            const gf_real t1 = GF_FABS(c1) + GF_FABS(ud[1] * c0);
            scale = ud[0] * c0 * c0 + ud[2] * t1 * t1;
        }
        gf_real b[2], inv;
        const gf_real s = bierman2(ud, c0, c1, q, b, &inv, 1);
        if (!GF_ISFINITE(s)) {
            return GF_ERR_NONFINITE;
        }
        if (!(q > 0) && !(s > GF_PD_RTOL * GF_R(2.0) * scale)) {
            return GF_ERR_SINGULAR;
        }
        const gf_real k = y * inv;
        in.nis += y * k;
        dp[0] += b[0] * k;
        dp[1] += b[1] * k;
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gate > 0 && in.nis > gate) {
        info_store(info, &in);
        return GF_ERR_GATED;
    }
    const int sw = nb.perm[0] != 0;
    nb.mu.v[0] += sw ? dp[1] : dp[0];
    nb.mu.v[1] += sw ? dp[0] : dp[1];
    if (!(belief2_z(nb.mu.v, ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    info_store(info, &in);
    *kf = nb;
    return GF_OK;
}

gf_status ref_uduc2_update(ref_udu2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas || !z || meas->m - 1u > 1u) {
        return GF_ERR_ARG;
    }
    gf_real qn[3];
    const gf_status st = meas2_check(meas, z, qn);
    return st != GF_OK ? st : uduc2_update_step(kf, meas, qn, z, info);
}

// 0 (finite) or NaN: every number of a 3-state belief and the variances
// d0 + U01^2 d1 + U02^2 d2 and d1 + U12^2 d2 its factors give.
REF_INLINE gf_real belief3_z(const gf_real mu[3], const gf_real ud[6])
{
    return Z(mu[0]) + Z(mu[1]) + Z(mu[2]) + Z(ud[0]) + Z(ud[1]) + Z(ud[2]) +
           Z(ud[3]) + Z(ud[4]) + Z(ud[5]) +
           Z(ud[0] + ud[1] * ud[2] * ud[1] + ud[3] * ud[5] * ud[3]) +
           Z(ud[2] + ud[4] * ud[5] * ud[4]);
}

// The prediction once R is checked and factored (rn: P^T R P's, as
// uduc2_predict_step's; thornton3 on P^T G P). The callback's
// mu_bar and G are not tested apart: a NaN or inf in either reaches mu or
// the factors (G_ij is a term of (G U)_ij), and the result is tested, as
// the library does; u reaches only the callback.
REF_INLINE gf_status uduc3_predict_step(ref_udu3 *ekf,
                                        const gf_ekf3_motion *motion,
                                        const gf_real rn[6], const gf_real *u)
{
    ref_udu3 nb = *ekf;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    const gf_status st = motion->g(motion->ctx, &ekf->mu, u, &nb.mu, &G);
    if (st != GF_OK) {
        return callback_status(st);
    }
    nb.mu.v[2] = wrap(nb.mu.v[2]);
    gf_mat3 Gp;
    gather(G.m[0], 3u, ekf->perm, Gp.m[0]);
    thornton3(nb.ud, &Gp, rn, 1);
    if (!(belief3_z(nb.mu.v, nb.ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    *ekf = nb;
    return GF_OK;
}

gf_status ref_uduc3_predict(ref_udu3 *ekf, const gf_ekf3_motion *motion,
                            const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    // P^T R P judged and factored
    gf_real rn[6];
    const gf_status st = noise3_p(motion->R.m[0], ekf->perm, rn);
    return st != GF_OK ? st : uduc3_predict_step(ekf, motion, rn, u);
}

// The checks of an EKF3 measurement model of m = 1 to 3 before its
// callback (z too, if not NULL), in the order of gf_ekf3_update's
// statuses: z's m entries and the gate finite; gate >= 0; Q's verdict (its
// leading m x m block), its factors into qn.
REF_INLINE gf_status meas3_check(const gf_ekf3_meas *meas, const gf_vec3 *z,
                                 gf_real qn[6])
{
    const unsigned m = meas->m;
    const gf_real gate = meas->gate;
    gf_real f = Z(gate);
    if (z) {
        for (unsigned i = 0; i < m; i++) {
            f += Z(z->v[i]);
        }
    }
    const gf_status st = meas_tail(f, gate, meas->Q.m[0][0], m, qn);
    if (st != GF_OK || m == 1u) {
        return st;
    }
    return m == 2u ? noise2_at(meas->Q.m[0], 3u, qn)
                   : noise3_at(meas->Q.m[0], qn);
}

// The correction once the model and z are checked and Q factored (qn):
// z_hat and H by the callback (its status, its m rows and z_hat finite),
// y = z - z_hat (entry i wrapped if angle_mask's bit i is set),
// H_w = U_Q^-1 H, y_w = U_Q^-1 y, then as uduc2_update_step: one Bierman
// update per whitened quantity on a copy, the NIS, the gate, the result
// finite, the copy written back.
REF_INLINE gf_status uduc3_update_step(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                                       const gf_real qn[6], const gf_vec3 *z,
                                       gf_innovation *info)
{
    const unsigned m = meas->m;
    const gf_real gate = meas->gate;
    // z_hat and H arrive as zeros
    gf_vec3 zh;
    gf_mat3 H;
    REF_UNROLL
    for (unsigned i = 0; i < 3u; i++) {
        zh.v[i] = 0;
        H.m[i][0] = 0;
        H.m[i][1] = 0;
        H.m[i][2] = 0;
    }
    const gf_status st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return callback_status(st);
    }
    gf_innovation in;
    gf_real *yw = zh.v, f = 0; // y_w where z_hat was
    in.m = m;
    in.y[1] = 0;
    in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        f += Z(zh.v[i]) + Z(H.m[i][0]) + Z(H.m[i][1]) + Z(H.m[i][2]);
        // y = z - h(mu_bar), wrapped if an angle
        gf_real y = z->v[i] - zh.v[i];
        if (meas->angle_mask & (1u << i)) {
            y = wrap(y);
        }
        in.y[i] = y;
        yw[i] = y;
    }
    if (!(f < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    // H_w = U_Q^-1 H, y_w = U_Q^-1 y, by back substitution from the last
    // quantity: the whitened quantities' noises are independent, d_i
    if (m > 2u) {
        qsub(&H, yw, 1u, qn[4], 2u);
        qsub(&H, yw, 0u, qn[3], 2u);
    }
    if (m > 1u) {
        qsub(&H, yw, 0u, qn[1], 1u);
    }
    ref_udu3 nb = *ekf;
    gf_real *ud = nb.ud;
    gf_real dp[3] = {0, 0, 0}; // mu - mu_bar in the factors' order
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        const gf_real q = qn[UD(i, i)];
        root3(&nb, H.m[i], q, dp);
        // the row in the factors' order, in place
        gf_real *h = H.m[i];
        const gf_real h0 = h[nb.perm[0]], h1 = h[nb.perm[1]];
        const gf_real h2 = h[nb.perm[2]];
        h[0] = h0;
        h[1] = h1;
        h[2] = h2;
        const gf_real y = yw[i] - (h[0] * dp[0] + h[1] * dp[1] + h[2] * dp[2]);
        gf_real scale = 0; // as in uduc2_update_step
        if (!(q > 0)) {
            const gf_real t1 = GF_FABS(h[1]) + GF_FABS(ud[1] * h[0]);
            const gf_real t2 =
                GF_FABS(h[2]) + GF_FABS(ud[3] * h[0]) + GF_FABS(ud[4] * h[1]);
            scale = ud[0] * h[0] * h[0] + ud[2] * t1 * t1 + ud[5] * t2 * t2;
        }
        gf_real b[3], inv;
        const gf_real s = bierman3(ud, h, q, b, &inv, 1);
        if (!GF_ISFINITE(s)) {
            return GF_ERR_NONFINITE;
        }
        if (!(q > 0) && !(s > GF_PD_RTOL * GF_R(3.0) * scale)) {
            return GF_ERR_SINGULAR;
        }
        const gf_real k = y * inv;
        in.nis += y * k;
        dp[0] += b[0] * k;
        dp[1] += b[1] * k;
        dp[2] += b[2] * k;
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gate > 0 && in.nis > gate) {
        info_store(info, &in);
        return GF_ERR_GATED;
    }
    nb.mu.v[nb.perm[0]] += dp[0];
    nb.mu.v[nb.perm[1]] += dp[1];
    nb.mu.v[nb.perm[2]] += dp[2];
    nb.mu.v[2] = wrap(nb.mu.v[2]);
    if (!(belief3_z(nb.mu.v, ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    info_store(info, &in);
    *ekf = nb;
    return GF_OK;
}

gf_status ref_uduc3_update(ref_udu3 *ekf, const gf_ekf3_meas *meas,
                           const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !z || !meas->h || meas->m - 1u > 2u) {
        return GF_ERR_ARG;
    }
    gf_real qn[6];
    const gf_status st = meas3_check(meas, z, qn);
    return st != GF_OK ? st : uduc3_update_step(ekf, meas, qn, z, info);
}

// ---- uducp: the prepared path's checks ----
//
// The models checked and R factored once (ref_uducp*_prepare_*, as
// gf_kf2_prepare_model/_meas and gf_ekf3_prepare_motion/_meas do); each
// step then tests only what changes from step to step: u (KF2) and z
// finite, the callbacks' status and outputs (EKF3), s (the exact-quantity
// rule), the NIS, the gate and the result, computed on a copy of the
// belief written only on success. The step itself is uduc's, inlined;
// the prediction takes P^T R P's factors from the prepared model, which
// holds them for every order of the states (made once, by swaps).

gf_status ref_uducp2_prepare_model(ref_kf2_pmodel *pm,
                                   const gf_kf2_model *model)
{
    if (!pm || !model) {
        return GF_ERR_ARG;
    }
    ref_kf2_pmodel p;
    const gf_status st = noise2(model->R.m[0], 2u, model2_z(model), p.rn[0].ud);
    if (st != GF_OK) {
        return st;
    }
    // the states swapped
    unsigned char perm[2] = {0, 1};
    gf_real dp[2];
    p.rn[1] = p.rn[0];
    udu_swap(p.rn[1].ud, perm, dp, 2u, 0u);
    p.model = *model;
    *pm = p;
    return GF_OK;
}

gf_status ref_uducp2_prepare_meas(ref_kf2_pmeas *pq, const gf_kf2_meas *meas)
{
    if (!pq || !meas || meas->m - 1u > 1u) {
        return GF_ERR_ARG;
    }
    ref_kf2_pmeas p;
    const gf_status st = meas2_check(meas, NULL, p.qn);
    if (st != GF_OK) {
        return st;
    }
    p.meas = *meas;
    *pq = p;
    return GF_OK;
}

gf_status ref_uducp2_predict(ref_udu2 *kf, const ref_kf2_pmodel *pm,
                             const gf_vec2 *u)
{
    if (!kf || !pm) {
        return GF_ERR_ARG;
    }
    if (u && !(Z(u->v[0]) + Z(u->v[1]) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    return uduc2_predict_step(kf, &pm->model, pm->rn[kf->perm[0]].ud, u);
}

gf_status ref_uducp2_update(ref_udu2 *kf, const ref_kf2_pmeas *pq,
                            const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !pq || !z) {
        return GF_ERR_ARG;
    }
    gf_real f = 0;
    for (unsigned i = 0; i < pq->meas.m; i++) {
        f += Z(z->v[i]);
    }
    if (!(f < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    return uduc2_update_step(kf, &pq->meas, pq->qn, z, info);
}

gf_status ref_uducp3_prepare_motion(ref_ekf3_pmotion *pm,
                                    const gf_ekf3_motion *motion)
{
    if (!pm || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    ref_ekf3_pmotion p;
    ref_noise3 rn;
    const gf_status st = noise3(motion->R.m[0], rn.ud);
    if (st != GF_OK) {
        return st;
    }
    // the other five orders of the states by adjacent swaps (at 1, 0, 1,
    // 0, 1 from the states' own: each order once)
    unsigned char perm[3] = {0, 1, 2};
    gf_real dp[3];
    p.rn[1] = rn;
    for (unsigned t = 0; t < 5u; t++) {
        udu_swap(rn.ud, perm, dp, 3u, (t + 1u) & 1u);
        p.rn[perm[0] * 3u + perm[1]] = rn;
    }
    p.motion = *motion;
    *pm = p;
    return GF_OK;
}

gf_status ref_uducp3_prepare_meas(ref_ekf3_pmeas *pq, const gf_ekf3_meas *meas)
{
    if (!pq || !meas || !meas->h || meas->m - 1u > 2u) {
        return GF_ERR_ARG;
    }
    ref_ekf3_pmeas p;
    const gf_status st = meas3_check(meas, NULL, p.qn);
    if (st != GF_OK) {
        return st;
    }
    p.meas = *meas;
    *pq = p;
    return GF_OK;
}

gf_status ref_uducp3_predict(ref_udu3 *ekf, const ref_ekf3_pmotion *pm,
                             const gf_real *u)
{
    if (!ekf || !pm) {
        return GF_ERR_ARG;
    }
    const unsigned slot = ekf->perm[0] * 3u + ekf->perm[1];
    return uduc3_predict_step(ekf, &pm->motion, pm->rn[slot].ud, u);
}

gf_status ref_uducp3_update(ref_udu3 *ekf, const ref_ekf3_pmeas *pq,
                            const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !pq || !z) {
        return GF_ERR_ARG;
    }
    gf_real f = 0;
    for (unsigned i = 0; i < pq->meas.m; i++) {
        f += Z(z->v[i]);
    }
    if (!(f < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    return uduc3_update_step(ekf, &pq->meas, pq->qn, z, info);
}

// ---- The checked floor's init and covariance ----
//
// The prior judged by hand as R is (noise2_at, noise3_at: closed form for
// 2 x 2, diagonal or factored from the last state for 3 x 3), mu finite
// first, then factored with the states reversed in about twice the
// precision (prior: the library's gf_udu_factor_n, written for n <= 3;
// the library's own copy, gf_udu_factor3, is 1064 B on Cortex-M4F -Os,
// these helpers 852 B), the heading wrapped, the belief's numbers
// tested finite before it is written.

// The prior's factors, once noise2_at / noise3_at accepted it, with the
// states reversed (perm (1 0), (2 1 0)), as the library's: t = P^T Sigma P
// (s's upper triangle read), column j from the last,
//   d_j = t_jj - sum_(k>j) U_jk d_k U_jk,
//   U_ij = (t_ij - sum_(k>j) U_ik d_k U_jk) / d_j,
// each sum and quotient in about twice gf_real's precision (Dekker's
// TwoProduct, Knuth's TwoSum, the factors' low parts l carried to first
// order) and each factor rounded once: a d_j of a nearly singular prior is
// the difference of nearly equal numbers, and the steps need it to its own
// relative precision. Every positive pivot is kept; one below GF_REAL_MIN
// is zero, with a zero column of U.

// Veltkamp's splitting constant, 2^ceil(p / 2) + 1.
#ifdef GF_SINGLE_PRECISION
#define SPLIT GF_R(4097.0)
#else
#define SPLIT GF_R(134217729.0)
#endif

// a b - p for p = fl(a b), exactly; 0 where a split leaves the range.
static REF_NOINLINE gf_real prod_err(gf_real a, gf_real b, gf_real p)
{
    const gf_real ca = SPLIT * a, cb = SPLIT * b;
    const gf_real ah = ca - (ca - a), bh = cb - (cb - b);
    const gf_real al = a - ah, bl = b - bh;
    const gf_real e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return GF_ISFINITE(e) ? e : GF_R(0.0);
}

// a + b - t for t = fl(a + b), exactly.
REF_INLINE gf_real sum_err(gf_real a, gf_real b, gf_real t)
{
    const gf_real bb = t - a;
    return (a - (t - bb)) + (b - bb);
}

// acc - a d b, its rounding and the low parts' terms (la, ld, lb) added
// to *e.
static REF_NOINLINE gf_real schur(gf_real acc, gf_real a, gf_real d, gf_real b,
                                  gf_real la, gf_real ld, gf_real lb,
                                  gf_real *e)
{
    const gf_real t1 = a * d, t = t1 * b, next = acc - t;
    const gf_real c = prod_err(t1, b, t) + prod_err(a, d, t1) * b + t1 * lb +
                      (la * d + a * ld) * b;
    *e += sum_err(acc, -t, next) - c;
    return next;
}

// d_j = x + e rounded once (e ignored if not finite), its low part in *l;
// zero below GF_REAL_MIN.
static REF_NOINLINE gf_real pivot(gf_real x, gf_real e, gf_real *l)
{
    e = GF_ISFINITE(e) ? e : GF_R(0.0);
    const gf_real d = x + e;
    const gf_real dl = sum_err(x, e, d);
    const int pos = d >= GF_REAL_MIN;
    *l = (pos && GF_ISFINITE(dl)) ? dl : GF_R(0.0);
    return pos ? d : GF_R(0.0);
}

// U_ij = (r + rl) / (d + dl) rounded once, its low part in *l; 0 if d is.
static REF_NOINLINE gf_real quot(gf_real r, gf_real rl, gf_real d, gf_real dl,
                                 gf_real *l)
{
    gf_real q = 0, ql = 0;
    if (d > 0) {
        rl = GF_ISFINITE(rl) ? rl : GF_R(0.0);
        q = r / d;
        const gf_real p = q * d;
        ql = (((r - p) - prod_err(q, d, p)) + rl - q * dl) / d;
        ql = GF_ISFINITE(ql) ? ql : GF_R(0.0);
        const gf_real u = q + ql;
        ql = sum_err(q, ql, u);
        q = u;
        ql = GF_ISFINITE(ql) ? ql : GF_R(0.0);
    }
    *l = ql;
    return q;
}

// The factors of P^T s P (n = 2 or 3, s rows of n), P the states
// reversed: t_ij = s_(n-1-i)(n-1-j), read from s's upper triangle.
static REF_NOINLINE void prior(const gf_real *s, unsigned n, gf_real *ud)
{
    gf_real lo[6]; // the factors' low parts
    for (unsigned j = n; j-- > 0u;) {
        const unsigned sj = n - 1u - j;
        gf_real e = 0, x = s[sj * n + sj], dl;
        for (unsigned k = j + 1u; k < n; k++) {
            x = schur(x, ud[UD(j, k)], ud[UD(k, k)], ud[UD(j, k)], lo[UD(j, k)],
                      lo[UD(k, k)], lo[UD(j, k)], &e);
        }
        const gf_real dj = pivot(x, e, &dl);
        for (unsigned i = 0; i < j; i++) {
            // state n - 1 - i > sj
            gf_real r = s[sj * n + n - 1u - i], rl = 0;
            for (unsigned k = j + 1u; k < n; k++) {
                r = schur(r, ud[UD(i, k)], ud[UD(k, k)], ud[UD(j, k)],
                          lo[UD(i, k)], lo[UD(k, k)], lo[UD(j, k)], &rl);
            }
            ud[UD(i, j)] = quot(r, rl, dj, dl, &lo[UD(i, j)]);
        }
        ud[UD(j, j)] = dj;
        lo[UD(j, j)] = dl;
    }
}

gf_status ref_uduc2_init(ref_udu2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!(Z(mu->v[0]) + Z(mu->v[1]) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    ref_udu2 nb = {*mu, {0}, {1, 0}};
    const gf_status st = noise2_at(sigma->m[0], 2u, nb.ud); // the verdict
    if (st != GF_OK) {
        return st;
    }
    prior(sigma->m[0], 2u, nb.ud);
    if (!(belief2_z(nb.mu.v, nb.ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    *kf = nb;
    return GF_OK;
}

gf_status ref_uduc3_init(ref_udu3 *ekf, const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!ekf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!(Z(mu->v[0]) + Z(mu->v[1]) + Z(mu->v[2]) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    ref_udu3 nb = {*mu, {0}, {2, 1, 0}};
    const gf_status st = noise3_at(sigma->m[0], nb.ud); // the verdict
    if (st != GF_OK) {
        return st;
    }
    prior(sigma->m[0], 3u, nb.ud);
    nb.mu.v[2] = wrap(mu->v[2]);
    if (!(belief3_z(nb.mu.v, nb.ud) < GF_R(1.0))) {
        return GF_ERR_NONFINITE;
    }
    *ekf = nb;
    return GF_OK;
}

// Sigma = P U D U^T P^T in closed form, each variance a sum of d_j U_ij^2.
gf_status ref_udu2_cov(const ref_udu2 *kf, gf_mat2 *sigma)
{
    if (!kf || !sigma) {
        return GF_ERR_ARG;
    }
    const gf_real d0 = kf->ud[0], u01 = kf->ud[1], d1 = kf->ud[2];
    const gf_real s01 = u01 * d1;
    const unsigned p0 = kf->perm[0];
    sigma->m[p0][p0] = d0 + u01 * s01;
    sigma->m[0][1] = s01;
    sigma->m[1][0] = s01;
    sigma->m[1u - p0][1u - p0] = d1;
    return GF_OK;
}

gf_status ref_udu3_cov(const ref_udu3 *ekf, gf_mat3 *sigma)
{
    if (!ekf || !sigma) {
        return GF_ERR_ARG;
    }
    const gf_real *ud = ekf->ud;
    const gf_real d0 = ud[0], u01 = ud[1], d1 = ud[2];
    const gf_real u02 = ud[3], u12 = ud[4], d2 = ud[5];
    const gf_real s02 = u02 * d2, s12 = u12 * d2, t01 = u01 * d1;
    const unsigned p0 = ekf->perm[0], p1 = ekf->perm[1], p2 = ekf->perm[2];
    gf_real(*o)[3] = sigma->m;
    o[p0][p0] = d0 + u01 * t01 + u02 * s02;
    o[p0][p1] = o[p1][p0] = t01 + u02 * s12;
    o[p0][p2] = o[p2][p0] = s02;
    o[p1][p1] = d1 + u12 * s12;
    o[p1][p2] = o[p2][p1] = s12;
    o[p2][p2] = d2;
    return GF_OK;
}
