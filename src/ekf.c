// SPDX-License-Identifier: MIT
// gf_ekf: the extended Kalman filter for n states, on gf_kf's belief,
// workspace and factored steps (src/kf_core.h).
#include <stddef.h>

#include "gaussfilt/ekf.h"

#include "gf_internal.h"
#include "kf_core.h"
#include "udu.h"

gf_status gf_ekf_init(gf_kf *ekf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work)
{
    return gf_kfc_init(ekf, n, mu, sigma, angles, work);
}

// R's verdict and factors (into Rf, Rd).
static gf_status ekf_motion_check(unsigned n, const gf_ekf_motion *motion,
                                  gf_kf_work *work, const gf_kf_factors **fac)
{
    if (!motion->g || !motion->R || n < 1u || n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    return gf_kfc_noise(motion->R, n, work, fac);
}

// mu_bar = g(u, mu) and G from the callback (mu_bar preset to mu, G to the
// identity), GF_ERR_NONFINITE unless both are finite, then the factored
// prediction.
static gf_status ekf_predict_step(gf_kf *ekf, const gf_ekf_motion *motion,
                                  const gf_real *u, const gf_real *Rf,
                                  const gf_real *Rd, gf_kf_work *work)
{
    const unsigned n = ekf->n;
    gf_real *mu_bar = work->mean;
    gf_real *G = work->rows;
    for (unsigned i = 0; i < n; i++) {
        mu_bar[i] = ekf->mu[i];
        for (unsigned j = 0; j < n; j++) {
            G[i * n + j] = (i == j) ? GF_R(1.0) : GF_R(0.0);
        }
    }
    const gf_status st = motion->g(motion->ctx, n, ekf->mu, u, mu_bar, G);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    // The callback's answer judged as gf_kf_predict judges A; an overflow
    // in the step is the result's test's (gf_kfc_predict).
    if (!gf_sum_finite(
            gf_nan_sum(gf_nan_sum(GF_R(0.0), mu_bar, n), G, n * n))) {
        return GF_ERR_NONFINITE;
    }
    return gf_kfc_predict(ekf, mu_bar, G, Rf, Rd, work);
}

gf_status gf_ekf_predict(gf_kf *ekf, const gf_ekf_motion *motion,
                         const gf_real *u, gf_kf_work *work)
{
    if (!ekf || !motion || !work) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *r = NULL;
    const gf_status st = ekf_motion_check(ekf->n, motion, work, &r);
    return st != GF_OK ? st
                       : ekf_predict_step(ekf, motion, u, r->F, r->d, work);
}

gf_status gf_ekf_prepare_motion(gf_ekf_pmotion *pm, unsigned n,
                                const gf_ekf_motion *motion, gf_kf_work *work)
{
    if (!pm || !motion || !work) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *r = NULL;
    const gf_status st = ekf_motion_check(n, motion, work, &r);
    if (st != GF_OK) {
        return st;
    }
    pm->motion = *motion;
    pm->n = n;
    gf_kfc_keep(r, n, pm->Rf, pm->Rd, NULL);
    return GF_OK;
}

gf_status gf_ekf_predict_prepared(gf_kf *ekf, const gf_ekf_pmotion *pm,
                                  const gf_real *u, gf_kf_work *work)
{
    if (!ekf || !pm || !work || !pm->motion.g || pm->n != ekf->n) {
        return GF_ERR_ARG;
    }
    return ekf_predict_step(ekf, &pm->motion, u, pm->Rf, pm->Rd, work);
}

// z_hat and H from the callback (both preset to zeros), y = z - z_hat
// (angle residuals wrapped) into work->in.y and work->yw, H whitened by Q's factors
// (H_w = F_Q^-1 H, in work->rows), then the correction (gf_kfc_correct).
static gf_status ekf_update_step(gf_kf *ekf, const gf_ekf_meas *meas,
                                 const gf_real *z, const gf_real *Qf,
                                 const gf_real *Qe, const unsigned *Qorder,
                                 gf_kf_innovation *info, gf_kf_work *work)
{
    const unsigned n = ekf->n, m = meas->m;
    gf_real *zh = work->mean;
    gf_real *y = work->in.y;
    gf_real *H = work->rows;
    for (unsigned i = 0; i < m; i++) {
        zh[i] = 0;
        for (unsigned j = 0; j < n; j++) {
            H[i * n + j] = 0;
        }
    }
    const gf_status st = meas->h(meas->ctx, n, m, ekf->mu, zh, H);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    if (!gf_sum_finite(gf_nan_sum(gf_nan_sum(GF_R(0.0), zh, m), H, m * n))) {
        return GF_ERR_NONFINITE;
    }
    for (unsigned i = 0; i < m; i++) {
        y[i] = z[i] - zh[i];
        if ((meas->angle_mask >> i) & 1u) {
            y[i] = gf_angle_wrap(y[i]);
        }
        work->yw[i] = y[i];
    }
    gf_udu_whiten(Qf, Qorder, m, H, n);
    return gf_kfc_correct(ekf, m, H, Qf, Qe, Qorder, meas->gate, info, work);
}

gf_status gf_ekf_update(gf_kf *ekf, const gf_ekf_meas *meas, const gf_real *z,
                        gf_kf_innovation *info, gf_kf_work *work)
{
    if (!ekf || !meas || !z || !work || !meas->h || ekf->n < 1u ||
        ekf->n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *q = NULL;
    const gf_status st =
        gf_kfc_meas_check(ekf->n, meas->m, meas->Q, meas->gate, z, work, &q);
    return st != GF_OK ? st
                       : ekf_update_step(ekf, meas, z, q->F, q->d, q->order,
                                         info, work);
}

gf_status gf_ekf_prepare_meas(gf_ekf_pmeas *pq, unsigned n,
                              const gf_ekf_meas *meas, gf_kf_work *work)
{
    if (!pq || !meas || !work || !meas->h || n < 1u || n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *q = NULL;
    const gf_status st =
        gf_kfc_meas_check(n, meas->m, meas->Q, meas->gate, NULL, work, &q);
    if (st != GF_OK) {
        return st;
    }
    pq->meas = *meas;
    pq->n = n;
    gf_kfc_keep(q, meas->m, pq->Qf, pq->Qe, pq->Qorder);
    return GF_OK;
}

gf_status gf_ekf_update_prepared(gf_kf *ekf, const gf_ekf_pmeas *pq,
                                 const gf_real *z, gf_kf_innovation *info,
                                 gf_kf_work *work)
{
    if (!ekf || !pq || !z || !work || !pq->meas.h || pq->n != ekf->n ||
        pq->meas.m < 1u || pq->meas.m > ekf->n) {
        return GF_ERR_ARG;
    }
    if (!gf_sum_finite(gf_nan_sum(GF_R(0.0), z, pq->meas.m))) {
        return GF_ERR_NONFINITE;
    }
    return ekf_update_step(ekf, &pq->meas, z, pq->Qf, pq->Qe, pq->Qorder, info,
                           work);
}
