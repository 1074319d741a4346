// SPDX-License-Identifier: MIT
#include "gaussfilt/ukf3.h"

#include "gf_filter.h"
#include "gf_internal.h"
#include "gf_meas3.h"
#include "ldl.h"

#define N_STATE 3u
#define N_SIGMA (2u * N_STATE + 1u)
#define HEADING_MASK (1u << 2) // state entry 2, theta, is an angle

// No array of sigma points or of their images is kept: each point is made
// when needed from the packed square root of Sigma (chi_j = mu + off_j),
// and its image is added to the sums at once (they are taken about the
// centre's image, which comes first). How the code is laid out for the
// stack: docs/ukf3.md.

// UKF3_SMALL_CALL: a small helper of the large frames, a call (never
// inlined) under -Os, inlined under gcc and clang otherwise.
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define UKF3_SMALL_CALL static inline __attribute__((always_inline))
#elif defined(__GNUC__)
#define UKF3_SMALL_CALL static __attribute__((noinline))
#else
#define UKF3_SMALL_CALL static
#endif

// Entry k of off_j = chi_j - mu: off_0 = 0, off_{1+i} = gamma L_i,
// off_{4+i} = -gamma L_i (L_i column i of L, packed as GF_TRI). With
// WEIGHTED added to k, entry k of w_i off_j (the weight read here, not
// passed in).
#define WEIGHTED 4u
static inline gf_real ukf3_offset(const gf_ukf3 *ukf, const gf_real l[6],
                                  unsigned j, unsigned k)
{
    const unsigned i = (j - 1u) % N_STATE;
    const unsigned e = k % WEIGHTED;
    gf_real o = 0;
    if (j > 0u && e >= i) {
        o = ukf->gamma * l[GF_TRI(e, i)];
    }
    o = (j > N_STATE) ? -o : o;
    return (k >= WEIGHTED) ? ukf->wi * o : o;
}

// chi_j = mu + off_j.
UKF3_SMALL_CALL void ukf3_sigma_point(const gf_ukf3 *ukf, const gf_real l[6],
                                      unsigned j, gf_vec3 *chi)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        const gf_real o = ukf3_offset(ukf, l, j, k);
        chi->v[k] = ukf->mu.v[k] + o;
    }
}

// The flagged entries among the first n of d wrapped to (-pi, pi], the
// entries from n on zeroed: the second half of a residual, and the last
// step of a mean. The one helper that calls gf_angle_wrap.
UKF3_SMALL_CALL void ukf3_wrap_flagged(gf_vec3 *d, unsigned n,
                                       unsigned angle_mask)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        if (k >= n) {
            d->v[k] = 0;
        } else if ((angle_mask & (1u << k)) != 0u) {
            d->v[k] = gf_angle_wrap(d->v[k]);
        } else {
            // kept as it is
        }
    }
}

// d = p - ref on the first n entries, those flagged in angle_mask wrapped,
// the rest zero; d may be p or ref.
static inline void ukf3_residual(const gf_vec3 *p, const gf_vec3 *ref,
                                 unsigned n, unsigned angle_mask, gf_vec3 *d)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        d->v[k] = p->v[k] - ref->v[k];
    }
    ukf3_wrap_flagged(d, n, angle_mask);
}

// The sums take differences of images of nearby points and weigh them by
// w_i ~ 1 / alpha^2 (ukf3.h): the rounding of the images, up to eps |.|
// an entry, reaches mean entry k as up to
//   b_k = eps w_i sum_{j>0, e_j,k != 0} (|Z_0,k| + |Z_j,k|),
// |Z_j,k| <= |Z_0,k| + |e_j,k|. The moments are taken as resolved while
// b_k is at most a quarter of the entry's predicted sigma: b_k^2 <= v / 16.
#define UNRESOLVED(b2, v) ((b2)*GF_R(16.0) > (v))

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
    // alpha in (0, 1], beta >= 0, kappa >= 0 keep n + lambda > 0; alpha
    // below GF_UKF3_ALPHA_MIN lets the rounding of the points' images,
    // divided by alpha^2, swamp the moments (ukf3.h).
    if (!(p->alpha >= GF_UKF3_ALPHA_MIN) || p->alpha > 1 || p->beta < 0 ||
        p->kappa < 0) {
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
    (void)gf_mat3_symmetrize(&r.sigma);
    // gamma = sqrt(n + lambda), w_i = 1 / (2 (n + lambda)); the centre's
    // weights w_m,0 = lambda / (n + lambda) and w_c,0 = w_m,0 + 1 -
    // alpha^2 + beta are never formed (see the sums below): only what is
    // left of them once folded, beta - alpha^2.
    r.gamma = GF_SQRT(nl);
    r.wi = GF_R(1.0) / (GF_R(2.0) * nl);
    r.wfold = p->beta - a2;
    *ukf = r;
    return GF_OK;
}

