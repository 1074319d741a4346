#include "gaussfilt/ekf3.h"

#include "gf_internal.h"

// gcc's basic-block vectorizer (on at -O2 since gcc 12) packs these scalar
// formulas into SSE2 pairs with more shuffles than it saves: scripts/bench
// counts more instructions and time per step with it. Off for this file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-tree-slp-vectorize")
#endif

gf_status gf_ekf3_motion_forward_turn(void *ctx, const gf_vec3 *mu,
                                      const gf_real *u, gf_vec3 *mu_bar,
                                      gf_mat3 *G)
{
    (void)ctx;
    if (!mu || !u || !mu_bar || !G) {
        return GF_ERR_ARG;
    }
    const gf_real d = u[0], phi = u[1], th = mu->v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    // g(u, x) = (x + d cos theta, y + d sin theta, theta + phi)
    mu_bar->v[0] = mu->v[0] + d * c;
    mu_bar->v[1] = mu->v[1] + d * s;
    mu_bar->v[2] = th + phi;
    // G = dg/dx, equation 4.1 (with d = 1 there)
    G->m[0][0] = 1; G->m[0][1] = 0; G->m[0][2] = -d * s;
    G->m[1][0] = 0; G->m[1][1] = 1; G->m[1][2] = d * c;
    G->m[2][0] = 0; G->m[2][1] = 0; G->m[2][2] = 1;
    return GF_OK;
}

gf_status gf_ekf3_meas_x(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                         gf_mat3 *H)
{
    (void)ctx;
    if (!mu_bar || !z_hat || !H) {
        return GF_ERR_ARG;
    }
    // h(x) = x, H = (1 0 0)
    z_hat->v[0] = mu_bar->v[0];
    H->m[0][0] = 1; H->m[0][1] = 0; H->m[0][2] = 0;
    return GF_OK;
}

gf_status gf_ekf3_meas_xy(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                          gf_mat3 *H)
{
    (void)ctx;
    if (!mu_bar || !z_hat || !H) {
        return GF_ERR_ARG;
    }
    // h(x) = (x, y), H = ((1 0 0), (0 1 0))
    z_hat->v[0] = mu_bar->v[0];
    z_hat->v[1] = mu_bar->v[1];
    H->m[0][0] = 1; H->m[0][1] = 0; H->m[0][2] = 0;
    H->m[1][0] = 0; H->m[1][1] = 1; H->m[1][2] = 0;
    return GF_OK;
}

gf_status gf_ekf3_init(gf_ekf3 *ekf, const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!ekf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!gf_vec3_is_finite_n(mu, 3)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat3_check_psd(sigma, 3);
    if (st != GF_OK) {
        return st;
    }
    ekf->mu = *mu;
    ekf->mu.v[2] = gf_angle_wrap(mu->v[2]);
    ekf->sigma = *sigma;
    gf_mat3_symmetrize(&ekf->sigma);
    return GF_OK;
}

#if !GF_SMALL // GF_SMALL: predict and update are in small.c

// How the checks stay cheap (as in kf2.c; docs/performance.md): a NaN or
// inf cannot vanish through + - *, so the finiteness of every input and of
// the result is tested by one isfinite() of the sum of the outputs. That
// test can only err on the safe side, and any doubt runs the full checks
// in the documented order, so failures keep their statuses.
// Under -Os the computations are left to the compiler (one copy, called),
// which keeps the flash cost of the slow paths small.
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define EKF3_INLINE static inline __attribute__((always_inline))
#define EKF3_SLOW static __attribute__((noinline, cold))
#define EKF3_OUTLINE static __attribute__((noinline))
#else
#define EKF3_INLINE static inline
#define EKF3_SLOW static
#define EKF3_OUTLINE static
#endif

// The angle a wrapped to (-pi, pi], with the common case inline.
EKF3_INLINE gf_real wrap(gf_real a)
{
    return (a > -GF_PI && a <= GF_PI) ? a : gf_angle_wrap(a);
}

