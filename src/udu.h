// SPDX-License-Identifier: MIT
// gaussfilt: the factored covariance of the Kalman filters, one
// implementation for any number of states n (docs/numerics.md).
//
// A belief carries Sigma = P U D U^T P^T: U unit upper triangular, D
// diagonal and >= 0, P a permutation of the states (perm[k] is the state
// of the factors' index k). Every step works on the factors and never
// forms Sigma:
//   prediction  Sigma_bar = (A P U) D (A P U)^T + F_R D_R F_R^T,
//               triangularised again by Thornton's modified weighted
//               Gram-Schmidt: each d_j a weighted sum of squares;
//   correction  Bierman's scalar update, one whitened measured quantity at
//               a time: each d_j scaled by a ratio of innovation variances
//               alpha_(j-1) / alpha_j in [0, 1].
// Bierman's update changes no entry of U for the state at the root (the
// last index, whose d is its whole variance), and loses digits in the
// entries of a state it measures far more precisely than it knew it
// anywhere else: before a correction, the state the most informative
// quantity measures is made the root (moved to the last index by
// gf_udu_swap, one adjacent pair at a time), which the next corrections
// then find in place.
// The accessor (gf_udu_to_cov) returns Sigma exactly symmetric.
//
// Packed storage, n (n + 1) / 2 numbers, column by column: U_ij (i < j)
// at GF_UD(i, j), d_j at GF_UD(j, j).
//
// Matrices passed in are row-major, rows of `stride` entries, indexed by
// state. The functions are static inline, the arithmetic written once,
// here: KF2 and EKF3 inline the steps for their size, steps.c and steps4.c
// compile them for gf_kf and gf_ekf of n = 2, 3 and 4 (an optimising build
// unrolls the loops), kf.c for any other n.
#ifndef GAUSSFILT_SRC_UDU_H
#define GAUSSFILT_SRC_UDU_H

#include <stddef.h>

#include "gf_internal.h"
#include "ldl.h"

#define GF_UD(i, j) ((j) * ((j) + 1u) / 2u + (i))
#define GF_UD_SIZE(n) ((n) * ((n) + 1u) / 2u)

// A correction makes the state its quantity measures most the root of the
// factors when the quantity tells more than this (sum_s h_s^2 Sigma_ss /
// e_i: by how much it can shrink a variance); below, Bierman's update
// loses fewer digits than this ratio, and the factors keep their order.
#ifndef GF_UDU_ROOT_TELL
#define GF_UDU_ROOT_TELL GF_R(16.0)
#endif

// The largest n of the forms that keep their O(n) scratch on their own
// stack (gf_udu_predict, gf_udu_correct: KF2 and EKF3, an array per
// vector, which an optimising build keeps in registers); the _s forms take
// it from the caller. A source that calls the former for filters of
// another size defines it first.
#ifndef GF_UDU_NMAX
#define GF_UDU_NMAX 3u
#endif

// F = I and d = the variances of s: a diagonal covariance's factors, and
// where gf_cov_pair starts.
GF_ALWAYS_INLINE void gf_cov_identity(unsigned n, gf_real *F, gf_real *d,
                                      const gf_real *s, unsigned stride)
{
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        d[i] = s[i * stride + i];
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            F[i * n + j] = (i == j) ? GF_R(1.0) : GF_R(0.0);
        }
    }
}

// gf_ldl's arithmetic on the 2 x 2 block of states a < b alone, in closed
// form: the first of positive variance the pivot j, then
// s_kk - (s_jk / s_jj) s_jk, zero up to GF_PD_RTOL s_kk. Writes F's entries
// (k, j), (j, k), d_j, d_k and order[0..1] = j, k (where F is not NULL);
// GF_ERR_NOT_PSD if the block is not PSD.
GF_ALWAYS_INLINE gf_status gf_cov_pair(const gf_real *s, unsigned stride,
                                       unsigned n, unsigned a, unsigned b,
                                       gf_real *F, gf_real *d, unsigned *order)
{
    unsigned j = b, k = a;
    if (s[a * stride + a] > 0) {
        j = a;
        k = b;
    }
    const gf_real sjj = s[j * stride + j], skk = s[k * stride + k];
    const gf_real sjk = s[a * stride + b];
    if (!(sjj > 0)) {
        return GF_ERR_NOT_PSD; // both variances zero, coupled
    }
    const gf_real l = sjk / sjj;
    gf_real dk = skk - l * sjk;
    if (!(dk >= -GF_PD_RTOL * skk)) {
        return GF_ERR_NOT_PSD;
    }
    if (!(dk > GF_PD_RTOL * skk)) {
        dk = 0;
    }
    if (F) {
        F[k * n + j] = l;
        F[j * n + k] = 0;
        d[j] = sjj;
        d[k] = dk;
        if (order) {
            order[0] = j;
            order[1] = k;
        }
    }
    return GF_OK;
}

