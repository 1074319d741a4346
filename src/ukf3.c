#include "gaussfilt/ukf3.h"

#include "gf_internal.h"

#define N_STATE 3u
#define N_SIGMA (2u * N_STATE + 1u)
#define HEADING_MASK (1u << 2) // state entry 2, theta, is an angle

static gf_real weight_m(const gf_ukf3 *ukf, unsigned j)
{
    return j == 0 ? ukf->wm0 : ukf->wi;
}

static gf_real weight_c(const gf_ukf3 *ukf, unsigned j)
{
    return j == 0 ? ukf->wc0 : ukf->wi;
}

// chi_0 = mu, chi_{1+i} = mu + gamma L_i, chi_{4+i} = mu - gamma L_i, with
// L_i the columns of a square root of sigma; off_j = chi_j - mu.
static gf_status sigma_points(const gf_ukf3 *ukf, gf_vec3 chi[N_SIGMA],
                              gf_vec3 off[N_SIGMA])
{
    gf_mat3 L;
    gf_status st = gf_mat3_sqrt_psd(&ukf->sigma, N_STATE, &L);
    if (st != GF_OK) {
        return st;
    }
    for (unsigned k = 0; k < N_STATE; k++) {
        off[0].v[k] = 0;
    }
    for (unsigned i = 0; i < N_STATE; i++) {
        for (unsigned k = 0; k < N_STATE; k++) {
            off[1 + i].v[k] = ukf->gamma * L.m[k][i];
            off[1 + N_STATE + i].v[k] = -ukf->gamma * L.m[k][i];
        }
    }
    for (unsigned j = 0; j < N_SIGMA; j++) {
        for (unsigned k = 0; k < N_STATE; k++) {
            chi[j].v[k] = ukf->mu.v[k] + off[j].v[k];
        }
    }
    return GF_OK;
}

// mean = sum_j w_m,j p_j on the first n entries, taken as p_0 plus the
// weighted residuals about p_0 (the weights sum to one): exact when the
// points coincide, and no large offsets cancel. An entry flagged in
// angle_mask has its residuals wrapped (the mean on the circle near p_0),
// and is wrapped itself.
static void weighted_mean(const gf_ukf3 *ukf, const gf_vec3 p[N_SIGMA],
                          unsigned n, unsigned angle_mask, gf_vec3 *mean)
{
    gf_vec3 r = {{0, 0, 0}};
    for (unsigned k = 0; k < n; k++) {
        const unsigned angle = (angle_mask >> k) & 1u;
        const gf_real ref = p[0].v[k];
        gf_real acc = 0;
        for (unsigned j = 1; j < N_SIGMA; j++) {
            gf_real d = p[j].v[k] - ref;
            acc += weight_m(ukf, j) * ((angle != 0u) ? gf_angle_wrap(d) : d);
        }
        r.v[k] = (angle != 0u) ? gf_angle_wrap(ref + acc) : ref + acc;
    }
    *mean = r;
}

// d = p - mean on the first n entries, angles wrapped, the rest zero.
static void residual(const gf_vec3 *p, const gf_vec3 *mean, unsigned n,
                     unsigned angle_mask, gf_vec3 *d)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        d->v[k] = 0;
    }
    for (unsigned k = 0; k < n; k++) {
        d->v[k] = p->v[k] - mean->v[k];
        if ((angle_mask >> k) & 1u) {
            d->v[k] = gf_angle_wrap(d->v[k]);
        }
    }
}

