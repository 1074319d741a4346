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

// 1 if x is zero (either sign): l = 0 leaves a row of the elimination as
// it is (a_ik - 0 a_jk is a_ik, a_jk finite; an infinite a_jk or a NaN
// makes the matrix indefinite whichever way, and the verdict is the
// same).
static inline int ldl_is_zero(gf_real x)
{
    return x >= 0 && x <= 0;
}

// The factors' entries of state k, of zero variance: d_k = 0 and column
// k of F the unit vector (where F and d are not NULL).
GF_ALWAYS_INLINE void ldl_zero_state(unsigned n, unsigned k, gf_real *F,
                                     gf_real *d)
{
    if (d) {
        d[k] = 0;
    }
    if (F) {
        for (unsigned i = 0; i < n; i++) {
            F[i * n + k] = (i == k) ? GF_R(1.0) : GF_R(0.0);
        }
    }
}

gf_status gf_ldl_core(const gf_real *s, unsigned stride, unsigned n, gf_real *F,
                      gf_real *d, unsigned *order, gf_real *a, unsigned *p)
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
            if (ldl_is_zero(l)) {
                continue; // row i left as it is: a_ik - 0 a_jk is a_ik
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
        ldl_zero_state(n, k, F, d);
    }
    return GF_OK;
}

// s's entry (i, k) from its upper triangle.
static inline gf_real ldl_upper(const gf_real *s, unsigned stride, unsigned i,
                                unsigned k)
{
    return (i < k) ? s[i * stride + k] : s[k * stride + i];
}

// gf_ldl for n <= 3 with no scratch: gf_ldl_core's arithmetic, each step in
// the same order, on scalars. The states in p's order are slots 0, 1, 2
// (states sa, sb, sc): sa the first of positive variance (if any), the
// other two in gf_ldl_core's order after its first swap; the second pivot's
// choice swaps slots 1 and 2. vX is the variance of slot X, xX its Schur
// complement so far (slot 0's is va), x01, x02, x12 the entries between
// slots (upper triangle), lb, lc the first pivot's multipliers, lk the
// second's; t the pivots passed. Nothing beyond the leading n x n block of
// s is read.
typedef struct {
    unsigned sa, sb, sc, t;
    gf_real va, vb, vc, xb, xc, x01, x02, x12, lb, lc, lk;
} ldl3;

// The slots and their entries from s.
GF_ALWAYS_INLINE void ldl3_load(const gf_real *s, unsigned stride, unsigned n,
                                ldl3 *q)
{
    q->sa = 0;
    q->sb = 1;
    q->sc = 2;
    // gf_ldl_core's first pivot: the first state of positive variance
    const int first1 = !(s[0] > 0) && n > 1u && s[stride + 1u] > 0;
    if (first1) {
        q->sa = 1;
        q->sb = 0;
    }
    if (!(s[0] > 0) && !first1 && n > 2u && s[2u * stride + 2u] > 0) {
        q->sa = 2;
        q->sc = 0;
    }
    q->va = s[q->sa * stride + q->sa];
    q->vb = 0;
    q->vc = 0;
    q->x01 = 0;
    q->x02 = 0;
    q->x12 = 0;
    if (n > 1u) {
        q->vb = s[q->sb * stride + q->sb];
        q->x01 = ldl_upper(s, stride, q->sa, q->sb);
    }
    if (n > 2u) {
        q->vc = s[q->sc * stride + q->sc];
        q->x02 = ldl_upper(s, stride, q->sa, q->sc);
        q->x12 = ldl_upper(s, stride, q->sb, q->sc);
    }
    q->xb = q->vb;
    q->xc = q->vc;
    q->lb = 0;
    q->lc = 0;
    q->lk = 0;
    q->t = 0;
}

// Slot 0 the pivot (n >= 2): a_ik -= (a_i0 / a_00) a_0k, with the
// multiplier of the lower state of the pair, as in gf_ldl_core; a zero
// multiplier leaves its row.
GF_ALWAYS_INLINE void ldl3_first(unsigned n, ldl3 *q)
{
    q->lb = q->x01 / q->va;
    q->lc = q->x02 / q->va;
    if (!ldl_is_zero(q->lb)) {
        q->xb -= q->lb * q->x01;
        if (n > 2u && q->sc > q->sb) {
            q->x12 -= q->lb * q->x02;
        }
    }
    if (n > 2u && !ldl_is_zero(q->lc)) {
        if (q->sb > q->sc) {
            q->x12 -= q->lc * q->x01;
        }
        q->xc -= q->lc * q->x02;
    }
}