// The verdict on a covariance passed in (R, Q, a prior) and, where F, d
// and order are not NULL, its factors as gf_ldl's (a, p: its scratch):
// GF_ERR_NONFINITE if an entry is not finite (the test rides on the
// symmetry pass), else symmetric within GF_SYM_RTOL (|s_ij - s_ji| <=
// GF_SYM_RTOL (|s_ij| + |s_ji|), the same for any scale), no negative
// variance, then gf_ldl's verdict; a diagonal matrix (the usual noise) is
// its own factorisation (F = I), and one of more than 3 states each
// coupled to at most one other is factored pair by pair (gf_cov_pair: the
// verdict gf_ldl gives each pair alone). Else GF_ERR_NOT_PSD.
GF_ALWAYS_INLINE gf_status gf_cov_factor_n(const gf_real *s, unsigned stride,
                                           unsigned n, gf_real *F, gf_real *d,
                                           unsigned *order, gf_real *a,
                                           unsigned *p)
{
    gf_real off = 0; // the sum of |off-diagonal entries|
    gf_real z = 0;   // gf_nan_sum's test of every entry
    gf_status st = GF_OK;
    // For n > 3: whether each state is coupled (a non-zero entry) to at
    // most one other, p[i] the state i is coupled to (i itself if none).
    int pairs = 0;
    if (n > 3u && p != NULL) {
        pairs = 1;
        for (unsigned i = 0; i < n; i++) {
            p[i] = i;
        }
    }
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        const gf_real sii = s[i * stride + i];
        z += sii * GF_R(0.0);
        GF_UNROLL
        for (unsigned j = i + 1u; j < n; j++) {
            const gf_real x = s[i * stride + j], y = s[j * stride + i];
            const gf_real ax = GF_FABS(x), ay = GF_FABS(y);
            if (!(GF_FABS(x - y) <= GF_SYM_RTOL * (ax + ay))) {
                st = GF_ERR_NOT_PSD;
                break;
            }
            z += x * GF_R(0.0) + y * GF_R(0.0);
            off += ax + ay;
            if (pairs && ax > 0 && p != NULL) {
                pairs = p[i] == i && p[j] == j;
                p[i] = j;
                p[j] = i;
            }
        }
        if (sii < 0) {
            st = GF_ERR_NOT_PSD;
        }
        if (st != GF_OK) {
            break;
        }
    }
    if (st != GF_OK) {
        // (a NaN or an infinity fails the symmetry test too)
        for (unsigned i = 0; i < n; i++) {
            z = gf_nan_sum(z, &s[i * stride], n);
        }
    }
    if (!gf_sum_finite(z)) {
        return GF_ERR_NONFINITE;
    }
    if (st != GF_OK) {
        return st;
    }
    if (off > 0 && n == 2u) {
        if (F) {
            gf_cov_identity(n, F, d, s, stride);
        }
        return gf_cov_pair(s, stride, n, 0u, 1u, F, d, order);
    }
    if (off > 0 && pairs) {
        // Each state coupled to at most one other (independent axes, a
        // clock's bias and drift): the pairs one at a time, each as
        // gf_ldl would factor it alone.
        if (F) {
            gf_cov_identity(n, F, d, s, stride);
        }
        unsigned t = 0;
        for (unsigned i = 0; i < n; i++) {
            if (p[i] == i) {
                if (order) {
                    order[t] = i;
                }
                t++;
            } else if (p[i] > i) {
                const gf_status pst = gf_cov_pair(s, stride, n, i, p[i], F, d,
                                                  order ? &order[t] : NULL);
                if (pst != GF_OK) {
                    return pst;
                }
                t += 2u;
            } else {
                // the second of a pair: taken with the first
            }
        }
        return GF_OK;
    }
    if (off > 0) {
        return gf_ldl(s, stride, n, F, d, order, a, p);
    }
    if (F) {
        gf_cov_identity(n, F, d, s, stride);
        GF_UNROLL
        for (unsigned i = 0; i < n; i++) {
            order[i] = i;
        }
    }
    return GF_OK;
}

// gf_cov_factor_n for n <= 3, gf_ldl's scratch its own.
GF_ALWAYS_INLINE gf_status gf_cov_factor(const gf_real *s, unsigned stride,
                                         unsigned n, gf_real *F, gf_real *d,
                                         unsigned *order)
{
    return gf_cov_factor_n(s, stride, n, F, d, order, NULL, NULL);
}

