// SPDX-License-Identifier: MIT
// gf_kf and the steps gf_ekf shares with it (src/kf_core.h): the factored
// core of src/udu.h for n states, 1 <= n <= GF_KF_NMAX, with the scratch
// in the caller's gf_kf_work.
#include <stddef.h>

#include "gaussfilt/kf.h"

#include "gf_internal.h"
#include "kf_core.h"
#include "ldl.h"
#include "udu.h"

// ---- shared with ekf.c ---------------------------------------------------

// dst's mu and factors = src's, for n states. (The copies are functions of
// their own, where restrict holds: the compiler's memcpy, never memmove.)
GF_NOINLINE void kfc_copy_moments(gf_kf *restrict dst,
                                  const gf_kf *restrict src, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        dst->mu[i] = src->mu[i];
    }
    for (unsigned k = 0; k < GF_KF_TRI(n); k++) {
        dst->ud[k] = src->ud[k];
    }
}

// *dst = *src for the parts an n-state belief uses (n, angles, mu, the
// factors and the permutation): the rest of dst is left as it is.
GF_NOINLINE void kfc_copy(gf_kf *restrict dst, const gf_kf *restrict src)
{
    const unsigned n = src->n;
    dst->n = n;
    dst->angles = src->angles;
    kfc_copy_moments(dst, src, n);
    for (unsigned k = 0; k < GF_KF_PERM_BYTES; k++) {
        dst->perm[k] = src->perm[k];
    }
}

gf_status gf_kfc_noise(const gf_real *s, unsigned n, gf_kf_work *work,
                       const gf_kf_factors **fac)
{
    gf_kf_factors *f = &work->noise;
    const gf_status st = gf_cov_factor(s, n, n, f->F, f->d, f->order);
    if (st == GF_OK && fac) {
        *fac = f;
    }
    return st;
}

