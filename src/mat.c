// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/mat.h"

#include "gf_internal.h"
#include "ldl.h"

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
    if (!s) {
        return GF_ERR_ARG;
    }
    gf_real F[4], d[2];
    unsigned order[2];
    return gf_cov_factor(s->m[0], 2, 2, F, d, order);
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
    gf_real th = GF_R(0.5) * gf_atan2(b, half);
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
    gf_real F[9], d[3];
    unsigned order[3];
    return gf_cov_factor(s->m[0], 3, n, F, d, order);
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