// Veltkamp's splitting constant for gf_real's p-bit significand,
// 2^ceil(p / 2) + 1: a = ah + al with ah and al of at most p / 2 bits,
// whose products are exact.
#ifdef GF_SINGLE_PRECISION
#define GF_UDU_SPLIT GF_R(4097.0) // 2^12 + 1
#else
#define GF_UDU_SPLIT GF_R(134217729.0) // 2^27 + 1
#endif

// a b - p for p = fl(a b), exactly (Dekker's TwoProduct: + - * only, each
// rounded to nearest, none fused; the library is compiled with
// -ffp-contract=off); 0 where a split leaves the range (|a| or |b| beyond
// the largest gf_real / GF_UDU_SPLIT): no correction there.
GF_ALWAYS_INLINE gf_real gf_udu_prod_err(gf_real a, gf_real b, gf_real p)
{
    const gf_real ca = GF_UDU_SPLIT * a, cb = GF_UDU_SPLIT * b;
    const gf_real ah = ca - (ca - a), bh = cb - (cb - b);
    const gf_real al = a - ah, bl = b - bh;
    const gf_real e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return GF_ISFINITE(e) ? e : GF_R(0.0);
}

// a + b - t for t = fl(a + b), exactly (Knuth's TwoSum).
GF_ALWAYS_INLINE gf_real gf_udu_sum_err(gf_real a, gf_real b, gf_real t)
{
    const gf_real bb = t - a;
    return (a - (t - bb)) + (b - bb);
}

// x - sum_(k>j) U_ik d_k U_jk for gf_udu_factor_n, in about twice gf_real's
// precision: the sum as a plain loop gives the return value, and *err
// collects its roundings (TwoSum, TwoProduct) and the low parts of the
// factors it reads (lo: U_ik + lo_ik, d_k + lo_kk) to first order, as
// Ogita, Rump and Oishi's compensated dot product does. *err is 0 where it
// is not finite (the plain sum is then returned alone).
GF_ALWAYS_INLINE gf_real gf_udu_schur(gf_real x, const gf_real *ud,
                                      const gf_real *lo, unsigned n, unsigned i,
                                      unsigned j, gf_real *err)
{
    gf_real acc = x, e = 0;
    for (unsigned k = j + 1u; k < n; k++) {
        const gf_real a = ud[GF_UD(i, k)], d = ud[GF_UD(k, k)];
        const gf_real b = ud[GF_UD(j, k)];
        const gf_real t1 = a * d, t = t1 * b, next = acc - t;
        // a d b (with the low parts) - t
        const gf_real c = gf_udu_prod_err(t1, b, t) +
                          gf_udu_prod_err(a, d, t1) * b + t1 * lo[GF_UD(j, k)] +
                          (lo[GF_UD(i, k)] * d + a * lo[GF_UD(k, k)]) * b;
        e += gf_udu_sum_err(acc, -t, next) - c;
        acc = next;
    }
    *err = GF_ISFINITE(e) ? e : GF_R(0.0);
    return acc;
}

// The factors of a covariance s that gf_cov_factor accepted, for a new
// belief: perm is the states reversed (state 0, most often a position, the
// measured quantity, at the root), then column j from the last, with
// t_k = d_k U_jk (s read at the states perm[i], perm[j]):
//   d_j  = s_jj - sum_(k>j) U_jk t_k,
//   U_ij = (s_ij - sum_(k>j) U_ik t_k) / d_j.
// A d_j is the variance of its state given the later ones: when s is
// nearly singular it is the difference of nearly equal numbers, and the
// steps that follow need it to its own relative precision (a prediction
// weights by it, an update scales it). So each sum and quotient is taken
// in about twice gf_real's precision (gf_udu_schur; lo: scratch of
// n (n + 1) / 2, the factors' low parts) and each factor rounded once:
// within a few ulps of the exact factors of s (docs/numerics.md). Every
// positive pivot is kept, however small (a direction taken as known
// exactly because its variance is at the rounding level of the others
// would make the filter overconfident there); one below GF_REAL_MIN is
// zero, with a zero column of U. s's upper triangle is read.
static inline void gf_udu_factor_n(const gf_real *s, unsigned stride,
                                   unsigned n, gf_real *ud, unsigned char *perm,
                                   gf_real *lo)
{
    for (unsigned k = 0; k < n; k++) {
        perm[k] = (unsigned char)(n - 1u - k);
    }
    for (unsigned k = n; k < (unsigned)sizeof(gf_real); k++) {
        perm[k] = 0; // a belief's unused bytes, set
    }
    for (unsigned j = n; j-- > 0u;) {
        const unsigned sj = perm[j];
        gf_real dl;
        const gf_real d0 =
            gf_udu_schur(s[sj * stride + sj], ud, lo, n, j, j, &dl);
        // d_j = dj + dl, dj rounded to nearest
        gf_real dj = d0 + dl;
        dl = gf_udu_sum_err(d0, dl, dj);
        if (!GF_ISFINITE(dl)) {
            dl = 0;
        }
        const int pos = dj >= GF_REAL_MIN;
        for (unsigned i = 0; i < j; i++) {
            const unsigned si = perm[i];
            gf_real rl;
            const gf_real r = gf_udu_schur(
                s[(si < sj ? si : sj) * stride + (si < sj ? sj : si)], ud, lo,
                n, i, j, &rl);
            // U_ij = (r + rl) / (dj + dl) = q + ql
            gf_real q = 0, ql = 0;
            if (pos) {
                q = r / dj;
                const gf_real p = q * dj;
                ql = (((r - p) - gf_udu_prod_err(q, dj, p)) + rl - q * dl) / dj;
                if (!GF_ISFINITE(ql)) {
                    ql = 0;
                }
                const gf_real u = q + ql;
                ql = gf_udu_sum_err(q, ql, u);
                q = u;
                if (!GF_ISFINITE(ql)) {
                    ql = 0;
                }
            }
            ud[GF_UD(i, j)] = q;
            lo[GF_UD(i, j)] = ql;
        }
        ud[GF_UD(j, j)] = pos ? dj : GF_R(0.0);
        lo[GF_UD(j, j)] = pos ? dl : GF_R(0.0);
    }
}

