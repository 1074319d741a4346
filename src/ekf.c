// SPDX-License-Identifier: MIT
// gf_ekf: the extended Kalman filter for n states, on gf_kf's belief,
// workspace and factored steps (src/kf_core.h).
#include <stddef.h>

#include "gaussfilt/ekf.h"

#include "gf_internal.h"
#include "kf_core.h"
#include "udu.h"

// The states in ekf->angles of ekf->mu wrapped into (-pi, pi] (once a
// step has written the belief: a wrapped entry is finite where it was).
static gf_status ekf_wrap(gf_status st, gf_kf *ekf)
{
    for (unsigned i = 0; st == GF_OK && i < ekf->n; i++) {
        if ((ekf->angles >> i) & 1u) {
            ekf->mu[i] = gf_angle_wrap(ekf->mu[i]);
        }
    }
    return st;
}

gf_status gf_ekf_init(gf_kf *ekf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work)
{
    return ekf_wrap(gf_kfc_init(ekf, n, mu, sigma, angles, work), ekf);
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
    return ekf_wrap(gf_kfc_predict(ekf, mu_bar, G, Rf, Rd, work), ekf);
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
// (angle residuals wrapped) into work->in.y and work->yw, H whitened by
// Q's factors (H_w = F_Q^-1 H, in work->rows): what the correction
// (gf_kfc_correct) takes.
static gf_status ekf_meas_eval(const gf_kf *ekf, const gf_ekf_meas *meas,
                               const gf_real *z, const gf_real *Qf,
                               const unsigned *Qorder, gf_kf_work *work)
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
    return GF_OK;
}

