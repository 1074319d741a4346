// gaussfilt: the compact KF2 and EKF3 steps of GF_SMALL (config.h).
//
// gf_kf2_predict/update and gf_ekf3_predict/update, for flash and stack
// instead of speed: one correction and one prediction routine shared by
// both filters (n = 2 or 3 states, m = 1..3 measured quantities), every
// model called through its pointer, no fast path. Same API, statuses,
// checks and order of checks as kf2.c and ekf3.c (which leave these four
// functions out under GF_SMALL), so the same tests pass.
//
// The routines work on the belief in place, through row-major pointers
// whose rows have n entries: KF2's 2x2 and EKF3's 3x3 matrices (C and H,
// Q, A and G, R) are read as they are, without padded copies. Results go
// to locals with rows of 3 and reach the belief only once all are finite.
// Compiled in every build; empty (but for the declarations of ekf3.h)
// without GF_SMALL.
#include "gaussfilt/ekf3.h"

#ifdef GF_SMALL

// 1 if the n entries of x are all finite.
static int all_finite(const gf_real *x, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        if (!GF_ISFINITE(x[i])) {
            return 0;
        }
    }
    return 1;
}

// u^T A v over the leading d x d block of a (rows of as entries).
static gf_real quad(const gf_real *u, const gf_real *a, unsigned as,
                    const gf_real *v, unsigned d)
{
    gf_real acc = 0;
    for (unsigned i = 0; i < d; i++) {
        for (unsigned j = 0; j < d; j++) {
            acc += u[i] * a[i * as + j] * v[j];
        }
    }
    return acc;
}

// Writes mu_new (n) and the upper triangle of s_new (rows of 3), mirrored
// so that Sigma is exactly symmetric, if all are finite; else
// GF_ERR_NONFINITE and the belief is untouched.
static gf_status commit(gf_real *mu, gf_real *sigma, unsigned n,
                        const gf_real *mu_new, const gf_real *s_new)
{
    if (!all_finite(mu_new, n)) {
        return GF_ERR_NONFINITE;
    }
    for (unsigned i = 0; i < n; i++) {
        if (!all_finite(&s_new[i * 3u + i], n - i)) {
            return GF_ERR_NONFINITE;
        }
    }
    for (unsigned i = 0; i < n; i++) {
        mu[i] = mu_new[i];
        for (unsigned j = i; j < n; j++) {
            sigma[i * n + j] = s_new[i * 3u + j];
            sigma[j * n + i] = s_new[i * 3u + j];
        }
    }
    return GF_OK;
}

// The prediction of both filters, mu_bar given:
//   Sigma_bar = G Sigma G^T + R (upper triangle of R, mirrored).
// g, sigma and r have rows of n entries.
static gf_status predict(gf_real *mu, gf_real *sigma, unsigned n,
                         const gf_real *mu_bar, const gf_real *g,
                         const gf_real *r)
{
    gf_real s[9];
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            s[i * 3u + j] = quad(&g[i * n], sigma, n, &g[j * n], n) +
                            r[i * n + j];
        }
    }
    return commit(mu, sigma, n, mu_bar, s);
}

// Solves l l^T x = b in place on the m entries of x (l lower triangular,
// rows of 3).
static void chol_solve(const gf_real *l, unsigned m, gf_real *x)
{
    for (unsigned i = 0; i < m; i++) { // l y = b
        for (unsigned k = 0; k < i; k++) {
            x[i] -= l[i * 3u + k] * x[k];
        }
        x[i] /= l[i * 3u + i];
    }
    for (unsigned i = m; i-- > 0;) { // l^T x = y
        for (unsigned k = i + 1; k < m; k++) {
            x[i] -= l[k * 3u + i] * x[k];
        }
        x[i] /= l[i * 3u + i];
    }
}

// Row i of I - K H (k: n x m, rows of 3; h: m x n, rows of n).
static void ikh_row(const gf_real *k, const gf_real *h, unsigned n,
                    unsigned m, unsigned i, gf_real *row)
{
    for (unsigned c = 0; c < n; c++) {
        row[c] = (i == c) ? GF_R(1.0) : GF_R(0.0);
        for (unsigned j = 0; j < m; j++) {
            row[c] -= k[i * 3u + j] * h[j * n + c];
        }
    }
}