// gf_udu_factor_n for n <= GF_UDU_NMAX, its scratch its own.
static inline void gf_udu_factor(const gf_real *s, unsigned stride, unsigned n,
                                 gf_real *ud, unsigned char *perm)
{
    gf_real lo[GF_UD_SIZE(GF_UDU_NMAX)];
    gf_udu_factor_n(s, stride, n, ud, perm, lo);
}

// Sigma = P U D U^T P^T into s (rows of stride), exactly symmetric:
//   Sigma_(perm i)(perm j) = sum_(k >= max(i, j)) U_ik d_k U_jk,  U_kk = 1,
// each variance a sum of non-negative terms. A variance below GF_REAL_MIN
// (its terms underflowed, where a covariance's may not have) is zero, with
// its row and column: that state is known exactly.
static inline void gf_udu_to_cov(const gf_real *ud, const unsigned char *perm,
                                 unsigned n, gf_real *s, unsigned stride)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            for (unsigned k = j; k < n; k++) {
                const gf_real uik = (k == i) ? GF_R(1.0) : ud[GF_UD(i, k)];
                const gf_real ujk = (k == j) ? GF_R(1.0) : ud[GF_UD(j, k)];
                acc += uik * ud[GF_UD(k, k)] * ujk;
            }
            s[perm[i] * stride + perm[j]] = acc;
            s[perm[j] * stride + perm[i]] = acc;
        }
    }
    for (unsigned i = 0; i < n; i++) {
        if (!(s[i * stride + i] >= GF_REAL_MIN)) {
            for (unsigned j = 0; j < n; j++) {
                s[i * stride + j] = 0;
                s[j * stride + i] = 0;
            }
        }
    }
}

// z plus 0 times every number of a belief's factors and every variance
// U D U^T gives them, sum_(k >= i) U_ik d_k U_ik as gf_udu_to_cov computes
// it: NaN if one is not finite (finite factors can still give a variance
// beyond the largest gf_real).
// For gf_sum_finite.
GF_ALWAYS_INLINE gf_real gf_udu_nan_sum(gf_real z, unsigned n,
                                        const gf_real *ud)
{
    gf_real acc = z;
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        gf_real v = ud[GF_UD(i, i)];
        GF_UNROLL
        for (unsigned k = i + 1u; k < n; k++) {
            v += ud[GF_UD(i, k)] * ud[GF_UD(k, k)] * ud[GF_UD(i, k)];
        }
        acc += v * GF_R(0.0);
    }
    return gf_nan_sum(acc, ud, GF_UD_SIZE(n));
}

// 1 if a factored belief (mu: n entries; ud: its packed factors)
// is all finite.
GF_ALWAYS_INLINE int gf_belief_finite(const gf_real *mu, const gf_real *ud,
                                      unsigned n)
{
    return gf_sum_finite(gf_udu_nan_sum(gf_nan_sum(GF_R(0.0), mu, n), n, ud));
}

