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
    // sin and cos theta land in G's third column (no local of ours has
    // its address taken, so this frame stays small under UKF3's and PF3's
    // large ones); their G entries are written below
    gf_sincos(th, &G->m[0][2], &G->m[1][2]);
    const gf_real s = G->m[0][2], c = G->m[1][2];
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
//
// Stack (issue 4: no public function deeper than 256 bytes on an MCU):
// each way through gf_ekf3_update (the built-in x, a scalar callback, m =
// 2 or 3) and the predict's callback way is a function of its own, so only
// one way's locals are ever on the stack, and none of them calls a helper
// that holds a 3x3 temporary of its own. Under -O2 the two scalar ways are
// inlined into gf_ekf3_update (W2's step in scripts/bench); under -Os every
// way is called, and the computations are left to the compiler (one copy,
// called), which keeps the flash cost of the slow paths small.
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define EKF3_INLINE static inline __attribute__((always_inline))
#define EKF3_SLOW static __attribute__((noinline, cold))
#define EKF3_OUTLINE static __attribute__((noinline))
#define EKF3_WAY static inline __attribute__((always_inline))
#elif defined(__GNUC__)
#define EKF3_INLINE static inline
#define EKF3_SLOW static __attribute__((noinline))
#define EKF3_OUTLINE static __attribute__((noinline))
#define EKF3_WAY static __attribute__((noinline))
#else
#define EKF3_INLINE static inline
#define EKF3_SLOW static
#define EKF3_OUTLINE static
#define EKF3_WAY static
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
        gf_mat3_sandwich(&G, &ekf->sigma, &G); // over G: no second 3x3
        n.n00 = g[0][0] + R->m[0][0];
        n.n01 = g[0][1] + R->m[0][1];
        n.n02 = g[0][2] + R->m[0][2];
        n.n11 = g[1][1] + R->m[1][1];
        n.n12 = g[1][2] + R->m[1][2];
        n.n22 = g[2][2] + R->m[2][2];
    }

    // mu_bar and G reach the outputs (a NaN or inf in G reaches every
    // entry of its row of G Sigma G^T, diagonal included), so do R's upper
    // entries (its lower ones passed the exact symmetry test or
    // gf_mat3_check_psd). Why outputs that are not all finite failed, in
    // the documented order: R first, then what g returned; a sum that only
    // overflowed is fine.
    if (!GF_ISFINITE(mu.v[0] + mu.v[1] + mu.v[2] + sym3_sum(&n))) {
        st = gf_mat3_check_psd(R, 3);
        if (st != GF_OK) {
            return st;
        }
        if (!gf_vec3_is_finite_n(&mu, 3) || !sym3_is_finite(&n)) {
            return GF_ERR_NONFINITE; // or overflow: keep the last good belief
        }
    }
    ekf->mu = mu;
    sym3_store(&ekf->sigma, &n);
    return GF_OK;
}

// The built-in motion, inline: the formulas of gf_ekf3_motion_forward_turn,
// with its Jacobian's shape known, so no call through the pointer, no G to
// fill and test. Same results to the bit. 1 with the belief written, or 0
// with nothing written on any doubt (a non-finite sum): the callback way
// then finds the status.
EKF3_WAY int ekf3_predict_builtin(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                                  const gf_real *u)
{
    const gf_real d = u[0], phi = u[1], th = ekf->mu.v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    const gf_real m0 = ekf->mu.v[0] + d * c, m1 = ekf->mu.v[1] + d * s;
    const gf_real m2 = wrap(th + phi);
    sym3 n = shear_sandwich(&ekf->sigma, -d * s, d * c, &motion->R);
    if (!GF_ISFINITE(m0 + m1 + m2 + sym3_sum(&n))) {
        return 0;
    }
    ekf->mu.v[0] = m0;
    ekf->mu.v[1] = m1;
    ekf->mu.v[2] = m2;
    sym3_store(&ekf->sigma, &n);
    return 1;
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    if (motion->g == gf_ekf3_motion_forward_turn && psd3_quick(&motion->R) &&
        u && ekf3_predict_builtin(ekf, motion, u)) {
        return GF_OK;
    }
    return ekf3_predict_callback(ekf, motion, u);
}

