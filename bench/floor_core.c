// SPDX-License-Identifier: MIT
// The loop floor: the least code that keeps KF2's, EKF3's and gf_kf's
// promises, in the core's loop style (one implementation for any n, n
// known only at run time), to show what a step and its flash cost at the
// least. Bench only, never linked by a filter.
//
// What it keeps of the API: every input checked finite, R and the prior
// judged positive semidefinite (a zero pivot allowed, scale-free
// tolerances), the belief factored U D U^T, Thornton's prediction and
// Bierman's update on the factors, m measured quantities one after
// another, the control input, the singular verdict of an exact quantity,
// the gate, and a failed call leaving the belief as it was.
// What it leaves out, against src/: the symmetry test, the pivoting of the
// verdict (a zero pivot judged by the 2 x 2 bound alone), the compensated
// factorisation of a prior, the move of a measured state to the root, the
// Joseph form for exact quantities, and correlated measurement noise (Q
// must be diagonal: its quantities are taken one at a time, unwhitened).
// fl_whiten, fl_hsh and fl_correct_exact serve the floor of the update
// with what the API must also hold (floor.c's *_update_api): a full Q
// whitened, the Joseph form for exact quantities, and their verdict on the
// update's prior.
#include <stddef.h>

#include "floor.h"

int fl_finite(const gf_real *x, unsigned n)
{
    gf_real z = 0;
    for (unsigned i = 0; i < n; i++) {
        z += x[i] * GF_R(0.0);
    }
    return z == 0;
}

// The verdict on s (n x n, rows of n) and its factors U D U^T (packed):
// d_j = s_jj - sum_(k>j) U_jk^2 d_k, U_ij = (s_ij - sum_(k>j) U_ik d_k U_jk)
// / d_j; a pivot up to GF_PD_RTOL s_jj is zero, and its column must be
// within the 2 x 2 bound.
gf_status fl_factor(const gf_real *s, unsigned n, gf_real *ud)
{
    if (!fl_finite(s, n * n)) {
        return GF_ERR_NONFINITE;
    }
    for (unsigned j = n; j-- > 0u;) {
        gf_real d = s[j * n + j];
        for (unsigned k = j + 1u; k < n; k++) {
            d -= ud[FL_UD(j, k)] * ud[FL_UD(j, k)] * ud[FL_UD(k, k)];
        }
        const gf_real tol = GF_PD_RTOL * s[j * n + j];
        if (d < -tol) {
            return GF_ERR_NOT_PSD;
        }
        for (unsigned i = 0; i < j; i++) {
            gf_real r = s[i * n + j];
            for (unsigned k = j + 1u; k < n; k++) {
                r -= ud[FL_UD(i, k)] * ud[FL_UD(k, k)] * ud[FL_UD(j, k)];
            }
            if (d > tol) {
                ud[FL_UD(i, j)] = r / d;
            } else if (r * r > tol * GF_PD_RTOL * s[i * n + i]) {
                return GF_ERR_NOT_PSD;
            } else {
                ud[FL_UD(i, j)] = 0;
            }
        }
        ud[FL_UD(j, j)] = (d > tol) ? d : GF_R(0.0);
    }
    return GF_OK;
}

// 1 if mu and every factor are finite.
int fl_belief_finite(const gf_real *mu, const gf_real *ud, unsigned n)
{
    return fl_finite(mu, n) && fl_finite(ud, n * (n + 1u) / 2u);
}