// The correction of both filters (Table 3.1/3.3, lines 4-6), inputs
// checked, the innovation y (m entries, angles wrapped) given:
//   S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T S^-1,  mu = mu_bar + K y,
//   Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T, exactly symmetric.
// h (m x n) and q (m x m) have rows of n entries; n = 3 wraps the heading.
// *nis = y^T S^-1 y on GF_OK and GF_ERR_GATED; the belief changes only on
// GF_OK.
static gf_status correct(gf_real *mu, gf_real *sigma, unsigned n,
                         const gf_real *h, const gf_real *q, unsigned m,
                         gf_real gate, const gf_real *y, gf_real *nis)
{
    gf_real l[9]; // S, then its Cholesky factor, then the new Sigma
    gf_real k[9]; // K, n x m
    gf_real a[3], b[3];

    // S (upper triangle of Q, mirrored)
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = i; j < m; j++) {
            l[i * 3u + j] = quad(&h[i * n], sigma, n, &h[j * n], n) +
                            q[i * n + j];
            l[j * 3u + i] = l[i * 3u + j];
        }
        if (!all_finite(&l[i * 3u], m)) {
            return GF_ERR_NONFINITE;
        }
    }
    // S = L L^T in place; a pivot not above GF_PD_RTOL times its diagonal
    // entry (or NaN) is singular, as gf_mat3_chol.
    for (unsigned j = 0; j < m; j++) {
        gf_real d = l[j * 3u + j];
        const gf_real sjj = d;
        for (unsigned c = 0; c < j; c++) {
            d -= l[j * 3u + c] * l[j * 3u + c];
        }
        if (!(d > GF_PD_RTOL * sjj)) {
            return GF_ERR_SINGULAR;
        }
        d = GF_SQRT(d);
        l[j * 3u + j] = d;
        for (unsigned i = j + 1; i < m; i++) {
            for (unsigned c = 0; c < j; c++) {
                l[i * 3u + j] -= l[i * 3u + c] * l[j * 3u + c];
            }
            l[i * 3u + j] /= d;
        }
    }

    // NIS = y^T S^-1 y
    gf_real v = 0;
    for (unsigned i = 0; i < m; i++) {
        a[i] = y[i];
    }
    chol_solve(l, m, a);
    for (unsigned i = 0; i < m; i++) {
        v += y[i] * a[i];
    }
    if (!GF_ISFINITE(v)) {
        return GF_ERR_NONFINITE;
    }
    *nis = v;
    if (gate > 0 && v > gate) {
        return GF_ERR_GATED;
    }

    // K: row i solves S k = row i of Sigma_bar H^T
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < m; j++) {
            a[j] = 0;
            for (unsigned c = 0; c < n; c++) {
                a[j] += sigma[i * n + c] * h[j * n + c];
            }
        }
        chol_solve(l, m, a);
        for (unsigned j = 0; j < m; j++) {
            k[i * 3u + j] = a[j];
        }
    }

    // Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T, upper triangle
    for (unsigned i = 0; i < n; i++) {
        ikh_row(k, h, n, m, i, a);
        for (unsigned j = i; j < n; j++) {
            ikh_row(k, h, n, m, j, b);
            l[i * 3u + j] = quad(a, sigma, n, b, n) +
                            quad(&k[i * 3u], q, n, &k[j * 3u], m);
        }
    }
    // mu = mu_bar + K y
    for (unsigned i = 0; i < n; i++) {
        a[i] = mu[i];
        for (unsigned j = 0; j < m; j++) {
            a[i] += k[i * 3u + j] * y[j];
        }
    }
    if (n == 3u) {
        a[2] = gf_angle_wrap(a[2]);
    }
    return commit(mu, sigma, n, a, l);
}

