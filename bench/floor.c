// SPDX-License-Identifier: MIT
// The loop floor of KF2, EKF3 and gf_kf (floor.h): each filter's own code,
// on the steps of floor_core.c.
#include "floor.h"

gf_status floor_kf2_init(floor_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    floor_kf2 nb;
    if (!fl_finite(mu->v, 2)) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = fl_factor(sigma->m[0], 2, nb.ud);
    if (st != GF_OK) {
        return st;
    }
    nb.mu = *mu;
    *kf = nb;
    return GF_OK;
}

gf_status floor_kf2_predict(floor_kf2 *kf, const gf_kf2_model *model,
                            const gf_vec2 *u)
{
    gf_real rud[3], w[2 * 2 * 2 + 4 + 4];
    if (!fl_finite(model->A.m[0], 4) || !fl_finite(model->B.m[0], 4) ||
        !fl_finite(model->c.v, 2) || (u && !fl_finite(u->v, 2))) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = fl_factor(model->R.m[0], 2, rud);
    if (st != GF_OK) {
        return st;
    }
    floor_kf2 nb;
    for (unsigned i = 0; i < 2u; i++) {
        nb.mu.v[i] = model->c.v[i];
        for (unsigned j = 0; j < 2u; j++) {
            nb.mu.v[i] += model->A.m[i][j] * kf->mu.v[j] +
                          (u ? model->B.m[i][j] * u->v[j] : GF_R(0.0));
        }
    }
    fl_predict(2, kf->ud, model->A.m[0], rud, nb.ud, w);
    if (!fl_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE;
    }
    *kf = nb;
    return GF_OK;
}

gf_status floor_kf2_update(floor_kf2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_real *nis)
{
    const unsigned m = meas->m;
    if (m < 1u || m > 2u) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(meas->C.m[0], 2u * m) || !fl_finite(meas->Q.m[0], 4) ||
        !fl_finite(meas->c.v, m) || !fl_finite(z->v, m) ||
        !fl_finite(&meas->gate, 1)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_real q[2], y[2], b[4];
    gf_status st = fl_noise_diag(meas->Q.m[0], 2, m, q);
    if (st != GF_OK) {
        return st;
    }
    for (unsigned i = 0; i < m; i++) {
        y[i] = z->v[i] - meas->c.v[i] -
               (meas->C.m[i][0] * kf->mu.v[0] + meas->C.m[i][1] * kf->mu.v[1]);
    }
    floor_kf2 nb = *kf;
    st = fl_correct_m(2, m, nb.ud, nb.mu.v, meas->C.m[0], q, y, nis, b);
    if (st != GF_OK) {
        return st;
    }
    if (meas->gate > 0 && *nis > meas->gate) {
        return GF_ERR_GATED;
    }
    if (!fl_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE;
    }
    *kf = nb;
    return GF_OK;
}

void floor_kf2_cov(const floor_kf2 *kf, gf_mat2 *sigma)
{
    fl_to_cov(kf->ud, 2, sigma->m[0]);
}

gf_status floor_ekf3_init(floor_ekf3 *ekf, const gf_vec3 *mu,
                          const gf_mat3 *sigma)
{
    floor_ekf3 nb;
    if (!fl_finite(mu->v, 3)) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = fl_factor(sigma->m[0], 3, nb.ud);
    if (st != GF_OK) {
        return st;
    }
    nb.mu = *mu;
    *ekf = nb;
    return GF_OK;
}

gf_status floor_ekf3_predict(floor_ekf3 *ekf, const gf_ekf3_motion *motion,
                             const gf_real *u)
{
    gf_real rud[6], w[3 * 3 * 2 + 6 + 6];
    if (!motion->g) {
        return GF_ERR_ARG;
    }
    gf_status st = fl_factor(motion->R.m[0], 3, rud);
    if (st != GF_OK) {
        return st;
    }
    floor_ekf3 nb;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    nb.mu = ekf->mu;
    st = motion->g(motion->ctx, &ekf->mu, u, &nb.mu, &G);
    if (st != GF_OK) {
        return st;
    }
    if (!fl_finite(G.m[0], 9)) {
        return GF_ERR_NONFINITE;
    }
    fl_predict(3, ekf->ud, G.m[0], rud, nb.ud, w);
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    if (!fl_belief_finite(nb.mu.v, nb.ud, 3)) {
        return GF_ERR_NONFINITE;
    }
    *ekf = nb;
    return GF_OK;
}

