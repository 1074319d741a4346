// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gaussfilt/ekf3.h"

#include "gf_filter.h"
#include "steps.h"

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

// The checks of a measurement model before its callback, in the order of
// the status rules: GF_ERR_ARG (h NULL; m not 1..3), GF_ERR_NONFINITE
// (z if not NULL, gate), GF_ERR_ARG (gate < 0), then Q's verdict
// (GF_ERR_NONFINITE, GF_ERR_NOT_PSD); on GF_OK, q holds Q's factors.
static gf_status ekf3_meas_check(const gf_ekf3_meas *meas, const gf_vec3 *z,
                                 gf_ekf3_qfactors *q)
{
    const unsigned m = meas->m;
    if (!meas->h || m < 1 || m > 3) {
        return GF_ERR_ARG;
    }
    if (!gf_sum_finite(z ? gf_nan_sum(meas->gate * GF_R(0.0), z->v, m)
                         : meas->gate * GF_R(0.0))) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    GF_UNROLL
    for (unsigned i = 0; i < 3u; i++) {
        q->Qf[i] = q->Qe[i] = 0;
    }
    if (m == 1u) {
        // one quantity's Q is its own factorisation: F = 1, e = Q
        q->Qe[0] = meas->Q.m[0][0];
        q->Qorder = 0x020100u; // the order 0, 1, 2
        return gf_noise1_check(meas->Q.m[0][0], NULL, NULL, NULL);
    }
    gf_real f[9];
    unsigned o[3];
    o[2] = 2u;
    const gf_status st = gf_cov_factor(meas->Q.m[0], 3, m, f, q->Qe, o);
    if (st != GF_OK) {
        return st;
    }
    q->Qf[0] = f[o[1] * m + o[0]];
    if (m > 2u) {
        q->Qf[1] = f[o[2] * m + o[0]];
        q->Qf[2] = f[o[2] * m + o[1]];
    }
    q->Qorder = o[0] | o[1] << 8u | o[2] << 16u;
    return GF_OK;
}

