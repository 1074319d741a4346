// SPDX-License-Identifier: MIT
// gf_kf and the steps gf_ekf shares with it (src/kf_core.h): the factored
// core of src/udu.h for n states, 1 <= n <= GF_KF_NMAX, with the scratch
// that grows with n^2 in the caller's gf_kf_work.
#include <stddef.h>

#include "gaussfilt/kf.h"

#include "kf_core.h"
#include "steps.h"

// ---- shared with ekf.c ---------------------------------------------------

// dst's mu and factors = src's, for n states (the order left as it is).
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
    unsigned *p = work->k;
    if (!fac) {
        return gf_cov_factor_n(s, n, n, NULL, NULL, NULL, work->x, p);
    }
    gf_kf_factors *f = &work->f;
    const gf_status st =
        gf_cov_factor_n(s, n, n, f->F, f->d, f->order, work->x, p);
    if (st == GF_OK) {
        *fac = f;
    }
    return st;
}

// The belief N(mu, sigma) of gf_kfc_init once sigma is judged: built in
// work->b (the factors' low parts in work->x), then *kf = it if finite. A
// frame of its own, reached by a tail call: the factorisation's registers
// and temporaries are not in gf_kfc_init's frame under gf_kfc_noise's
// verdict.
GF_NOINLINE gf_status kfc_init_belief(gf_kf *kf, unsigned n, const gf_real *mu,
                                      const gf_real *sigma, unsigned angles,
                                      gf_kf_work *work)
{
    gf_kf *nb = &work->b;
    nb->n = n;
    nb->angles = angles;
    for (unsigned k = 0; k < GF_KF_PERM_BYTES; k++) {
        nb->perm[k] = 0;
    }
    gf_udu_factor_n(sigma, n, n, nb->ud, nb->perm, work->x); // (x: free again)
    for (unsigned i = 0; i < GF_KF_NMAX; i++) {
        nb->mu[i] = i < n ? mu[i] : GF_R(0.0);
        if (i < n && (angles >> i) & 1u) {
            nb->mu[i] = gf_angle_wrap(mu[i]);
        }
    }
    for (unsigned k = GF_KF_TRI(n); k < GF_KF_TRI(GF_KF_NMAX); k++) {
        nb->ud[k] = 0;
    }
    if (!gf_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE; // a variance at the end of the range
    }
    *kf = *nb;
    return GF_OK;
}