gf_status floor_ekf3_update(floor_ekf3 *ekf, const gf_ekf3_meas *meas,
                            const gf_vec3 *z, gf_real *nis)
{
    const unsigned m = meas->m;
    if (!meas->h || m < 1u || m > 3u) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(meas->Q.m[0], 9) || !fl_finite(z->v, m) ||
        !fl_finite(&meas->gate, 1)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_real q[3], y[3], b[6];
    gf_status st = fl_noise_diag(meas->Q.m[0], 3, m, q);
    if (st != GF_OK) {
        return st;
    }
    gf_vec3 zh = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return st;
    }
    if (!fl_finite(H.m[0], 3u * m) || !fl_finite(zh.v, m)) {
        return GF_ERR_NONFINITE;
    }
    for (unsigned i = 0; i < m; i++) {
        y[i] = z->v[i] - zh.v[i];
        if ((meas->angle_mask >> i) & 1u) {
            y[i] = gf_angle_wrap(y[i]);
        }
    }
    floor_ekf3 nb = *ekf;
    st = fl_correct_m(3, m, nb.ud, nb.mu.v, H.m[0], q, y, nis, b);
    if (st != GF_OK) {
        return st;
    }
    if (meas->gate > 0 && *nis > meas->gate) {
        return GF_ERR_GATED;
    }
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    if (!fl_belief_finite(nb.mu.v, nb.ud, 3)) {
        return GF_ERR_NONFINITE;
    }
    *ekf = nb;
    return GF_OK;
}

void floor_ekf3_cov(const floor_ekf3 *ekf, gf_mat3 *sigma)
{
    fl_to_cov(ekf->ud, 3, sigma->m[0]);
}

gf_status floor_kf_init(floor_kf *kf, unsigned n, const gf_real *mu,
                        const gf_real *sigma, floor_kf_work *work)
{
    floor_kf *nb = &work->belief;
    if (n < 1u || n > GF_KF_NMAX) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(mu, n)) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = fl_factor(sigma, n, nb->ud);
    if (st != GF_OK) {
        return st;
    }
    nb->n = n;
    for (unsigned i = 0; i < n; i++) {
        nb->mu[i] = mu[i];
    }
    *kf = *nb;
    return GF_OK;
}

gf_status floor_kf_predict(floor_kf *kf, const gf_kf_model *model,
                           const gf_real *u, floor_kf_work *work)
{
    const unsigned n = kf->n, nu = (u && model->B) ? model->nu : 0u;
    if (!fl_finite(model->A, n * n) || !fl_finite(u ? u : model->A, nu) ||
        !fl_finite(nu ? model->B : model->A, n * nu) ||
        !fl_finite(model->c ? model->c : model->A, model->c ? n : 0u)) {
        return GF_ERR_NONFINITE;
    }
    gf_real *rud = work->rud, *w = work->steps;
    const gf_status st = fl_factor(model->R, n, rud);
    if (st != GF_OK) {
        return st;
    }
    floor_kf *nb = &work->belief;
    nb->n = n;
    // mu_bar = A mu + B u + c
    for (unsigned i = 0; i < n; i++) {
        gf_real acc = model->c ? model->c[i] : GF_R(0.0);
        for (unsigned j = 0; j < n; j++) {
            acc += model->A[i * n + j] * kf->mu[j];
        }
        for (unsigned j = 0; j < nu; j++) {
            acc += model->B[i * nu + j] * u[j];
        }
        nb->mu[i] = acc;
    }
    fl_predict(n, kf->ud, model->A, rud, nb->ud, w);
    if (!fl_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE;
    }
    *kf = *nb;
    return GF_OK;
}