gf_status gf_ukf3_init(gf_ukf3 *ukf, const gf_vec3 *mu, const gf_mat3 *sigma,
                       const gf_ukf3_params *p)
{
    if (!ukf || !mu || !sigma || !p) {
        return GF_ERR_ARG;
    }
    if (!gf_vec3_is_finite_n(mu, N_STATE) || !GF_ISFINITE(p->alpha) ||
        !GF_ISFINITE(p->beta) || !GF_ISFINITE(p->kappa)) {
        return GF_ERR_NONFINITE;
    }
    // alpha in (0, 1], beta >= 0, kappa >= 0 keep n + lambda > 0.
    if (!(p->alpha > 0) || p->alpha > 1 || p->beta < 0 || p->kappa < 0) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    const gf_real n = (gf_real)N_STATE;
    // lambda = alpha^2 (n + kappa) - n, so n + lambda = alpha^2 (n + kappa)
    const gf_real a2 = p->alpha * p->alpha;
    const gf_real nl = a2 * (n + p->kappa);
    if (!(nl > 0) || !GF_ISFINITE(GF_R(1.0) / nl)) {
        return GF_ERR_ARG;
    }
    gf_ukf3 r;
    r.mu = *mu;
    r.mu.v[2] = gf_angle_wrap(mu->v[2]);
    r.sigma = *sigma;
    gf_mat3_symmetrize(&r.sigma);
    // gamma = sqrt(n + lambda)
    r.gamma = GF_SQRT(nl);
    // w_m0 = lambda / (n + lambda), w_c0 = w_m0 + (1 - alpha^2 + beta),
    // w_i = 1 / (2 (n + lambda))
    r.wm0 = (nl - n) / nl;
    r.wc0 = r.wm0 + (GF_R(1.0) - a2 + p->beta);
    r.wi = GF_R(1.0) / (GF_R(2.0) * nl);
    *ukf = r;
    return GF_OK;
}

gf_status gf_ukf3_predict(gf_ukf3 *ukf, const gf_ekf3_motion *motion,
                          const gf_real *u)
{
    if (!ukf || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&motion->R, N_STATE);
    if (st != GF_OK) {
        return st;
    }

    // chi_{t-1} = (mu, mu + gamma sqrt(Sigma), mu - gamma sqrt(Sigma))
    gf_vec3 chi[N_SIGMA], off[N_SIGMA], y[N_SIGMA];
    st = sigma_points(ukf, chi, off);
    if (st != GF_OK) {
        return st;
    }
    // chi_bar*_j = g(u, chi_j); G is not needed
    for (unsigned j = 0; j < N_SIGMA; j++) {
        gf_mat3 G_unused;
        y[j] = chi[j];
        st = motion->g(motion->ctx, &chi[j], u, &y[j], &G_unused);
        if (st != GF_OK) {
            return gf_callback_status(st);
        }
        if (!gf_vec3_is_finite_n(&y[j], N_STATE)) {
            return GF_ERR_NONFINITE;
        }
    }

    // mu_bar = sum_j w_m,j chi_bar*_j (heading on the circle)
    gf_vec3 mu;
    weighted_mean(ukf, y, N_STATE, HEADING_MASK, &mu);

    // Sigma_bar = sum_j w_c,j (chi_bar*_j - mu_bar)(...)^T + R
    gf_mat3 sigma = motion->R;
    gf_mat3_symmetrize(&sigma);
    for (unsigned j = 0; j < N_SIGMA; j++) {
        gf_vec3 d;
        residual(&y[j], &mu, N_STATE, HEADING_MASK, &d);
        const gf_real w = weight_c(ukf, j);
        for (unsigned a = 0; a < N_STATE; a++) {
            for (unsigned b = a; b < N_STATE; b++) {
                sigma.m[a][b] += w * d.v[a] * d.v[b];
            }
        }
    }
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned b = 0; b < a; b++) {
            sigma.m[a][b] = sigma.m[b][a];
        }
    }
    if (!gf_vec3_is_finite_n(&mu, N_STATE) || !gf_mat3_is_finite(&sigma)) {
        return GF_ERR_NONFINITE;
    }
    st = gf_mat3_check_psd(&sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    ukf->mu = mu;
    ukf->sigma = sigma;
    return GF_OK;
}