// A cheap sufficient test that R is a covariance: exactly symmetric and
// diagonally dominant (r_ii >= sum of |r_ij| over j != i: PSD by
// Gershgorin), the usual shape of a process noise. NaN fails it; inf may
// pass (it then reaches Sigma_bar and the isfinite() of the outputs).
// Whatever it rejects goes to gf_mat3_check_psd, the exact test (all
// principal minors, symmetry within GF_SYM_RTOL).
EKF3_INLINE int psd3_quick(const gf_mat3 *R)
{
    const gf_real(*r)[3] = R->m;
    const gf_real b = GF_FABS(r[0][1]), c = GF_FABS(r[0][2]);
    const gf_real e = GF_FABS(r[1][2]);
    return GF_FABS(r[0][1] - r[1][0]) + GF_FABS(r[0][2] - r[2][0]) +
                   GF_FABS(r[1][2] - r[2][1]) <= 0 &&
           r[0][0] >= b + c && r[1][1] >= b + e && r[2][2] >= c + e;
}

// Why a prediction whose outputs were not all finite failed, in the order
// gf_ekf3_predict reports it; GF_OK if only the cheap test doubted.
EKF3_SLOW gf_status predict_diagnose(const gf_ekf3_motion *motion,
                                     const gf_vec3 *mu, const gf_mat3 *G)
{
    gf_status st = gf_mat3_check_psd(&motion->R, 3);
    if (st != GF_OK) {
        return st;
    }
    return (gf_vec3_is_finite_n(mu, 3) && gf_mat3_is_finite(G)) ? GF_OK
                                                          : GF_ERR_NONFINITE;
}

// The unique entries of a symmetric 3x3.
typedef struct sym3 {
    gf_real n00, n01, n02, n11, n12, n22;
} sym3;

// G Sigma G^T + R for G = I + a e0 e2^T + b e1 e2^T, the form of every
// motion that moves the position by a heading-dependent step (the built-in
// one, eq. 4.1): 16 flops instead of 75, and 6 for R (upper triangle).
EKF3_INLINE sym3 shear_sandwich(const gf_mat3 *S, gf_real a, gf_real b,
                                const gf_mat3 *R)
{
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    const gf_real t02 = s02 + a * s22, t12 = s12 + b * s22;
    sym3 n;
    n.n00 = s00 + a * s02 + a * t02 + R->m[0][0];
    n.n01 = s01 + a * s12 + b * t02 + R->m[0][1];
    n.n02 = t02 + R->m[0][2];
    n.n11 = s11 + b * s12 + b * t12 + R->m[1][1];
    n.n12 = t12 + R->m[1][2];
    n.n22 = s22 + R->m[2][2];
    return n;
}

// Writes a symmetric result, mirrored: exactly symmetric.
static void sym3_store(gf_mat3 *o, const sym3 *n)
{
    o->m[0][0] = n->n00;
    o->m[0][1] = o->m[1][0] = n->n01;
    o->m[0][2] = o->m[2][0] = n->n02;
    o->m[1][1] = n->n11;
    o->m[1][2] = o->m[2][1] = n->n12;
    o->m[2][2] = n->n22;
}

EKF3_INLINE gf_real sym3_sum(const sym3 *n)
{
    return n->n00 + n->n01 + n->n02 + n->n11 + n->n12 + n->n22;
}

static int sym3_is_finite(const sym3 *n)
{
    return GF_ISFINITE(n->n00) && GF_ISFINITE(n->n01) &&
           GF_ISFINITE(n->n02) && GF_ISFINITE(n->n11) &&
           GF_ISFINITE(n->n12) && GF_ISFINITE(n->n22);
}