// The second pivot (n = 3): the larger x / v of slots 1 and 2 (a tie keeps
// slot 1), into slot 1.
GF_ALWAYS_INLINE void ldl3_choose(ldl3 *q)
{
    const gf_real rb = (q->vb > 0) ? q->xb / q->vb : GF_R(0.0);
    const gf_real rc = (q->vc > 0) ? q->xc / q->vc : GF_R(0.0);
    const gf_real best = (rb > -1) ? rb : GF_R(-1.0);
    if (rc > best) {
        const unsigned su = q->sb;
        q->sb = q->sc;
        q->sc = su;
        gf_real r = q->vb;
        q->vb = q->vc;
        q->vc = r;
        r = q->xb;
        q->xb = q->xc;
        q->xc = r;
        r = q->lb;
        q->lb = q->lc;
        q->lc = r;
    }
}

// The elimination: the pivots passed into q->t.
GF_ALWAYS_INLINE void ldl3_eliminate(unsigned n, ldl3 *q)
{
    const gf_real rtol = GF_PD_RTOL;
    if (!(q->va > rtol * q->va)) { // (NaN fails)
        return;
    }
    q->t = 1;
    if (n < 2u) {
        return;
    }
    ldl3_first(n, q);
    if (n > 2u) {
        ldl3_choose(q);
    }
    if (!(q->xb > rtol * q->vb)) {
        return;
    }
    q->t = 2;
    if (n < 3u) {
        return;
    }
    q->lk = q->x12 / q->xb;
    if (!ldl_is_zero(q->lk)) {
        q->xc -= q->lk * q->x12;
    }
    if (q->xc > rtol * q->vc) {
        q->t = 3;
    }
}

// The pivots' columns of F (n x n, may be NULL) and their d (may be NULL),
// as gf_ldl_core writes them.
GF_ALWAYS_INLINE void ldl3_pivots(const ldl3 *q, unsigned n, gf_real *F,
                                  gf_real *d)
{
    if (d) {
        if (q->t > 0u) {
            d[q->sa] = q->va;
        }
        if (q->t > 1u) {
            d[q->sb] = q->xb;
        }
        if (q->t > 2u) {
            d[q->sc] = q->xc;
        }
    }
    if (!F) {
        return;
    }
    if (q->t > 0u) {
        F[q->sa * n + q->sa] = 1;
        if (n > 1u) {
            F[q->sb * n + q->sa] = q->lb;
        }
        if (n > 2u) {
            F[q->sc * n + q->sa] = q->lc;
        }
    }
    if (q->t > 1u) {
        F[q->sa * n + q->sb] = 0;
        F[q->sb * n + q->sb] = 1;
        if (n > 2u) {
            F[q->sc * n + q->sb] = q->lk;
        }
    }
    if (q->t > 2u) {
        F[q->sa * n + q->sc] = 0;
        F[q->sb * n + q->sc] = 0;
        F[q->sc * n + q->sc] = 1;
    }
}

// 1 if slot u (t <= u < n), a zero one, passes gf_ldl_core's checks: its
// Schur complement >= -GF_PD_RTOL times its variance, and each entry to a
// zero slot before it within the 2x2 bound, both sides widened by
// GF_PD_RTOL times their variance.
GF_ALWAYS_INLINE int ldl3_zero_ok(const ldl3 *q, unsigned u)
{
    const gf_real rtol = GF_PD_RTOL;
    const gf_real vk = (u == 0u) ? q->va : (u == 1u) ? q->vb : q->vc;
    const gf_real xk = (u == 0u) ? q->va : (u == 1u) ? q->xb : q->xc;
    if (!(xk >= -rtol * vk)) {
        return 0;
    }
    const gf_real zk = ((xk > 0) ? xk : GF_R(0.0)) + rtol * vk;
    if (u > 0u && q->t == 0u &&
        !gf_coupled_ok((u == 1u) ? q->x01 : q->x02,
                       ((q->va > 0) ? q->va : GF_R(0.0)) + rtol * q->va, zk)) {
        return 0;
    }
    return !(u == 2u && q->t < 2u &&
             !gf_coupled_ok(
                 q->x12, ((q->xb > 0) ? q->xb : GF_R(0.0)) + rtol * q->vb, zk));
}

gf_status gf_ldl_small(const gf_real *s, unsigned stride, unsigned n,
                       gf_real *F, gf_real *d, unsigned *order)
{
    if (n > 3u) {
        return GF_ERR_ARG;
    }
    if (n == 0) {
        return GF_OK;
    }
    ldl3 q;
    ldl3_load(s, stride, n, &q);
    ldl3_eliminate(n, &q);
    ldl3_pivots(&q, n, F, d);
    if (order) {
        order[0] = q.sa;
        if (n > 1u) {
            order[1] = q.sb;
        }
        if (n > 2u) {
            order[2] = q.sc;
        }
    }
    // The slots left (t..n-1, if any) have zero variance.
    for (unsigned u = q.t; u < n; u++) {
        if (!ldl3_zero_ok(&q, u)) {
            return GF_ERR_NOT_PSD;
        }
        const unsigned k = (u == 0u) ? q.sa : (u == 1u) ? q.sb : q.sc;
        ldl_zero_state(n, k, F, d);
    }
    return GF_OK;
}