// The new belief of a prediction, written to the filter once
// gf_mat3_check_psd has accepted its Sigma.
typedef struct ukf3_belief {
    gf_vec3 mu;
    gf_mat3 sigma;
} ukf3_belief;

// l = sqrt(Sigma), packed: gf_sqrt_psd_packed in a frame of its own, so
// that the steps' large frames neither hold its inlined arithmetic's
// temporaries nor save the registers it keeps across the square roots.
GF_NOINLINE void ukf3_sigma_sqrt(const gf_mat3 *sigma, gf_real l[6])
{
    gf_sqrt_psd_packed(sigma, N_STATE, l);
}

// The prediction's working set, in the frame of gf_ukf3_predict: the
// arguments, sqrt(Sigma) (packed), the new belief, Sigma_bar's upper
// triangle summed packed in s (entry (a, c), a <= c, at GF_TRI(c, a)), the
// mean's sum m and, in b, the rounding bound of each mean entry
// (UNRESOLVED) summed in the order of the points. nb.mu keeps the centre's
// image while the points are summed, and nb.sigma is g's G until s is
// unpacked into it.
typedef struct ukf3_pred {
    const gf_ukf3 *ukf;
    const gf_ekf3_motion *motion;
    const gf_real *u;
    gf_real l[6];
    gf_real s[6];
    gf_vec3 m;
    gf_vec3 b;
    ukf3_belief nb;
} ukf3_pred;

// Image j's terms (j > 0), e_j = chi_bar*_j - chi_bar*_0 in e, added to
// the sums.
GF_NOINLINE void ukf3_predict_add(ukf3_pred *w, const gf_vec3 *e)
{
    const gf_real wi = w->ukf->wi;
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real we = wi * e->v[a];
        w->m.v[a] += we;
        for (unsigned c = a; c < N_STATE; c++) {
            w->s[GF_TRI(c, a)] += we * e->v[c];
        }
        if (GF_FABS(e->v[a]) > 0) {
            w->b.v[a] += GF_R(2.0) * GF_FABS(w->nb.mu.v[a]) + GF_FABS(e->v[a]);
        }
    }
}

// G = I in w->nb.sigma, then chi_j (sigma_point, a tail call): a call of
// its own, so that predict_point keeps fewer registers (and saves fewer)
// across g's call.
UKF3_SMALL_CALL void ukf3_point_start(ukf3_pred *w, unsigned j, gf_vec3 *chi)
{
    static const gf_mat3 identity = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    w->nb.sigma = identity;
    ukf3_sigma_point(w->ukf, w->l, j, chi);
}

// Point j through g: chi_j, then chi_bar*_j = g(u, chi_j) in e (G is not
// needed, but it arrives as the identity: ekf3.h's promise to every
// motion callback), kept as the centre's image (j = 0) or taken as its
// residual about it and added to the sums. A call of its own, so that
// only the point and its image are on the stack above the working set
// while g runs; the sums are added in a call of their own after g has
// returned.
GF_NOINLINE gf_status ukf3_predict_point(ukf3_pred *w, unsigned j)
{
    gf_vec3 chi;
    gf_vec3 e;
    ukf3_point_start(w, j, &chi);
    e = chi;
    const gf_status st =
        w->motion->g(w->motion->ctx, &chi, w->u, &e, &w->nb.sigma);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    if (!gf_vec3_is_finite_n(&e, N_STATE)) {
        return GF_ERR_NONFINITE;
    }
    if (j == 0u) {
        w->nb.mu = e; // chi_bar*_0, the centre's image
    } else {
        ukf3_residual(&e, &w->nb.mu, N_STATE, HEADING_MASK, &e);
        ukf3_predict_add(w, &e);
    }
    return GF_OK;
}