// gf_ekf3_predict with the motion called through its pointer.
EKF3_OUTLINE gf_status ekf3_predict_callback(gf_ekf3 *ekf,
                                             const gf_ekf3_motion *motion,
                                             const gf_real *u)
{
    const gf_mat3 *R = &motion->R;
    gf_status st;
    if (!psd3_quick(R)) {
        st = gf_mat3_check_psd(R, 3);
        if (st != GF_OK) {
            return st;
        }
    }

    // mu_bar = g(u, mu), G = dg/dx at mu
    gf_vec3 mu = ekf->mu;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    st = motion->g(motion->ctx, &ekf->mu, u, &mu, &G);
    if (st != GF_OK) {
        gf_status rs = gf_mat3_check_psd(R, 3); // inf in R comes first
        return rs != GF_OK ? rs : gf_callback_status(st);
    }
    mu.v[2] = wrap(mu.v[2]);

    // Sigma_bar = G Sigma G^T + R; Sigma symmetric: 6 unique entries.
    sym3 n;
    gf_real(*g)[3] = G.m;
    if (GF_FABS(g[0][1]) + GF_FABS(g[1][0]) + GF_FABS(g[2][0]) +
            GF_FABS(g[2][1]) + GF_FABS(g[0][0] - 1) + GF_FABS(g[1][1] - 1) +
            GF_FABS(g[2][2] - 1) <= 0) { // (NaN fails the test)
        n = shear_sandwich(&ekf->sigma, g[0][2], g[1][2], R);
    } else {
        gf_mat3 t;
        gf_mat3_sandwich(&G, &ekf->sigma, &t);
        n.n00 = t.m[0][0] + R->m[0][0];
        n.n01 = t.m[0][1] + R->m[0][1];
        n.n02 = t.m[0][2] + R->m[0][2];
        n.n11 = t.m[1][1] + R->m[1][1];
        n.n12 = t.m[1][2] + R->m[1][2];
        n.n22 = t.m[2][2] + R->m[2][2];
    }

    // mu_bar and G reach the outputs, so do R's upper entries (its lower
    // ones passed the exact symmetry test or gf_mat3_check_psd).
    if (!GF_ISFINITE(mu.v[0] + mu.v[1] + mu.v[2] + sym3_sum(&n))) {
        st = predict_diagnose(motion, &mu, &G);
        if (st != GF_OK) {
            return st;
        }
        if (!gf_vec3_is_finite_n(&mu, 3) || !sym3_is_finite(&n)) {
            return GF_ERR_NONFINITE; // overflow: keep the last good belief
        }
    }
    ekf->mu = mu;
    sym3_store(&ekf->sigma, &n);
    return GF_OK;
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    if (motion->g != gf_ekf3_motion_forward_turn || !u ||
        !psd3_quick(&motion->R)) {
        return ekf3_predict_callback(ekf, motion, u);
    }
    // The built-in motion, inline: the formulas of
    // gf_ekf3_motion_forward_turn, with its Jacobian's shape known, so no
    // call through the pointer, no G to fill and test. Same results to the
    // bit. Any doubt (a non-finite sum) goes the callback way, which finds
    // the status.
    const gf_real d = u[0], phi = u[1], th = ekf->mu.v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    const gf_real m0 = ekf->mu.v[0] + d * c, m1 = ekf->mu.v[1] + d * s;
    const gf_real m2 = wrap(th + phi);
    sym3 n = shear_sandwich(&ekf->sigma, -d * s, d * c, &motion->R);
    if (!GF_ISFINITE(m0 + m1 + m2 + sym3_sum(&n))) {
        return ekf3_predict_callback(ekf, motion, u);
    }
    ekf->mu.v[0] = m0;
    ekf->mu.v[1] = m1;
    ekf->mu.v[2] = m2;
    sym3_store(&ekf->sigma, &n);
    return GF_OK;
}

