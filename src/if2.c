// SPDX-License-Identifier: MIT
#include "gaussfilt/if2.h"

#include "gf_filter.h"
#include "gf_internal.h"

gf_status gf_if2_init(gf_if2 *inf, const gf_mat2 *omega, const gf_vec2 *xi)
{
    if (!inf || !omega || !xi) {
        return GF_ERR_ARG;
    }
    const gf_status st = gf_prior2_check(xi, omega);
    if (st != GF_OK) {
        return st;
    }
    inf->omega = *omega;
    (void)gf_mat2_symmetrize(&inf->omega);
    inf->xi = *xi;
    return GF_OK;
}

gf_status gf_if2_from_moments(gf_if2 *inf, const gf_vec2 *mu,
                              const gf_mat2 *sigma)
{
    if (!inf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_prior2_check(mu, sigma);
    if (st != GF_OK) {
        return st;
    }
    // Omega = Sigma^-1 (GF_ERR_SINGULAR for Sigma_0 = 0 or Sigma_1 = R)
    gf_if2 r;
    st = gf_mat2_spd_inv(sigma, &r.omega);
    if (st != GF_OK) {
        return st;
    }
    // xi = Omega mu
    (void)gf_mat2_mulv(&r.omega, mu, &r.xi);
    if (!gf_mat2_is_finite(&r.omega) || !gf_vec2_is_finite(&r.xi)) {
        return GF_ERR_NONFINITE;
    }
    *inf = r;
    return GF_OK;
}

// The moments of a canonical belief with positive-definite Omega, written
// straight to mu and sigma: the callers pass their own scratch and keep it
// only on GF_OK (no second copy here, on top of theirs).
static gf_status if2_moments(const gf_if2 *inf, gf_vec2 *mu, gf_mat2 *sigma)
{
    // Sigma = Omega^-1, mu = Sigma xi
    const gf_status st = gf_mat2_spd_inv(&inf->omega, sigma);
    if (st != GF_OK) {
        return st;
    }
    (void)gf_mat2_mulv(sigma, &inf->xi, mu);
    if (!gf_mat2_is_finite(sigma) || !gf_vec2_is_finite(mu)) {
        return GF_ERR_NONFINITE;
    }
    return GF_OK;
}

gf_status gf_if2_to_moments(const gf_if2 *inf, gf_vec2 *mu, gf_mat2 *sigma)
{
    if (!inf || (!mu && !sigma)) {
        return GF_ERR_ARG;
    }
    gf_vec2 m;
    gf_mat2 s;
    gf_status st = if2_moments(inf, &m, &s);
    if (st != GF_OK) {
        return st;
    }
    if (mu) {
        *mu = m;
    }
    if (sigma) {
        *sigma = s;
    }
    return GF_OK;
}

gf_status gf_if2_predict(gf_if2 *inf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!inf || !model) {
        return GF_ERR_ARG;
    }
    if (!gf_mat2_is_finite(&model->A) || !gf_mat2_is_finite(&model->B) ||
        !gf_vec2_is_finite(&model->c) || (u && !gf_vec2_is_finite(u))) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(&model->R);
    if (st != GF_OK) {
        return st;
    }

    // Omega^-1 and Omega^-1 xi: the first inversion
    gf_vec2 mu;
    gf_mat2 sigma;
    st = if2_moments(inf, &mu, &sigma);
    if (st != GF_OK) {
        return st;
    }

    // A Omega^-1 xi + B u + c
    gf_vec2 mu_bar;
    (void)gf_mat2_mulv(&model->A, &mu, &mu_bar);
    if (u) {
        gf_vec2 bu;
        (void)gf_mat2_mulv(&model->B, u, &bu);
        mu_bar.v[0] += bu.v[0];
        mu_bar.v[1] += bu.v[1];
    }
    mu_bar.v[0] += model->c.v[0];
    mu_bar.v[1] += model->c.v[1];

    // A Omega^-1 A^T + R
    gf_mat2 sig_bar;
    (void)gf_mat2_sandwich(&model->A, &sigma, &sig_bar);
    sig_bar.m[0][0] += model->R.m[0][0];
    sig_bar.m[0][1] +=
        GF_R(0.5) * model->R.m[0][1] + GF_R(0.5) * model->R.m[1][0];
    sig_bar.m[1][1] += model->R.m[1][1];
    sig_bar.m[1][0] = sig_bar.m[0][1];

    // Omega_bar = (A Omega^-1 A^T + R)^-1: the second inversion
    gf_if2 r;
    st = gf_mat2_spd_inv(&sig_bar, &r.omega);
    if (st != GF_OK) {
        return st;
    }
    // xi_bar = Omega_bar (A Omega^-1 xi + B u + c)
    (void)gf_mat2_mulv(&r.omega, &mu_bar, &r.xi);

    if (!gf_mat2_is_finite(&r.omega) || !gf_vec2_is_finite(&r.xi)) {
        return GF_ERR_NONFINITE;
    }
    *inf = r;
    return GF_OK;
}