// The prediction's moments from the sums, into w->nb, checked finite and
// resolved (not yet PSD).
GF_NOINLINE gf_status ukf3_predict_moments(ukf3_pred *w)
{
    const gf_ukf3 *ukf = w->ukf;
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real fm = ukf->wfold * w->m.v[a];
        for (unsigned c = a; c < N_STATE; c++) {
            w->s[GF_TRI(c, a)] += fm * w->m.v[c];
        }
    }
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned c = 0; c < N_STATE; c++) {
            w->nb.sigma.m[a][c] =
                (a < c) ? w->s[GF_TRI(c, a)] : w->s[GF_TRI(a, c)];
        }
        w->nb.mu.v[a] = w->nb.mu.v[a] + w->m.v[a];
    }
    ukf3_wrap_flagged(&w->nb.mu, N_STATE, HEADING_MASK);
    if (!gf_vec3_is_finite_n(&w->nb.mu, N_STATE) ||
        !gf_mat3_is_finite(&w->nb.sigma)) {
        return GF_ERR_NONFINITE;
    }
    for (unsigned k = 0; k < N_STATE; k++) {
        const gf_real bk = w->b.v[k] * (GF_REAL_EPSILON * ukf->wi);
        if (UNRESOLVED(bk * bk, w->nb.sigma.m[k][k])) {
            return GF_ERR_UNDEFINED;
        }
    }
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
    st = gf_mat3_check_psd(&ukf->sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    // The moments about the centre's image, e_j = chi_bar*_j - chi_bar*_0
    // (heading wrapped), so that no weight larger than w_i is used:
    //   m = sum_{j>0} w_i e_j,  mu_bar = chi_bar*_0 + m,
    //   Sigma_bar = sum_{j>0} w_i e_j e_j^T + (beta - alpha^2) m m^T + R,
    // Table 3.4's sums with the centre's weights folded in (e_0 = 0, the
    // w_m,j sum to 1 and the w_c,j to 2 - alpha^2 + beta). As written in
    // the book, w_c,0 ~ -1/alpha^2 multiplies (chi_bar*_0 - mu_bar), an
    // O(1) quantity carrying the rounding of the points divided by
    // alpha^2: for a small alpha the terms cancel and leave that rounding.
    ukf3_pred w;
    w.ukf = ukf;
    w.motion = motion;
    w.u = u;
    w.m.v[0] = w.m.v[1] = w.m.v[2] = 0;
    w.b = w.m;
    ukf3_sigma_sqrt(&ukf->sigma, w.l);
    for (unsigned a = 0; a < N_STATE; a++) { // R, symmetrized
        w.s[GF_TRI(a, a)] = motion->R.m[a][a];
        for (unsigned c = a + 1u; c < N_STATE; c++) {
            w.s[GF_TRI(c, a)] =
                GF_R(0.5) * motion->R.m[a][c] + GF_R(0.5) * motion->R.m[c][a];
        }
    }
    for (unsigned j = 0; j < N_SIGMA; j++) {
        st = ukf3_predict_point(&w, j);
        if (st != GF_OK) {
            return st;
        }
    }
    st = ukf3_predict_moments(&w);
    if (st != GF_OK) {
        return st;
    }
    st = gf_mat3_check_psd(&w.nb.sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    ukf->mu = w.nb.mu;
    ukf->sigma = w.nb.sigma;
    return GF_OK;
}

// The update's working set, in the frame of update_step: what passes from
// one phase to the next (the points, the gain, the verdict), each member
// doing duty in more than one:
// - l: the packed square root of Sigma_bar while the points are measured,
//   then u = L_S^-1 y in its first m entries and the NIS at UPD_NIS;
// - s: S = Q + the sums (lower triangle packed), then L_S in place, then
//   the posterior's d (update_verdict);
// - pxz: Sigma^xz, then W = L_S^-1 (Sigma^xz)^T row by row in place,
//   then the posterior's F (update_verdict);
// - y: Z_0, then z_hat, then the innovation y = z - z_hat;
// - mu: m_z while the points are summed, then the posterior mean;
// - sigma: h's H (not read) while the points are measured, then the
//   posterior Sigma.
#define UPD_NIS 3u
typedef struct ukf3_upd {
    gf_real l[6];
    gf_real s[6];
    gf_mat3 pxz;
    gf_vec3 y;
    gf_vec3 mu;
    gf_mat3 sigma;
} ukf3_upd;

// One sigma point of the update and its image through h.
typedef struct ukf3_point {
    gf_vec3 chi;
    gf_vec3 dz;
} ukf3_point;

// dz = h(chi) (first m entries, the rest zero), checked finite, h's H (not
// read) into w->sigma.
UKF3_SMALL_CALL gf_status ukf3_point_image(const gf_ekf3_meas *meas,
                                           ukf3_point *p, ukf3_upd *w)
{
    p->dz.v[0] = p->dz.v[1] = p->dz.v[2] = 0;
    const gf_status st = meas->h(meas->ctx, &p->chi, &p->dz, &w->sigma);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    if (!gf_vec3_is_finite_n(&p->dz, meas->m)) {
        return GF_ERR_NONFINITE;
    }
    return GF_OK;
}

// S = Q (m x m, symmetrized; lower triangle packed, zero past the m x m
// block), Sigma^xz = 0 and m_z = 0, before the sums over the points.
UKF3_SMALL_CALL void ukf3_moments_init(const gf_ekf3_meas *meas, ukf3_upd *w)
{
    static const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned b = 0; b <= a; b++) {
            w->s[GF_TRI(a, b)] = (a < meas->m) ? GF_R(0.5) * meas->Q.m[a][b] +
                                                     GF_R(0.5) * meas->Q.m[b][a]
                                               : GF_R(0.0);
        }
        w->mu.v[a] = 0;
    }
    w->pxz = zero;
}

