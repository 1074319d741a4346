// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/kf2.h"

#include "gf_filter.h"
#include "gf_internal.h"
#include "ldl.h"
#include "udu.h"

// The checks of a motion model (and of u, if not NULL), in the order of
// gf_kf2_predict's statuses; on GF_OK, Rf and Rd hold R's factors.
static gf_status kf2_model_check(const gf_kf2_model *model, const gf_vec2 *u,
                                 gf_real Rf[4], gf_real Rd[2])
{
    gf_real z = gf_nan_sum(GF_R(0.0), model->A.m[0], 4);
    z = gf_nan_sum(z, model->B.m[0], 4);
    z = gf_nan_sum(z, model->c.v, 2);
    if (u) {
        z = gf_nan_sum(z, u->v, 2);
    }
    if (!gf_sum_finite(z)) {
        return GF_ERR_NONFINITE;
    }
    unsigned order[2];
    return gf_cov_factor(model->R.m[0], 2, 2, Rf, Rd, order);
}

// The checks of a measurement model, in the order of gf_kf2_update's
// statuses; on GF_OK, q holds Q's factors and the whitened rows
// C_w = F^-1 C.
static gf_status kf2_meas_check(const gf_kf2_meas *meas, gf_kf2_qfactors *q)
{
    const unsigned m = meas->m;
    if (m < 1u || m > 2u) {
        return GF_ERR_ARG;
    }
    gf_real f = gf_nan_sum(meas->gate * GF_R(0.0), meas->C.m[0], 2u * m);
    f = gf_nan_sum(f, meas->c.v, m);
    if (!gf_sum_finite(f)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    const gf_status st =
        gf_cov_factor(meas->Q.m[0], 2, m, q->Qf, q->Qe, q->Qorder);
    if (st != GF_OK) {
        return st;
    }
    q->Cw = meas->C;
    gf_udu_whiten(q->Qf, q->Qorder, m, q->Cw.m[0], 2);
    return GF_OK;
}

gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    const gf_status st = gf_prior2_check(mu, sigma);
    if (st != GF_OK) {
        return st;
    }
    gf_kf2 nb;
    gf_real work[GF_UDU_FACTOR_WORK(2u)];
    gf_udu_factor(sigma->m[0], 2, 2, nb.ud, nb.perm, work);
    nb.mu = *mu;
    if (!gf_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE; // a variance at the end of the range
    }
    *kf = nb;
    return GF_OK;
}

gf_status gf_kf2_cov(const gf_kf2 *kf, gf_mat2 *sigma)
{
    if (!kf || !sigma) {
        return GF_ERR_ARG;
    }
    gf_udu_to_cov(kf->ud, kf->perm, 2, sigma->m[0], 2);
    return GF_OK;
}