// gf_ekf3_update for m = 2 and 3, its input checks (gf_meas3_check) done:
// Cholesky of S, the factored Joseph form. Few live temporaries, each
// reused as it frees up: H (then I - K H, then the new Sigma), K (after P =
// Sigma_bar H^T), L (S, then its Cholesky factor; packed), v (z_hat, then
// S^-1 y, then the new mu) and the innovation.
EKF3_OUTLINE gf_status ekf3_update_general(gf_ekf3 *ekf,
                                           const gf_ekf3_meas *meas,
                                           const gf_vec3 *z,
                                           gf_innovation *info)
{
    const unsigned m = meas->m;
    const gf_mat3 *sig = &ekf->sigma;
    gf_innovation in;
    gf_vec3 v = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    gf_mat3 K;
    gf_real L[6];

    // z_hat = h(mu_bar), H = dh/dx at mu_bar (first m rows)
    gf_status st = meas->h(meas->ctx, &ekf->mu, &v, &H);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    for (unsigned i = m; i < 3; i++) { // rows the model must not use
        H.m[i][0] = H.m[i][1] = H.m[i][2] = 0;
    }
    if (!gf_vec3_is_finite_n(&v, m) || !gf_mat3_is_finite(&H)) {
        return GF_ERR_NONFINITE;
    }
    // y = z - h(mu_bar), angle residuals wrapped
    in.m = m;
    in.y[0] = in.y[1] = in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - v.v[i];
        if (meas->angle_mask & (1u << i)) {
            in.y[i] = gf_angle_wrap(in.y[i]);
        }
    }

    // P = Sigma_bar H^T (3 x m), in K
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            K.m[i][j] = sig->m[i][0] * H.m[j][0] + sig->m[i][1] * H.m[j][1] +
                        sig->m[i][2] * H.m[j][2];
        }
    }
    // S = H P + Q (m x m, Q's two halves averaged), lower triangle in L,
    // factored there: S = L L^T. A NaN or inf in S (which the
    // factorisation would reject) is reported as such.
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = i; j < m; j++) {
            L[GF_TRI(j, i)] = H.m[i][0] * K.m[0][j] + H.m[i][1] * K.m[1][j] +
                              H.m[i][2] * K.m[2][j] +
                              GF_R(0.5) * (meas->Q.m[i][j] + meas->Q.m[j][i]);
            if (!GF_ISFINITE(L[GF_TRI(j, i)])) {
                return GF_ERR_NONFINITE;
            }
        }
    }
    st = gf_chol_packed(L, m);
    if (st != GF_OK) {
        return st;
    }
    // S^-1 y, then K = P S^-1 (row i of K solves S k = row i of P)
    v.v[0] = in.y[0];
    v.v[1] = in.y[1];
    v.v[2] = in.y[2];
    for (unsigned i = 0; i < 4; i++) {
        gf_chol_solve_packed(L, m, i == 0 ? v.v : K.m[i - 1]);
    }
    // NIS = y^T S^-1 y
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        in.nis += in.y[i] * v.v[i];
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }

    // mu = mu_bar + K y
    v = ekf->mu;
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            v.v[i] += K.m[i][j] * in.y[j];
        }
    }
    v.v[2] = gf_angle_wrap(v.v[2]);

    // Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T. First I - K H over
    // H, column by column (column c of I - K H needs column c of H alone).
    for (unsigned c = 0; c < 3; c++) {
        gf_real a0 = c == 0 ? GF_R(1.0) : GF_R(0.0);
        gf_real a1 = c == 1 ? GF_R(1.0) : GF_R(0.0);
        gf_real a2 = c == 2 ? GF_R(1.0) : GF_R(0.0);
        for (unsigned j = 0; j < m; j++) {
            a0 -= K.m[0][j] * H.m[j][c];
            a1 -= K.m[1][j] * H.m[j][c];
            a2 -= K.m[2][j] * H.m[j][c];
        }
        H.m[0][c] = a0;
        H.m[1][c] = a1;
        H.m[2][c] = a2;
    }
    // Then row i of T = (I - K H) Sigma_bar, and the upper entries (i, j)
    // of T (I - K H)^T + K Q K^T, over row i of I - K H (no longer needed
    // once T's row is formed; rows j > i are read, not written).
    gf_real(*a)[3] = H.m;
    gf_real sum = v.v[0] + v.v[1] + v.v[2];
    for (unsigned i = 0; i < 3; i++) {
        const gf_real t0 = a[i][0] * sig->m[0][0] + a[i][1] * sig->m[1][0] +
                           a[i][2] * sig->m[2][0];
        const gf_real t1 = a[i][0] * sig->m[0][1] + a[i][1] * sig->m[1][1] +
                           a[i][2] * sig->m[2][1];
        const gf_real t2 = a[i][0] * sig->m[0][2] + a[i][1] * sig->m[1][2] +
                           a[i][2] * sig->m[2][2];
        for (unsigned j = i; j < 3; j++) {
            gf_real kqk = 0;
            for (unsigned r = 0; r < m; r++) {
                for (unsigned c = 0; c < m; c++) {
                    kqk += K.m[i][r] * meas->Q.m[r][c] * K.m[j][c];
                }
            }
            a[i][j] = (t0 * a[j][0] + t1 * a[j][1] + t2 * a[j][2]) + kqk;
            sum += a[i][j];
        }
    }
    gf_mat3 *n = &H; // the new Sigma, upper triangle
    // The one test of the fast paths, then the entries if in doubt
    if (!GF_ISFINITE(sum)) {
        n->m[1][0] = n->m[0][1];
        n->m[2][0] = n->m[0][2];
        n->m[2][1] = n->m[1][2];
        if (!gf_vec3_is_finite_n(&v, 3) || !gf_mat3_is_finite(n)) {
            return GF_ERR_NONFINITE;
        }
    }
    ekf->mu = v;
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = i; j < 3; j++) {
            ekf->sigma.m[i][j] = ekf->sigma.m[j][i] = n->m[i][j];
        }
    }
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
    ekf3_update1 r;
    // y = z - h(mu_bar) (wrapped if an angle) first and the heading's wrap
    // last, so that no value is held across their calls (a smaller frame
    // where they are not inline).
    r.y = z->v[0] - zh;
    if (meas->angle_mask & 1u) {
        r.y = wrap(r.y);
    }
    const gf_mat3 *S = &ekf->sigma;
    const gf_real s00 = S->m[0][0], s01 = S->m[0][1], s02 = S->m[0][2];
    const gf_real s11 = S->m[1][1], s12 = S->m[1][2], s22 = S->m[2][2];
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
    // NIS = y s^-1 y
    r.nis = r.y * si * r.y;
    // K = p s^-1, mu = mu_bar + K y
    const gf_real k0 = p0 * si, k1 = p1 * si, k2 = p2 * si;
    r.m[0] = ekf->mu.v[0] + k0 * r.y;
    r.m[1] = ekf->mu.v[1] + k1 * r.y;
    r.m[2] = ekf->mu.v[2] + k2 * r.y;
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
    r.m[2] = wrap(r.m[2]);
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