gf_status floor_kf_update(floor_kf *kf, const gf_kf_meas *meas,
                          const gf_real *z, gf_real *nis, floor_kf_work *work)
{
    const unsigned n = kf->n, m = meas->m;
    if (m < 1u || m > n) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(meas->C, m * n) || !fl_finite(meas->Q, m * m) ||
        !fl_finite(z, m) || !fl_finite(&meas->gate, 1) ||
        !fl_finite(meas->c ? meas->c : z, m)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_real *q = work->rud, *y = &work->rud[GF_KF_NMAX];
    gf_status st = fl_noise_diag(meas->Q, m, m, q);
    if (st != GF_OK) {
        return st;
    }
    // y = z - c - C mu
    for (unsigned i = 0; i < m; i++) {
        y[i] = z[i] - (meas->c ? meas->c[i] : GF_R(0.0));
        for (unsigned j = 0; j < n; j++) {
            y[i] -= meas->C[i * n + j] * kf->mu[j];
        }
    }
    floor_kf *nb = &work->belief;
    *nb = *kf;
    st = fl_correct_m(n, m, nb->ud, nb->mu, meas->C, q, y, nis, work->steps);
    if (st != GF_OK) {
        return st;
    }
    if (meas->gate > 0 && *nis > meas->gate) {
        return GF_ERR_GATED;
    }
    if (!fl_belief_finite(nb->mu, nb->ud, n)) {
        return GF_ERR_NONFINITE;
    }
    *kf = *nb;
    return GF_OK;
}

void floor_kf_cov(const floor_kf *kf, gf_real *sigma)
{
    fl_to_cov(kf->ud, kf->n, sigma);
}

// ---- the updates with what the API must also hold ------------------------
//
// What the floors above leave out of gf_kf2_update and gf_ekf3_update and
// the library's update must hold on the stack: Q's factors for m > 1 (here
// fl_factor's packed U D U^T, the least layout), the whitened C or H, the
// whitened innovations beside the innovation returned, the belief's copy
// (kept unchanged on failure), and the n^2 + 2n scratch of the Joseph form
// for an exact quantity (fl_correct_exact), with the S_ii of exact
// quantities on the update's prior (an exact quantity along an earlier
// one's direction is singular). Left out still: the pivoted verdict of Q
// and the move to the root, so the floor is a lower bound of what the
// library's update must hold.

// One scalar update per whitened quantity i (row h_i of hw, rows of n;
// noise d_i of qud; whitened innovation yw_i at the prior mean mu0), each
// at the mean the earlier ones gave; *nis their sum. x: scratch of
// n^2 + 2n (Bierman's b its first n).
static gf_status floor_correct_all(unsigned n, unsigned m, gf_real *ud,
                                   gf_real *mu, const gf_real *mu0,
                                   const gf_real *hw, const gf_real *qud,
                                   const gf_real *yw, gf_real *nis, gf_real *x)
{
    gf_real es[3]; // each exact quantity's h Sigma h^T on the prior
    for (unsigned i = 0; i < m; i++) {
        es[i] = (qud[FL_UD(i, i)] > 0) ? GF_R(0.0) : fl_hsh(n, ud, &hw[i * n]);
    }
    int exact_before = 0;
    *nis = 0;
    for (unsigned i = 0; i < m; i++) {
        const gf_real *h = &hw[i * n];
        const gf_real r = qud[FL_UD(i, i)];
        gf_real y = yw[i], ni = 0;
        for (unsigned j = 0; j < n; j++) {
            y -= h[j] * (mu[j] - mu0[j]);
        }
        const gf_real sii = exact_before ? es[i] : GF_R(0.0);
        exact_before = exact_before || !(r > 0);
        const gf_status st =
            (r > 0) ? fl_correct(n, ud, mu, h, r, y, &ni, x)
                    : fl_correct_exact(n, ud, mu, h, sii, y, &ni, x);
        if (st != GF_OK) {
            return st;
        }
        *nis += ni;
    }
    return GF_OK;
}