// The prediction once model and u are checked, R factored (Rf, Rd):
//   mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R.
// The belief is written only if all of it is finite.
static gf_status kf2_predict_step(gf_kf2 *kf, const gf_kf2_model *model,
                                  const gf_real Rf[4], const gf_real Rd[2],
                                  const gf_vec2 *u)
{
    gf_kf2 nb = *kf;
    const gf_real *uv = (u != NULL) ? u->v : NULL;
    for (unsigned i = 0; i < 2u; i++) {
        nb.mu.v[i] = gf_mean_row(model->A.m[i], kf->mu.v, 2u, i, model->c.v[i],
                                 model->B.m[i], uv, 2u);
    }
    gf_real work[GF_UDU_PREDICT_WORK(2u)];
    gf_udu_predict(2u, kf->ud, nb.ud, kf->perm, model->A.m[0], Rf, Rd, work);
    if (!gf_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    *kf = nb;
    return GF_OK;
}

// y = z - c - C mu_bar into y[0..m).
static void kf2_innovation(const gf_kf2_meas *meas, const gf_vec2 *z,
                           const gf_kf2 *kf, gf_real *y)
{
    for (unsigned i = 0; i < meas->m; i++) {
        y[i] = z->v[i] - meas->c.v[i] -
               (meas->C.m[i][0] * kf->mu.v[0] + meas->C.m[i][1] * kf->mu.v[1]);
    }
}

// The correction, once m and z are checked, with Q's factors and C_w
// prepared or, where prepared is NULL, made here once kf2_meas_check has
// checked meas (z first: the statuses are the same in either order):
//   y = z - c - C mu_bar,  y_w = F^-1 y,
// then one scalar update per row of C_w (gf_udu_correct), the gate on the
// NIS, and the belief written only if every quantity passed. Q's factors
// and the belief's copy live in blocks of their own: one frame holds them
// in turn, not both (C_w and Q's noises copied across). y is not kept
// through the correction: info's is computed again, from the same z and
// mu_bar (kf is written last).
static gf_status kf2_update_step(gf_kf2 *kf, const gf_kf2_meas *meas,
                                 const gf_kf2_qfactors *prepared,
                                 const gf_vec2 *z, gf_innovation *info)
{
    const unsigned m = meas->m;
    if (m < 1u || m > 2u) {
        return GF_ERR_ARG;
    }
    if (!gf_all_finite(z->v, m)) {
        return GF_ERR_NONFINITE;
    }
    gf_real yw[2], e[2], nis;
    gf_mat2 cw;
    gf_status st;
    {
        gf_kf2_qfactors own;
        const gf_kf2_qfactors *q = prepared;
        if (!q) {
            st = kf2_meas_check(meas, &own);
            if (st != GF_OK) {
                return st;
            }
            q = &own;
        }
        cw = q->Cw;
        e[0] = q->Qe[0];
        e[1] = (m > 1u) ? q->Qe[1] : GF_R(0.0);
        kf2_innovation(meas, z, kf, yw);
        gf_udu_whiten(q->Qf, q->Qorder, m, yw, 1);
    }
    {
        gf_kf2 nb = *kf;
        gf_real work[GF_UDU_CORRECT_WORK(2u)];
        st = gf_udu_correct(2u, nb.ud, nb.perm, m, cw.m[0], e, yw, nb.mu.v,
                            &nis, work);
        if (st != GF_OK) {
            return st;
        }
        const int finite = gf_belief_finite(nb.mu.v, nb.ud, 2);
        st = gf_update_status(nis, meas->gate, finite);
        if (info && (st == GF_OK || st == GF_ERR_GATED)) {
            info->m = meas->m;
            info->y[1] = 0;
            info->y[2] = 0;
            info->nis = nis;
            kf2_innovation(meas, z, kf, info->y);
        }
        if (st == GF_OK) {
            *kf = nb;
        }
    }
    return st;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    gf_real Rf[4], Rd[2];
    const gf_status st = kf2_model_check(model, u, Rf, Rd);
    return st != GF_OK ? st : kf2_predict_step(kf, model, Rf, Rd, u);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z,
                        gf_innovation *info)
{
    if (!kf || !meas || !z) {
        return GF_ERR_ARG;
    }
    return kf2_update_step(kf, meas, NULL, z, info);
}

gf_status gf_kf2_prepare_model(gf_kf2_pmodel *pm, const gf_kf2_model *model)
{
    if (!pm || !model) {
        return GF_ERR_ARG;
    }
    gf_kf2_pmodel p;
    const gf_status st = kf2_model_check(model, NULL, p.Rf, p.Rd);
    if (st != GF_OK) {
        return st;
    }
    p.model = *model;
    *pm = p;
    return GF_OK;
}

gf_status gf_kf2_prepare_meas(gf_kf2_pmeas *pq, const gf_kf2_meas *meas)
{
    if (!pq || !meas) {
        return GF_ERR_ARG;
    }
    gf_kf2_pmeas p;
    const gf_status st = kf2_meas_check(meas, &p.q);
    if (st != GF_OK) {
        return st;
    }
    p.meas = *meas;
    *pq = p;
    return GF_OK;
}

// The prepared steps: the model was checked and factored by prepare, so
// only u or z are checked (z in kf2_update_step); the step itself is the
// same.
gf_status gf_kf2_predict_prepared(gf_kf2 *kf, const gf_kf2_pmodel *pm,
                                  const gf_vec2 *u)
{
    if (!kf || !pm) {
        return GF_ERR_ARG;
    }
    if (u && !gf_all_finite(u->v, 2)) {
        return GF_ERR_NONFINITE;
    }
    return kf2_predict_step(kf, &pm->model, pm->Rf, pm->Rd, u);
}

gf_status gf_kf2_update_prepared(gf_kf2 *kf, const gf_kf2_pmeas *pq,
                                 const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !pq || !z) {
        return GF_ERR_ARG;
    }
    return kf2_update_step(kf, &pq->meas, &pq->q, z, info);
}