// Thornton: the factors of W diag(wd) W^T, W = [A U | U_R] (n rows of 2n),
// by the modified weighted Gram-Schmidt, from the last row up.
void fl_predict(unsigned n, const gf_real *ud, const gf_real *A,
                const gf_real *rud, gf_real *out, gf_real *w)
{
    const unsigned cols = 2u * n;
    gf_real *wd = &w[n * cols], *c = &wd[cols];
    for (unsigned j = 0; j < n; j++) {
        wd[j] = ud[FL_UD(j, j)];
        wd[n + j] = rud[FL_UD(j, j)];
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            gf_real acc = A[i * n + j];
            for (unsigned l = 0; l < j; l++) {
                acc += A[i * n + l] * ud[FL_UD(l, j)];
            }
            w[i * cols + j] = acc;
            w[i * cols + n + j] = (i == j)  ? GF_R(1.0)
                                  : (i < j) ? rud[FL_UD(i, j)]
                                            : GF_R(0.0);
        }
    }
    for (unsigned j = n; j-- > 0u;) {
        const gf_real *wj = &w[j * cols];
        gf_real dj = 0;
        for (unsigned k = 0; k < cols; k++) {
            c[k] = wd[k] * wj[k];
            dj += wj[k] * c[k];
        }
        const gf_real inv = (dj > 0) ? GF_R(1.0) / dj : GF_R(0.0);
        for (unsigned i = 0; i < j; i++) {
            gf_real *wi = &w[i * cols];
            gf_real acc = 0;
            for (unsigned k = 0; k < cols; k++) {
                acc += wi[k] * c[k];
            }
            const gf_real uij = acc * inv;
            for (unsigned k = 0; k < cols; k++) {
                wi[k] -= uij * wj[k];
            }
            out[FL_UD(i, j)] = uij;
        }
        out[FL_UD(j, j)] = dj;
    }
}

// Bierman: one scalar quantity h x + v, v ~ N(0, r), innovation y, in
// place on ud and mu; GF_ERR_SINGULAR for an exact one of zero variance.
gf_status fl_correct(unsigned n, gf_real *ud, gf_real *mu, const gf_real *h,
                     gf_real r, gf_real y, gf_real *nis, gf_real *b)
{
    gf_real alpha = r, inv_prev = 0;
    for (unsigned j = 0; j < n; j++) {
        gf_real fj = h[j];
        for (unsigned i = 0; i < j; i++) {
            fj += ud[FL_UD(i, j)] * h[i];
        }
        const gf_real d = ud[FL_UD(j, j)], gj = d * fj, a1 = alpha + fj * gj;
        gf_real inv = 0;
        if (a1 > 0) {
            inv = GF_R(1.0) / a1;
            ud[FL_UD(j, j)] = d * (alpha * inv);
        }
        for (unsigned i = 0; i < j; i++) {
            const gf_real uij = ud[FL_UD(i, j)];
            ud[FL_UD(i, j)] = uij - b[i] * fj * inv_prev;
            b[i] += uij * gj;
        }
        b[j] = gj;
        alpha = a1;
        inv_prev = inv;
    }
    if (!(alpha > 0)) {
        return GF_ERR_SINGULAR;
    }
    const gf_real k = y * inv_prev;
    *nis = y * k;
    for (unsigned j = 0; j < n; j++) {
        mu[j] += b[j] * k;
    }
    return GF_OK;
}

void fl_to_cov(const gf_real *ud, unsigned n, gf_real *s)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            for (unsigned k = j; k < n; k++) {
                const gf_real uik = (k == i) ? GF_R(1.0) : ud[FL_UD(i, k)];
                const gf_real ujk = (k == j) ? GF_R(1.0) : ud[FL_UD(j, k)];
                acc += uik * ud[FL_UD(k, k)] * ujk;
            }
            s[i * n + j] = acc;
            s[j * n + i] = acc;
        }
    }
}

gf_status fl_noise_diag(const gf_real *Q, unsigned stride, unsigned m,
                        gf_real *q)
{
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < m; j++) {
            const gf_real x = Q[i * stride + j];
            if (i == j ? x < 0 : !(x == 0)) {
                return GF_ERR_NOT_PSD;
            }
        }
        q[i] = Q[i * stride + i];
    }
    return GF_OK;
}

gf_status fl_correct_m(unsigned n, unsigned m, gf_real *ud, gf_real *mu,
                       const gf_real *H, const gf_real *q, const gf_real *y,
                       gf_real *nis, gf_real *b)
{
    gf_real *dx = &b[n], total = 0;
    for (unsigned j = 0; j < n; j++) {
        dx[j] = 0;
    }
    for (unsigned i = 0; i < m; i++) {
        const gf_real *h = &H[i * n];
        gf_real yi = y[i], part;
        for (unsigned j = 0; j < n; j++) {
            yi -= h[j] * dx[j];
        }
        const gf_status st = fl_correct(n, ud, dx, h, q[i], yi, &part, b);
        if (st != GF_OK) {
            return st;
        }
        total += part;
    }
    for (unsigned j = 0; j < n; j++) {
        mu[j] += dx[j];
    }
    *nis = total;
    return GF_OK;
}