// Point j's terms (j > 0) of m_z, S and Sigma^xz added to w, dz_j in dz
// (zero past the m measured entries, so the sums there stay zero).
UKF3_SMALL_CALL void ukf3_update_add(const gf_ukf3 *ukf, unsigned j,
                                     const gf_vec3 *dz, ukf3_upd *w)
{
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real wz = ukf->wi * dz->v[a];
        w->mu.v[a] += wz;
        for (unsigned b = 0; b <= a; b++) {
            w->s[GF_TRI(a, b)] += wz * dz->v[b];
        }
    }
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real wo = ukf3_offset(ukf, w->l, j, WEIGHTED + a);
        for (unsigned b = 0; b < N_STATE; b++) {
            w->pxz.m[a][b] += wo * dz->v[b];
        }
    }
}

// predict_moments' test for the update's m measured entries, z0 the
// centre's image and s = Q + sum_{j>0} w_i dz_j dz_j^T (packed), with no
// sums of |dz_j,k| kept: a zero spread (s_kk = Q_kk) has nothing to
// round, and otherwise, by Cauchy-Schwarz over the six points,
// sum_j |dz_j,k| <= sqrt(6 raw / w_i), raw = s_kk - Q_kk, so
//   b_k^2 <= (eps w_i)^2 (2 (12 |z0_k|)^2 + 12 raw / w_i).
// GF_ERR_UNDEFINED when an entry is not resolved, else GF_OK.
static gf_status ukf3_update_resolved(const gf_ukf3 *ukf,
                                      const gf_ekf3_meas *meas,
                                      const gf_vec3 *z0, const gf_real s[6])
{
    const gf_real ew = GF_REAL_EPSILON * ukf->wi;
    for (unsigned k = 0; k < meas->m; k++) {
        const gf_real v = s[GF_TRI(k, k)];
        const gf_real raw = v - meas->Q.m[k][k];
        if (raw > 0) { // s_kk >= Q_kk: only nonnegative terms were added
            const gf_real b2 = ew * ew *
                               (GF_R(288.0) * z0->v[k] * z0->v[k] +
                                GF_R(12.0) * raw / ukf->wi);
            if (UNRESOLVED(b2, v)) {
                return GF_ERR_UNDEFINED;
            }
        }
    }
    return GF_OK;
}

