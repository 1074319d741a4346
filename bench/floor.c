// SPDX-License-Identifier: MIT
// The loop floor of KF2 (floor.h): the filter's own code, on the steps of
// floor_core.c.
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

gf_status floor_kf2_predict(floor_kf2 *kf, const gf_kf2_model *model)
{
    gf_real rud[3], w[2 * 2 * 2 + 4 + 4];
    if (!fl_finite(model->A.m[0], 4) || !fl_finite(model->B.m[0], 4) ||
        !fl_finite(model->c.v, 2)) {
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
            nb.mu.v[i] += model->A.m[i][j] * kf->mu.v[j];
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
    if (meas->m != 1u) {
        return GF_ERR_ARG;
    }
    const gf_real q = meas->Q.m[0][0];
    const gf_real t =
        q * GF_R(0.0) + z->v[0] * GF_R(0.0) + meas->gate * GF_R(0.0);
    if (!fl_finite(meas->C.m[0], 2) || !(t == 0)) {
        return GF_ERR_NONFINITE;
    }
    if (q < 0 || meas->gate < 0) {
        return q < 0 ? GF_ERR_NOT_PSD : GF_ERR_ARG;
    }
    floor_kf2 nb = *kf;
    const gf_real *h = meas->C.m[0];
    const gf_real y =
        z->v[0] - meas->c.v[0] - (h[0] * kf->mu.v[0] + h[1] * kf->mu.v[1]);
    gf_real b[2];
    const gf_status st = fl_correct(2, nb.ud, nb.mu.v, h, q, y, nis, b);
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
    if (!meas->h || meas->m != 1u) {
        return GF_ERR_ARG;
    }
    const gf_real q = meas->Q.m[0][0];
    const gf_real t =
        q * GF_R(0.0) + z->v[0] * GF_R(0.0) + meas->gate * GF_R(0.0);
    if (!(t == 0)) {
        return GF_ERR_NONFINITE;
    }
    if (q < 0 || meas->gate < 0) {
        return q < 0 ? GF_ERR_NOT_PSD : GF_ERR_ARG;
    }
    gf_vec3 zh = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    gf_status st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return st;
    }
    if (!fl_finite(H.m[0], 3) || !(zh.v[0] * GF_R(0.0) == 0)) {
        return GF_ERR_NONFINITE;
    }
    gf_real y = z->v[0] - zh.v[0];
    if (meas->angle_mask & 1u) {
        y = gf_angle_wrap(y);
    }
    floor_ekf3 nb = *ekf;
    gf_real b[3];
    st = fl_correct(3, nb.ud, nb.mu.v, H.m[0], q, y, nis, b);
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