// x <- U^-1 x for m quantities whose noise is Q = U D U^T (fl_factor's
// packed factors), x m rows of cols, by back substitution:
//   x_i <- x_i - sum_(k>i) U_ik x_k;
// the rows then have independent noises d_i.
void fl_whiten(const gf_real *qud, unsigned m, gf_real *x, unsigned cols)
{
    for (unsigned i = m; i-- > 0u;) {
        for (unsigned k = i + 1u; k < m; k++) {
            for (unsigned c = 0; c < cols; c++) {
                x[i * cols + c] -= qud[FL_UD(i, k)] * x[k * cols + c];
            }
        }
    }
}

gf_real fl_hsh(unsigned n, const gf_real *ud, const gf_real *h)
{
    gf_real s = 0;
    for (unsigned j = 0; j < n; j++) {
        gf_real fj = h[j];
        for (unsigned i = 0; i < j; i++) {
            fj += ud[FL_UD(i, j)] * h[i];
        }
        s += fj * (ud[FL_UD(j, j)] * fj);
    }
    return s;
}

// An exact quantity (r = 0) in the Joseph form on the factors, as
// src/udu.c's: f = U^T h, s = f^T D f, b = U D f, K = b / s,
//   Sigma+ = W D W^T,  W = U - K f^T,
// triangularised by the modified weighted Gram-Schmidt; mu += K y.
// GF_ERR_SINGULAR unless s > GF_PD_RTOL sii (sii: its h Sigma h^T on the
// update's prior after an earlier exact quantity, else 0). x: scratch of
// n^2 + 2n.
gf_status fl_correct_exact(unsigned n, gf_real *ud, gf_real *mu,
                           const gf_real *h, gf_real sii, gf_real y,
                           gf_real *nis, gf_real *x)
{
    gf_real *w = x, *wd = &x[n * n], *f = &wd[n];
    gf_real s = 0;
    for (unsigned j = 0; j < n; j++) {
        gf_real fj = h[j];
        for (unsigned i = 0; i < j; i++) {
            fj += ud[FL_UD(i, j)] * h[i];
        }
        wd[j] = ud[FL_UD(j, j)];
        f[j] = fj;
        s += fj * (wd[j] * fj);
    }
    if (!(s > GF_PD_RTOL * sii) || !(s > 0)) {
        return GF_ERR_SINGULAR;
    }
    const gf_real inv = GF_R(1.0) / s, k = y * inv;
    *nis = y * k;
    for (unsigned i = 0; i < n; i++) {
        gf_real acc = wd[i] * f[i];
        for (unsigned j = i + 1u; j < n; j++) {
            acc += ud[FL_UD(i, j)] * (wd[j] * f[j]);
        }
        mu[i] += acc * k;
        for (unsigned j = 0; j < n; j++) {
            const gf_real uij = (j > i)    ? ud[FL_UD(i, j)]
                                : (j == i) ? GF_R(1.0)
                                           : GF_R(0.0);
            w[i * n + j] = uij - acc * inv * f[j];
        }
    }
    // f is free now: the Gram-Schmidt's c (written out here as in
    // fl_predict: one out of line made the floor's steps 44 B deeper)
    for (unsigned j = n; j-- > 0u;) {
        const gf_real *wj = &w[j * n];
        gf_real dj = 0;
        for (unsigned c = 0; c < n; c++) {
            f[c] = wd[c] * wj[c];
            dj += wj[c] * f[c];
        }
        const gf_real dinv = (dj > 0) ? GF_R(1.0) / dj : GF_R(0.0);
        for (unsigned i = 0; i < j; i++) {
            gf_real *wi = &w[i * n];
            gf_real acc = 0;
            for (unsigned c = 0; c < n; c++) {
                acc += wi[c] * f[c];
            }
            const gf_real uij = acc * dinv;
            for (unsigned c = 0; c < n; c++) {
                wi[c] -= uij * wj[c];
            }
            ud[FL_UD(i, j)] = uij;
        }
        ud[FL_UD(j, j)] = dj;
    }
    return GF_OK;
}
