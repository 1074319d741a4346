#include "gaussfilt/ekf3.h"

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
    // its address taken, so this frame stays small under UKF3's and PF3's
    // large ones); their G entries are written below
    gf_sincos(th, &G->m[0][2], &G->m[1][2]);
    const gf_real s = G->m[0][2], c = G->m[1][2];
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
    if (!gf_vec3_is_finite_n(mu, 3)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat3_check_psd(sigma, 3);
    if (st != GF_OK) {
        return st;
    }
    ekf->mu = *mu;
    ekf->mu.v[2] = gf_angle_wrap(mu->v[2]);
    ekf->sigma = *sigma;
    (void)gf_mat3_symmetrize(&ekf->sigma);
    return GF_OK;
}

// The prediction (Table 3.3, lines 2-3):
//   mu_bar = g(u, mu),  Sigma_bar = G Sigma G^T + R,
// the covariance through its factors (gf_cov_predict). R is checked first,
// then the callback runs; the belief is written only if all is finite.
gf_status gf_ekf3_predict(gf_ekf3 *ekf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ekf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    gf_real f[3][3], e[3]; // R's factors (unused)
    gf_status st = gf_psd_check(motion->R.m[0], 3, 3, f, e);
    if (st != GF_OK) {
        return st;
    }
    gf_ekf3 nb;
    gf_mat3 G = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    nb.mu = ekf->mu;
    st = motion->g(motion->ctx, &ekf->mu, u, &nb.mu, &G);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    // A NaN or inf in mu_bar or G reaches the result (G_ij is W_ij's
    // term with u_jj = 1, and W_ii^2 d_i + ... Sigma_bar_ii's), so does an
    // overflow: one test of the result stands for all.
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    gf_cov_predict(ekf->sigma.m[0], 3, G.m[0], motion->R.m[0],
                   nb.sigma.m[0]);
    if (!gf_all_finite(nb.mu.v, 3) || !gf_all_finite(nb.sigma.m[0], 9)) {
        return GF_ERR_NONFINITE; // keep the last good belief
    }
    *ekf = nb;
    return GF_OK;
}

// The correction (Table 3.3, lines 4-6): z_hat = h(mu_bar) and H from the
// callback, y = z - z_hat (angle residuals wrapped), then gf_cov_correct
// (the quantities decorrelated by Q's factors, one Bierman scalar update
// each), the gate on the total NIS, and the belief written only if every
// quantity passed and all is finite.
gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_meas3_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    const unsigned m = meas->m;
    gf_vec3 zh = {{0, 0, 0}};
    gf_mat3 H = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    st = meas->h(meas->ctx, &ekf->mu, &zh, &H);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    gf_innovation in;
    gf_real y[3];
    in.m = m;
    for (unsigned i = 0; i < 3u; i++) {
        in.y[i] = 0;
        if (i >= m) {
            continue;
        }
        if (!GF_ISFINITE(zh.v[i]) || !GF_ISFINITE(H.m[i][0]) ||
            !GF_ISFINITE(H.m[i][1]) || !GF_ISFINITE(H.m[i][2])) {
            return GF_ERR_NONFINITE;
        }
        in.y[i] = z->v[i] - zh.v[i];
        if (meas->angle_mask & (1u << i)) {
            in.y[i] = gf_angle_wrap(in.y[i]);
        }
        y[i] = in.y[i];
    }
    gf_real v[3][3], e[3];
    (void)gf_udu_factor(meas->Q.m[0], 3, m, 1, v, e);
    gf_ekf3 nb = *ekf;
    st = gf_cov_correct(3, nb.mu.v, nb.sigma.m[0], m, H.m[0], y, v, e,
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
    nb.mu.v[2] = gf_angle_wrap(nb.mu.v[2]);
    if (!gf_all_finite(nb.mu.v, 3) || !gf_all_finite(nb.sigma.m[0], 9)) {
        return GF_ERR_NONFINITE;
    }
    *ekf = nb;
    if (info) {
        *info = in;
    }
    return GF_OK;
}
