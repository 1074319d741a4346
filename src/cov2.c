// SPDX-License-Identifier: MIT
#include "gaussfilt/cov2.h"

#include "gf_internal.h"

gf_status gf_cov2_correlation(const gf_mat2 *s, gf_real *rho)
{
    if (!s || !rho) {
        return GF_ERR_ARG;
    }
    if (!gf_mat2_is_finite(s)) {
        return GF_ERR_NONFINITE;
    }
    gf_real a = s->m[0][0], c = s->m[1][1];
    gf_real b = GF_R(0.5) * s->m[0][1] + GF_R(0.5) * s->m[1][0];
    // Undefined, not a division by zero, when a variance is zero (t = 0 of
    // Table 1.1: the state is known exactly).
    if (!(a > 0) || !(c > 0)) {
        return GF_ERR_UNDEFINED;
    }
    // sqrt(a) sqrt(c), not sqrt(a c), which could overflow.
    gf_real r = b / (GF_SQRT(a) * GF_SQRT(c));
    *rho = r > 1 ? GF_R(1.0) : (r < -1 ? GF_R(-1.0) : r);
    return GF_OK;
}

gf_status gf_cov2_ellipse(const gf_mat2 *s, gf_real p, gf_ellipse *e)
{
    if (!s || !e || !(p > 0) || !(p < 1)) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat2_check_psd(s);
    if (st != GF_OK) {
        return st;
    }
    gf_vec2 lambda;
    gf_real angle;
    st = gf_mat2_eig_sym(s, &lambda, &angle);
    if (st != GF_OK) {
        return st;
    }
    // k^2 = -2 ln(1 - p): the chi-square quantile with two degrees of
    // freedom. Rounding can leave a PSD matrix's small eigenvalue at -0.
    gf_real k2 = -GF_R(2.0) * gf_log(GF_R(1.0) - p);
    gf_real l2 = lambda.v[1] > 0 ? lambda.v[1] : GF_R(0.0);
    // sqrt(k2) sqrt(lambda), not sqrt(k2 lambda), which could overflow.
    gf_real k = GF_SQRT(k2);
    gf_real a = k * GF_SQRT(lambda.v[0]), b = k * GF_SQRT(l2);
    if (!GF_ISFINITE(a) || !GF_ISFINITE(b)) {
        return GF_ERR_NONFINITE;
    }
    e->a = a;
    e->b = b;
    e->angle = angle;
    return GF_OK;
}

gf_status gf_cov2_marginal(const gf_mat3 *s, unsigned i, unsigned j,
                           gf_mat2 *out)
{
    if (!s || !out || i > 2 || j > 2) {
        return GF_ERR_ARG;
    }
    gf_mat2 r;
    r.m[0][0] = s->m[i][i];
    r.m[0][1] = s->m[i][j];
    r.m[1][0] = s->m[j][i];
    r.m[1][1] = s->m[j][j];
    *out = r;
    return GF_OK;
}