// The points, w->l holding sqrt(Sigma_bar): chi_bar = (mu_bar, mu_bar +-
// gamma sqrt(Sigma_bar)), Z_j = h(chi_bar_j), the moments about Z_0 as in
// gf_ukf3_predict, one pass over the points, with dz_j = Z_j - Z_0 (angles
// wrapped) and off_j = chi_bar_j - mu_bar:
//   m_z = sum_{j>0} w_i dz_j,
//   S = sum_{j>0} w_i dz_j dz_j^T + Q,  Sigma^xz = sum_{j>0} w_i off_j dz_j^T
// (S m x m, lower triangle packed; Sigma^xz 3 x m), Z_0 in w->y. Table
// 3.4's Sigma^xz has dz_j - m_z in place of dz_j; the off_j sum to zero.
// A call of its own: only the point and its image are on the stack above
// the working set while h runs (in point_image) and dz_j is wrapped (in
// residual).
GF_NOINLINE gf_status ukf3_update_points(const gf_ukf3 *ukf,
                                         const gf_ekf3_meas *meas, ukf3_upd *w)
{
    ukf3_point p;
    for (unsigned j = 0; j < N_SIGMA; j++) {
        ukf3_sigma_point(ukf, w->l, j, &p.chi);
        const gf_status st = ukf3_point_image(meas, &p, w);
        if (st != GF_OK) {
            return st;
        }
        if (j == 0u) {
            w->y = p.dz; // Z_0
        } else {
            ukf3_residual(&p.dz, &w->y, meas->m, meas->angle_mask, &p.dz);
            ukf3_update_add(ukf, j, &p.dz, w);
        }
    }
    return GF_OK;
}

// The end of the moments, once the points are summed (update_resolved
// first):
//   z_hat = Z_0 + m_z,  S += (beta - alpha^2) m_z m_z^T,
// then y = z - z_hat (angle residuals wrapped) in w->y.
GF_NOINLINE gf_status ukf3_update_zhat(const gf_ukf3 *ukf,
                                       const gf_ekf3_meas *meas,
                                       const gf_vec3 *z, ukf3_upd *w)
{
    const unsigned m = meas->m;
    const unsigned mask = meas->angle_mask;
    const gf_status st = ukf3_update_resolved(ukf, meas, &w->y, w->s);
    if (st != GF_OK) {
        return st;
    }
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real fm = ukf->wfold * w->mu.v[a];
        for (unsigned b = 0; b <= a; b++) {
            w->s[GF_TRI(a, b)] += fm * w->mu.v[b];
        }
        w->y.v[a] = w->y.v[a] + w->mu.v[a];
    }
    ukf3_wrap_flagged(&w->y, m, mask);
    // y = z - z_hat, angle residuals wrapped
    ukf3_residual(z, &w->y, m, mask, &w->y);
    return GF_OK;
}