// gf_ekf3_update for any m (used for m = 2 and 3): Cholesky of S.
EKF3_OUTLINE gf_status ekf3_update_general(gf_ekf3 *ekf,
                                           const gf_ekf3_meas *meas,
                                           const gf_vec3 *z,
                                           gf_innovation *info)
{
    if (!ekf) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_meas3_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    const unsigned m = meas->m;

    // z_hat = h(mu_bar), H = dh/dx at mu_bar (first m rows)
    gf_vec3 zh = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    for (unsigned i = m; i < 3; i++) { // rows the model must not use
        zh.v[i] = 0;
        H.m[i][0] = H.m[i][1] = H.m[i][2] = 0;
    }
    if (!gf_vec3_is_finite_n(&zh, m) || !gf_mat3_is_finite(&H)) {
        return GF_ERR_NONFINITE;
    }

    const gf_mat3 *sig = &ekf->sigma;
    // PHt = Sigma_bar H^T (3 x m), S = H Sigma_bar H^T + Q (m x m)
    gf_mat3 PHt = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            PHt.m[i][j] = sig->m[i][0] * H.m[j][0] + sig->m[i][1] * H.m[j][1] +
                          sig->m[i][2] * H.m[j][2];
        }
    }
    gf_mat3 S = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = i; j < m; j++) {
            S.m[i][j] = H.m[i][0] * PHt.m[0][j] + H.m[i][1] * PHt.m[1][j] +
                        H.m[i][2] * PHt.m[2][j] +
                        GF_R(0.5) * (meas->Q.m[i][j] + meas->Q.m[j][i]);
            S.m[j][i] = S.m[i][j];
        }
    }
    gf_mat3 L;
    st = gf_mat3_chol(&S, m, &L);
    if (st != GF_OK) {
        return gf_mat3_is_finite(&S) ? st : GF_ERR_NONFINITE;
    }

    // y = z - h(mu_bar), angle residuals wrapped
    gf_innovation in;
    in.m = m;
    in.y[0] = in.y[1] = in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - zh.v[i];
        if (meas->angle_mask & (1u << i)) {
            in.y[i] = gf_angle_wrap(in.y[i]);
        }
    }
    // NIS = y^T S^-1 y
    gf_vec3 yv = {{in.y[0], in.y[1], in.y[2]}}, Siy;
    gf_mat3_chol_solve(&L, m, &yv, &Siy);
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        in.nis += in.y[i] * Siy.v[i];
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }

    // K = Sigma_bar H^T S^-1: row i of K solves S k = row i of PHt
    gf_mat3 K = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < 3; i++) {
        gf_vec3 row = {{PHt.m[i][0], PHt.m[i][1], PHt.m[i][2]}}, k;
        gf_mat3_chol_solve(&L, m, &row, &k);
        for (unsigned j = 0; j < m; j++) {
            K.m[i][j] = k.v[j];
        }
    }

    // mu = mu_bar + K y
    gf_vec3 mu = ekf->mu;
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            mu.v[i] += K.m[i][j] * in.y[j];
        }
    }
    mu.v[2] = gf_angle_wrap(mu.v[2]);

    // Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T, then symmetrized
    gf_mat3 IKH = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned k = 0; k < 3; k++) {
            for (unsigned j = 0; j < m; j++) {
                IKH.m[i][k] -= K.m[i][j] * H.m[j][k];
            }
        }
    }
    gf_mat3 sigma;
    gf_mat3_sandwich(&IKH, sig, &sigma);
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned k = i; k < 3; k++) {
            gf_real kqk = 0;
            for (unsigned a = 0; a < m; a++) {
                for (unsigned b = 0; b < m; b++) {
                    kqk += K.m[i][a] * meas->Q.m[a][b] * K.m[k][b];
                }
            }
            sigma.m[i][k] += kqk;
            sigma.m[k][i] = sigma.m[i][k];
        }
    }

    if (!gf_vec3_is_finite_n(&mu, 3) || !gf_mat3_is_finite(&sigma)) {
        return GF_ERR_NONFINITE;
    }
    ekf->mu = mu;
    ekf->sigma = sigma;
    if (info) {
        *info = in;
    }
    return GF_OK;
}