// The modified weighted Gram-Schmidt: the factors U D U^T (into ud) of
// W diag(wd) W^T, W n rows of cols, from the last row up:
//   c = diag(wd) w_j,  d_j = w_j . c,
//   U_ij = (w_i . c) / d_j,  w_i -= U_ij w_j   (i < j).
// Each d_j is a weighted sum of squares: never negative. A d_j below
// GF_REAL_MIN (every term zero, or too few digits to tell it from zero) is
// zero, with a zero column of U: that state is known exactly once the
// later ones are. w is overwritten; c: scratch of cols entries.
GF_ALWAYS_INLINE void gf_mwgs(unsigned n, unsigned cols, gf_real *w,
                              const gf_real *wd, gf_real *ud, gf_real *c)
{
    const unsigned stride = cols;
    GF_UNROLL
    for (unsigned j = n; j-- > 0u;) {
        const gf_real *wj = &w[j * stride];
        gf_real dj = 0;
        GF_UNROLL
        for (unsigned k = 0; k < cols; k++) {
            c[k] = wd[k] * wj[k];
            dj += wj[k] * c[k];
        }
        if (!(dj >= GF_REAL_MIN)) {
            dj = 0;
        }
        const gf_real inv = (dj > 0) ? GF_R(1.0) / dj : GF_R(0.0);
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            gf_real *wi = &w[i * stride];
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned k = 0; k < cols; k++) {
                acc += wi[k] * c[k];
            }
            const gf_real uij = acc * inv;
            GF_UNROLL
            for (unsigned k = 0; k < cols; k++) {
                wi[k] -= uij * wj[k];
            }
            ud[GF_UD(i, j)] = uij;
        }
        ud[GF_UD(j, j)] = dj;
    }
}

// The prediction's covariance (Thornton's time update), in place on ud:
//   Sigma_bar = W diag(w_d) W^T,  W = [P^T A P U | P^T F_R],  w_d = [D | D_R],
// with R = F_R diag(D_R) F_R^T given by its factors (gf_cov_factor: fr
// n x n, rows of n, by state; a column of zero weight adds nothing), then
// gf_mwgs into ud_new (ud itself, or another belief's factors). a: n x n,
// rows of n, by state. Scratch, caller-owned: w n rows of 2n, wd and v
// 2n each.
GF_ALWAYS_INLINE void
gf_udu_predict_s(unsigned n, const gf_real *ud, gf_real *ud_new,
                 const unsigned char *perm, const gf_real *a, const gf_real *fr,
                 const gf_real *dr, gf_real *w, gf_real *wd, gf_real *v)
{
    const unsigned stride = 2u * n;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        wd[j] = ud[GF_UD(j, j)];
        wd[n + j] = dr[j];
    }
    // (P^T A P U)_ij = A_(pi)(pj) + sum_(l<j) A_(pi)(pl) U_lj
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        const gf_real *ai = &a[perm[i] * n];
        const gf_real *fi = &fr[perm[i] * n];
        gf_real *wi = &w[i * stride];
        gf_real *ap = v; // row i of P^T A P
        GF_UNROLL
        for (unsigned l = 0; l < n; l++) {
            ap[l] = ai[perm[l]];
            wi[n + l] = fi[l];
        }
        unsigned oj = 0; // column j of U: ud[oj + l] = U_lj
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            gf_real acc = ap[j];
            GF_UNROLL
            for (unsigned l = 0; l < j; l++) {
                acc += ap[l] * ud[oj + l];
            }
            wi[j] = acc;
            oj += j + 1u;
        }
    }
    gf_mwgs(n, stride, w, wd, ud_new, v);
}

// gf_udu_predict_s with v on its own stack (n <= GF_UDU_NMAX).
GF_ALWAYS_INLINE void gf_udu_predict(unsigned n, const gf_real *ud,
                                     gf_real *ud_new, const unsigned char *perm,
                                     const gf_real *a, const gf_real *fr,
                                     const gf_real *dr, gf_real *w, gf_real *wd)
{
    gf_real v[2u * GF_UDU_NMAX];
    gf_udu_predict_s(n, ud, ud_new, perm, a, fr, dr, w, wd, v);
}

// The state measured by the row h (by state) with the largest share of
// h Sigma h^T, h_s^2 Sigma_ss; sigma_d (if not NULL) receives Sigma's
// diagonal in the factors' order: sigma_d[i] = sum_(k >= i) U_ik^2 d_k,
// the variance of the state perm[i]; *total the sum of the shares, in the
// factors' order.
GF_ALWAYS_INLINE unsigned gf_udu_main_state(unsigned n, const gf_real *ud,
                                            const unsigned char *perm,
                                            const gf_real *h, gf_real *sigma_d,
                                            gf_real *total)
{
    unsigned best = 0;
    gf_real most = -1, acc = 0;
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        gf_real v = ud[GF_UD(i, i)];
        GF_UNROLL
        for (unsigned k = i + 1u; k < n; k++) {
            v += ud[GF_UD(i, k)] * ud[GF_UD(i, k)] * ud[GF_UD(k, k)];
        }
        const unsigned s = perm[i];
        if (sigma_d) {
            sigma_d[i] = v;
        }
        const gf_real part = h[s] * h[s] * v;
        acc += part;
        if (part > most) {
            most = part;
            best = s;
        }
    }
    *total = acc;
    return best;
}