gf_status gf_kfc_init(gf_kf *kf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work)
{
    if (!kf || !mu || !sigma || !work || n < 1u || n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    if (!gf_sum_finite(gf_nan_sum(GF_R(0.0), mu, n))) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = gf_kfc_noise(sigma, n, work, NULL);
    if (st != GF_OK) {
        return st;
    }
    return kfc_init_belief(kf, n, mu, sigma, angles, work);
}

// The factored steps: KF2's and EKF3's for n = 2 and 3, and those for 4
// (steps.c, steps4.c: the loops unrolled), compiled here for any other n.
GF_NOINLINE void kfc_udu_predict(unsigned n, const gf_real *ud, gf_real *ud_new,
                                 const unsigned char *perm, const gf_real *G,
                                 const gf_real *Rf, const gf_real *Rd,
                                 gf_kf_work *work)
{
    gf_real *w = work->w;
    if (n == 2u) {
        gf_udu_predict2(ud, ud_new, perm, G, Rf, Rd, w);
    } else if (n == 3u) {
        gf_udu_predict3(ud, ud_new, perm, G, Rf, Rd, w);
    } else if (n == 4u) {
        gf_udu_predict4(ud, ud_new, perm, G, Rf, Rd, w);
    } else {
        gf_udu_predict_s(n, ud, ud_new, perm, G, Rf, Rd, w, GF_KFC_S(work, 2),
                         &w[GF_UDU_SV(n)]);
    }
}

// gf_udu_correct_s for any n, as gf_udu_correct2 for 2: a frame of its
// own, reached by a tail call as those for n = 2, 3, 4 are.
GF_NOINLINE gf_status kfc_correct_n(unsigned m, const gf_real *hw,
                                    const gf_real *e, gf_kf_work *work)
{
    const unsigned n = work->b.n;
    return gf_udu_correct_s(n, work->b.ud, work->b.perm, m, hw, e, work->s,
                            work->b.mu, &work->in.nis, &work->w[GF_UDU_SV(n)]);
}

// The correction of work->b's factors (gf_udu_correct2's arguments).
GF_NOINLINE gf_status kfc_udu_correct(unsigned m, const gf_real *hw,
                                      const gf_real *e, gf_kf_work *work)
{
    const unsigned n = work->b.n;
    if (n == 2u) {
        return gf_udu_correct2(m, hw, e, work);
    }
    if (n == 3u) {
        return gf_udu_correct3(m, hw, e, work);
    }
    if (n == 4u) {
        return gf_udu_correct4(m, hw, e, work);
    }
    return kfc_correct_n(m, hw, e, work);
}

gf_status gf_kfc_predict(gf_kf *kf, const gf_real *mu_bar, const gf_real *G,
                         const gf_real *Rf, const gf_real *Rd, gf_kf_work *work)
{
    const unsigned n = kf->n;
    gf_kf *nb = &work->b; // its mu and factors (the order stays kf's)
    for (unsigned i = 0; i < n; i++) {
        nb->mu[i] =
            ((kf->angles >> i) & 1u) ? gf_angle_wrap(mu_bar[i]) : mu_bar[i];
    }
    // Sigma_bar = G Sigma G^T + R on the factors (Thornton)
    kfc_udu_predict(n, kf->ud, nb->ud, kf->perm, G, Rf, Rd, work);
    if (!gf_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    kfc_copy_moments(kf, nb, n);
    return GF_OK;
}

// *info = *in (if info is not NULL), the entries of y past m zero.
static void kfc_info(gf_kf_innovation *info, const gf_kf_innovation *in)
{
    if (info) {
        info->m = in->m;
        info->nis = in->nis;
        for (unsigned i = 0; i < GF_KF_NMAX; i++) {
            info->y[i] = i < in->m ? in->y[i] : GF_R(0.0);
        }
    }
}

gf_status gf_kfc_update_begin(const gf_kf *kf, unsigned m, const gf_real *Qf,
                              const unsigned *Qorder, gf_kf_work *work)
{
    work->in.m = m;
    if (m > 1u) {
        gf_udu_whiten(Qf, Qorder, m, work->s, 1);
    }
    kfc_copy(&work->b, kf);
    return GF_OK;
}

gf_status gf_kfc_update(gf_kf *kf, const gf_real *hw, const gf_real *Qe,
                        gf_real gate, gf_kf_innovation *info, gf_kf_work *work)
{
    gf_kf *nb = &work->b;
    gf_kf_innovation *in = &work->in;
    const gf_status st = kfc_udu_correct(in->m, hw, Qe, work);
    if (st != GF_OK) {
        return st;
    }
    if (!GF_ISFINITE(in->nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gate > 0 && in->nis > gate) {
        kfc_info(info, in);
        return GF_ERR_GATED;
    }
    const unsigned n = nb->n;
    for (unsigned i = 0; i < n; i++) {
        if ((nb->angles >> i) & 1u) {
            nb->mu[i] = gf_angle_wrap(nb->mu[i]);
        }
    }
    if (!gf_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE;
    }
    kfc_copy(kf, nb);
    kfc_info(info, in);
    return GF_OK;
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

// mu_bar = A mu + B u + c, into work->s, then the factored prediction.
static gf_status kf_predict_step(gf_kf *kf, const gf_kf_model *model,
                                 const gf_real *u, const gf_real *Rf,
                                 const gf_real *Rd, gf_kf_work *work)
{
    const unsigned n = kf->n;
    gf_real *mu_bar = GF_KFC_S(work, 4);
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
// work->f (gf_kfc_noise) and F_Q^-1 C in work->x. The factors' pointer is
// this frame's, so that the callers keep no local whose address is taken
// (gf_kf_update's last call is then a tail call).
static gf_status kf_meas_check(unsigned n, const gf_kf_meas *meas,
                               const gf_real *z, gf_kf_work *work)
{
    const gf_kf_factors *q = NULL;
    const gf_kf_factors **fac = &q;
    gf_real *Cw = work->x;
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
    const gf_status st =
        gf_kfc_meas_check(n, m, meas->Q, meas->gate, z, work, fac);
    if (st != GF_OK) {
        return st;
    }
    // C_w = F_Q^-1 C, column by column
    for (unsigned k = 0; k < m * n; k++) {
        Cw[k] = meas->C[k];
    }
    if (m > 1u) {
        gf_udu_whiten_rows((*fac)->F, (*fac)->order, m, Cw, n);
    }
    return GF_OK;
}

// y = z - c - C mu_bar into work->in.y and work->s (y_w to be).
GF_NOINLINE void kf_innovation(const gf_kf *kf, const gf_kf_meas *meas,
                               const gf_real *z, gf_kf_work *work)
{
    const unsigned n = kf->n, m = meas->m;
    gf_real *y = work->in.y;
    // (z_i - c_i) - (C mu)_i: KF2's order of operations
    for (unsigned i = 0; i < m; i++) {
        gf_real dot = meas->C[(size_t)i * n] * kf->mu[0];
        for (unsigned j = 1; j < n; j++) {
            dot += meas->C[i * n + j] * kf->mu[j];
        }
        y[i] = z[i] - (meas->c ? meas->c[i] : GF_R(0.0)) - dot;
        work->s[i] = y[i];
    }
}

gf_status gf_kf_update(gf_kf *kf, const gf_kf_meas *meas, const gf_real *z,
                       gf_kf_innovation *info, gf_kf_work *work)
{
    if (!kf || !meas || !z || !work || kf->n < 1u || kf->n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    // Q's factors in work->f, the whitened rows in work->x
    const gf_status st = kf_meas_check(kf->n, meas, z, work);
    if (st != GF_OK) {
        return st;
    }
    // then the correction, a tail call (gf_kfc_update_begin)
    kf_innovation(kf, meas, z, work);
    (void)gf_kfc_update_begin(kf, meas->m, work->f.F, work->f.order, work);
    return gf_kfc_update(kf, work->x, work->f.d, meas->gate, info, work);
}

gf_status gf_kf_prepare_meas(gf_kf_pmeas *pq, unsigned n,
                             const gf_kf_meas *meas, gf_kf_work *work)
{
    if (!pq || !meas || !work) {
        return GF_ERR_ARG;
    }
    const gf_status st = kf_meas_check(n, meas, NULL, work);
    const gf_kf_factors *q = &work->f;
    if (st != GF_OK) {
        return st;
    }
    pq->meas = *meas;
    pq->n = n;
    gf_kfc_keep(q, meas->m, pq->Qf, pq->Qe, pq->Qorder);
    for (unsigned k = 0; k < meas->m * n; k++) {
        pq->Cw[k] = work->x[k];
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
    (void)gf_kfc_update_begin(kf, pq->meas.m, pq->Qf, pq->Qorder, work);
    return gf_kfc_update(kf, pq->Cw, pq->Qe, pq->meas.gate, info, work);
}