// A scalar update's results, before anything is written.
typedef struct ekf3_update1 {
    gf_real s, si, y, nis;
    gf_real m[3];
    gf_real n00, n01, n02, n11, n12, n22;
} ekf3_update1;

// A scalar update from z_hat and the row h = H (NULL: H = (1 0 0), the
// built-in measurement of x): S is a number, so no factorisation and no
// solve.
EKF3_INLINE ekf3_update1 ekf3_update1_compute(const gf_ekf3 *ekf,
                                              const gf_ekf3_meas *meas,
                                              const gf_vec3 *z, gf_real zh,
                                              const gf_real *h)
{
    const gf_mat3 *S = &ekf->sigma;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
    ekf3_update1 r;
    gf_real p0, p1, p2;

    // p = Sigma_bar H^T, s = H p + Q
    if (h) {
        const gf_real h0 = h[0], h1 = h[1], h2 = h[2];
        p0 = s00 * h0 + s01 * h1 + s02 * h2;
        p1 = s01 * h0 + s11 * h1 + s12 * h2;
        p2 = s02 * h0 + s12 * h1 + s22 * h2;
        r.s = meas->Q.m[0][0] + (h0 * p0 + h1 * p1 + h2 * p2);
    } else { // H = (1 0 0): the same values, without the zero products
        p0 = s00;
        p1 = s01;
        p2 = s02;
        r.s = meas->Q.m[0][0] + s00;
    }
    const gf_real si = GF_R(1.0) / r.s;
    r.si = si;
    // y = z - h(mu_bar) (wrapped if an angle), NIS = y s^-1 y
    r.y = z->v[0] - zh;
    if (meas->angle_mask & 1u) {
        r.y = wrap(r.y);
    }
    r.nis = r.y * si * r.y;
    // K = p s^-1, mu = mu_bar + K y
    const gf_real k0 = p0 * si, k1 = p1 * si, k2 = p2 * si;
    r.m[0] = ekf->mu.v[0] + k0 * r.y;
    r.m[1] = ekf->mu.v[1] + k1 * r.y;
    r.m[2] = wrap(ekf->mu.v[2] + k2 * r.y);
    // Joseph form multiplied out for a scalar measurement, as in kf2.c:
    // Sigma = Sigma_bar - K p^T - p K^T + s K K^T
    //       = Sigma_bar - p K^T + K w^T,  w = s K - p;
    // the upper triangle, mirrored on commit.
    const gf_real w0 = r.s * k0 - p0, w1 = r.s * k1 - p1;
    const gf_real w2 = r.s * k2 - p2;
    r.n00 = s00 - p0 * k0 + k0 * w0;
    r.n01 = s01 - p0 * k1 + k0 * w1;
    r.n02 = s02 - p0 * k2 + k0 * w2;
    r.n11 = s11 - p1 * k1 + k1 * w1;
    r.n12 = s12 - p1 * k2 + k1 * w2;
    r.n22 = s22 - p2 * k2 + k2 * w2;
    return r;
}

// The cheap test of a scalar update: z, Q and the model's z_hat and H
// reach s or the NIS; s^-1 > 0 fails for s < 0, -0, inf and NaN (s = +0
// gives an infinite NIS); see gf_ekf3_predict.
EKF3_INLINE int ekf3_update1_ok(const gf_ekf3_meas *meas,
                                const ekf3_update1 *r)
{
    const gf_real q = meas->Q.m[0][0], gate = meas->gate;
    return q >= 0 && gate >= 0 && r->si > 0 &&
           GF_ISFINITE(r->nis + gate + r->m[0] + r->m[1] + r->m[2] +
                       r->n00 + r->n01 + r->n02 + r->n11 + r->n12 + r->n22);
}