gf_status gf_kfc_init(gf_kf *kf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work)
{
    if (!kf || !mu || !sigma || !work || n < 1u || n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    if (!gf_all_finite(mu, n)) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = gf_kfc_noise(sigma, n, work, NULL);
    if (st != GF_OK) {
        return st;
    }
    // the belief, built in work->belief with every unused entry zero
    gf_kf *nb = &work->belief;
    nb->n = n;
    nb->angles = angles;
    for (unsigned k = 0; k < GF_KF_PERM_BYTES; k++) {
        nb->perm[k] = 0;
    }
    gf_udu_factor(sigma, n, n, nb->ud, nb->perm, work->steps);
    for (unsigned i = 0; i < n; i++) {
        nb->mu[i] = mu[i];
    }
    if (!gf_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE; // a variance at the end of the range
    }
    kfc_copy(kf, nb);
    for (unsigned i = n; i < GF_KF_NMAX; i++) {
        kf->mu[i] = 0;
    }
    for (unsigned k = GF_KF_TRI(n); k < GF_KF_TRI(GF_KF_NMAX); k++) {
        kf->ud[k] = 0;
    }
    return GF_OK;
}

gf_status gf_kfc_predict(gf_kf *kf, const gf_real *mu_bar, const gf_real *G,
                         const gf_real *Rf, const gf_real *Rd, gf_kf_work *work)
{
    const unsigned n = kf->n;
    gf_kf *nb = &work->belief; // its mu and factors (the order stays kf's)
    for (unsigned i = 0; i < n; i++) {
        nb->mu[i] = mu_bar[i];
    }
    // Sigma_bar = G Sigma G^T + R on the factors (Thornton)
    gf_udu_predict(n, kf->ud, nb->ud, kf->perm, G, Rf, Rd, work->steps);
    if (!gf_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    kfc_copy_moments(kf, nb, n);
    return GF_OK;
}

// *info = *in (if info is not NULL and st is GF_OK or GF_ERR_GATED), the
// entries of y past m zero. Returns st.
static gf_status kfc_info(gf_status st, gf_kf_innovation *info,
                          const gf_kf_innovation *in)
{
    if (info && (st == GF_OK || st == GF_ERR_GATED)) {
        info->m = in->m;
        info->nis = in->nis;
        for (unsigned i = 0; i < GF_KF_NMAX; i++) {
            info->y[i] = i < in->m ? in->y[i] : GF_R(0.0);
        }
    }
    return st;
}

gf_status gf_kfc_correct(gf_kf *kf, unsigned m, const gf_real *hw,
                         const gf_real *Qf, const gf_real *Qe,
                         const unsigned *Qorder, gf_real gate,
                         gf_kf_innovation *info, gf_kf_work *work)
{
    gf_kf *nb = &work->belief;
    gf_kf_innovation *in = &work->in;
    const unsigned n = kf->n;
    in->m = m;
    gf_udu_whiten(Qf, Qorder, m, work->yw, 1);
    kfc_copy(nb, kf);
    gf_status st = gf_udu_correct(n, nb->ud, nb->perm, m, hw, Qe, work->yw,
                                  nb->mu, &in->nis, work->steps);
    if (st != GF_OK) {
        return st;
    }
    st = gf_update_status(in->nis, gate, gf_belief_finite(nb->mu, nb->ud, n));
    if (st == GF_OK) {
        kfc_copy(kf, nb);
    }
    return kfc_info(st, info, in);
}

gf_status gf_kfc_meas_check(unsigned n, unsigned m, const gf_real *Q,
                            gf_real gate, const gf_real *z, gf_kf_work *work,
                            const gf_kf_factors **fac)
{
    if (!Q || m < 1u || m > n) {
        return GF_ERR_ARG;
    }
    gf_real f = gate * GF_R(0.0);
    if (z) {
        f = gf_nan_sum(f, z, m);
    }
    if (!gf_sum_finite(f)) {
        return GF_ERR_NONFINITE;
    }
    if (gate < 0) {
        return GF_ERR_ARG;
    }
    return gf_kfc_noise(Q, m, work, fac);
}

void gf_kfc_keep(const gf_kf_factors *fac, unsigned m, gf_real *F, gf_real *d,
                 unsigned *order)
{
    for (unsigned k = 0; k < m * m; k++) {
        F[k] = fac->F[k];
    }
    for (unsigned k = 0; k < m; k++) {
        d[k] = fac->d[k];
        if (order) {
            order[k] = fac->order[k];
        }
    }
}

// ---- gf_kf ---------------------------------------------------------------

gf_status gf_kf_init(gf_kf *kf, unsigned n, const gf_real *mu,
                     const gf_real *sigma, gf_kf_work *work)
{
    return gf_kfc_init(kf, n, mu, sigma, 0, work);
}

gf_status gf_kf_cov(const gf_kf *kf, gf_real *sigma)
{
    if (!kf || !sigma || kf->n < 1u || kf->n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    gf_udu_to_cov(kf->ud, kf->perm, kf->n, sigma, kf->n);
    return GF_OK;
}

// The checks of a motion model for n states (and of u, if not NULL), in
// the order of gf_kf_predict's statuses; on GF_OK, Rf and Rd hold R's
// factors.
static gf_status kf_model_check(unsigned n, const gf_kf_model *model,
                                const gf_real *u, gf_kf_work *work,
                                const gf_kf_factors **fac)
{
    if (!model->A || !model->R || (model->nu > 0u && !model->B) || n < 1u ||
        n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    gf_real z = gf_nan_sum(GF_R(0.0), model->A, n * n);
    if (model->nu > 0u) {
        z = gf_nan_sum(z, model->B, n * model->nu);
        if (u) {
            z = gf_nan_sum(z, u, model->nu);
        }
    }
    if (model->c) {
        z = gf_nan_sum(z, model->c, n);
    }
    if (!gf_sum_finite(z)) {
        return GF_ERR_NONFINITE;
    }
    return gf_kfc_noise(model->R, n, work, fac);
}

// mu_bar = A mu + B u + c, into work->mean, then the factored prediction.
static gf_status kf_predict_step(gf_kf *kf, const gf_kf_model *model,
                                 const gf_real *u, const gf_real *Rf,
                                 const gf_real *Rd, gf_kf_work *work)
{
    const unsigned n = kf->n;
    gf_real *mu_bar = work->mean;
    const gf_real *c = model->c;
    const unsigned nu = (u != NULL) ? model->nu : 0u;
    for (unsigned i = 0; i < n; i++) {
        mu_bar[i] =
            gf_mean_row(&model->A[(size_t)i * n], kf->mu, n, i,
                        (c != NULL) ? c[i] : GF_R(0.0),
                        (nu > 0u) ? &model->B[(size_t)i * nu] : NULL, u, nu);
    }
    return gf_kfc_predict(kf, mu_bar, model->A, Rf, Rd, work);
}

gf_status gf_kf_predict(gf_kf *kf, const gf_kf_model *model, const gf_real *u,
                        gf_kf_work *work)
{
    if (!kf || !model || !work) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *r = NULL;
    const gf_status st = kf_model_check(kf->n, model, u, work, &r);
    return st != GF_OK ? st : kf_predict_step(kf, model, u, r->F, r->d, work);
}

gf_status gf_kf_prepare_model(gf_kf_pmodel *pm, unsigned n,
                              const gf_kf_model *model, gf_kf_work *work)
{
    if (!pm || !model || !work) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *r = NULL;
    const gf_status st = kf_model_check(n, model, NULL, work, &r);
    if (st != GF_OK) {
        return st;
    }
    pm->model = *model;
    pm->n = n;
    gf_kfc_keep(r, n, pm->Rf, pm->Rd, NULL);
    return GF_OK;
}

gf_status gf_kf_predict_prepared(gf_kf *kf, const gf_kf_pmodel *pm,
                                 const gf_real *u, gf_kf_work *work)
{
    if (!kf || !pm || !work || pm->n != kf->n) {
        return GF_ERR_ARG;
    }
    if (u && pm->model.nu > 0u &&
        !gf_sum_finite(gf_nan_sum(GF_R(0.0), u, pm->model.nu))) {
        return GF_ERR_NONFINITE;
    }
    return kf_predict_step(kf, &pm->model, u, pm->Rf, pm->Rd, work);
}

// The checks of a measurement model for n states (and of z, if not NULL),
// in the order of gf_kf_update's statuses; on GF_OK, Q's factors are in
// work->noise (gf_kfc_noise) and F_Q^-1 C in work->rows.
static gf_status kf_meas_check(unsigned n, const gf_kf_meas *meas,
                               const gf_real *z, gf_kf_work *work)
{
    const unsigned m = meas->m;
    if (!meas->C || m < 1u || m > n) {
        return GF_ERR_ARG;
    }
    gf_real f = gf_nan_sum(GF_R(0.0), meas->C, m * n);
    if (meas->c) {
        f = gf_nan_sum(f, meas->c, m);
    }
    if (!gf_sum_finite(f)) {
        return GF_ERR_NONFINITE;
    }
    const gf_kf_factors *q = NULL;
    const gf_status st =
        gf_kfc_meas_check(n, m, meas->Q, meas->gate, z, work, &q);
    if (st != GF_OK) {
        return st;
    }
    // C_w = F_Q^-1 C
    gf_real *Cw = work->rows;
    for (unsigned k = 0; k < m * n; k++) {
        Cw[k] = meas->C[k];
    }
    gf_udu_whiten(q->F, q->order, m, Cw, n);
    return GF_OK;
}

// y = z - c - C mu_bar into work->in.y and work->yw (y_w to be):
// (z_i - c_i) - (C mu)_i, KF2's order of operations.
static void kf_innovation(const gf_kf *kf, const gf_kf_meas *meas,
                          const gf_real *z, gf_kf_work *work)
{
    const unsigned n = kf->n, m = meas->m;
    for (unsigned i = 0; i < m; i++) {
        gf_real dot = meas->C[(size_t)i * n] * kf->mu[0];
        for (unsigned j = 1; j < n; j++) {
            dot += meas->C[(size_t)i * n + j] * kf->mu[j];
        }
        work->in.y[i] = z[i] - (meas->c ? meas->c[i] : GF_R(0.0)) - dot;
        work->yw[i] = work->in.y[i];
    }
}

gf_status gf_kf_update(gf_kf *kf, const gf_kf_meas *meas, const gf_real *z,
                       gf_kf_innovation *info, gf_kf_work *work)
{
    if (!kf || !meas || !z || !work || kf->n < 1u || kf->n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    const gf_status st = kf_meas_check(kf->n, meas, z, work);
    if (st != GF_OK) {
        return st;
    }
    kf_innovation(kf, meas, z, work);
    const gf_kf_factors *q = &work->noise;
    return gf_kfc_correct(kf, meas->m, work->rows, q->F, q->d, q->order,
                          meas->gate, info, work);
}

gf_status gf_kf_prepare_meas(gf_kf_pmeas *pq, unsigned n,
                             const gf_kf_meas *meas, gf_kf_work *work)
{
    if (!pq || !meas || !work) {
        return GF_ERR_ARG;
    }
    const gf_status st = kf_meas_check(n, meas, NULL, work);
    if (st != GF_OK) {
        return st;
    }
    const gf_kf_factors *q = &work->noise;
    pq->meas = *meas;
    pq->n = n;
    gf_kfc_keep(q, meas->m, pq->Qf, pq->Qe, pq->Qorder);
    for (unsigned k = 0; k < meas->m * n; k++) {
        pq->Cw[k] = work->rows[k];
    }
    return GF_OK;
}

gf_status gf_kf_update_prepared(gf_kf *kf, const gf_kf_pmeas *pq,
                                const gf_real *z, gf_kf_innovation *info,
                                gf_kf_work *work)
{
    if (!kf || !pq || !z || !work || pq->n != kf->n || pq->meas.m < 1u ||
        pq->meas.m > kf->n) {
        return GF_ERR_ARG;
    }
    if (!gf_sum_finite(gf_nan_sum(GF_R(0.0), z, pq->meas.m))) {
        return GF_ERR_NONFINITE;
    }
    kf_innovation(kf, &pq->meas, z, work);
    return gf_kfc_correct(kf, pq->meas.m, pq->Cw, pq->Qf, pq->Qe, pq->Qorder,
                          pq->meas.gate, info, work);
}