// The checks of a motion model before its callback: GF_ERR_ARG (g NULL),
// R's verdict; on GF_OK, rf and rd hold R's factors.
static gf_status ekf3_motion_check(const gf_ekf3_motion *motion, gf_real rf[9],
                                   gf_real rd[3])
{
    if (!motion->g) {
        return GF_ERR_ARG;
    }
    unsigned order[3];
    return gf_cov_factor(motion->R.m[0], 3, 3, rf, rd, order);
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
    gf_udu_factor3(sigma->m[0], 3, 3, nb.ud, nb.perm);
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

// The prediction's mean (Table 3.3, line 2) and Jacobian by the callback:
// mu_bar = g(u, mu) (heading wrapped), G = dg/dx at mu. Called from the
// entry points, so the callback runs above the time update's frame.
GF_ALWAYS_INLINE gf_status ekf3_motion_eval(const gf_ekf3 *ekf,
                                            const gf_ekf3_motion *motion,
                                            const gf_real *u, gf_vec3 *mu_bar,
                                            gf_mat3 *G)
{
    // (mu_bar arrives as a copy of mu, G as the identity: ekf3.h)
    *mu_bar = ekf->mu;
    GF_UNROLL
    for (unsigned i = 0; i < 3u; i++) {
        G->m[i][0] = G->m[i][1] = G->m[i][2] = 0;
        G->m[i][i] = 1;
    }
    const gf_status st = motion->g(motion->ctx, &ekf->mu, u, mu_bar, G);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    mu_bar->v[2] = gf_angle_wrap(mu_bar->v[2]);
    return GF_OK;
}

// The prediction's covariance (Table 3.3, line 3) once R is factored (rf,
// rd): Sigma_bar = G Sigma G^T + R on its factors (gf_udu_predict; g: G,
// rows of 3); the belief (mu_bar, Sigma_bar) is written only if all is
// finite. A NaN or inf in mu_bar or G reaches the result (G_ij is a term
// of (G U)_ij with U_jj = 1, and of some d_j or U_ij of the result), so
// does an overflow: one test of the result stands for all.
static gf_status ekf3_predict_step(gf_ekf3 *ekf, const gf_vec3 *mu_bar,
                                   const gf_real *g, const gf_real rf[9],
                                   const gf_real rd[3])
{
    gf_real ud[6];
    {
        gf_real w[2u * 3u * 3u], wd[2u * 3u];
        gf_udu_predict(3u, ekf->ud, ud, ekf->perm, g, rf, rd, w, wd);
    }
    if (!gf_belief_finite(mu_bar->v, ud, 3)) {
        return GF_ERR_NONFINITE; // keep the last good belief
    }
    ekf->mu = *mu_bar;
    GF_UNROLL
    for (unsigned j = 0; j < 6u; j++) {
        ekf->ud[j] = ud[j];
    }
    return GF_OK;
}

// The correction (Table 3.3, lines 4-6) once Q is factored: z_hat =
// h(mu_bar) and H from the callback, y = z - z_hat (angle residuals
// wrapped), both whitened by Q's factors (y_w = F^-1 y, H_w = F^-1 H),
// then one scalar update per quantity (gf_udu_correct), the gate on the
// total NIS, and the belief written only if every quantity passed and all
// is finite. z and Q's factors (gf_ekf3_qfactors: order Qorder, f Qf, e
// Qe) come by value, numbers and not pointers: in registers (on the
// Cortex-M4F z, f and e in s0-s8), so that each entry point's last call,
// to this function, is a tail call and the deepest frame is this one,
// however deep the checks before it went.
GF_NOIPA gf_status ekf3_update_step(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                                    gf_innovation *info, unsigned order,
                                    gf_real z0, gf_real z1, gf_real z2,
                                    gf_real f0, gf_real f1, gf_real f2,
                                    gf_real e0, gf_real e1, gf_real e2)
{
    const unsigned m = meas->m;
    const gf_real e[3] = {e0, e1, e2};
    gf_real yw[3] = {z0, z1, z2}; // z, then y, then y_w
    gf_mat3 H;
    gf_innovation in;
    {
        // z_hat and the rows of H the callback fills arrive as zeros
        gf_vec3 zh;
        GF_UNROLL
        for (unsigned i = 0; i < 3u; i++) {
            zh.v[i] = 0;
            H.m[i][0] = H.m[i][1] = H.m[i][2] = 0;
        }
        const gf_status cst = meas->h(meas->ctx, &ekf->mu, &zh, &H);
        if (cst != GF_OK) {
            return gf_callback_status(cst);
        }
        // only the m rows are the callback's answer
        gf_real f = GF_R(0.0);
        GF_UNROLL
        for (unsigned i = 0; i < 3u; i++) {
            if (i < m) {
                f = gf_nan_sum(f + zh.v[i] * GF_R(0.0), H.m[i], 3);
            }
        }
        if (!gf_sum_finite(f)) {
            return GF_ERR_NONFINITE;
        }
        in.m = m;
        // y = z - z_hat, angle residuals wrapped
        GF_UNROLL
        for (unsigned i = 0; i < 3u; i++) {
            in.y[i] = 0;
            if (i < m) {
                in.y[i] = yw[i] - zh.v[i];
                if (meas->angle_mask & (1u << i)) {
                    in.y[i] = gf_angle_wrap(in.y[i]);
                }
            }
            yw[i] = in.y[i];
        }
    }
    if (m > 1u) {
        // H_w = F^-1 H, y_w = F^-1 y, F's entries below its diagonal put
        // back where gf_cov_factor wrote them (rows of m): the whitening
        // reads no other
        const unsigned o[3] = {order & 255u, (order >> 8u) & 255u,
                               order >> 16u};
        gf_real f[9];
        f[o[1] * m + o[0]] = f0;
        if (m > 2u) {
            f[o[2] * m + o[0]] = f1;
            f[o[2] * m + o[1]] = f2;
        }
        gf_udu_whiten_rows(f, o, m, H.m[0], 3);
        gf_udu_whiten_rows(f, o, m, yw, 1);
    }
    gf_ekf3 nb = *ekf;
    gf_status st =
        gf_udu_correct(3u, nb.ud, nb.perm, m, H.m[0], e, yw, nb.mu.v, &in.nis);
    if (st != GF_OK) {
        return st;
    }
    st = gf_innovation_verdict(&in, meas->gate, info);
    if (st != GF_OK) {
        return st;
    }
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    st = gf_update_done(gf_belief_finite(nb.mu.v, nb.ud, 3), &in, info);
    if (st == GF_OK) {
        *ekf = nb;
    }
    return st;
}

// The prediction once R is factored: the model in this frame (inlined into
// the entry points), then the time update in its own.
GF_ALWAYS_INLINE gf_status ekf3_predict(gf_ekf3 *ekf,
                                        const gf_ekf3_motion *motion,
                                        const gf_real *u, const gf_real rf[9],
                                        const gf_real rd[3])
{
    gf_vec3 mu_bar;
    gf_mat3 G;
    const gf_status st = ekf3_motion_eval(ekf, motion, u, &mu_bar, &G);
    return st != GF_OK ? st : ekf3_predict_step(ekf, &mu_bar, G.m[0], rf, rd);
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion) {
        return GF_ERR_ARG;
    }
    gf_real rf[9], rd[3];
    const gf_status st = ekf3_motion_check(motion, rf, rd);
    return st != GF_OK ? st : ekf3_predict(ekf, motion, u, rf, rd);
}

// ekf3_update_step with z's m entries and Q's factors q as it takes them.
GF_ALWAYS_INLINE gf_status ekf3_update_with(gf_ekf3 *ekf,
                                            const gf_ekf3_meas *meas,
                                            const gf_ekf3_qfactors *q,
                                            const gf_vec3 *z,
                                            gf_innovation *info)
{
    const unsigned m = meas->m;
    return ekf3_update_step(ekf, meas, info, q->Qorder, z->v[0],
                            m > 1u ? z->v[1] : GF_R(0.0),
                            m > 2u ? z->v[2] : GF_R(0.0), q->Qf[0], q->Qf[1],
                            q->Qf[2], q->Qe[0], q->Qe[1], q->Qe[2]);
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !z) {
        return GF_ERR_ARG;
    }
    gf_ekf3_qfactors a;
    {
        // (the factors' copy in memory gone before the last call)
        gf_ekf3_qfactors q;
        const gf_status st = ekf3_meas_check(meas, z, &q);
        if (st != GF_OK) {
            return st;
        }
        a = q;
    }
    return ekf3_update_with(ekf, meas, &a, z, info);
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
    gf_ekf3_pmeas p;
    const gf_status st = ekf3_meas_check(meas, NULL, &p.q);
    if (st != GF_OK) {
        return st;
    }
    p.meas = *meas;
    *pq = p;
    return GF_OK;
}

gf_status gf_ekf3_predict_prepared(gf_ekf3 *ekf, const gf_ekf3_pmotion *pm,
                                   const gf_real *u)
{
    if (!ekf || !pm || !pm->motion.g) {
        return GF_ERR_ARG;
    }
    return ekf3_predict(ekf, &pm->motion, u, pm->Rf, pm->Rd);
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
    return ekf3_update_with(ekf, &pq->meas, &pq->q, z, info);
}