// The rest of a scalar update once its checks have passed: the gate, then
// the belief and info.
static gf_status ekf3_update1_finish(gf_ekf3 *ekf,
                                     const gf_ekf3_meas *meas,
                                     const ekf3_update1 *r,
                                     gf_innovation *info)
{
    gf_innovation in;
    in.m = 1;
    in.y[0] = r->y;
    in.y[1] = in.y[2] = 0;
    in.nis = r->nis;
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }
    ekf->mu.v[0] = r->m[0];
    ekf->mu.v[1] = r->m[1];
    ekf->mu.v[2] = r->m[2];
    gf_real(*o)[3] = ekf->sigma.m;
    o[0][0] = r->n00;
    o[0][1] = o[1][0] = r->n01;
    o[0][2] = o[2][0] = r->n02;
    o[1][1] = r->n11;
    o[1][2] = o[2][1] = r->n12;
    o[2][2] = r->n22;
    if (info) {
        *info = in;
    }
    return GF_OK;
}

// The checks gf_ekf3_update makes before it calls h, in its order.
// A scalar update the cheap test doubted: every check in the documented
// order, then the same computation again.
EKF3_SLOW gf_status ekf3_update1_slow(gf_ekf3 *ekf,
                                      const gf_ekf3_meas *meas,
                                      const gf_vec3 *z, gf_innovation *info,
                                      gf_real zh, const gf_real *h)
{
    gf_status st = gf_meas3_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    if (!(GF_ISFINITE(zh) && GF_ISFINITE(h[0]) && GF_ISFINITE(h[1]) &&
          GF_ISFINITE(h[2]))) {
        return GF_ERR_NONFINITE;
    }
    ekf3_update1 r = ekf3_update1_compute(ekf, meas, z, zh, h);
    if (!GF_ISFINITE(r.s)) {
        return GF_ERR_NONFINITE;
    }
    if (!(r.s > 0)) {
        return GF_ERR_SINGULAR;
    }
    if (!GF_ISFINITE(r.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (!(meas->gate > 0 && r.nis > meas->gate) &&
        !(GF_ISFINITE(r.m[0]) && GF_ISFINITE(r.m[1]) && GF_ISFINITE(r.m[2]) &&
          GF_ISFINITE(r.n00) && GF_ISFINITE(r.n01) && GF_ISFINITE(r.n02) &&
          GF_ISFINITE(r.n11) && GF_ISFINITE(r.n12) && GF_ISFINITE(r.n22))) {
        return GF_ERR_NONFINITE;
    }
    return ekf3_update1_finish(ekf, meas, &r, info);
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !meas->h || !z || meas->m < 1 || meas->m > 3) {
        return GF_ERR_ARG;
    }
    if (meas->m != 1) {
        return ekf3_update_general(ekf, meas, z, info);
    }
    if (meas->h == gf_ekf3_meas_x) {
        // The built-in measurement of x, inline: z_hat = x, H = (1 0 0).
        // Any doubt goes the callback way below, which finds the status.
        ekf3_update1 r = ekf3_update1_compute(ekf, meas, z, ekf->mu.v[0], 0);
        if (ekf3_update1_ok(meas, &r)) {
            return ekf3_update1_finish(ekf, meas, &r, info);
        }
    }
    // z_hat = h(mu_bar), H = dh/dx at mu_bar; only row 0 is read for m = 1
    // (the model may write the others; they are ignored, as in the general
    // path).
    gf_vec3 zh;
    gf_mat3 H;
    zh.v[0] = 0;
    H.m[0][0] = H.m[0][1] = H.m[0][2] = 0;
    gf_status st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        gf_status pre = gf_meas3_check(meas, z);
        return pre != GF_OK ? pre : gf_callback_status(st);
    }
    ekf3_update1 r = ekf3_update1_compute(ekf, meas, z, zh.v[0], H.m[0]);
    if (!ekf3_update1_ok(meas, &r)) {
        return ekf3_update1_slow(ekf, meas, z, info, zh.v[0], H.m[0]);
    }
    return ekf3_update1_finish(ekf, meas, &r, info);
}

#endif // GF_SMALL
