// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/kf2.h"

#define GF_UDU_NMAX 2u // (src/udu.h's scratch: two states)
#include "gf_filter.h"
#include "steps.h"

// The checks of a motion model (and of u, if not NULL), in the order of
// gf_kf2_predict's statuses; on GF_OK, rf and rd hold R's factors.
static gf_status kf2_model_check(const gf_kf2_model *model, const gf_vec2 *u,
                                 gf_real rf[4], gf_real rd[2])
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
    return gf_cov_factor(model->R.m[0], 2, 2, rf, rd, order);
}

// The checks of a measurement model (and of z, if not NULL), in the order
// of gf_kf2_update's statuses; on GF_OK, q holds Q's factors and the
// whitened rows F^-1 C. For m = 1, q may be NULL (nothing is written): one
// quantity's Q is its own factorisation, F = 1, e = Q, and C its own
// whitened row.
static gf_status kf2_meas_check(const gf_kf2_meas *meas, const gf_vec2 *z,
                                gf_kf2_qfactors *q)
{
    const unsigned m = meas->m;
    if (m < 1 || m > 2) {
        return GF_ERR_ARG;
    }
    gf_real f = gf_nan_sum(meas->gate * GF_R(0.0), meas->C.m[0], 2 * m);
    f = gf_nan_sum(f, meas->c.v, m);
    if (z) {
        f = gf_nan_sum(f, z->v, m);
    }
    if (!gf_sum_finite(f)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    if (m == 1u) {
        if (!q) {
            return gf_noise1_check(meas->Q.m[0][0], NULL, NULL, NULL);
        }
        q->Cw = meas->C;
        return gf_noise1_check(meas->Q.m[0][0], q->Qf, q->Qe, q->Qorder);
    }
    const gf_status st =
        gf_cov_factor(meas->Q.m[0], 2, m, q->Qf, q->Qe, q->Qorder);
    if (st != GF_OK) {
        return st;
    }
    // C_w = F^-1 C
    q->Cw = meas->C;
    gf_udu_whiten_rows(q->Qf, q->Qorder, m, q->Cw.m[0], 2);
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
    gf_udu_factor3(sigma->m[0], 2, 2, nb.ud, nb.perm);
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

// The prediction once model and u are checked, R factored (rf, rd):
//   mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R.
// The belief is written only if all of it is finite.
static gf_status kf2_predict_step(gf_kf2 *kf, const gf_kf2_model *model,
                                  const gf_real rf[4], const gf_real rd[2],
                                  const gf_vec2 *u)
{
    gf_kf2 nb = *kf;
    const gf_real *uv = (u != NULL) ? u->v : NULL;
    GF_UNROLL
    for (unsigned i = 0; i < 2u; i++) {
        nb.mu.v[i] = gf_mean_row(model->A.m[i], kf->mu.v, 2u, i, model->c.v[i],
                                 model->B.m[i], uv, 2u);
    }
    {
        gf_real w[2u * 2u * 2u], wd[2u * 2u];
        gf_udu_predict(2u, nb.ud, nb.ud, nb.perm, model->A.m[0], rf, rd, w, wd);
    }
    if (!gf_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    *kf = nb;
    return GF_OK;
}

// The correction once meas and z are checked, Q factored and C whitened
// (q; NULL for one quantity of meas itself, its C and Q their own
// whitened form):
//   y = z - c - C mu_bar,  y_w = F^-1 y,
// then one scalar update per row of C_w (gf_udu_correct), the gate on the
// NIS, and the belief written only if every quantity passed.
static gf_status kf2_update_step(gf_kf2 *kf, const gf_kf2_meas *meas,
                                 const gf_kf2_qfactors *q, const gf_vec2 *z,
                                 gf_innovation *info)
{
    const unsigned m = meas->m;
    gf_innovation in;
    gf_real yw[2];
    in.m = m;
    in.y[0] = 0;
    in.y[1] = 0;
    in.y[2] = 0;
    GF_UNROLL
    for (unsigned i = 0; i < m; i++) {
        in.y[i] =
            z->v[i] - meas->c.v[i] -
            (meas->C.m[i][0] * kf->mu.v[0] + meas->C.m[i][1] * kf->mu.v[1]);
        yw[i] = in.y[i];
    }
    if (m > 1u) {
        gf_udu_whiten_rows(q->Qf, q->Qorder, m, yw, 1);
    }
    gf_kf2 nb = *kf;
    gf_real dx[2] = {0, 0};
    gf_status st =
        gf_udu_correct(2u, nb.ud, nb.perm, m, q ? q->Cw.m[0] : meas->C.m[0],
                       q ? q->Qe : &meas->Q.m[0][0], yw, dx, &in.nis);
    if (st != GF_OK) {
        return st;
    }
    st = gf_innovation_verdict(&in, meas->gate, info);
    if (st != GF_OK) {
        return st;
    }
    nb.mu.v[0] += dx[0];
    nb.mu.v[1] += dx[1];
    st = gf_update_done(gf_belief_finite(nb.mu.v, nb.ud, 2), &in, info);
    if (st == GF_OK) {
        *kf = nb;
    }
    return st;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    gf_real rf[4], rd[2];
    const gf_status st = kf2_model_check(model, u, rf, rd);
    return st != GF_OK ? st : kf2_predict_step(kf, model, rf, rd, u);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas, const gf_vec2 *z,
                        gf_innovation *info)
{
    if (!kf || !meas || !z) {
        return GF_ERR_ARG;
    }
    // (one quantity is read from meas itself: its C and Q are their own
    // whitened form)
    if (meas->m == 1u) {
        const gf_status st = kf2_meas_check(meas, z, NULL);
        return st != GF_OK ? st : kf2_update_step(kf, meas, NULL, z, info);
    }
    gf_kf2_qfactors q;
    const gf_status st = kf2_meas_check(meas, z, &q);
    return st != GF_OK ? st : kf2_update_step(kf, meas, &q, z, info);
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
    const gf_status st = kf2_meas_check(meas, NULL, &p.q);
    if (st != GF_OK) {
        return st;
    }
    p.meas = *meas;
    *pq = p;
    return GF_OK;
}

// The prepared steps: the model was checked and factored by prepare, so
// only u or z are checked; the step itself is the same.
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
    if (!kf || !pq || !z || pq->meas.m < 1 || pq->meas.m > 2) {
        return GF_ERR_ARG;
    }
    if (!gf_all_finite(z->v, pq->meas.m)) {
        return GF_ERR_NONFINITE;
    }
    return kf2_update_step(kf, &pq->meas, &pq->q, z, info);
}
