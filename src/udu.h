// SPDX-License-Identifier: MIT
// gaussfilt: the factored covariance of the Kalman filters, one
// implementation for any number of states n (docs/numerics.md).
//
// A belief carries Sigma = U D U^T: U unit upper triangular, D diagonal
// and >= 0. Every step works on the factors and never forms Sigma:
//   prediction  Sigma_bar = (A U) D (A U)^T + G Q_d G^T (R = G Q_d G^T),
//               triangularised again by Thornton's modified weighted
//               Gram-Schmidt: each d_j a weighted sum of squares;
//   correction  Bierman's scalar update, one whitened measured quantity at
//               a time: each d_j scaled by a ratio of innovation variances
//               alpha_(j-1) / alpha_j in [0, 1].
// No step can make a variance negative or Sigma asymmetric; the
// accessor (gf_udu_to_cov) returns Sigma exactly symmetric.
//
// Packed storage, n (n + 1) / 2 numbers, column by column: U_ij (i < j)
// at GF_UD(i, j), d_j at GF_UD(j, j).
//
// Matrices passed in are row-major, rows of `stride` entries. The
// functions are static inline: each filter's source compiles them for its
// own n (an optimising build unrolls the loops, a build for size keeps
// them); the arithmetic is written once, here.
#ifndef GAUSSFILT_SRC_UDU_H
#define GAUSSFILT_SRC_UDU_H

#include "gf_internal.h"

#define GF_UD(i, j) ((j) * ((j) + 1u) / 2u + (i))
#define GF_UD_SIZE(n) ((n) * ((n) + 1u) / 2u)

// The largest n these functions take (the size of their O(n) locals).
#define GF_UDU_NMAX 3u

// 1 if x^2 <= y z for y, z >= 0, without a product that could overflow
// or a square root: (x / y) x <= z, and for y = 0 only x = 0. The same
// answer for any power of two times x, y and z.
static inline int gf_coupled_ok(gf_real x, gf_real y, gf_real z)
{
    if (!(y > 0)) {
        return !(GF_FABS(x) > 0);
    }
    return (x / y) * x <= z;
}

// The verdict on a symmetric matrix s passed in (finite: the caller tests
// that), and its factors U D U^T into ud (packed; written even when the
// verdict is not GF_OK). Column j from the last: with t_k = d_k U_jk,
//   d_j  = s_jj - sum_(k>j) U_jk t_k,
//   U_ij = (s_ij - sum_(k>j) U_ik t_k) / d_j.
// GF_ERR_NOT_PSD if an off-diagonal pair differs by more than GF_SYM_RTOL
// (|s_ij| + |s_ji|), or a pivot d_j is below -GF_PD_RTOL s_jj. A pivot up
// to GF_PD_RTOL s_jj is zero (semidefinite in that direction): its column
// of U is zero, and every entry that couples it to a state i must then
// be within the 2x2 bound r_ij^2 <= r_ii d_j, both sides widened by
// GF_PD_RTOL times their variance (r: what is left of s once the later
// columns are taken out), else GF_ERR_NOT_PSD. Every test is relative to
// s's own diagonal: the correlation form, the same in any units.
GF_ALWAYS_INLINE gf_status gf_udu_factor(const gf_real *s, unsigned stride,
                                         unsigned n, gf_real *ud)
{
    const gf_real rtol = GF_PD_RTOL;
    // A diagonal matrix (the usual noise) is its own factorisation.
    gf_real off = 0;
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i + 1u; j < n; j++) {
            off += GF_FABS(s[i * stride + j]) + GF_FABS(s[j * stride + i]);
        }
    }
    if (!(off > 0)) {
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            const gf_real sjj = s[j * stride + j];
            if (sjj < 0) {
                return GF_ERR_NOT_PSD;
            }
            ud[GF_UD(j, j)] = sjj;
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                ud[GF_UD(i, j)] = 0;
            }
        }
        return GF_OK;
    }
    GF_UNROLL
    for (unsigned j = n; j-- > 0u;) {
        const gf_real sjj = s[j * stride + j];
        gf_real dj = sjj;
        GF_UNROLL
        for (unsigned k = j + 1u; k < n; k++) {
            dj -= ud[GF_UD(j, k)] * ud[GF_UD(k, k)] * ud[GF_UD(j, k)];
        }
        const int pos = dj > rtol * sjj;
        if (!pos && !(dj >= -rtol * sjj)) {
            return GF_ERR_NOT_PSD;
        }
        const gf_real inv = pos ? GF_R(1.0) / dj : GF_R(0.0);
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            const gf_real sij = s[i * stride + j], sji = s[j * stride + i];
            if (!(GF_FABS(sij - sji) <=
                  GF_SYM_RTOL * (GF_FABS(sij) + GF_FABS(sji)))) {
                return GF_ERR_NOT_PSD;
            }
            gf_real r = sij;
            GF_UNROLL
            for (unsigned k = j + 1u; k < n; k++) {
                r -= ud[GF_UD(i, k)] * ud[GF_UD(k, k)] * ud[GF_UD(j, k)];
            }
            if (!pos) {
                const gf_real sii = s[i * stride + i];
                gf_real rii = sii;
                GF_UNROLL
                for (unsigned k = j + 1u; k < n; k++) {
                    rii -= ud[GF_UD(i, k)] * ud[GF_UD(k, k)] *
                           ud[GF_UD(i, k)];
                }
                if (!gf_coupled_ok(r, (rii > 0 ? rii : GF_R(0.0)) + rtol * sii,
                                   (dj > 0 ? dj : GF_R(0.0)) + rtol * sjj)) {
                    return GF_ERR_NOT_PSD;
                }
            }
            ud[GF_UD(i, j)] = r * inv;
        }
        ud[GF_UD(j, j)] = pos ? dj : GF_R(0.0);
    }
    return GF_OK;
}