// The gain: S = L_S L_S^T in place, u = L_S^-1 y and the NIS (the gate
// applied here, info written if gated), then the posterior into w->mu
// and w->sigma, checked finite (not yet PSD). With W = L_S^-1
// (Sigma^xz)^T (m x 3, row by row in place of Sigma^xz's columns), the
// gain K = Sigma^xz S^-1 gives
//   mu = mu_bar + K y = mu_bar + W^T u  (heading wrapped),
//   Sigma = Sigma_bar - K S K^T = Sigma_bar - W^T W  (symmetric as built).
GF_NOINLINE gf_status ukf3_update_gain(const gf_ukf3 *ukf,
                                       const gf_ekf3_meas *meas,
                                       gf_innovation *info, ukf3_upd *w)
{
    const unsigned m = meas->m;
    // S = L_S L_S^T in place (a non-finite entry fails it too)
    for (unsigned k = 0; k < GF_TRI(m, 0u); k++) {
        if (!GF_ISFINITE(w->s[k])) {
            return GF_ERR_NONFINITE;
        }
    }
    const gf_status st = gf_chol_packed(w->s, m);
    if (st != GF_OK) {
        return st;
    }
    // u = L_S^-1 y, NIS = y^T S^-1 y = u^T u
    gf_real *u = w->l;
    gf_innovation in;
    in.m = m;
    in.nis = 0;
    for (unsigned i = 0; i < N_STATE; i++) {
        in.y[i] = w->y.v[i];
        u[i] = w->y.v[i];
    }
    for (unsigned i = 0; i < m; i++) {
        for (unsigned k = 0; k < i; k++) {
            u[i] -= w->s[GF_TRI(i, k)] * u[k];
        }
        u[i] /= w->s[GF_TRI(i, i)];
        in.nis += u[i] * u[i];
    }
    w->l[UPD_NIS] = in.nis;
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_update_status(in.nis, meas->gate, 1) == GF_ERR_GATED) {
        return gf_innovation_keep(GF_ERR_GATED, &in, info);
    }
    for (unsigned a = 0; a < N_STATE; a++) { // row a of Sigma^xz: L_S w = p_a
        for (unsigned i = 0; i < m; i++) {
            for (unsigned k = 0; k < i; k++) {
                w->pxz.m[a][i] -= w->s[GF_TRI(i, k)] * w->pxz.m[a][k];
            }
            w->pxz.m[a][i] /= w->s[GF_TRI(i, i)];
        }
    }
    w->mu = ukf->mu;
    w->sigma = ukf->sigma;
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned i = 0; i < m; i++) {
            w->mu.v[a] += w->pxz.m[a][i] * u[i];
        }
        for (unsigned b = a; b < N_STATE; b++) {
            gf_real ksk = 0;
            for (unsigned i = 0; i < m; i++) {
                ksk += w->pxz.m[a][i] * w->pxz.m[b][i];
            }
            w->sigma.m[a][b] -= ksk;
            w->sigma.m[b][a] = w->sigma.m[a][b];
        }
    }
    w->mu.v[2] = gf_angle_wrap(w->mu.v[2]);
    if (!gf_vec3_is_finite_n(&w->mu, N_STATE) ||
        !gf_mat3_is_finite(&w->sigma)) {
        return GF_ERR_NONFINITE;
    }
    return GF_OK;
}

// The verdict on the posterior Sigma in w->sigma (gf_cov_factor, as
// gf_mat3_check_psd), its factors F and d written to pxz and s, no longer
// needed once the gain has built the posterior: only the pivots' order in
// this frame, on top of the working set.
GF_NOINLINE gf_status ukf3_update_verdict(ukf3_upd *w)
{
    unsigned order[N_STATE];
    return gf_cov_factor(w->sigma.m[0], N_STATE, N_STATE, w->pxz.m[0], w->s,
                         order);
}

// The posterior of w into ukf, and the innovation into info (if not
// NULL: gf_innovation_keep's fields), once the posterior is accepted.
UKF3_SMALL_CALL void ukf3_update_commit(gf_ukf3 *ukf, unsigned m,
                                        gf_innovation *info, const ukf3_upd *w)
{
    ukf->mu = w->mu;
    ukf->sigma = w->sigma;
    if (info) {
        info->m = m;
        info->y[0] = w->y.v[0];
        info->y[1] = w->y.v[1];
        info->y[2] = w->y.v[2];
        info->nis = w->l[UPD_NIS];
    }
}

// The update once its inputs are checked: the points, the gain, then the
// posterior's verdict (update_verdict) from this frame, which holds the
// working set alone; ukf and info written only if it is PSD.
GF_NOINLINE gf_status ukf3_update_step(gf_ukf3 *ukf, const gf_ekf3_meas *meas,
                                       const gf_vec3 *z, gf_innovation *info)
{
    ukf3_upd w;
    ukf3_sigma_sqrt(&ukf->sigma, w.l);
    ukf3_moments_init(meas, &w);
    gf_status st = ukf3_update_points(ukf, meas, &w);
    if (st == GF_OK) {
        st = ukf3_update_zhat(ukf, meas, z, &w);
    }
    if (st == GF_OK) {
        st = ukf3_update_gain(ukf, meas, info, &w);
    }
    if (st == GF_OK) {
        st = ukf3_update_verdict(&w);
    }
    if (st == GF_OK) {
        ukf3_update_commit(ukf, meas->m, info, &w);
    }
    return st;
}

gf_status gf_ukf3_update(gf_ukf3 *ukf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ukf) {
        return GF_ERR_ARG;
    }
    gf_status st = z ? gf_meas3_verdict(meas, z) : GF_ERR_ARG;
    if (st != GF_OK) {
        return st;
    }
    st = gf_mat3_check_psd(&ukf->sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    // the update's frame only now, once the checks' calls have returned
    return ukf3_update_step(ukf, meas, z, info);
}