// Swaps the factors' indices k and k + 1: the same Sigma, with the state
// perm[k + 1] at index k and perm[k] at k + 1. Only the two columns change
// (the rows of the later columns swap). With a = U_k(k+1),
//   d'_(k+1) = d_k + a^2 d_(k+1),  r = d_(k+1) / d'_(k+1),
//   U'_k(k+1) = a r,  d'_k = d_k r,
//   U'_ik = U_i(k+1) - a U_ik,  U'_i(k+1) = (d_k / d'_(k+1)) U_ik + a r U_i(k+1)
// (i < k): the two columns' d u u^T terms refactored, with no
// subtraction of variances. A d' below GF_REAL_MIN is zero, with its
// column (as gf_mwgs's): if d'_(k+1) is, d_k and a^2 d_(k+1) are zero, and
// d'_k = d_(k+1).
GF_ALWAYS_INLINE void gf_udu_swap(unsigned n, unsigned k, gf_real *ud,
                                  unsigned char *perm)
{
    const unsigned ok = GF_UD(0u, k), ol = GF_UD(0u, k + 1u);
    const gf_real a = ud[ol + k], dk = ud[ok + k], dl = ud[ol + k + 1u];
    const gf_real dq = dk + a * a * dl;
    gf_real r = 0, sk = 0, dp = dl;
    if (dq >= GF_REAL_MIN) {
        const gf_real inv = GF_R(1.0) / dq;
        r = dl * inv;
        sk = dk * inv;
        dp = dk * r;
    }
    const gf_real beta = a * r;
    const int zk = !(dp >= GF_REAL_MIN);
    for (unsigned i = 0; i < k; i++) {
        const gf_real uk = ud[ok + i], ul = ud[ol + i];
        ud[ok + i] = zk ? GF_R(0.0) : ul - a * uk;
        ud[ol + i] = sk * uk + beta * ul;
    }
    ud[ok + k] = zk ? GF_R(0.0) : dp;
    ud[ol + k] = beta;
    ud[ol + k + 1u] = (dq >= GF_REAL_MIN) ? dq : GF_R(0.0);
    for (unsigned j = k + 2u; j < n; j++) {
        const unsigned oj = GF_UD(0u, j);
        const gf_real t = ud[oj + k];
        ud[oj + k] = ud[oj + k + 1u];
        ud[oj + k + 1u] = t;
    }
    const unsigned char t = perm[k];
    perm[k] = perm[k + 1u];
    perm[k + 1u] = t;
}