gf_status gf_ukf3_update(gf_ukf3 *ukf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ukf) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_meas3_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    const unsigned m = meas->m;

    // chi_bar = (mu_bar, mu_bar +- gamma sqrt(Sigma_bar)), Z_j = h(chi_bar_j)
    gf_vec3 chi[N_SIGMA], off[N_SIGMA], Z[N_SIGMA];
    st = sigma_points(ukf, chi, off);
    if (st != GF_OK) {
        return st;
    }
    for (unsigned j = 0; j < N_SIGMA; j++) {
        gf_mat3 H_unused;
        Z[j].v[0] = Z[j].v[1] = Z[j].v[2] = 0;
        st = meas->h(meas->ctx, &chi[j], &Z[j], &H_unused);
        if (st != GF_OK) {
            return gf_callback_status(st);
        }
        if (!gf_vec3_is_finite_n(&Z[j], m)) {
            return GF_ERR_NONFINITE;
        }
    }

    // z_hat = sum_j w_m,j Z_j
    gf_vec3 zh;
    weighted_mean(ukf, Z, m, meas->angle_mask, &zh);

    // S = sum_j w_c,j (Z_j - z_hat)(Z_j - z_hat)^T + Q   (m x m)
    // Sigma^xz = sum_j w_c,j (chi_bar_j - mu_bar)(Z_j - z_hat)^T   (3 x m)
    gf_mat3 S = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    gf_mat3 Pxz = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned a = 0; a < m; a++) {
        for (unsigned b = 0; b < m; b++) {
            S.m[a][b] = GF_R(0.5) * (meas->Q.m[a][b] + meas->Q.m[b][a]);
        }
    }
    for (unsigned j = 0; j < N_SIGMA; j++) {
        gf_vec3 dz;
        residual(&Z[j], &zh, m, meas->angle_mask, &dz);
        const gf_real w = weight_c(ukf, j);
        for (unsigned a = 0; a < m; a++) {
            for (unsigned b = 0; b < m; b++) {
                S.m[a][b] += w * dz.v[a] * dz.v[b];
            }
        }
        for (unsigned a = 0; a < N_STATE; a++) {
            for (unsigned b = 0; b < m; b++) {
                Pxz.m[a][b] += w * off[j].v[a] * dz.v[b];
            }
        }
    }
    gf_mat3 L;
    st = gf_mat3_chol(&S, m, &L);
    if (st != GF_OK) {
        return gf_mat3_is_finite(&S) ? st : GF_ERR_NONFINITE;
    }

    // y = z - z_hat, angle residuals wrapped; NIS = y^T S^-1 y
    gf_innovation in;
    gf_vec3 yv, Siy;
    residual(z, &zh, m, meas->angle_mask, &yv);
    in.m = m;
    for (unsigned i = 0; i < N_STATE; i++) {
        in.y[i] = yv.v[i];
    }
    gf_mat3_chol_solve(&L, m, &yv, &Siy);
    in.nis = 0;
    for (unsigned i = 0; i < m; i++) {
        in.nis += in.y[i] * Siy.v[i];
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }

    // K = Sigma^xz S^-1: row i of K solves S k = row i of Sigma^xz
    gf_mat3 K = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned i = 0; i < N_STATE; i++) {
        gf_vec3 row = {{Pxz.m[i][0], Pxz.m[i][1], Pxz.m[i][2]}}, k;
        gf_mat3_chol_solve(&L, m, &row, &k);
        for (unsigned j = 0; j < m; j++) {
            K.m[i][j] = k.v[j];
        }
    }

    // mu = mu_bar + K (z - z_hat)
    gf_vec3 mu = ukf->mu;
    for (unsigned i = 0; i < N_STATE; i++) {
        for (unsigned j = 0; j < m; j++) {
            mu.v[i] += K.m[i][j] * in.y[j];
        }
    }
    mu.v[2] = gf_angle_wrap(mu.v[2]);

    // Sigma = Sigma_bar - K S K^T, with K S = Sigma^xz: K S K^T =
    // Sigma^xz K^T, taken on the upper triangle and mirrored.
    gf_mat3 sigma = ukf->sigma;
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned b = a; b < N_STATE; b++) {
            gf_real ksk = 0;
            for (unsigned j = 0; j < m; j++) {
                ksk += GF_R(0.5) * (Pxz.m[a][j] * K.m[b][j] +
                                    K.m[a][j] * Pxz.m[b][j]);
            }
            sigma.m[a][b] -= ksk;
            sigma.m[b][a] = sigma.m[a][b];
        }
    }

    if (!gf_vec3_is_finite_n(&mu, N_STATE) || !gf_mat3_is_finite(&sigma)) {
        return GF_ERR_NONFINITE;
    }
    st = gf_mat3_check_psd(&sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    ukf->mu = mu;
    ukf->sigma = sigma;
    if (info) {
        *info = in;
    }
    return GF_OK;
}
