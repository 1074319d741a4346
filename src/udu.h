// gaussfilt: the covariance arithmetic of KF2 and EKF3, one implementation
// for n = 2 or 3 states (docs/numerics.md says why it is this one).
//
// The belief keeps Sigma itself (mu and Sigma stay readable, and no larger
// than n + n^2 numbers), but every step works on a factorisation
// Sigma = F D F^T (D >= 0 diagonal; F unit lower triangular in the order
// of its pivots, each pivot the largest left relative to its own variance,
// so that |F_ij| sqrt(d_j) <= sqrt(Sigma_ii): no entry of F grows):
//   prediction  Sigma_bar = (A F) D (A F)^T + R, a sum of squares with
//               weights d_k >= 0, so no variance can come out negative;
//   correction  the Joseph form on the factors, one measured quantity at a
//               time (the measurement noise decorrelated first): with
//               f = F^T h, s = r + sum d_k f_k^2 (a sum of non-negative
//               terms) and K = F D f / s, the factor becomes [F - K f^T, K]
//               with weights [D, r]: (I - K h) Sigma (I - K h)^T + r K K^T,
//               without ever forming the difference of two covariances.
// Matrices are row-major with rows of `stride` entries (n for the belief
// and the models: KF2's 2x2 and EKF3's 3x3 read in place).
//
// Included by kf2.c, ekf3.c and mat.c. The factorisation and the verdict
// are functions of mat.c (one copy, the largest part); the steps are
// static inline, each filter's copy compiled for its own n, so that an
// optimising build unrolls their loops (sizes 2 and 3 known), while a
// build for size keeps them as loops. One implementation either way.
#ifndef GAUSSFILT_SRC_UDU_H
#define GAUSSFILT_SRC_UDU_H

#include <stddef.h>

#include "gf_internal.h"

// Columns of a factor: the n states, then one per measured quantity.
#define GF_FCOLS 6u

// s = F diag(d) F^T for the leading n x n block of a symmetric s (upper
// triangle read). The pivot of each step is the state whose variance left
// (once the earlier pivots' states are known) is the largest relative to
// its own variance: the pivots of the correlation form D^-1/2 S D^-1/2,
// in [0, 1], the same in any units; at the first step, where all are 1,
// the state `first` if its variance is positive (n: the first such).
// order[t] is the state of step t;
// column order[t] of F is 1 there and zero on the earlier pivots' rows.
// F, d and order may be NULL (a verdict only); F's columns beyond n are
// not written.
//
// check != 0 judges s: a pivot up to GF_PD_RTOL is zero, and then so is
// every state left (none is larger): each variance left must be >=
// -GF_PD_RTOL times its own and each entry left coupling two of them
// within the 2x2 bound a_ik^2 <= a_ii a_kk, both sides widened by
// GF_PD_RTOL times their variance; else GF_ERR_NOT_PSD. check == 0 (the
// filter's own covariance, positive semidefinite but rounded) keeps every
// positive pivot, however small: taking a direction as known exactly
// because its variance is at the rounding level of the others would make
// the filter overconfident there, the collapse this arithmetic exists to
// prevent.
// Defined in mat.c (one copy for every filter and the verdicts).
gf_status gf_ldl(const gf_real *s, unsigned stride, unsigned n, int check,
                 unsigned first, gf_real (*F)[GF_FCOLS], gf_real *d,
                 unsigned *order);

// gf_ldl's arithmetic, inlined into the filters' steps (where n is known);
// gf_ldl itself is one copy, in mat.c, for the verdicts.
// 1 if |x|^2 <= y z for y, z >= 0, written without a product that could
// overflow or a square root: (x / y) x <= z, and for y = 0 only x = 0.
// The same answer for any power of two times x, y and z.
static inline int gf_coupled_ok(gf_real x, gf_real y, gf_real z)
{
    if (!(y > 0)) {
        return !(GF_FABS(x) > 0);
    }
    return (x / y) * x <= z;
}