// One scalar correction (Bierman's update), in place on ud, for the
// measured quantity z = h x + v, v ~ N(0, r), r >= 0, whose innovation at
// the current mean is y; hp = P^T h and dx in the factors' order. With
// f = U^T hp, g = D f and alpha_(-1) = r,
//   alpha_j = alpha_(j-1) + f_j g_j,
//   d_j    <- d_j alpha_(j-1) / alpha_j,
//   U_ij   <- U_ij - b_i f_j / alpha_(j-1),  b_i <- b_i + U_ij g_j (i < j),
//   b_j    =  g_j,
// then K = b / alpha_(n-1), alpha_(n-1) = h Sigma h^T + r = s:
//   dx += K y,  *nis += y^2 / s.
// A zero alpha (an exact quantity, r = 0, on the states taken so far; or
// one below GF_REAL_MIN, too small to invert) leaves U as it is (b is zero
// there) and d_j as it is while alpha stays zero; the first d_j to make it
// positive becomes zero: that direction is now known exactly. A d_j
// below GF_REAL_MIN becomes zero, with its column of U. GF_ERR_NONFINITE
// if s overflows; GF_ERR_SINGULAR if r = 0
// and s is zero relative to its terms before cancellation,
// sum_j d_j (|h_j| + sum_(i<j) |U_ij h_i|)^2 (the same in any units);
// ud and dx are partly written then. b: scratch of n. (f_j is taken from
// column j of U before the column changes.)
GF_ALWAYS_INLINE gf_status gf_udu_update(unsigned n, gf_real *ud,
                                         const gf_real *hp, gf_real r,
                                         gf_real y, gf_real *dx, gf_real *nis,
                                         gf_real *b)
{
    // (oj: column j of the packed factors, ud[oj + i] = U_ij, ud[oj + j] =
    // d_j)
    // An exact quantity's scale: h Sigma h^T without its cancellations
    gf_real scale = 0;
    if (!(r > 0)) {
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            gf_real t = GF_FABS(hp[j]);
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                t += GF_FABS(ud[GF_UD(i, j)] * hp[i]);
            }
            scale += ud[GF_UD(j, j)] * t * t;
        }
    }
    gf_real alpha = r, inv_prev = 0;
    unsigned oj = 0;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        // f_j = (U^T hp)_j
        gf_real fj = hp[j];
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            fj += ud[oj + i] * hp[i];
        }
        const gf_real d = ud[oj + j];
        const gf_real gj = d * fj;
        const gf_real a1 = alpha + fj * gj;
        gf_real inv = 0;
        if (a1 >= GF_REAL_MIN) { // (a smaller one is zero: 1 / a1 overflows)
            inv = GF_R(1.0) / a1;
            ud[oj + j] = d * (alpha * inv);
        }
        const gf_real p = -fj * inv_prev;
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            const gf_real uij = ud[oj + i];
            ud[oj + i] = uij + b[i] * p;
            b[i] += uij * gj;
        }
        b[j] = gj;
        alpha = a1;
        inv_prev = inv;
        oj += j + 1u;
    }
    if (!GF_ISFINITE(alpha)) {
        return GF_ERR_NONFINITE;
    }
    if (!(r > 0) && !(alpha > GF_PD_RTOL * (gf_real)n * scale)) {
        return GF_ERR_SINGULAR;
    }
    const gf_real k = y * inv_prev; // y / s
    *nis += y * k;
    oj = 0;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        dx[j] += b[j] * k;
        if (!(ud[oj + j] >= GF_REAL_MIN)) {
            GF_UNROLL
            for (unsigned i = 0; i <= j; i++) {
                ud[oj + i] = 0;
            }
        }
        oj += j + 1u;
    }
    return GF_OK;
}

// The whitening of m measured quantities whose noise is Q = F diag(e) F^T
// (gf_cov_factor: f m x m, rows of m; order its pivots' order, in which F
// is unit lower triangular): x <- F^-1 x in place, x of m entries spaced
// `step` apart, by substitution in that order (no division):
//   x_i <- x_i - sum_(k before i) F_ik x_k.
// The quantities F^-1 z then have independent noises e.
static inline void gf_udu_whiten(const gf_real *f, const unsigned *order,
                                 unsigned m, gf_real *x, unsigned step)
{
    for (unsigned t = 1; t < m; t++) {
        const unsigned i = order[t];
        for (unsigned u = 0; u < t; u++) {
            const unsigned k = order[u];
            x[i * step] -= f[i * m + k] * x[k * step];
        }
    }
}

// gf_udu_whiten's substitution on m rows of `cols` entries at once (x
// row-major: a quantity's row, then the next), each column whitened as
// gf_udu_whiten would: the same arithmetic, one pass over Q's factor.
GF_ALWAYS_INLINE void gf_udu_whiten_rows(const gf_real *f,
                                         const unsigned *order, unsigned m,
                                         gf_real *x, unsigned cols)
{
    for (unsigned t = 1; t < m; t++) {
        gf_real *xi = &x[order[t] * cols];
        for (unsigned u = 0; u < t; u++) {
            const unsigned k = order[u];
            const gf_real fik = f[order[t] * m + k];
            if (!(GF_FABS(fik) > 0)) {
                continue; // (x finite: subtracting 0 x changes nothing)
            }
            GF_UNROLL
            for (unsigned c = 0; c < cols; c++) {
                xi[c] -= fik * x[k * cols + c];
            }
        }
    }
}

