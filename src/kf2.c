#include "gaussfilt/kf2.h"

static int vec2_is_finite(const gf_vec2 *x)
{
    return GF_ISFINITE(x->v[0]) && GF_ISFINITE(x->v[1]);
}

gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!vec2_is_finite(mu)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(sigma);
    if (st != GF_OK) {
        return st;
    }
    kf->mu = *mu;
    kf->sigma = *sigma;
    gf_mat2_symmetrize(&kf->sigma);
    return GF_OK;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    if (!gf_mat2_is_finite(&model->A) || !gf_mat2_is_finite(&model->B) ||
        !vec2_is_finite(&model->c) || (u && !vec2_is_finite(u))) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(&model->R);
    if (st != GF_OK) {
        return st;
    }

    // mu_bar = A mu + B u + c
    gf_vec2 mu;
    gf_mat2_mulv(&model->A, &kf->mu, &mu);
    if (u) {
        gf_vec2 bu;
        gf_mat2_mulv(&model->B, u, &bu);
        mu.v[0] += bu.v[0];
        mu.v[1] += bu.v[1];
    }
    mu.v[0] += model->c.v[0];
    mu.v[1] += model->c.v[1];

    // Sigma_bar = A Sigma A^T + R
    gf_mat2 sigma;
    gf_mat2_sandwich(&model->A, &kf->sigma, &sigma);
    sigma.m[0][0] += model->R.m[0][0];
    sigma.m[0][1] += model->R.m[0][1];
    sigma.m[1][1] += model->R.m[1][1];
    sigma.m[1][0] = sigma.m[0][1];

    if (!vec2_is_finite(&mu) || !gf_mat2_is_finite(&sigma)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    kf->mu = mu;
    kf->sigma = sigma;
    return GF_OK;
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas || !z || meas->m < 1 || meas->m > 2) {
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
    gf_mat2 Q = {{{0, 0}, {0, 0}}};
    if (m == 1) {
        Q.m[0][0] = meas->Q.m[0][0];
        if (!GF_ISFINITE(Q.m[0][0])) {
            return GF_ERR_NONFINITE;
        }
        if (Q.m[0][0] < 0) {
            return GF_ERR_NOT_PSD;
        }
    } else {
        gf_status st = gf_mat2_check_psd(&meas->Q);
        if (st != GF_OK) {
            return st;
        }
        Q = meas->Q;
    }

    const gf_vec2 *mu = &kf->mu;
    const gf_mat2 *sig = &kf->sigma;

    // PCt = Sigma_bar C^T (2 x m); S = C Sigma_bar C^T + Q (m x m)
    gf_mat2 PCt = {{{0, 0}, {0, 0}}};
    for (unsigned j = 0; j < m; j++) {
        PCt.m[0][j] = sig->m[0][0] * meas->C.m[j][0] +
                      sig->m[0][1] * meas->C.m[j][1];
        PCt.m[1][j] = sig->m[1][0] * meas->C.m[j][0] +
                      sig->m[1][1] * meas->C.m[j][1];
    }
    gf_mat2 S = Q;
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < m; j++) {
            S.m[i][j] += meas->C.m[i][0] * PCt.m[0][j] +
                         meas->C.m[i][1] * PCt.m[1][j];
        }
    }

    // S^-1, in closed form
    gf_mat2 Si = {{{0, 0}, {0, 0}}};
    if (m == 1) {
        if (!GF_ISFINITE(S.m[0][0])) {
            return GF_ERR_NONFINITE;
        }
        if (!(S.m[0][0] > 0)) {
            return GF_ERR_SINGULAR;
        }
        Si.m[0][0] = GF_R(1.0) / S.m[0][0];
    } else {
        gf_status st = gf_mat2_spd_inv(&S, &Si);
        if (st != GF_OK) {
            return st;
        }
    }

    // y = z - c - C mu_bar
    gf_innovation in;
    in.m = m;
    in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - meas->c.v[i] -
                  (meas->C.m[i][0] * mu->v[0] + meas->C.m[i][1] * mu->v[1]);
    }
    // NIS = y^T S^-1 y
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < m; j++) {
            in.nis += in.y[i] * Si.m[i][j] * in.y[j];
        }
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate > 0 && in.nis > meas->gate) {
        if (info) {
            *info = in;
        }
        return GF_ERR_GATED;
    }

    // K = Sigma_bar C^T S^-1 (2 x m)
    gf_mat2 K = {{{0, 0}, {0, 0}}};
    for (unsigned i = 0; i < 2; i++) {
        for (unsigned j = 0; j < m; j++) {
            for (unsigned k = 0; k < m; k++) {
                K.m[i][j] += PCt.m[i][k] * Si.m[k][j];
            }
        }
    }

    // mu = mu_bar + K y
    gf_vec2 mu_new = *mu;
    for (unsigned j = 0; j < m; j++) {
        mu_new.v[0] += K.m[0][j] * in.y[j];
        mu_new.v[1] += K.m[1][j] * in.y[j];
    }

    // Sigma = (I - K C) Sigma_bar (I - K C)^T + K Q K^T, then symmetrized
    gf_mat2 IKC = {{{1, 0}, {0, 1}}};
    for (unsigned i = 0; i < 2; i++) {
        for (unsigned k = 0; k < 2; k++) {
            for (unsigned j = 0; j < m; j++) {
                IKC.m[i][k] -= K.m[i][j] * meas->C.m[j][k];
            }
        }
    }
    gf_mat2 sig_new, KQ = {{{0, 0}, {0, 0}}};
    gf_mat2_sandwich(&IKC, sig, &sig_new);
    for (unsigned i = 0; i < 2; i++) {
        for (unsigned j = 0; j < m; j++) {
            for (unsigned k = 0; k < m; k++) {
                KQ.m[i][j] += K.m[i][k] * Q.m[k][j];
            }
        }
    }
    for (unsigned i = 0; i < 2; i++) {
        for (unsigned k = 0; k < 2; k++) {
            for (unsigned j = 0; j < m; j++) {
                sig_new.m[i][k] += KQ.m[i][j] * K.m[k][j];
            }
        }
    }
    gf_mat2_symmetrize(&sig_new);

    if (!vec2_is_finite(&mu_new) || !gf_mat2_is_finite(&sig_new)) {
        return GF_ERR_NONFINITE;
    }
    kf->mu = mu_new;
    kf->sigma = sig_new;
    if (info) {
        *info = in;
    }
    return GF_OK;
}