static inline gf_status gf_ldl_inline(const gf_real *s, unsigned stride,
                                      unsigned n, int check, unsigned first,
                                      gf_real (*F)[GF_FCOLS], gf_real *d,
                                      unsigned *order)
{
    const gf_real rtol = check ? GF_PD_RTOL : GF_R(0.0);
    gf_real a[3][3]; // the Schur complements (upper triangle, by state)
    unsigned p[3] = {0, 1, 2}; // p[t..n-1]: the states not pivots yet
    if (n > 3u) {
        return GF_ERR_ARG;
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned k = i; k < n; k++) {
            a[i][k] = s[i * stride + k];
        }
    }
    // The first pivot: all ratios are 1 there (0 for a zero variance):
    // the caller's `first` if its variance is positive, else the first
    // state whose variance is.
    unsigned f0 = (first < n && s[first * stride + first] > 0) ? first : n;
    for (unsigned k = 0; k < n && f0 == n; k++) {
        if (s[k * stride + k] > 0) {
            f0 = k;
        }
    }
    if (f0 < n) {
        p[f0] = 0;
        p[0] = f0;
    }
    unsigned t = 0;
    for (; t < n; t++) {
        // the pivot: the largest a_jj / s_jj left (a tie keeps p's order)
        if (t > 0u && t + 1u < n) {
            gf_real best = -1;
            unsigned at = t;
            for (unsigned u = t; u < n; u++) {
                const unsigned k = p[u];
                const gf_real skk = s[k * stride + k];
                const gf_real ratio = (skk > 0) ? a[k][k] / skk : GF_R(0.0);
                if (ratio > best) {
                    best = ratio;
                    at = u;
                }
            }
            const unsigned sw = p[at];
            p[at] = p[t];
            p[t] = sw;
        }
        const unsigned j = p[t];
        const gf_real pj = a[j][j];
        if (!(pj > rtol * s[j * stride + j])) { // (NaN fails)
            break; // this one and every state left are zero: below
        }
        if (d) {
            d[j] = pj;
        }
        if (F) {
            for (unsigned u = 0; u < t; u++) {
                F[p[u]][j] = 0;
            }
            F[j][j] = 1;
        }
        // a_ik -= (a_ij / a_jj) a_jk over the states left, upper triangle
        for (unsigned u = t + 1u; u < n; u++) {
            const unsigned i = p[u];
            const gf_real aij = (i < j) ? a[i][j] : a[j][i];
            const gf_real l = aij / pj;
            if (F) {
                F[i][j] = l;
            }
            for (unsigned v = t + 1u; v < n; v++) {
                const unsigned k = p[v];
                if (k >= i) {
                    a[i][k] -= l * ((k < j) ? a[k][j] : a[j][k]);
                }
            }
        }
    }
    if (order) {
        for (unsigned u = 0; u < n; u++) {
            order[u] = p[u];
        }
    }
    // The states left (p[t..n-1], if any) have zero variance.
    for (unsigned u = t; u < n; u++) {
        const unsigned k = p[u];
        const gf_real skk = s[k * stride + k];
        if (check) {
            if (!(a[k][k] >= -rtol * skk)) {
                return GF_ERR_NOT_PSD;
            }
            for (unsigned w = t; w < u; w++) {
                const unsigned i = p[w];
                const gf_real aii = a[i][i] > 0 ? a[i][i] : GF_R(0.0);
                const gf_real akk = a[k][k] > 0 ? a[k][k] : GF_R(0.0);
                const gf_real aik = (i < k) ? a[i][k] : a[k][i];
                if (!gf_coupled_ok(aik, aii + rtol * s[i * stride + i],
                                   akk + rtol * skk)) {
                    return GF_ERR_NOT_PSD;
                }
            }
        }
        if (d) {
            d[k] = 0;
        }
        if (F) {
            for (unsigned i = 0; i < n; i++) {
                F[i][k] = (i == k) ? GF_R(1.0) : GF_R(0.0);
            }
        }
    }
    return GF_OK;
}