// Sigma = U D U^T into s (rows of stride), exactly symmetric:
//   Sigma_ij = sum_(k >= max(i, j)) U_ik d_k U_jk,  U_kk = 1,
// each variance a sum of non-negative terms.
static inline void gf_udu_to_cov(const gf_real *ud, unsigned n, gf_real *s,
                                 unsigned stride)
{
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned k = j; k < n; k++) {
                const gf_real uik = (k == i) ? GF_R(1.0) : ud[GF_UD(i, k)];
                const gf_real ujk = (k == j) ? GF_R(1.0) : ud[GF_UD(j, k)];
                acc += uik * ud[GF_UD(k, k)] * ujk;
            }
            s[i * stride + j] = acc;
            s[j * stride + i] = acc;
        }
    }
}

// The prediction's covariance (Thornton's time update), in place on ud:
//   Sigma_bar = W diag(w_d) W^T,  W = [A U | G],  w_d = [D | Q_d],
// with R = G Q_d G^T given by its factors rf (packed), then U_bar D_bar U_bar^T = W diag(w_d) W^T by
// the modified weighted Gram-Schmidt, from the last row up:
//   c = diag(w_d) w_j,  d_j = w_j . c,
//   U_ij = (w_i . c) / d_j,  w_i -= U_ij w_j   (i < j).
// A d_j below GF_REAL_MIN (every term zero, or too few digits to tell it
// from zero) is zero, with a zero column of U: that state is known exactly
// once the later ones are. a: n x n, rows of n. w: scratch of n rows of
// 2n, wd: scratch of 2n (caller-owned).
static inline void gf_udu_predict(unsigned n, gf_real *ud, const gf_real *a,
                                  const gf_real *rf, gf_real *w,
                                  gf_real *wd)
{
    const unsigned cols2 = 2u * n;
    // W = [A U | G]: (A U)_ij = A_ij + sum_(l<j) A_il U_lj
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        wd[j] = ud[GF_UD(j, j)];
        GF_UNROLL
        for (unsigned i = 0; i < n; i++) {
            gf_real acc = a[i * n + j];
            GF_UNROLL
            for (unsigned l = 0; l < j; l++) {
                acc += a[i * n + l] * ud[GF_UD(l, j)];
            }
            w[i * cols2 + j] = acc;
        }
    }
    // G: the unit upper triangular factor of R, weights Q_d (zero
    // weights included: every row has 2n entries)
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        wd[n + j] = rf[GF_UD(j, j)];
        GF_UNROLL
        for (unsigned i = 0; i < n; i++) {
            w[i * cols2 + n + j] = (i < j)    ? rf[GF_UD(i, j)]
                                   : (i == j) ? GF_R(1.0)
                                              : GF_R(0.0);
        }
    }
    // Modified weighted Gram-Schmidt, rows n-1 .. 0
    GF_UNROLL
    for (unsigned j = n; j-- > 0u;) {
        gf_real c[2u * GF_UDU_NMAX];
        gf_real *wj = &w[j * cols2];
        gf_real dj = 0;
        GF_UNROLL
        for (unsigned k = 0; k < cols2; k++) {
            c[k] = wd[k] * wj[k];
            dj += wj[k] * c[k];
        }
        if (!(dj >= GF_REAL_MIN)) {
            dj = 0;
        }
        const gf_real inv = (dj > 0) ? GF_R(1.0) / dj : GF_R(0.0);
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            gf_real *wi = &w[i * cols2];
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned k = 0; k < cols2; k++) {
                acc += wi[k] * c[k];
            }
            const gf_real uij = acc * inv;
            GF_UNROLL
            for (unsigned k = 0; k < cols2; k++) {
                wi[k] -= uij * wj[k];
            }
            ud[GF_UD(i, j)] = uij;
        }
        ud[GF_UD(j, j)] = dj;
    }
}