// The correction with m whitened quantities (rows of hw, stride n, by
// state; e their noises; yw their whitened innovations at mu_bar), in
// their order, one after another, each made the root first if it tells
// more than GF_UDU_ROOT_TELL (sum_s h_s^2 Sigma_ss / e_i: its main state,
// gf_udu_main_state, moved to the factors' last index by gf_udu_swap),
// each innovation taken at the mean the earlier ones gave:
//   y_i = yw_i - hw_i . dx,  then gf_udu_update.
// The step mu - mu_bar is added to x (n entries, by state: mu_bar on
// entry, mu on GF_OK), *nis receives the sum of the scalar NIS, which is
// y^T S^-1 y. Statuses as gf_udu_update. Scratch, caller-owned, vectors
// of n: sd (Sigma's diagonal in the factors' order; NULL: no pre-test,
// below), dp (P^T dx), hp (P^T h_i), b (gf_udu_update's).
GF_ALWAYS_INLINE gf_status gf_udu_correct_v(
    unsigned n, gf_real *ud, unsigned char *perm, unsigned m, const gf_real *hw,
    const gf_real *e, const gf_real *yw, gf_real *x, gf_real *nis, gf_real *sd,
    gf_real *dp, gf_real *hp, gf_real *b)
{
    *nis = 0;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        dp[j] = 0;
    }
    // Of m > 1 quantities, one is first judged on sd, the variances the
    // last search for a main state found (kept with their states through
    // the swaps): O(n), where the search is O(n^2). Variances only shrink
    // in an update, so a quantity that tells too little on sd does now.
    // (Worth it for large n; KF2 and EKF3 search on every quantity.)
    const gf_real *const pre = (m > 1u) ? sd : NULL;
    if (pre != NULL) {
        gf_real t;
        (void)gf_udu_main_state(n, ud, perm, hw, sd, &t);
    }
    for (unsigned i = 0; i < m; i++) {
        const gf_real *h = &hw[i * n];
        // A quantity that tells more than GF_UDU_ROOT_TELL makes its main
        // state the root first (Bierman's update then leaves its row of U
        // alone); one that tells less loses fewer digits than that ratio.
        // A quantity of the root's state alone is in place already.
        int others = 0;
        GF_UNROLL
        for (unsigned j = 0; j + 1u < n; j++) {
            if (GF_FABS(h[perm[j]]) > 0) {
                others = 1;
            }
        }
        gf_real v = 0;
        if (others && pre != NULL) {
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                v += h[perm[j]] * h[perm[j]] * pre[j];
            }
        }
        if (others && (pre == NULL || v > GF_UDU_ROOT_TELL * e[i])) {
            const unsigned main = gf_udu_main_state(n, ud, perm, h, sd, &v);
            if (v > GF_UDU_ROOT_TELL * e[i] && perm[n - 1u] != main) {
                // main's index moved last one swap at a time, dp's and
                // sd's entries with their states
                unsigned at = 0;
                for (unsigned j = 0; j < n; j++) {
                    if (perm[j] == main) {
                        at = j;
                    }
                }
                for (unsigned k = at; k + 1u < n; k++) {
                    const gf_real dk = dp[k];
                    dp[k] = dp[k + 1u];
                    dp[k + 1u] = dk;
                    if (sd != NULL) {
                        const gf_real sk = sd[k];
                        sd[k] = sd[k + 1u];
                        sd[k + 1u] = sk;
                    }
                    gf_udu_swap(n, k, ud, perm);
                }
            }
        }
        // In the factors' order: hp = P^T h_i, dp = P^T dx
        gf_real yi = yw[i];
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            hp[j] = h[perm[j]];
            yi -= hp[j] * dp[j];
        }
        const gf_status st = gf_udu_update(n, ud, hp, e[i], yi, dp, nis, b);
        if (st != GF_OK) {
            return st;
        }
    }
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        x[perm[j]] += dp[j];
    }
    return GF_OK;
}

// gf_udu_correct_v on the caller's scratch: sv 4n entries.
GF_ALWAYS_INLINE gf_status gf_udu_correct_s(unsigned n, gf_real *ud,
                                            unsigned char *perm, unsigned m,
                                            const gf_real *hw, const gf_real *e,
                                            const gf_real *yw, gf_real *x,
                                            gf_real *nis, gf_real *sv)
{
    return gf_udu_correct_v(n, ud, perm, m, hw, e, yw, x, nis, sv, &sv[n],
                            &sv[2u * n], &sv[3u * n]);
}

// gf_udu_correct_v with its scratch on its own stack, an array per vector
// (n <= GF_UDU_NMAX), and no pre-test (sd NULL): for n <= 3 the search
// costs about what the test does, and sd would cost the frame 16 B.
GF_ALWAYS_INLINE gf_status gf_udu_correct(unsigned n, gf_real *ud,
                                          unsigned char *perm, unsigned m,
                                          const gf_real *hw, const gf_real *e,
                                          const gf_real *yw, gf_real *x,
                                          gf_real *nis)
{
    gf_real dp[GF_UDU_NMAX];
    // (set, for gcc's analyzer, which cannot follow hp and b through the
    // loops that write them; the stores are dead in an optimised build)
    gf_real hp[GF_UDU_NMAX] = {0}, b[GF_UDU_NMAX] = {0};
    return gf_udu_correct_v(n, ud, perm, m, hw, e, yw, x, nis, NULL, dp, hp, b);
}

#endif
