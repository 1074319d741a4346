// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "ldl.h"

// ---- the verdict and the factors of a covariance passed in ------------

// 1 if the state p[u], one of the zero ones left (p[t..n-1]), is coupled to
// each zero one before it, p[w] (t <= w < u), within the 2x2 bound
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
        if (!gf_coupled_ok(aik, aii + rtol * s[i * stride + i],
                           akk + rtol * s[k * stride + k])) {
            return 0;
        }
    }
    return 1;
}

// gf_ldl with its scratch given.
static gf_status ldl_core(const gf_real *s, unsigned stride, unsigned n,
                          gf_real *F, gf_real *d, unsigned *order, gf_real *a,
                          unsigned *p)
{
    const gf_real rtol = GF_PD_RTOL;
    // a: the Schur complements (upper triangle, by state, rows of n);
    // p[t..n-1]: the states not pivots yet
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
    // The states left (p[t..n-1], if any) have zero variance.
    for (unsigned u = t; u < n; u++) {
        const unsigned k = p[u];
        const gf_real skk = s[k * stride + k];
        if (!(a[k * n + k] >= -rtol * skk)) {
            return GF_ERR_NOT_PSD;
        }
        if (!ldl_zero_coupled(s, stride, n, a, p, t, u)) {
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

gf_status gf_ldl(const gf_real *s, unsigned stride, unsigned n, gf_real *F,
                 gf_real *d, unsigned *order, gf_real *a, unsigned *p)
{
    if (a && p) {
        return ldl_core(s, stride, n, F, d, order, a, p);
    }
    if (n > 3u) {
        return GF_ERR_ARG;
    }
    gf_real a3[3 * 3]; // n <= 3: the scratch is here
    unsigned p3[3];
    return ldl_core(s, stride, n, F, d, order, a3, p3);
}
