#include "gaussfilt/ekf3.h"

static int vec3_is_finite(const gf_vec3 *x, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        if (!GF_ISFINITE(x->v[i])) {
            return 0;
        }
    }
    return 1;
}

// A model callback's status, with anything that is not a known failure
// mapped to GF_ERR_MODEL; so is GF_ERR_GATED, which only the filter's own
// gate may report (the caller then expects the innovation to be written).
static gf_status callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
               ? GF_ERR_MODEL : st;
}

gf_status gf_ekf3_motion_forward_turn(void *ctx, const gf_vec3 *mu,
                                      const gf_real *u, gf_vec3 *mu_bar,
                                      gf_mat3 *G)
{
    (void)ctx;
    if (!mu || !u || !mu_bar || !G) {
        return GF_ERR_ARG;
    }
    const gf_real d = u[0], phi = u[1], th = mu->v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    // g(u, x) = (x + d cos theta, y + d sin theta, theta + phi)
    mu_bar->v[0] = mu->v[0] + d * c;
    mu_bar->v[1] = mu->v[1] + d * s;
    mu_bar->v[2] = th + phi;
    // G = dg/dx, equation 4.1 (with d = 1 there)
    G->m[0][0] = 1; G->m[0][1] = 0; G->m[0][2] = -d * s;
    G->m[1][0] = 0; G->m[1][1] = 1; G->m[1][2] = d * c;
    G->m[2][0] = 0; G->m[2][1] = 0; G->m[2][2] = 1;
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
    H->m[0][0] = 1; H->m[0][1] = 0; H->m[0][2] = 0;
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
    H->m[0][0] = 1; H->m[0][1] = 0; H->m[0][2] = 0;
    H->m[1][0] = 0; H->m[1][1] = 1; H->m[1][2] = 0;
    return GF_OK;
}

gf_status gf_ekf3_init(gf_ekf3 *ekf, const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!ekf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!vec3_is_finite(mu, 3)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat3_check_psd(sigma, 3);
    if (st != GF_OK) {
        return st;
    }
    ekf->mu = *mu;
    ekf->mu.v[2] = gf_angle_wrap(mu->v[2]);
    ekf->sigma = *sigma;
    gf_mat3_symmetrize(&ekf->sigma);
    return GF_OK;
}

gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&motion->R, 3);
    if (st != GF_OK) {
        return st;
    }

    // mu_bar = g(u, mu), G = dg/dx at mu
    gf_vec3 mu = ekf->mu;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    st = motion->g(motion->ctx, &ekf->mu, u, &mu, &G);
    if (st != GF_OK) {
        return callback_status(st);
    }
    if (!vec3_is_finite(&mu, 3) || !gf_mat3_is_finite(&G)) {
        return GF_ERR_NONFINITE;
    }
    mu.v[2] = gf_angle_wrap(mu.v[2]);

    // Sigma_bar = G Sigma G^T + R
    gf_mat3 sigma;
    gf_mat3_sandwich(&G, &ekf->sigma, &sigma);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            sigma.m[i][j] += motion->R.m[i][j];
        }
    }
    gf_mat3_symmetrize(&sigma);

    if (!gf_mat3_is_finite(&sigma)) {
        return GF_ERR_NONFINITE;
    }
    ekf->mu = mu;
    ekf->sigma = sigma;
    return GF_OK;
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !meas->h || !z || meas->m < 1 || meas->m > 3) {
        return GF_ERR_ARG;
    }
    const unsigned m = meas->m;
    if (!vec3_is_finite(z, m) || !GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&meas->Q, m);
    if (st != GF_OK) {
        return st;
    }

    // z_hat = h(mu_bar), H = dh/dx at mu_bar (first m rows)
    gf_vec3 zh = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return callback_status(st);
    }
    for (unsigned i = m; i < 3; i++) { // rows the model must not use
        zh.v[i] = 0;
        H.m[i][0] = H.m[i][1] = H.m[i][2] = 0;
    }
    if (!vec3_is_finite(&zh, m) || !gf_mat3_is_finite(&H)) {
        return GF_ERR_NONFINITE;
    }

    const gf_mat3 *sig = &ekf->sigma;
    // PHt = Sigma_bar H^T (3 x m), S = H Sigma_bar H^T + Q (m x m)
    gf_mat3 PHt = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            PHt.m[i][j] = sig->m[i][0] * H.m[j][0] + sig->m[i][1] * H.m[j][1] +
                          sig->m[i][2] * H.m[j][2];
        }
    }
    gf_mat3 S = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = i; j < m; j++) {
            S.m[i][j] = H.m[i][0] * PHt.m[0][j] + H.m[i][1] * PHt.m[1][j] +
                        H.m[i][2] * PHt.m[2][j] +
                        GF_R(0.5) * (meas->Q.m[i][j] + meas->Q.m[j][i]);
            S.m[j][i] = S.m[i][j];
        }
    }
    gf_mat3 L;
    st = gf_mat3_chol(&S, m, &L);
    if (st != GF_OK) {
        return gf_mat3_is_finite(&S) ? st : GF_ERR_NONFINITE;
    }

    // y = z - h(mu_bar), angle residuals wrapped
    gf_innovation in;
    in.m = m;
    in.y[0] = in.y[1] = in.y[2] = 0;
    for (unsigned i = 0; i < m; i++) {
        in.y[i] = z->v[i] - zh.v[i];
        if (meas->angle_mask & (1u << i)) {
            in.y[i] = gf_angle_wrap(in.y[i]);
        }
    }
    // NIS = y^T S^-1 y
    gf_vec3 yv = {{in.y[0], in.y[1], in.y[2]}}, Siy;
    gf_mat3_chol_solve(&L, m, &yv, &Siy);
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        in.nis += in.y[i] * Siy.v[i];
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate > 0 && in.nis > meas->gate) {
        if (info) {
            *info = in;
        }
        return GF_ERR_GATED;
    }

    // K = Sigma_bar H^T S^-1: row i of K solves S k = row i of PHt
    gf_mat3 K = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < 3; i++) {
        gf_vec3 row = {{PHt.m[i][0], PHt.m[i][1], PHt.m[i][2]}}, k;
        gf_mat3_chol_solve(&L, m, &row, &k);
        for (unsigned j = 0; j < m; j++) {
            K.m[i][j] = k.v[j];
        }
    }

    // mu = mu_bar + K y
    gf_vec3 mu = ekf->mu;
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < m; j++) {
            mu.v[i] += K.m[i][j] * in.y[j];
        }
    }
    mu.v[2] = gf_angle_wrap(mu.v[2]);

    // Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T, then symmetrized
    gf_mat3 IKH = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned k = 0; k < 3; k++) {
            for (unsigned j = 0; j < m; j++) {
                IKH.m[i][k] -= K.m[i][j] * H.m[j][k];
            }
        }
    }
    gf_mat3 sigma;
    gf_mat3_sandwich(&IKH, sig, &sigma);
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned k = i; k < 3; k++) {
            gf_real kqk = 0;
            for (unsigned a = 0; a < m; a++) {
                for (unsigned b = 0; b < m; b++) {
                    kqk += K.m[i][a] * meas->Q.m[a][b] * K.m[k][b];
                }
            }
            sigma.m[i][k] += kqk;
            sigma.m[k][i] = sigma.m[i][k];
        }
    }

    if (!vec3_is_finite(&mu, 3) || !gf_mat3_is_finite(&sigma)) {
        return GF_ERR_NONFINITE;
    }
    ekf->mu = mu;
    ekf->sigma = sigma;
    if (info) {
        *info = in;
    }
    return GF_OK;
}
