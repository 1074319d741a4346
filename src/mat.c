// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/mat.h"

#include "udu.h"

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

// The verdict on a covariance passed in (n x n block, rows of stride):
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (gf_cov_factor), else GF_OK.
static gf_status psd_check(const gf_real *s, unsigned stride, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        if (!gf_all_finite(&s[(size_t)i * stride], n)) {
            return GF_ERR_NONFINITE;
        }
    }
    return gf_cov_factor(s, stride, n, NULL, NULL, NULL);
}

// ---- 2x2 -----------------------------------------------------------------

gf_status gf_mat2_mul(const gf_mat2 *a, const gf_mat2 *b, gf_mat2 *out)
{
    if (!a || !b || !out) {
        return GF_ERR_ARG;
    }
    gf_mat2 r;
    r.m[0][0] = a->m[0][0] * b->m[0][0] + a->m[0][1] * b->m[1][0];
    r.m[0][1] = a->m[0][0] * b->m[0][1] + a->m[0][1] * b->m[1][1];
    r.m[1][0] = a->m[1][0] * b->m[0][0] + a->m[1][1] * b->m[1][0];
    r.m[1][1] = a->m[1][0] * b->m[0][1] + a->m[1][1] * b->m[1][1];
    *out = r;
    return GF_OK;
}

gf_status gf_mat2_mulv(const gf_mat2 *a, const gf_vec2 *x, gf_vec2 *out)
{
    if (!a || !x || !out) {
        return GF_ERR_ARG;
    }
    gf_vec2 r;
    r.v[0] = a->m[0][0] * x->v[0] + a->m[0][1] * x->v[1];
    r.v[1] = a->m[1][0] * x->v[0] + a->m[1][1] * x->v[1];
    *out = r;
    return GF_OK;
}

gf_status gf_mat2_sandwich(const gf_mat2 *a, const gf_mat2 *s, gf_mat2 *out)
{
    if (!a || !s || !out) {
        return GF_ERR_ARG;
    }
    // t = a s, then out = t a^T; only the upper triangle is computed.
    gf_mat2 t, r;
    (void)gf_mat2_mul(a, s, &t);
    r.m[0][0] = t.m[0][0] * a->m[0][0] + t.m[0][1] * a->m[0][1];
    r.m[0][1] = t.m[0][0] * a->m[1][0] + t.m[0][1] * a->m[1][1];
    r.m[1][1] = t.m[1][0] * a->m[1][0] + t.m[1][1] * a->m[1][1];
    r.m[1][0] = r.m[0][1];
    *out = r;
    return GF_OK;
}

gf_status gf_mat2_symmetrize(gf_mat2 *s)
{
    if (!s) {
        return GF_ERR_ARG;
    }
    gf_real o = GF_R(0.5) * s->m[0][1] + GF_R(0.5) * s->m[1][0];
    s->m[0][1] = o;
    s->m[1][0] = o;
    return GF_OK;
}

int gf_mat2_is_finite(const gf_mat2 *a)
{
    return a && gf_all_finite(a->m[0], 4);
}

gf_status gf_mat2_check_psd(const gf_mat2 *s)
{
    return s ? psd_check(s->m[0], 2, 2) : GF_ERR_ARG;
}

gf_status gf_mat2_spd_inv(const gf_mat2 *s, gf_mat2 *inv)
{
    if (!s || !inv) {
        return GF_ERR_ARG;
    }
    gf_real a = s->m[0][0];
    gf_real b = GF_R(0.5) * s->m[0][1] + GF_R(0.5) * s->m[1][0];
    gf_real c = s->m[1][1];
    if (!(GF_ISFINITE(a) && GF_ISFINITE(b) && GF_ISFINITE(c))) {
        return GF_ERR_NONFINITE;
    }
    // Positive definite iff a > 0, c > 0 and det > 0; det is tested
    // against the scale a c so that the verdict does not depend on units,
    // on the correlation form (r = b / sqrt(a c), det / (a c) = 1 - r^2),
    // so that nothing overflows for entries up to the largest gf_real.
    if (!(a > 0) || !(c > 0)) {
        return GF_ERR_SINGULAR;
    }
    gf_real sa = GF_SQRT(a), scc = GF_SQRT(c);
    gf_real rr = (b / sa) / scc;
    gf_real dn = GF_R(1.0) - rr * rr; // det / (a c)
    if (!(dn > GF_PD_RTOL)) {
        return GF_ERR_SINGULAR;
    }
    gf_real i00 = (GF_R(1.0) / a) / dn, i11 = (GF_R(1.0) / c) / dn;
    gf_real i01 = -((rr / sa) / scc) / dn;
    if (!GF_ISFINITE(i00) || !GF_ISFINITE(i11) || !GF_ISFINITE(i01)) {
        return GF_ERR_SINGULAR; // an inverse beyond the range of gf_real
    }
    gf_mat2 r;
    r.m[0][0] = i00;
    r.m[1][1] = i11;
    r.m[0][1] = i01;
    r.m[1][0] = i01;
    *inv = r;
    return GF_OK;
}