// A scalar update the cheap test doubted, r computed from z_hat and the
// row h: every check of gf_ekf3_update in the documented order (those
// before h is called first), then the rest.
EKF3_SLOW gf_status ekf3_update1_slow(gf_ekf3 *ekf,
                                      const gf_ekf3_meas *meas,
                                      const gf_vec3 *z, gf_innovation *info,
                                      gf_real zh, const gf_real *h,
                                      const ekf3_update1 *r)
{
    gf_status st = gf_meas3_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    if (!(GF_ISFINITE(zh) && GF_ISFINITE(h[0]) && GF_ISFINITE(h[1]) &&
          GF_ISFINITE(h[2]))) {
        return GF_ERR_NONFINITE;
    }
    if (!GF_ISFINITE(r->s)) {
        return GF_ERR_NONFINITE;
    }
    if (!(r->s > 0)) {
        return GF_ERR_SINGULAR;
    }
    if (!GF_ISFINITE(r->nis)) {
        return GF_ERR_NONFINITE;
    }
    if (!(meas->gate > 0 && r->nis > meas->gate) &&
        !(GF_ISFINITE(r->m[0]) && GF_ISFINITE(r->m[1]) &&
          GF_ISFINITE(r->m[2]) && GF_ISFINITE(r->n00) &&
          GF_ISFINITE(r->n01) && GF_ISFINITE(r->n02) &&
          GF_ISFINITE(r->n11) && GF_ISFINITE(r->n12) &&
          GF_ISFINITE(r->n22))) {
        return GF_ERR_NONFINITE;
    }
    return ekf3_update1_finish(ekf, meas, r, info);
}

// A scalar update with the built-in measurement of x, inline: z_hat = x,
// H = (1 0 0). GF_OK or GF_ERR_GATED when done; GF_ERR_NONFINITE, with
// nothing written, on any doubt (the callback way then finds the status).
EKF3_WAY gf_status ekf3_update1_x(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                                  const gf_vec3 *z, gf_innovation *info)
{
    const ekf3_update1 r = ekf3_update1_compute(ekf, meas, z, ekf->mu.v[0], 0);
    if (!ekf3_update1_ok(meas, &r)) {
        return GF_ERR_NONFINITE;
    }
    return ekf3_update1_finish(ekf, meas, &r, info);
}

// A scalar update with the model called through its pointer.
EKF3_WAY gf_status ekf3_update1_callback(gf_ekf3 *ekf,
                                         const gf_ekf3_meas *meas,
                                         const gf_vec3 *z,
                                         gf_innovation *info)
{
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
    const ekf3_update1 r =
        ekf3_update1_compute(ekf, meas, z, zh.v[0], H.m[0]);
    if (!ekf3_update1_ok(meas, &r)) {
        return ekf3_update1_slow(ekf, meas, z, info, zh.v[0], H.m[0], &r);
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
        const gf_status st = gf_meas3_check(meas, z);
        return st != GF_OK ? st : ekf3_update_general(ekf, meas, z, info);
    }
    if (meas->h == gf_ekf3_meas_x) {
        const gf_status st = ekf3_update1_x(ekf, meas, z, info);
        if (st != GF_ERR_NONFINITE) {
            return st;
        }
    }
    return ekf3_update1_callback(ekf, meas, z, info);
}

#endif // GF_SMALL