// The updates call the evaluation and the correction in turn from their
// own frames (their frames side by side): a step function of their own
// that called both measured 96 B deeper on the Cortex-M4F, over the
// target.
gf_status gf_ekf_update(gf_kf *ekf, const gf_ekf_meas *meas, const gf_real *z,
                        gf_kf_innovation *info, gf_kf_work *work)
{
    if (!ekf || !meas || !z || !work || !meas->h || ekf->n < 1u ||
        ekf->n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    const gf_kf_factors *q = NULL;
    gf_status st =
        gf_kfc_meas_check(ekf->n, meas->m, meas->Q, meas->gate, z, work, &q);
    if (st == GF_OK) {
        st = ekf_meas_eval(ekf, meas, z, q->F, q->order, work);
    }
    return st != GF_OK
               ? st
               : ekf_wrap(gf_kfc_correct(ekf, meas->m, work->rows, q->F, q->d,
                                         q->order, meas->gate, info, work),
                          ekf);
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
    const gf_status st =
        ekf_meas_eval(ekf, &pq->meas, z, pq->Qf, pq->Qorder, work);
    return st != GF_OK ? st
                       : ekf_wrap(gf_kfc_correct(ekf, pq->meas.m, work->rows,
                                                 pq->Qf, pq->Qe, pq->Qorder,
                                                 pq->meas.gate, info, work),
                                  ekf);
}

// ---- checking a model's Jacobians ---------------------------------------

// The central differences' step at |x| <= 1: about eps^(1/3), a power of
// two so that x +- h_j is exact there.
#ifdef GF_SINGLE_PRECISION
#define EKF_CHECK_STEP GF_R(0.00390625) // 2^-8
#else
#define EKF_CHECK_STEP GF_R(7.62939453125e-06) // 2^-17
#endif

// f(x) (rows entries) and its Jacobian J (rows x n) from the motion, or
// from the measurement if motion is NULL (rows: n, or meas->m); the
// callback's presets as the steps give them.
static gf_status ekf_check_eval(const gf_ekf_motion *motion,
                                const gf_ekf_meas *meas, unsigned n,
                                unsigned rows, const gf_real *x,
                                const gf_real *u, gf_real *f, gf_real *J)
{
    for (unsigned i = 0; i < rows; i++) {
        f[i] = motion ? x[i] : GF_R(0.0);
        for (unsigned j = 0; j < n; j++) {
            J[i * n + j] = (motion && i == j) ? GF_R(1.0) : GF_R(0.0);
        }
    }
    gf_status st;
    if (motion) {
        st = motion->g(motion->ctx, n, x, u, f, J);
    } else if (meas) {
        st = meas->h(meas->ctx, n, rows, x, f, J);
    } else {
        st = GF_ERR_ARG;
    }
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    return gf_sum_finite(
               gf_nan_sum(gf_nan_sum(GF_R(0.0), f, rows), J, rows * n))
               ? GF_OK
               : GF_ERR_NONFINITE;
}

// One model's Jacobian against its central differences (wrap: the outputs
// that are angles), the worst entry kept in *best.
static gf_status ekf_check_jacobian(const gf_ekf_motion *motion,
                                    const gf_ekf_meas *meas, unsigned n,
                                    unsigned rows, const gf_real *mu,
                                    const gf_real *u, unsigned wrap,
                                    gf_ekf_check *best, gf_kf_work *work)
{
    gf_real *J0 = work->rows;
    gf_real *fp = work->steps, *fm = &fp[n], *x = &fm[n], *Jt = &x[n];
    gf_status st = ekf_check_eval(motion, meas, n, rows, mu, u, fp, J0);
    for (unsigned j = 0; j < n && st == GF_OK; j++) {
        for (unsigned k = 0; k < n; k++) {
            x[k] = mu[k];
        }
        const gf_real a = GF_FABS(mu[j]) > 1 ? GF_FABS(mu[j]) : GF_R(1.0);
        const gf_real hi = mu[j] + EKF_CHECK_STEP * a;
        const gf_real lo = mu[j] - EKF_CHECK_STEP * a;
        x[j] = hi;
        st = ekf_check_eval(motion, meas, n, rows, x, u, fp, Jt);
        x[j] = lo;
        if (st == GF_OK) {
            st = ekf_check_eval(motion, meas, n, rows, x, u, fm, Jt);
        }
        for (unsigned i = 0; i < rows && st == GF_OK; i++) {
            gf_real d = fp[i] - fm[i];
            if (i < 32u && ((wrap >> i) & 1u)) {
                d = gf_angle_wrap(d);
            }
            const gf_real D = d / (hi - lo), J = J0[i * n + j];
            gf_real den = GF_R(1000.0) * GF_REAL_EPSILON *
                          (GF_FABS(fp[i]) + GF_FABS(fm[i])) / (hi - lo);
            den = GF_FABS(J) > den ? GF_FABS(J) : den;
            den = GF_FABS(D) > den ? GF_FABS(D) : den;
            const gf_real e = den > 0 ? GF_FABS(J - D) / den : GF_R(0.0);
            if (e > best->worst) {
                best->worst = e;
                best->jacobian = motion ? 0u : 1u;
                best->row = i;
                best->col = j;
                best->given = J;
                best->numeric = D;
            }
        }
    }
    return st;
}

gf_status gf_ekf_check_model(const gf_ekf_motion *motion,
                             const gf_ekf_meas *meas, unsigned n,
                             const gf_real *mu, const gf_real *u,
                             unsigned angles, gf_ekf_check *out,
                             gf_kf_work *work)
{
    if (!out || !mu || !work || (!motion && !meas) || n < 1u ||
        n > GF_KF_NMAX || (motion && !motion->g) ||
        (meas && (!meas->h || meas->m < 1u || meas->m > n))) {
        return GF_ERR_ARG;
    }
    if (!gf_all_finite(mu, n)) {
        return GF_ERR_NONFINITE;
    }
    gf_ekf_check best = {0, 0, 0, 0, 0, 0};
    gf_status st = GF_OK;
    if (motion) {
        st = ekf_check_jacobian(motion, NULL, n, n, mu, u, angles, &best, work);
    }
    if (st == GF_OK && meas) {
        st = ekf_check_jacobian(NULL, meas, n, meas->m, mu, NULL,
                                meas->angle_mask, &best, work);
    }
    if (st == GF_OK) {
        *out = best;
    }
    return st;
}