gf_status gf_mat2_eig_sym(const gf_mat2 *s, gf_vec2 *lambda, gf_real *angle)
{
    if (!s || !lambda || !angle) {
        return GF_ERR_ARG;
    }
    if (!gf_mat2_is_finite(s)) {
        return GF_ERR_NONFINITE;
    }
    gf_real a = s->m[0][0], c = s->m[1][1];
    gf_real b = GF_R(0.5) * s->m[0][1] + GF_R(0.5) * s->m[1][0];
    // Halves before sums and a scaled hypotenuse, so that entries near the
    // largest finite value do not overflow.
    gf_real mean = GF_R(0.5) * a + GF_R(0.5) * c;
    gf_real half = GF_R(0.5) * a - GF_R(0.5) * c;
    gf_real sc = GF_FABS(half) > GF_FABS(b) ? GF_FABS(half) : GF_FABS(b);
    gf_real d = 0;
    if (sc > 0) {
        gf_real hs = half / sc, bs = b / sc;
        d = sc * GF_SQRT(hs * hs + bs * bs);
    }
    gf_real l1 = mean + d;
    // The smaller eigenvalue from the determinant when that avoids
    // cancellation (l1 far from zero), else by difference; the
    // determinant divided through by l1 first, so it cannot overflow.
    gf_real l2 = (GF_FABS(l1) > GF_FABS(mean - d)) ? (a / l1) * c - (b / l1) * b
                                                   : mean - d;
    gf_real th = GF_R(0.5) * GF_ATAN2(b, half);
    if (th <= -GF_R(0.5) * GF_PI) {
        th += GF_PI;
    }
    if (!GF_ISFINITE(l1) || !GF_ISFINITE(l2)) {
        return GF_ERR_NONFINITE; // an eigenvalue beyond the largest float
    }
    lambda->v[0] = l1;
    lambda->v[1] = l2;
    *angle = th;
    return GF_OK;
}

// ---- 3x3 -----------------------------------------------------------------

gf_status gf_mat3_mul(const gf_mat3 *a, const gf_mat3 *b, gf_mat3 *out)
{
    if (!a || !b || !out) {
        return GF_ERR_ARG;
    }
    gf_mat3 r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] +
                        a->m[i][2] * b->m[2][j];
        }
    }
    *out = r;
    return GF_OK;
}

gf_status gf_mat3_mulv(const gf_mat3 *a, const gf_vec3 *x, gf_vec3 *out)
{
    if (!a || !x || !out) {
        return GF_ERR_ARG;
    }
    gf_vec3 r;
    for (int i = 0; i < 3; i++) {
        r.v[i] =
            a->m[i][0] * x->v[0] + a->m[i][1] * x->v[1] + a->m[i][2] * x->v[2];
    }
    *out = r;
    return GF_OK;
}

gf_status gf_mat3_sandwich(const gf_mat3 *a, const gf_mat3 *s, gf_mat3 *out)
{
    if (!a || !s || !out) {
        return GF_ERR_ARG;
    }
    // The upper triangle row by row (no 3x3 temporary for a s, no call),
    // then mirrored.
    gf_mat3 r;
    gf_sandwich_upper(a, s, &r);
    r.m[1][0] = r.m[0][1];
    r.m[2][0] = r.m[0][2];
    r.m[2][1] = r.m[1][2];
    *out = r;
    return GF_OK;
}

gf_status gf_mat3_symmetrize(gf_mat3 *s)
{
    if (!s) {
        return GF_ERR_ARG;
    }
    for (int i = 0; i < 3; i++) {
        for (int j = i + 1; j < 3; j++) {
            gf_real o = GF_R(0.5) * s->m[i][j] + GF_R(0.5) * s->m[j][i];
            s->m[i][j] = o;
            s->m[j][i] = o;
        }
    }
    return GF_OK;
}

int gf_mat3_is_finite(const gf_mat3 *a)
{
    return a && gf_all_finite(a->m[0], 9);
}

gf_status gf_mat3_check_psd(const gf_mat3 *s, unsigned n)
{
    if (!s || n < 1 || n > 3) {
        return GF_ERR_ARG;
    }
    return psd_check(s->m[0], 3, n);
}

gf_status gf_mat3_chol(const gf_mat3 *s, unsigned n, gf_mat3 *l)
{
    if (!s || !l || n < 1 || n > 3) {
        return GF_ERR_ARG;
    }
    gf_real p[6];
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j <= i; j++) {
            p[GF_TRI(i, j)] = s->m[i][j];
        }
    }
    gf_status st = gf_chol_packed(p, n);
    if (st != GF_OK) {
        return st;
    }
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < 3; j++) {
            l->m[i][j] = (i < n && j <= i) ? p[GF_TRI(i, j)] : GF_R(0.0);
        }
    }
    return GF_OK;
}

gf_status gf_mat3_chol_solve(const gf_mat3 *l, unsigned n, const gf_vec3 *b,
                             gf_vec3 *x)
{
    if (!l || !b || !x || n < 1 || n > 3) {
        return GF_ERR_ARG;
    }
    // l's lower triangle packed, then the packed solver (gf_internal.h)
    gf_real p[6] = {0, 0, 0, 0, 0, 0};
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j <= i; j++) {
            p[GF_TRI(i, j)] = l->m[i][j];
        }
    }
    gf_vec3 y = *b;
    gf_chol_solve_packed(p, n, y.v);
    *x = y;
    return GF_OK;
}

// ---- positive semidefinite square root -----------------------------------

gf_status gf_mat3_sqrt_psd(const gf_mat3 *s, unsigned n, gf_mat3 *l)
{
    if (!s || !l || n < 1 || n > 3) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(s, n);
    if (st != GF_OK) {
        return st;
    }
    // Cholesky-Banachiewicz on the symmetrized block; a pivot that is zero
    // within the tolerance leaves its column zero (the matrix has no spread
    // in that direction once the earlier ones are accounted for). Packed
    // by gf_sqrt_psd_packed (UKF3's and PF3's), then unpacked.
    // p is zero beyond the block, and l may be s: written only now.
    gf_real p[6];
    gf_sqrt_psd_packed(s, n, p);
    for (unsigned i = 0; i < 3u; i++) {
        for (unsigned j = 0; j < 3u; j++) {
            l->m[i][j] = (j <= i) ? p[GF_TRI(i, j)] : GF_R(0.0);
        }
    }
    return GF_OK;
}
