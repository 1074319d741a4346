#include <stddef.h>

#include "gaussfilt/kf2.h"

#include "udu.h"

// The checks of a motion model (and of u, if not NULL), in the order of
// gf_kf2_predict's statuses.
static gf_status model_check(const gf_kf2_model *model, const gf_vec2 *u)
{
    if (!gf_all_finite(model->A.m[0], 4) || !gf_all_finite(model->B.m[0], 4) ||
        !gf_all_finite(model->c.v, 2) || (u && !gf_all_finite(u->v, 2))) {
        return GF_ERR_NONFINITE;
    }
    return gf_psd_check(model->R.m[0], 2, 2);
}

// The checks of a measurement model (and of z, if not NULL), in the order
// of gf_kf2_update's statuses.
static gf_status meas_check(const gf_kf2_meas *meas, const gf_vec2 *z)
{
    const unsigned m = meas->m;
    if (m < 1 || m > 2) {
        return GF_ERR_ARG;
    }
    for (unsigned i = 0; i < m; i++) {
        if (!GF_ISFINITE(meas->C.m[i][0]) || !GF_ISFINITE(meas->C.m[i][1]) ||
            !GF_ISFINITE(meas->c.v[i]) || (z && !GF_ISFINITE(z->v[i]))) {
            return GF_ERR_NONFINITE;
        }
    }
    if (!GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    return gf_psd_check(meas->Q.m[0], 2, m);
}

gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!gf_vec2_is_finite(mu)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(sigma);
    if (st != GF_OK) {
        return st;
    }
    kf->mu = *mu;
    kf->sigma = *sigma;
    (void)gf_mat2_symmetrize(&kf->sigma);
    return GF_OK;
}

// The prediction once model and u are checked:
//   mu_bar = A mu + B u + c,  Sigma_bar = A Sigma A^T + R.
// The belief is written only if all of it is finite.
static gf_status predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    gf_kf2 nb = *kf;
    (void)gf_mat2_mulv(&model->A, &kf->mu, &nb.mu);
    if (u) {
        gf_vec2 bu;
        (void)gf_mat2_mulv(&model->B, u, &bu);
        nb.mu.v[0] += bu.v[0];
        nb.mu.v[1] += bu.v[1];
    }
    nb.mu.v[0] += model->c.v[0];
    nb.mu.v[1] += model->c.v[1];
    gf_cov_predict(kf->sigma.m[0], 2, model->A.m[0], model->R.m[0],
                   nb.sigma.m[0]);
    if (!gf_all_finite(nb.mu.v, 2) || !gf_all_finite(nb.sigma.m[0], 4)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    *kf = nb;
    return GF_OK;
}

// The correction once meas and z are checked:
//   y = z - c - C mu_bar, then gf_cov_correct (S = C Sigma_bar C^T + Q,
//   K = Sigma_bar C^T S^-1, mu = mu_bar + K y, Sigma = (I - K C)
//   Sigma_bar, by Bierman's factored update), the gate on the NIS.
static gf_status update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    const unsigned m = meas->m;
    gf_innovation in;
    gf_real y[2] = {0, 0}, h[2][2] = {{0, 0}, {0, 0}}, e[3] = {0, 0, 0};
    in.m = m;
    in.y[1] = in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - meas->c.v[i] -
                  (meas->C.m[i][0] * kf->mu.v[0] +
                   meas->C.m[i][1] * kf->mu.v[1]);
        y[i] = in.y[i];
        h[i][0] = meas->C.m[i][0];
        h[i][1] = meas->C.m[i][1];
    }
    gf_decorrelate(meas->Q.m[0], 2, m, h[0], y, e);
    gf_kf2 nb = *kf;
    gf_status st = gf_cov_correct(2, nb.mu.v, nb.sigma.m[0], m, h[0], y, e,
                                  &in.nis);
    if (st != GF_OK) {
        return st;
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }
    if (!gf_all_finite(nb.mu.v, 2) || !gf_all_finite(nb.sigma.m[0], 4)) {
        return GF_ERR_NONFINITE;
    }
    *kf = nb;
    if (info) {
        gf_info_store(info, &in);
    }
    return GF_OK;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    gf_status st = model_check(model, u);
    return st != GF_OK ? st : predict(kf, model, u);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas || !z) {
        return GF_ERR_ARG;
    }
    gf_status st = meas_check(meas, z);
    return st != GF_OK ? st : update(kf, meas, z, info);
}

gf_status gf_kf2_prepare_model(gf_kf2_pmodel *pm, const gf_kf2_model *model)
{
    if (!pm || !model) {
        return GF_ERR_ARG;
    }
    gf_status st = model_check(model, NULL);
    if (st != GF_OK) {
        return st;
    }
    pm->model = *model;
    return GF_OK;
}

gf_status gf_kf2_prepare_meas(gf_kf2_pmeas *pq, const gf_kf2_meas *meas)
{
    if (!pq || !meas) {
        return GF_ERR_ARG;
    }
    gf_status st = meas_check(meas, NULL);
    if (st != GF_OK) {
        return st;
    }
    pq->meas = *meas;
    return GF_OK;
}

// The prepared steps: the model was checked by prepare, so only u or z
// are; the step itself is the same.
gf_status gf_kf2_predict_prepared(gf_kf2 *kf, const gf_kf2_pmodel *pm,
                                  const gf_vec2 *u)
{
    if (!kf || !pm) {
        return GF_ERR_ARG;
    }
    if (u && !gf_vec2_is_finite(u)) {
        return GF_ERR_NONFINITE;
    }
    return predict(kf, &pm->model, u);
}

gf_status gf_kf2_update_prepared(gf_kf2 *kf, const gf_kf2_pmeas *pq,
                                 const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !pq || !z || pq->meas.m < 1 || pq->meas.m > 2) {
        return GF_ERR_ARG;
    }
    for (unsigned i = 0; i < pq->meas.m; i++) {
        if (!GF_ISFINITE(z->v[i])) {
            return GF_ERR_NONFINITE;
        }
    }
    return update(kf, &pq->meas, z, info);
}