// The verdict on a covariance passed in (n x n block, rows of stride):
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (not symmetric within GF_SYM_RTOL, a
// negative variance, or gf_ldl's verdict), else GF_OK.
// Defined in mat.c.
gf_status gf_psd_check(const gf_real *s, unsigned stride, unsigned n);

// A covariance with a zero variance (in F W F^T a sum of non-negative
// terms, so zero only when every term is) has zero covariances in its row
// and column: the state is known exactly. So has a variance below the
// smallest normal number (GF_REAL_MIN): it carries too few digits to be
// told from zero, and its covariances too few to stay within
// Cauchy-Schwarz, which the correlation form would then fail.
static inline void gf_zero_known(gf_real *sigma, unsigned n)
{
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        if (!(sigma[i * n + i] >= GF_REAL_MIN)) {
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                sigma[i * n + j] = 0;
                sigma[j * n + i] = 0;
            }
        }
    }
}

// out = G Sigma G^T + R as (G F) D (G F)^T + R (Sigma = F D F^T), the
// upper triangle of R, exactly symmetric; out may not be sigma.
static inline void gf_cov_predict(const gf_real *sigma, unsigned n,
                                  const gf_real *g, const gf_real *r,
                                  gf_real *out)
{
    gf_real f[3][GF_FCOLS], d[3];
    (void)gf_ldl_inline(sigma, n, n, 0, n, f, d, NULL);
    // W = G F, into out's place (rows of n)
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned k = 0; k < n; k++) {
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned l = 0; l < n; l++) {
                acc += g[i * n + l] * f[l][k];
            }
            out[i * n + k] = acc;
        }
    }
    // Sigma_bar = W D W^T + R, W's rows kept in f
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned k = 0; k < n; k++) {
            f[i][k] = out[i * n + k];
        }
    }
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            gf_real acc = r[i * n + j];
            GF_UNROLL
            for (unsigned k = 0; k < n; k++) {
                acc += f[i][k] * d[k] * f[j][k];
            }
            out[i * n + j] = acc;
            out[j * n + i] = acc;
        }
    }
    gf_zero_known(out, n);
}

// The measurement noise decorrelated: q (m x m, rows of n, checked by
// gf_psd_check) = V E V^T by gf_ldl, then h (m rows of n) and y (m
// entries) replaced by V^-1 h and V^-1 y in place, e the noises of the m
// quantities so made (independent). V^-1 by substitution in the pivots'
// order, in which V is unit lower triangular.
static inline void gf_decorrelate(const gf_real *q, unsigned n, unsigned m,
                                  gf_real *h, gf_real *y, gf_real e[3])
{
    gf_real v[3][GF_FCOLS];
    unsigned order[3] = {0, 0, 0};
    (void)gf_ldl(q, n, m, 1, m, v, e, order);
    for (unsigned t = 0; t < m; t++) {
        const unsigned i = order[t];
        for (unsigned u = 0; u < t; u++) {
            const unsigned k = order[u];
            const gf_real vik = v[i][k];
            y[i] -= vik * y[k];
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                h[i * n + j] -= vik * h[k * n + j];
            }
        }
    }
}

