// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/ekf3.h"

#include "gf_filter.h"
#include "gf_internal.h"
#include "gf_meas3.h"
#include "ldl.h"
#include "udu.h"

gf_status gf_ekf3_motion_forward_turn(void *ctx, const gf_vec3 *mu,
                                      const gf_real *u, gf_vec3 *mu_bar,
                                      gf_mat3 *G)
{
    (void)ctx;
    if (!mu || !u || !mu_bar || !G) {
        return GF_ERR_ARG;
    }
    const gf_real d = u[0], phi = u[1], th = mu->v[2];
    // sin and cos theta land in G's third column (no local of ours has
    // its address taken); their G entries are written below
    gf_sincos(th, &G->m[0][2], &G->m[1][2]);
    const gf_real s = G->m[0][2], c = G->m[1][2];
    // g(u, x) = (x + d cos theta, y + d sin theta, theta + phi)
    mu_bar->v[0] = mu->v[0] + d * c;
    mu_bar->v[1] = mu->v[1] + d * s;
    mu_bar->v[2] = th + phi;
    // G = dg/dx, equation 4.1 (with d = 1 there)
    G->m[0][0] = 1;
    G->m[0][1] = 0;
    G->m[0][2] = -d * s;
    G->m[1][0] = 0;
    G->m[1][1] = 1;
    G->m[1][2] = d * c;
    G->m[2][0] = 0;
    G->m[2][1] = 0;
    G->m[2][2] = 1;
    return GF_OK;
}

gf_status gf_ekf3_meas_x(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                         gf_mat3 *H)
{
    (void)ctx;
    if (!mu_bar || !z_hat || !H) {
        return GF_ERR_ARG;
    }
    // h(x) = x, H = (1 0 0)
    z_hat->v[0] = mu_bar->v[0];
    H->m[0][0] = 1;
    H->m[0][1] = 0;
    H->m[0][2] = 0;
    return GF_OK;
}

gf_status gf_ekf3_meas_xy(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                          gf_mat3 *H)
{
    (void)ctx;
    if (!mu_bar || !z_hat || !H) {
        return GF_ERR_ARG;
    }
    // h(x) = (x, y), H = ((1 0 0), (0 1 0))
    z_hat->v[0] = mu_bar->v[0];
    z_hat->v[1] = mu_bar->v[1];
    H->m[0][0] = 1;
    H->m[0][1] = 0;
    H->m[0][2] = 0;
    H->m[1][0] = 0;
    H->m[1][1] = 1;
    H->m[1][2] = 0;
    return GF_OK;
}

// The checks of a motion model before its callback: GF_ERR_ARG (g NULL),
// R's verdict; on GF_OK, Rf and Rd hold R's factors. (Not inlined: the
// verdict's pivot order stays in this frame, not under the prediction.)
GF_NOINLINE gf_status ekf3_motion_check(const gf_ekf3_motion *motion,
                                        gf_real Rf[9], gf_real Rd[3])
{
    if (!motion->g) {
        return GF_ERR_ARG;
    }
    unsigned order[3];
    return gf_cov_factor(motion->R.m[0], 3, 3, Rf, Rd, order);
}

gf_status gf_ekf3_init(gf_ekf3 *ekf, const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!ekf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    const gf_status st = gf_prior3_check(mu, sigma);
    if (st != GF_OK) {
        return st;
    }
    gf_ekf3 nb;
    gf_real work[GF_UDU_FACTOR_WORK(3u)];
    gf_udu_factor(sigma->m[0], 3, 3, nb.ud, nb.perm, work);
    nb.mu = *mu;
    nb.mu.v[2] = gf_angle_wrap(mu->v[2]);
    if (!gf_belief_finite(nb.mu.v, nb.ud, 3)) {
        return GF_ERR_NONFINITE; // a variance at the end of the range
    }
    *ekf = nb;
    return GF_OK;
}

gf_status gf_ekf3_cov(const gf_ekf3 *ekf, gf_mat3 *sigma)
{
    if (!ekf || !sigma) {
        return GF_ERR_ARG;
    }
    gf_udu_to_cov(ekf->ud, ekf->perm, 3, sigma->m[0], 3);
    return GF_OK;
}

// The prediction, Table 3.3, lines 2-3, with R's factors prepared (or,
// where prepared is NULL, factored here by ekf3_motion_check, before the
// callback runs):
//   mu_bar = g(u, mu) (heading wrapped), G = dg/dx at mu (the callback's;
//   mu_bar preset to mu, G to the identity),
//   Sigma_bar = G Sigma G^T + R on the factors (gf_udu_predict).
// The belief is written only if all of it is finite: a NaN or inf in
// mu_bar or G reaches the result (G_ij is a term of (G U)_ij with U_jj =
// 1, and of some d_j or U_ij of the result), so does an overflow. One
// block s holds the prediction's scratch and then the new factors; R's
// own factors lie in its last 12 entries (the scratch's last 2n and the
// new factors), which gf_udu_predict reads before it writes there.
static gf_status ekf3_predict_step(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                                   const gf_ekf3_pmotion *prepared,
                                   const gf_real *u)
{
    gf_real s[GF_UDU_PREDICT_WORK(3u) + GF_UD_SIZE(3u)];
    gf_real *ud_new = &s[GF_UDU_PREDICT_WORK(3u)];
    gf_real *own = &s[GF_UDU_PREDICT_WORK(3u) - 2u * 3u]; // R's F, then d
    gf_status st = GF_OK;
    if (!prepared) {
        st = ekf3_motion_check(motion, own, &own[9]);
        if (st != GF_OK) {
            return st;
        }
    }
    gf_vec3 mu_bar = ekf->mu;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    st = motion->g(motion->ctx, &ekf->mu, u, &mu_bar, &G);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    mu_bar.v[2] = gf_angle_wrap(mu_bar.v[2]);
    gf_udu_predict(3u, ekf->ud, ud_new, ekf->perm, G.m[0],
                   prepared ? prepared->Rf : own,
                   prepared ? prepared->Rd : &own[9], s);
    if (!gf_belief_finite(mu_bar.v, ud_new, 3)) {
        return GF_ERR_NONFINITE; // keep the last good belief
    }
    ekf->mu = mu_bar;
    for (unsigned k = 0; k < GF_UD_SIZE(3u); k++) {
        ekf->ud[k] = ud_new[k];
    }
    return GF_OK;
}