// Writes the innovation of an update that reached the gate.
static void report(gf_innovation *info, unsigned m, const gf_real *y,
                   gf_real nis)
{
    if (info) {
        info->m = m;
        for (unsigned i = 0; i < 3u; i++) {
            info->y[i] = (i < m) ? y[i] : GF_R(0.0);
        }
        info->nis = nis;
    }
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    if (!gf_mat2_is_finite(&model->A) || !gf_mat2_is_finite(&model->B) ||
        !all_finite(model->c.v, 2) || (u && !all_finite(u->v, 2))) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(&model->R);
    if (st != GF_OK) {
        return st;
    }
    // mu_bar = A mu + B u + c
    gf_real mu[2];
    for (unsigned i = 0; i < 2u; i++) {
        mu[i] = model->A.m[i][0] * kf->mu.v[0] +
                model->A.m[i][1] * kf->mu.v[1];
        if (u) {
            mu[i] += model->B.m[i][0] * u->v[0] + model->B.m[i][1] * u->v[1];
        }
        mu[i] += model->c.v[i];
    }
    // Sigma_bar = A Sigma A^T + R
    return predict(kf->mu.v, kf->sigma.m[0], 2, mu, model->A.m[0],
                   model->R.m[0]);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas || !z || meas->m < 1 || meas->m > 2) {
        return GF_ERR_ARG;
    }
    const unsigned m = meas->m;
    for (unsigned i = 0; i < m; i++) {
        if (!all_finite(meas->C.m[i], 2) || !GF_ISFINITE(meas->c.v[i]) ||
            !GF_ISFINITE(z->v[i])) {
            return GF_ERR_NONFINITE;
        }
    }
    if (!GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_status st;
    if (m == 1u) {
        st = !GF_ISFINITE(meas->Q.m[0][0]) ? GF_ERR_NONFINITE
             : (meas->Q.m[0][0] < 0)       ? GF_ERR_NOT_PSD
                                           : GF_OK;
    } else {
        st = gf_mat2_check_psd(&meas->Q);
    }
    if (st != GF_OK) {
        return st;
    }
    // y = z - c - C mu_bar
    gf_real y[2], nis = 0;
    for (unsigned i = 0; i < m; i++) {
        y[i] = z->v[i] - meas->c.v[i] -
               (meas->C.m[i][0] * kf->mu.v[0] + meas->C.m[i][1] * kf->mu.v[1]);
    }
    st = correct(kf->mu.v, kf->sigma.m[0], 2, meas->C.m[0], meas->Q.m[0], m,
                 meas->gate, y, &nis);
    if (st == GF_OK || st == GF_ERR_GATED) {
        report(info, m, y, nis);
    }
    return st;
}

// A model callback's status, as ekf3.c maps it: anything that is not a
// known failure, and GF_ERR_GATED, become GF_ERR_MODEL.
static gf_status callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
               ? GF_ERR_MODEL : st;
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&motion->R, 3);
    if (st != GF_OK) {
        return st;
    }
    // mu_bar = g(u, mu), G = dg/dx at mu
    gf_vec3 mu = ekf->mu;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    st = motion->g(motion->ctx, &ekf->mu, u, &mu, &G);
    if (st != GF_OK) {
        return callback_status(st);
    }
    mu.v[2] = gf_angle_wrap(mu.v[2]);
    // Sigma_bar = G Sigma G^T + R (a non-finite G reaches the diagonal)
    return predict(ekf->mu.v, ekf->sigma.m[0], 3, mu.v, G.m[0],
                   motion->R.m[0]);
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !meas->h || !z || meas->m < 1 || meas->m > 3) {
        return GF_ERR_ARG;
    }
    const unsigned m = meas->m;
    if (!all_finite(z->v, m) || !GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&meas->Q, m);
    if (st != GF_OK) {
        return st;
    }
    // z_hat = h(mu_bar), H = dh/dx at mu_bar (first m rows read)
    gf_vec3 y = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &y, &H);
    if (st != GF_OK) {
        return callback_status(st);
    }
    // y = z - h(mu_bar), angle residuals wrapped
    for (unsigned i = 0; i < m; i++) {
        if (!GF_ISFINITE(y.v[i]) || !all_finite(H.m[i], 3)) {
            return GF_ERR_NONFINITE;
        }
        y.v[i] = z->v[i] - y.v[i];
        if (meas->angle_mask & (1u << i)) {
            y.v[i] = gf_angle_wrap(y.v[i]);
        }
    }
    gf_real nis = 0;
    st = correct(ekf->mu.v, ekf->sigma.m[0], 3, H.m[0], meas->Q.m[0], m,
                 meas->gate, y.v, &nis);
    if (st == GF_OK || st == GF_ERR_GATED) {
        report(info, m, y.v, nis);
    }
    return st;
}

#endif