// The correction with m = 1..n measured quantities whose noises e (from
// gf_decorrelate) are independent, in place on the caller's copies: mu
// (mu_bar in, mu out), sigma (Sigma_bar in, Sigma out); h (m rows of n)
// and y (z - h(mu_bar)) as gf_decorrelate left them. One quantity after
// another, each innovation taken at the mean the earlier ones gave; *nis =
// the sum of y_i^2 / s_i, which is y^T S^-1 y. GF_ERR_NONFINITE (an
// innovation variance overflowed), GF_ERR_SINGULAR (a quantity with no
// noise, e_i = 0, whose h Sigma h^T is zero relative to n sum h_j^2
// Sigma_jj, its bound by Cauchy-Schwarz: the same in any units); the
// outputs are partly written then.
static inline gf_status gf_cov_correct(unsigned n, gf_real *mu,
                                       gf_real *sigma, unsigned m,
                                       const gf_real *h, const gf_real *y,
                                       const gf_real e[3], gf_real *nis)
{
    gf_real f[3][GF_FCOLS], w[GF_FCOLS];
    if (n > 3u || m > n) {
        return GF_ERR_ARG;
    }
    // The quantities in the order of how much they tell, the largest
    // sum_j h_j^2 Sigma_jj / e_i first (a ratio of variances of z_i: the
    // same in any units; e_i = 0, an exact quantity, before all), and the
    // first one's main state (the largest h_j^2 Sigma_jj) the first pivot:
    // its column of F then carries the most precise direction alone, and
    // F - K c^T does not cancel in the others.
    unsigned rank[3] = {0, 1, 2};
    gf_real tell[3] = {0, 0, 0};
    unsigned first = 0;
    for (unsigned i = 0; i < m; i++) {
        gf_real v = 0;
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            v += h[i * n + j] * h[i * n + j] * sigma[j * n + j];
        }
        tell[i] = (e[i] > 0) ? v / e[i] : (gf_real)INFINITY;
    }
    for (unsigned i = 1; i < m; i++) { // insertion sort, largest first
        for (unsigned k = i; k > 0u && tell[rank[k]] > tell[rank[k - 1u]]; k--) {
            const unsigned r = rank[k];
            rank[k] = rank[k - 1u];
            rank[k - 1u] = r;
        }
    }
    {
        gf_real most = -1;
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            const gf_real hj = h[rank[0] * n + j];
            const gf_real part = hj * hj * sigma[j * n + j];
            if (part > most) {
                first = j;
                most = part;
            }
        }
    }
    (void)gf_ldl_inline(sigma, n, n, 0, first, f, w, NULL);
    gf_real dx[3] = {0, 0, 0}; // mu - mu_bar so far
    gf_real total = 0;
    unsigned cols = n;
    for (unsigned t = 0; t < m; t++) {
        const unsigned i = rank[t];
        const gf_real *hi = &h[i * n];
        // this quantity's innovation, at the mean of the ones before it
        gf_real yi = y[i];
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            yi -= hi[j] * dx[j];
        }
        // c = F^T h (into g), s = e_i + sum w_k c_k^2, b = F W c
        gf_real g[GF_FCOLS], s = e[i];
        for (unsigned k = 0; k < cols; k++) {
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                acc += hi[j] * f[j][k];
            }
            g[k] = acc;
            s += w[k] * acc * acc;
        }
        if (!GF_ISFINITE(s)) {
            return GF_ERR_NONFINITE;
        }
        if (!(e[i] > 0)) {
            gf_real scale = 0;
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                scale += hi[j] * hi[j] * sigma[j * n + j];
            }
            if (!(s > GF_PD_RTOL * (gf_real)n * scale)) {
                return GF_ERR_SINGULAR;
            }
        }
        // K = b / s; mu += K y_i, NIS += y_i^2 / s; F -= K c^T, then K
        // joins F as a column of weight e_i
        const gf_real gi = yi / s;
        total += yi * gi;
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            gf_real b = 0;
            for (unsigned k = 0; k < cols; k++) {
                b += f[j][k] * w[k] * g[k];
            }
            dx[j] += b * gi;
            const gf_real kj = b / s;
            for (unsigned k = 0; k < cols; k++) {
                f[j][k] -= kj * g[k];
            }
            f[j][cols] = kj;
        }
        w[cols] = e[i];
        cols++;
    }
    // Sigma = F W F^T, exactly symmetric, every variance a sum of
    // non-negative terms
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            for (unsigned k = 0; k < cols; k++) {
                acc += f[i][k] * w[k] * f[j][k];
            }
            sigma[i * n + j] = acc;
            sigma[j * n + i] = acc;
        }
    }
    gf_zero_known(sigma, n);
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        mu[j] += dx[j];
    }
    *nis = total;
    return GF_OK;
}

#endif
