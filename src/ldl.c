// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "ldl.h"

#include "gf_internal.h"

// 1 if the state k, one of the zero ones left, is coupled to each zero one
// before it (p[t..] up to k) within the 2x2 bound a_ik^2 <= a_ii a_kk, both
// sides widened by GF_PD_RTOL times their variance: (a_ik / a_ii) a_ik <=
// a_kk, with no product that could overflow, and for a_ii = 0 only
// a_ik = 0; the same answer for any power of two times s.
static int ldl_zero_coupled(const gf_real *s, unsigned stride, unsigned n,
                            const gf_real *a, const unsigned *p, unsigned t,
                            unsigned k)
{
    const gf_real akk = (a[k * n + k] > 0 ? a[k * n + k] : GF_R(0.0)) +
                        GF_PD_RTOL * s[k * stride + k];
    for (unsigned w = t; p[w] != k; w++) {
        const unsigned i = p[w];
        const gf_real aii = (a[i * n + i] > 0 ? a[i * n + i] : GF_R(0.0)) +
                            GF_PD_RTOL * s[i * stride + i];
        const gf_real aik = a[i * n + k];
        if (!(aii > 0) ? GF_FABS(aik) > 0 : !((aik / aii) * aik <= akk)) {
            return 0;
        }
    }
    return 1;
}

gf_status gf_cov_factor(const gf_real *s, unsigned stride, unsigned n,
                        gf_real *F, gf_real *d, unsigned *order)
{
    // Every entry finite (gf_nan_sum), then symmetric, variances >= 0.
    gf_real z = 0;
    for (unsigned i = 0; i < n; i++) {
        z = gf_nan_sum(z, &s[(size_t)i * stride], n);
    }
    if (!gf_sum_finite(z)) {
        return GF_ERR_NONFINITE;
    }
    int diagonal = 1;
    for (unsigned i = 0; i < n; i++) {
        if (s[i * stride + i] < 0) {
            return GF_ERR_NOT_PSD;
        }
        for (unsigned j = i + 1u; j < n; j++) {
            const gf_real x = s[i * stride + j], y = s[j * stride + i];
            if (!(GF_FABS(x - y) <= GF_SYM_RTOL * (GF_FABS(x) + GF_FABS(y)))) {
                return GF_ERR_NOT_PSD;
            }
            diagonal = diagonal && !(GF_FABS(x) + GF_FABS(y) > 0);
        }
    }
    if (diagonal) { // its own factorisation: F = I, d the variances
        for (unsigned i = 0; i < n; i++) {
            d[i] = s[i * stride + i];
            order[i] = i;
            for (unsigned j = 0; j < n; j++) {
                F[i * n + j] = (i == j) ? GF_R(1.0) : GF_R(0.0);
            }
        }
        return GF_OK;
    }
    // The pivoted LDL^T, in F: a column of F holds the Schur complements
    // a_ik of the states not pivots yet (kept symmetric: each entry computed
    // once, from the upper triangle, and mirrored) until its state is a
    // pivot, then its column of F. order[t..n-1]: the states not pivots yet.
    gf_real *a = F;
    unsigned *p = order;
    for (unsigned i = 0; i < n; i++) {
        p[i] = i;
        for (unsigned k = 0; k < n; k++) {
            a[i * n + k] = (i < k) ? s[i * stride + k] : s[k * stride + i];
        }
    }
    unsigned t = 0;
    for (; t < n; t++) {
        // the pivot: the largest a_jj / s_jj left, in [0, 1] (a tie keeps
        // p's order, so the search ends at a ratio of 1: a state untouched
        // so far, a_jj = s_jj; at t = 0, the first of positive variance)
        gf_real best = -1;
        unsigned at = t;
        int whole = 0; // a ratio of 1 found
        for (unsigned u = t; u < n && t + 1u < n && !whole; u++) {
            const unsigned k = p[u];
            const gf_real skk = s[k * stride + k];
            gf_real ratio = (skk > 0) ? GF_R(1.0) : GF_R(0.0);
            if (skk > 0 && a[k * n + k] < skk) {
                ratio = a[k * n + k] / skk;
            }
            if (ratio > best) {
                best = ratio;
                at = u;
                whole = !(ratio < 1);
            }
        }
        const unsigned j = p[at];
        p[at] = p[t];
        p[t] = j;
        const gf_real pj = a[j * n + j];
        if (!(pj > GF_PD_RTOL * s[j * stride + j])) { // (NaN fails)
            break; // this one and every state left are zero: below
        }
        d[j] = pj;
        // a_ik -= (a_ij / a_jj) a_jk over the states left; l = a_ij / a_jj
        // is F_ij, in a_ij's place
        for (unsigned u = t + 1u; u < n; u++) {
            const unsigned i = p[u];
            const gf_real l = a[i * n + j] / pj;
            a[i * n + j] = l;
            for (unsigned v = t + 1u; v < n && !(l >= 0 && l <= 0); v++) {
                const unsigned k = p[v];
                if (k >= i) {
                    a[i * n + k] -= l * a[j * n + k];
                    a[k * n + i] = a[i * n + k];
                }
            }
        }
        // column j of F: 1 at j, 0 on the earlier pivots' rows
        for (unsigned u = 0; u <= t; u++) {
            F[p[u] * n + j] = (u == t) ? GF_R(1.0) : GF_R(0.0);
        }
    }
    // The states left (p[t..n-1], if any) have zero variance, each within
    // GF_PD_RTOL: then d_k = 0 and column k of F the unit vector.
    for (unsigned u = t; u < n; u++) {
        const unsigned k = p[u];
        if (!(a[k * n + k] >= -GF_PD_RTOL * s[k * stride + k]) ||
            !ldl_zero_coupled(s, stride, n, a, p, t, k)) {
            return GF_ERR_NOT_PSD;
        }
    }
    for (unsigned u = t; u < n; u++) {
        const unsigned k = p[u];
        d[k] = 0;
        for (unsigned i = 0; i < n; i++) {
            F[i * n + k] = (i == k) ? GF_R(1.0) : GF_R(0.0);
        }
    }
    return GF_OK;
}