gf_status floor_kf2_update_api(floor_kf2 *kf, const gf_kf2_meas *meas,
                               const gf_vec2 *z, gf_innovation *info)
{
    const unsigned m = meas->m;
    if (m < 1u || m > 2u) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(meas->C.m[0], 2u * m) || !fl_finite(meas->c.v, m) ||
        !fl_finite(z->v, m) || !(meas->gate * GF_R(0.0) == 0)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_real qud[3];
    gf_status st = fl_factor(meas->Q.m[0], m, qud);
    if (st != GF_OK) {
        return st;
    }
    gf_innovation in = {m, {0, 0, 0}, 0};
    gf_mat2 cw = meas->C;
    gf_real yw[2];
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - meas->c.v[i] -
                  (cw.m[i][0] * kf->mu.v[0] + cw.m[i][1] * kf->mu.v[1]);
        yw[i] = in.y[i];
    }
    fl_whiten(qud, m, cw.m[0], 2);
    fl_whiten(qud, m, yw, 1);
    floor_kf2 nb = *kf;
    gf_real x[2 * 2 + 2 * 2];
    st = floor_correct_all(2, m, nb.ud, nb.mu.v, kf->mu.v, cw.m[0], qud, yw,
                           &in.nis, x);
    if (st != GF_OK) {
        return st;
    }
    if (meas->gate > 0 && in.nis > meas->gate) {
        st = GF_ERR_GATED;
    } else if (!fl_belief_finite(nb.mu.v, nb.ud, 2)) {
        return GF_ERR_NONFINITE;
    } else {
        *kf = nb;
    }
    if (info) {
        *info = in;
    }
    return st;
}

gf_status floor_ekf3_update_api(floor_ekf3 *ekf, const gf_ekf3_meas *meas,
                                const gf_vec3 *z, gf_innovation *info)
{
    const unsigned m = meas->m;
    if (!meas->h || m < 1u || m > 3u) {
        return GF_ERR_ARG;
    }
    if (!fl_finite(z->v, m) || !(meas->gate * GF_R(0.0) == 0)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_real qud[6];
    gf_status st;
    {
        gf_real q[9]; // Q's m x m block, rows of m
        for (unsigned i = 0; i < m; i++) {
            for (unsigned j = 0; j < m; j++) {
                q[i * m + j] = meas->Q.m[i][j];
            }
        }
        st = fl_factor(q, m, qud);
    }
    if (st != GF_OK) {
        return st;
    }
    gf_vec3 yw = {{0, 0, 0}}; // z_hat, then y, then y_w
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &yw, &H);
    if (st != GF_OK) {
        return st;
    }
    if (!fl_finite(H.m[0], 3u * m) || !fl_finite(yw.v, m)) {
        return GF_ERR_NONFINITE;
    }
    gf_innovation in = {m, {0, 0, 0}, 0};
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - yw.v[i];
        if (meas->angle_mask & (1u << i)) {
            in.y[i] = gf_angle_wrap(in.y[i]);
        }
        yw.v[i] = in.y[i];
    }
    fl_whiten(qud, m, H.m[0], 3);
    fl_whiten(qud, m, yw.v, 1);
    floor_ekf3 nb = *ekf;
    gf_real x[3 * 3 + 2 * 3];
    st = floor_correct_all(3, m, nb.ud, nb.mu.v, ekf->mu.v, H.m[0], qud, yw.v,
                           &in.nis, x);
    if (st != GF_OK) {
        return st;
    }
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    if (meas->gate > 0 && in.nis > meas->gate) {
        st = GF_ERR_GATED;
    } else if (!fl_belief_finite(nb.mu.v, nb.ud, 3)) {
        return GF_ERR_NONFINITE;
    } else {
        *ekf = nb;
    }
    if (info) {
        *info = in;
    }
    return st;
}