// The correction, Table 3.3, lines 4-6, with Q's factors prepared (or,
// where prepared is NULL, factored here once gf_meas3_check has checked
// meas and z): z_hat = h(mu_bar) and H from the callback (both preset to
// zeros), y = z - z_hat (angle residuals wrapped), both whitened by Q's
// factors (y_w = F^-1 y, H_w = F^-1 H), then one scalar update per
// quantity (gf_udu_correct), the gate on the total NIS, and the belief
// written only if every quantity passed and all is finite. Q's factors
// and the belief's copy live in blocks of their own: one frame holds them
// in turn, not both.
static gf_status ekf3_update_step(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                                  const gf_ekf3_qfactors *prepared,
                                  const gf_vec3 *z, gf_innovation *info)
{
    const unsigned m = meas->m;
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    gf_vec3 yw = {{0, 0, 0}}; // z_hat, then y, then y_w
    gf_innovation in = {m, {0, 0, 0}, 0};
    gf_real e[3]; // the noises of the whitened quantities, Q's Qe
    gf_status st = GF_OK;
    {
        gf_ekf3_qfactors own;
        const gf_ekf3_qfactors *q = prepared;
        if (!q) {
            st = gf_meas3_check(meas, z, &own);
            if (st != GF_OK) {
                return st;
            }
            q = &own;
        }
        st = meas->h(meas->ctx, &ekf->mu, &yw, &H);
        if (st != GF_OK) {
            return gf_callback_status(st);
        }
        // only the m rows are the callback's answer
        if (!gf_sum_finite(
                gf_nan_sum(gf_nan_sum(GF_R(0.0), yw.v, m), H.m[0], 3u * m))) {
            return GF_ERR_NONFINITE;
        }
        for (unsigned i = 0; i < m; i++) {
            e[i] = q->Qe[i];
        }
        for (unsigned i = 0; i < m; i++) {
            in.y[i] = z->v[i] - yw.v[i];
            if (meas->angle_mask & (1u << i)) {
                in.y[i] = gf_angle_wrap(in.y[i]);
            }
            yw.v[i] = in.y[i];
        }
        gf_udu_whiten(q->Qf, q->Qorder, m, H.m[0], 3);
        gf_udu_whiten(q->Qf, q->Qorder, m, yw.v, 1);
    }
    {
        gf_ekf3 nb = *ekf;
        gf_real work[GF_UDU_CORRECT_WORK(3u)];
        st = gf_udu_correct(3u, nb.ud, nb.perm, m, H.m[0], e, yw.v, nb.mu.v,
                            &in.nis, work);
        if (st != GF_OK) {
            return st;
        }
        nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
        st = gf_update_status(in.nis, meas->gate,
                              gf_belief_finite(nb.mu.v, nb.ud, 3));
        if (st == GF_OK) {
            *ekf = nb;
        }
    }
    return gf_innovation_keep(st, &in, info);
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion) {
        return GF_ERR_ARG;
    }
    return ekf3_predict_step(ekf, motion, NULL, u);
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !z) {
        return GF_ERR_ARG;
    }
    return ekf3_update_step(ekf, meas, NULL, z, info);
}

gf_status gf_ekf3_prepare_motion(gf_ekf3_pmotion *pm,
                                 const gf_ekf3_motion *motion)
{
    if (!pm || !motion) {
        return GF_ERR_ARG;
    }
    gf_ekf3_pmotion p;
    const gf_status st = ekf3_motion_check(motion, p.Rf, p.Rd);
    if (st != GF_OK) {
        return st;
    }
    p.motion = *motion;
    *pm = p;
    return GF_OK;
}

gf_status gf_ekf3_prepare_meas(gf_ekf3_pmeas *pq, const gf_ekf3_meas *meas)
{
    if (!pq || !meas) {
        return GF_ERR_ARG;
    }
    gf_ekf3_pmeas p = {*meas, {{0}, {0}, {0}}};
    const gf_status st = gf_meas3_check(meas, NULL, &p.q);
    if (st != GF_OK) {
        return st;
    }
    *pq = p;
    return GF_OK;
}

gf_status gf_ekf3_predict_prepared(gf_ekf3 *ekf, const gf_ekf3_pmotion *pm,
                                   const gf_real *u)
{
    if (!ekf || !pm || !pm->motion.g) {
        return GF_ERR_ARG;
    }
    return ekf3_predict_step(ekf, &pm->motion, pm, u);
}

gf_status gf_ekf3_update_prepared(gf_ekf3 *ekf, const gf_ekf3_pmeas *pq,
                                  const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !pq || !z || !pq->meas.h || pq->meas.m < 1 || pq->meas.m > 3) {
        return GF_ERR_ARG;
    }
    if (!gf_all_finite(z->v, pq->meas.m)) {
        return GF_ERR_NONFINITE;
    }
    return ekf3_update_step(ekf, &pq->meas, &pq->q, z, info);
}