// One scalar correction (Bierman's update), in place on ud, for the
// measured quantity z = h x + v, v ~ N(0, r), r >= 0, whose innovation at
// the current mean is y: with f = U^T h, g = D f and alpha_(-1) = r,
//   alpha_j = alpha_(j-1) + f_j g_j,
//   d_j    <- d_j alpha_(j-1) / alpha_j,
//   U_ij   <- U_ij - b_i f_j / alpha_(j-1),  b_i <- b_i + U_ij g_j (i < j),
//   b_j    =  g_j,
// then K = b / alpha_(n-1), alpha_(n-1) = h Sigma h^T + r = s:
//   dx += K y,  *nis += y^2 / s.
// A zero alpha (an exact quantity, r = 0, on the states taken so far)
// leaves U as it is (b is zero there) and d_j as it is while alpha stays
// zero; the first d_j to make it positive becomes zero: that direction
// is now known exactly. A d_j below GF_REAL_MIN becomes zero, with its
// column of U. GF_ERR_NONFINITE if s overflows; GF_ERR_SINGULAR if r = 0
// and s is zero relative to its terms before cancellation,
// sum_j d_j (|h_j| + sum_(i<j) |U_ij h_i|)^2 (the same in any units);
// ud and dx are partly written then.
static inline gf_status gf_udu_update(unsigned n, gf_real *ud,
                                      const gf_real *h, gf_real r,
                                      gf_real y, gf_real *dx, gf_real *nis)
{
    gf_real f[GF_UDU_NMAX], b[GF_UDU_NMAX];
    // f = U^T h
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        gf_real acc = h[j];
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            acc += ud[GF_UD(i, j)] * h[i];
        }
        f[j] = acc;
    }
    // An exact quantity's scale: h Sigma h^T without its cancellations
    gf_real scale = 0;
    if (!(r > 0)) {
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            gf_real t = GF_FABS(h[j]);
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                t += GF_FABS(ud[GF_UD(i, j)] * h[i]);
            }
            scale += ud[GF_UD(j, j)] * t * t;
        }
    }
    gf_real alpha = r, inv_prev = 0;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        const gf_real d = ud[GF_UD(j, j)];
        const gf_real fj = f[j], gj = d * fj;
        const gf_real a1 = alpha + fj * gj;
        gf_real inv = 0;
        if (a1 > 0) {
            inv = GF_R(1.0) / a1;
            ud[GF_UD(j, j)] = d * alpha * inv;
        }
        const gf_real p = -fj * inv_prev;
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            const gf_real uij = ud[GF_UD(i, j)];
            ud[GF_UD(i, j)] = uij + b[i] * p;
            b[i] += uij * gj;
        }
        b[j] = gj;
        alpha = a1;
        inv_prev = inv;
    }
    if (!GF_ISFINITE(alpha)) {
        return GF_ERR_NONFINITE;
    }
    if (!(r > 0) && !(alpha > GF_PD_RTOL * (gf_real)n * scale)) {
        return GF_ERR_SINGULAR;
    }
    const gf_real k = y * inv_prev; // y / s
    *nis += y * k;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        dx[j] += b[j] * k;
        if (!(ud[GF_UD(j, j)] >= GF_REAL_MIN)) {
            ud[GF_UD(j, j)] = 0;
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                ud[GF_UD(i, j)] = 0;
            }
        }
    }
    return GF_OK;
}

// The whitening of m measured quantities whose noise is Q = V E V^T (qf,
// packed; V unit upper triangular): x <- V^-1 x in place, x of m entries
// spaced `step` apart, by back substitution (no division):
//   x_i <- x_i - sum_(k>i) V_ik x_k,  i = m-1 .. 0.
// The quantities V^-1 z then have independent noises E.
static inline void gf_udu_whiten(const gf_real *qf, unsigned m, gf_real *x,
                                 unsigned step)
{
    for (unsigned i = m; i-- > 0u;) {
        for (unsigned k = i + 1u; k < m; k++) {
            x[i * step] -= qf[GF_UD(i, k)] * x[k * step];
        }
    }
}

// The correction with m whitened quantities (rows of hw, stride n; their
// noises on qf's diagonal; yw their whitened innovations at mu_bar), one
// after another, each innovation taken at the mean the earlier ones gave:
//   y_i = yw_i - hw_i . dx,  then gf_udu_update.
// dx (n entries) receives mu - mu_bar, *nis the sum of the scalar NIS,
// which is y^T S^-1 y. Statuses as gf_udu_update.
static inline gf_status gf_udu_correct(unsigned n, gf_real *ud, unsigned m,
                                       const gf_real *hw, const gf_real *qf,
                                       const gf_real *yw, gf_real *dx,
                                       gf_real *nis)
{
    *nis = 0;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        dx[j] = 0;
    }
    for (unsigned i = 0; i < m; i++) {
        const gf_real *hi = &hw[i * n];
        gf_real yi = yw[i];
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            yi -= hi[j] * dx[j];
        }
        const gf_status st =
            gf_udu_update(n, ud, hi, qf[GF_UD(i, i)], yi, dx, nis);
        if (st != GF_OK) {
            return st;
        }
    }
    return GF_OK;
}

#endif
