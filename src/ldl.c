// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "ldl.h"

// 1 if x^2 <= y z for y, z >= 0, without a product that could overflow
// or a square root: (x / y) x <= z, and for y = 0 only x = 0. The same
// answer for any power of two times x, y and z.
static int ldl_coupled_ok(gf_real x, gf_real y, gf_real z)
{
    if (!(y > 0)) {
        return !(GF_FABS(x) > 0);
    }
    return (x / y) * x <= z;
}

// 1 if the state p[u], one of the zero ones left (p[t..n-1]), is coupled
// to each zero one before it, p[w] (t <= w < u), within the 2x2 bound
// a_ik^2 <= a_ii a_kk, both sides widened by GF_PD_RTOL times their
// variance.
static int ldl_zero_coupled(const gf_real *s, unsigned stride, unsigned n,
                            const gf_real *a, const unsigned *p, unsigned t,
                            unsigned u)
{
    const gf_real rtol = GF_PD_RTOL;
    const unsigned k = p[u];
    const gf_real akk = a[k * n + k] > 0 ? a[k * n + k] : GF_R(0.0);
    for (unsigned w = t; w < u; w++) {
        const unsigned i = p[w];
        const gf_real aii = a[i * n + i] > 0 ? a[i * n + i] : GF_R(0.0);
        const gf_real aik = (i < k) ? a[i * n + k] : a[k * n + i];
        if (!ldl_coupled_ok(aik, aii + rtol * s[i * stride + i],
                            akk + rtol * s[k * stride + k])) {
            return 0;
        }
    }
    return 1;
}

// The pivoted LDL^T of gf_cov_factor (s checked finite and symmetric):
// a holds the Schur complements (upper triangle, by state, rows of n),
// p[t..n-1] the states not pivots yet.
static gf_status ldl_factor(const gf_real *s, unsigned stride, unsigned n,
                            gf_real *F, gf_real *d, unsigned *order,
                            gf_real *a, unsigned *p)
{
    const gf_real rtol = GF_PD_RTOL;
    for (unsigned i = 0; i < n; i++) {
        p[i] = i;
        for (unsigned k = i; k < n; k++) {
            a[i * n + k] = s[i * stride + k];
        }
    }
    // The first pivot: all ratios are 1 there (0 for a zero variance):
    // the first state whose variance is positive.
    unsigned f0 = n;
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
                const gf_real ratio =
                    (skk > 0) ? a[k * n + k] / skk : GF_R(0.0);
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
        const gf_real pj = a[j * n + j];
        if (!(pj > rtol * s[j * stride + j])) { // (NaN fails)
            break; // this one and every state left are zero: below
        }
        if (d) {
            d[j] = pj;
        }
        if (F) {
            for (unsigned u = 0; u < t; u++) {
                F[p[u] * n + j] = 0;
            }
            F[j * n + j] = 1;
        }
        // a_ik -= (a_ij / a_jj) a_jk over the states left, upper triangle
        for (unsigned u = t + 1u; u < n; u++) {
            const unsigned i = p[u];
            const gf_real aij = (i < j) ? a[i * n + j] : a[j * n + i];
            const gf_real l = aij / pj;
            if (F) {
                F[i * n + j] = l;
            }
            if (l >= 0 && l <= 0) {
                continue; // l = 0 leaves row i as it is
            }
            for (unsigned v = t + 1u; v < n; v++) {
                const unsigned k = p[v];
                if (k >= i) {
                    a[i * n + k] -= l * ((k < j) ? a[k * n + j] : a[j * n + k]);
                }
            }
        }
    }
    if (order) {
        for (unsigned u = 0; u < n; u++) {
            order[u] = p[u];
        }
    }
    // The states left (p[t..n-1], if any) have zero variance: d_k = 0 and
    // column k of F the unit vector.
    for (unsigned u = t; u < n; u++) {
        const unsigned k = p[u];
        if (!(a[k * n + k] >= -rtol * s[k * stride + k]) ||
            !ldl_zero_coupled(s, stride, n, a, p, t, u)) {
            return GF_ERR_NOT_PSD;
        }
        if (d) {
            d[k] = 0;
        }
        if (F) {
            for (unsigned i = 0; i < n; i++) {
                F[i * n + k] = (i == k) ? GF_R(1.0) : GF_R(0.0);
            }
        }
    }
    return GF_OK;
}

gf_status gf_cov_factor(const gf_real *s, unsigned stride, unsigned n,
                        gf_real *F, gf_real *d, unsigned *order, gf_real *a,
                        unsigned *p)
{
    // Every entry finite (gf_nan_sum), then symmetric, variances >= 0.
    gf_real z = 0;
    for (unsigned i = 0; i < n; i++) {
        z = gf_nan_sum(z, &s[i * stride], n);
    }
    if (!gf_sum_finite(z)) {
        return GF_ERR_NONFINITE;
    }
    gf_real off = 0; // the sum of |off-diagonal entries|
    for (unsigned i = 0; i < n; i++) {
        if (s[i * stride + i] < 0) {
            return GF_ERR_NOT_PSD;
        }
        for (unsigned j = i + 1u; j < n; j++) {
            const gf_real x = s[i * stride + j], y = s[j * stride + i];
            if (!(GF_FABS(x - y) <= GF_SYM_RTOL * (GF_FABS(x) + GF_FABS(y)))) {
                return GF_ERR_NOT_PSD;
            }
            off += GF_FABS(x) + GF_FABS(y);
        }
    }
    if (off > 0) {
        return ldl_factor(s, stride, n, F, d, order, a, p);
    }
    // diagonal: F = I, d = the variances
    for (unsigned i = 0; F != NULL && i < n; i++) {
        d[i] = s[i * stride + i];
        order[i] = i;
        for (unsigned j = 0; j < n; j++) {
            F[i * n + j] = (i == j) ? GF_R(1.0) : GF_R(0.0);
        }
    }
    return GF_OK;
}