// The innovation of the moments form (for info and the gate):
// y = z - c - C mu_bar, NIS = y^T (C Sigma_bar C^T + Q)^-1 y, into out
// (the caller's scratch, kept only on GF_OK; the caller judges the NIS).
static gf_status if2_innovation(const gf_if2 *inf, const gf_kf2_meas *meas,
                                const gf_vec2 *z, gf_innovation *out)
{
    const unsigned m = meas->m;
    gf_vec2 mu;
    gf_mat2 sig, S;
    gf_status st = if2_moments(inf, &mu, &sig);
    if (st != GF_OK) {
        return st;
    }
    // S = C Sigma_bar C^T + Q. For m = 1 only S[0][0] is used (row 1 of
    // C, which need not be set, does not enter it), inverted as a scalar;
    // for m = 2, S^-1 replaces Sigma_bar.
    (void)gf_mat2_sandwich(&meas->C, &sig, &S);
    S.m[0][0] += meas->Q.m[0][0];
    if (m == 1) {
        if (!GF_ISFINITE(S.m[0][0])) {
            return GF_ERR_NONFINITE;
        }
        if (!(S.m[0][0] > 0)) {
            return GF_ERR_SINGULAR;
        }
        sig.m[0][0] = GF_R(1.0) / S.m[0][0];
    } else {
        S.m[0][1] += meas->Q.m[0][1];
        S.m[1][0] += meas->Q.m[1][0];
        S.m[1][1] += meas->Q.m[1][1];
        st = gf_mat2_spd_inv(&S, &sig);
        if (st != GF_OK) {
            return st;
        }
    }
    out->m = m;
    out->y[0] = out->y[1] = out->y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        out->y[i] = z->v[i] - meas->c.v[i] -
                    (meas->C.m[i][0] * mu.v[0] + meas->C.m[i][1] * mu.v[1]);
    }
    out->nis = 0;
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < m; j++) {
            out->nis += out->y[i] * sig.m[i][j] * out->y[j];
        }
    }
    return GF_OK;
}

gf_status gf_if2_update(gf_if2 *inf, const gf_kf2_meas *meas, const gf_vec2 *z,
                        gf_innovation *info)
{
    if (!inf || !meas || !z || meas->m < 1 || meas->m > 2) {
        return GF_ERR_ARG;
    }
    const unsigned m = meas->m;
    for (unsigned i = 0; i < m; i++) {
        if (!GF_ISFINITE(meas->C.m[i][0]) || !GF_ISFINITE(meas->C.m[i][1]) ||
            !GF_ISFINITE(meas->c.v[i]) || !GF_ISFINITE(z->v[i])) {
            return GF_ERR_NONFINITE;
        }
    }
    if (!GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }

    // Q^-1 (m x m); a zero variance is infinite information: singular.
    gf_mat2 Qi = {{{0, 0}, {0, 0}}};
    gf_status st;
    if (m == 1) {
        const gf_real q = meas->Q.m[0][0];
        if (!GF_ISFINITE(q)) {
            return GF_ERR_NONFINITE;
        }
        if (q < 0) {
            return GF_ERR_NOT_PSD;
        }
        if (!(q > 0)) {
            return GF_ERR_SINGULAR;
        }
        Qi.m[0][0] = GF_R(1.0) / q;
    } else {
        st = gf_mat2_check_psd(&meas->Q);
        if (st != GF_OK) {
            return st;
        }
        st = gf_mat2_spd_inv(&meas->Q, &Qi);
        if (st != GF_OK) {
            return st;
        }
    }

    gf_innovation in = {0u, {0, 0, 0}, 0};
    if (info || meas->gate > 0) {
        st = if2_innovation(inf, meas, z, &in);
        if (st != GF_OK) {
            return st;
        }
        st = gf_update_status(in.nis, meas->gate, 1);
        if (st != GF_OK) {
            return gf_innovation_keep(st, &in, info); // (gated: info kept)
        }
    }

    {
        // CtQi = C^T Q^-1 (2 x m)
        gf_mat2 CtQi = {{{0, 0}, {0, 0}}};
        for (unsigned i = 0; i < 2; i++) {
            for (unsigned j = 0; j < m; j++) {
                for (unsigned k = 0; k < m; k++) {
                    CtQi.m[i][j] += meas->C.m[k][i] * Qi.m[k][j];
                }
            }
        }
        // Omega = Omega_bar + C^T Q^-1 C,  xi = xi_bar + C^T Q^-1 (z - c)
        gf_if2 r = *inf;
        for (unsigned i = 0; i < 2; i++) {
            for (unsigned j = 0; j < m; j++) {
                r.omega.m[i][0] += CtQi.m[i][j] * meas->C.m[j][0];
                r.omega.m[i][1] += CtQi.m[i][j] * meas->C.m[j][1];
                r.xi.v[i] += CtQi.m[i][j] * (z->v[j] - meas->c.v[j]);
            }
        }
        (void)gf_mat2_symmetrize(&r.omega);
        // An information below the smallest normal number (its products
        // underflowed where a coupling's may not have) is zero, with its
        // row and column of Omega and its entry of xi: nothing is known
        // of that state, and Omega stays positive semidefinite.
        for (unsigned i = 0; i < 2u; i++) {
            if (r.omega.m[i][i] < GF_REAL_MIN) {
                r.omega.m[i][0] = r.omega.m[0][i] = 0;
                r.omega.m[i][1] = r.omega.m[1][i] = 0;
                r.xi.v[i] = 0;
            }
        }

        st = gf_innovation_keep(
            (gf_mat2_is_finite(&r.omega) && gf_vec2_is_finite(&r.xi))
                ? GF_OK
                : GF_ERR_NONFINITE,
            &in, info);
        if (st == GF_OK) {
            *inf = r;
        }
    }
    return st;
}
