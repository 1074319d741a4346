#include "gaussfilt/ukf3.h"

#include "gf_internal.h"

#define N_STATE 3u
#define N_SIGMA (2u * N_STATE + 1u)
#define HEADING_MASK (1u << 2) // state entry 2, theta, is an angle

// Stack (a firmware target gives a public function 256 bytes, built-in
// models included; scripts/footprint): no array of sigma points is kept.
// Each point is made when needed from the packed square root of Sigma
// (chi_j = mu + off_j); the prediction keeps the 7 images through g, the
// update none (it calls h twice per point: once for z_hat, once for the
// moments about it). The locals of successive phases are grouped so that
// the compiler can lay them over each other, and the helpers under the
// deepest frames are leaves or call only gf_angle_wrap.

// UKF3_SMALL_CALL: a small helper of the large frames, called under -Os
// (its few bytes of frame on top of theirs cost less than its code inlined
// into theirs), inlined under gcc and clang otherwise, for speed.
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define UKF3_SMALL_CALL static inline __attribute__((always_inline))
#else
#define UKF3_SMALL_CALL static
#endif

static inline gf_real weight_c(const gf_ukf3 *ukf, unsigned j)
{
    return j == 0 ? ukf->wc0 : ukf->wi;
}

// Entry k of off_j = chi_j - mu: off_0 = 0, off_{1+i} = gamma L_i,
// off_{4+i} = -gamma L_i (L_i column i of L, packed as GF_TRI). With
// WEIGHTED added to k, entry k of w_c,j off_j: the weight is read here,
// so that no caller keeps it in an FP register across the call (which
// its large frame would have to save; an argument more would go on the
// stack on Arm).
#define WEIGHTED 4u
static inline gf_real offset(const gf_ukf3 *ukf, const gf_real l[6],
                             unsigned j, unsigned k)
{
    const unsigned i = (j - 1u) % N_STATE;
    const unsigned e = k % WEIGHTED;
    gf_real o = 0;
    if (j > 0u && e >= i) {
        o = ukf->gamma * l[GF_TRI(e, i)];
    }
    o = (j > N_STATE) ? -o : o;
    return (k >= WEIGHTED) ? weight_c(ukf, j) * o : o;
}

// chi_j = mu + off_j (the offset first: no float is kept across
// offset's call).
UKF3_SMALL_CALL void sigma_point(const gf_ukf3 *ukf, const gf_real l[6],
                                 unsigned j, gf_vec3 *chi)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        const gf_real o = offset(ukf, l, j, k);
        chi->v[k] = ukf->mu.v[k] + o;
    }
}

// Entry e of a residual finished by the bits of wrap_flagged for it: bit
// 0 clear, zeroed; else bit 3 set, wrapped; else kept.
GF_ALWAYS_INLINE void wrap_entry(gf_real *e, unsigned b)
{
    if ((b & 1u) == 0u) {
        *e = 0;
    } else if ((b & (1u << N_STATE)) != 0u) {
        *e = gf_angle_wrap(*e);
    } else {
        // kept as it is
    }
}

// The flagged entries among the first n of d wrapped to (-pi, pi], the
// entries from n on zeroed: the second half of a residual, and the last
// step of a mean. The one helper that calls out (gf_angle_wrap), so that
// the large frames above it need not; entry by entry, so that only d and
// the bits (k: entry k kept, 3 + k: entry k wrapped) are kept across the
// calls.
UKF3_SMALL_CALL void wrap_flagged(gf_vec3 *d, unsigned n,
                                  unsigned angle_mask)
{
    const unsigned keep = (1u << n) - 1u;
    const unsigned bits = keep | ((angle_mask & keep) << N_STATE);
    wrap_entry(&d->v[0], bits);
    wrap_entry(&d->v[1], bits >> 1);
    wrap_entry(&d->v[2], bits >> 2);
}

// d = p - ref on the first n entries, those flagged in angle_mask wrapped,
// the rest zero; d may be p or ref.
GF_ALWAYS_INLINE void residual(const gf_vec3 *p, const gf_vec3 *ref,
                               unsigned n, unsigned angle_mask, gf_vec3 *d)
{
    for (unsigned k = 0; k < N_STATE; k++) {
        d->v[k] = p->v[k] - ref->v[k];
    }
    wrap_flagged(d, n, angle_mask);
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
    (void)gf_mat3_symmetrize(&r.sigma);
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
    st = gf_mat3_check_psd(&ukf->sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }

    // chi_{t-1} = (mu, mu + gamma sqrt(Sigma), mu - gamma sqrt(Sigma)),
    // made in y; then chi_bar*_j = g(u, chi_j) replaces chi_j (G is not
    // needed).
    gf_vec3 y[N_SIGMA];
    {
        gf_real l[6];
        gf_sqrt_psd_packed(&ukf->sigma, N_STATE, l);
        for (unsigned j = 0; j < N_SIGMA; j++) {
            sigma_point(ukf, l, j, &y[j]);
        }
    }
    for (unsigned j = 0; j < N_SIGMA; j++) {
        gf_vec3 chi = y[j];
        // G is not used, but it arrives as the identity (ekf3.h's promise
        // to every motion callback).
        gf_mat3 G_unused = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
        st = motion->g(motion->ctx, &chi, u, &y[j], &G_unused);
        if (st != GF_OK) {
            return gf_callback_status(st);
        }
        if (!gf_vec3_is_finite_n(&y[j], N_STATE)) {
            return GF_ERR_NONFINITE;
        }
    }

    // mu_bar = sum_j w_m,j chi_bar*_j (heading on the circle), taken as
    // chi_bar*_0 plus the weighted residuals about it (the weights sum to
    // one, and w_m,j = w_i for j > 0): exact when the points coincide, and
    // no large offsets cancel.
    {
        gf_vec3 mu = {{0, 0, 0}};
        for (unsigned j = 1; j < N_SIGMA; j++) {
            // the residual about chi_bar*_0 entry by entry (no vector
            // of it on the stack), the heading wrapped
            const gf_real dth = gf_angle_wrap(y[j].v[2] - y[0].v[2]);
            mu.v[0] += ukf->wi * (y[j].v[0] - y[0].v[0]);
            mu.v[1] += ukf->wi * (y[j].v[1] - y[0].v[1]);
            mu.v[2] += ukf->wi * dth;
        }
        for (unsigned k = 0; k < N_STATE; k++) {
            mu.v[k] = y[0].v[k] + mu.v[k];
        }
        wrap_flagged(&mu, N_STATE, HEADING_MASK);

        // Sigma_bar = sum_j w_c,j (chi_bar*_j - mu_bar)(...)^T + R, the
        // residuals in place of the points
        gf_mat3 sigma = motion->R;
        (void)gf_mat3_symmetrize(&sigma);
        for (unsigned j = 0; j < N_SIGMA; j++) {
            residual(&y[j], &mu, N_STATE, HEADING_MASK, &y[j]);
            const gf_real w = weight_c(ukf, j);
            for (unsigned a = 0; a < N_STATE; a++) {
                for (unsigned b = a; b < N_STATE; b++) {
                    sigma.m[a][b] += w * y[j].v[a] * y[j].v[b];
                }
            }
        }
        for (unsigned a = 0; a < N_STATE; a++) {
            for (unsigned b = 0; b < a; b++) {
                sigma.m[a][b] = sigma.m[b][a];
            }
        }
        if (!gf_vec3_is_finite_n(&mu, N_STATE) ||
            !gf_mat3_is_finite(&sigma)) {
            return GF_ERR_NONFINITE;
        }
        st = gf_mat3_check_psd(&sigma, N_STATE);
        if (st != GF_OK) {
            return st;
        }
        ukf->mu = mu;
        ukf->sigma = sigma;
    }
    return GF_OK;
}

// One sigma point of the update at a time: the packed square root of
// Sigma_bar, the point, its image Z through h and h's unused H.
typedef struct ukf3_point {
    gf_real l[6];
    gf_vec3 chi;
    gf_vec3 Z;
    gf_mat3 H;
} ukf3_point;

// Z = h(chi_bar_j) (first m entries, the rest zero), checked finite.
GF_ALWAYS_INLINE gf_status measure(const gf_ukf3 *ukf,
                                   const gf_ekf3_meas *meas, unsigned j,
                                   ukf3_point *p)
{
    sigma_point(ukf, p->l, j, &p->chi);
    p->Z.v[0] = p->Z.v[1] = p->Z.v[2] = 0;
    const gf_status st = meas->h(meas->ctx, &p->chi, &p->Z, &p->H);
    if (st != GF_OK) {
        return gf_callback_status(st);
    }
    return gf_vec3_is_finite_n(&p->Z, meas->m) ? GF_OK : GF_ERR_NONFINITE;
}

// S = Q (m x m, symmetrized; lower triangle packed, zero past the m x m
// block) and Sigma^xz = 0, before the sums over the points.
static void moments_init(const gf_ekf3_meas *meas, gf_real s[6],
                         gf_mat3 *pxz)
{
    static const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned b = 0; b <= a; b++) {
            s[GF_TRI(a, b)] =
                (a < meas->m) ? GF_R(0.5) * (meas->Q.m[a][b] + meas->Q.m[b][a])
                              : GF_R(0.0);
        }
    }
    *pxz = zero;
}

// Point j's terms of S and Sigma^xz, dz_j in p->Z (zero past the m
// measured entries, so the sums there stay zero).
static void accumulate(const gf_ukf3 *ukf, unsigned j, const ukf3_point *p,
                       gf_real s[6], gf_mat3 *pxz)
{
    const gf_real w = weight_c(ukf, j);
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned b = 0; b <= a; b++) {
            s[GF_TRI(a, b)] += w * p->Z.v[a] * p->Z.v[b];
        }
    }
    for (unsigned a = 0; a < N_STATE; a++) {
        const gf_real wo = offset(ukf, p->l, j, WEIGHTED + a);
        for (unsigned b = 0; b < N_STATE; b++) {
            pxz->m[a][b] += wo * p->Z.v[b];
        }
    }
}

// What the update needs once the points are done with: the innovation,
// the posterior, and u = L_S^-1 y.
typedef struct ukf3_post {
    gf_innovation in;
    gf_vec3 u;
    gf_vec3 mu;
    gf_mat3 sigma;
} ukf3_post;

// The posterior, written to ukf only if finite and PSD. With S = L_S L_S^T
// (l_s packed), W = L_S^-1 (Sigma^xz)^T (m x 3, row by row in place of
// Sigma^xz's columns) and u = L_S^-1 y in q->u, the gain K = Sigma^xz S^-1
// gives
//   mu = mu_bar + K y = mu_bar + W^T u  (heading wrapped),
//   Sigma = Sigma_bar - K S K^T = Sigma_bar - W^T W  (symmetric as built).
static gf_status posterior(gf_ukf3 *ukf, const gf_real l_s[6],
                           gf_mat3 *pxz, ukf3_post *q)
{
    const unsigned m = q->in.m;
    for (unsigned a = 0; a < N_STATE; a++) { // row a of Sigma^xz: L_S w = p_a
        for (unsigned i = 0; i < m; i++) {
            for (unsigned k = 0; k < i; k++) {
                pxz->m[a][i] -= l_s[GF_TRI(i, k)] * pxz->m[a][k];
            }
            pxz->m[a][i] /= l_s[GF_TRI(i, i)];
        }
    }
    q->mu = ukf->mu;
    q->sigma = ukf->sigma;
    for (unsigned a = 0; a < N_STATE; a++) {
        for (unsigned i = 0; i < m; i++) {
            q->mu.v[a] += pxz->m[a][i] * q->u.v[i];
        }
        for (unsigned b = a; b < N_STATE; b++) {
            gf_real ksk = 0;
            for (unsigned i = 0; i < m; i++) {
                ksk += pxz->m[a][i] * pxz->m[b][i];
            }
            q->sigma.m[a][b] -= ksk;
            q->sigma.m[b][a] = q->sigma.m[a][b];
        }
    }
    q->mu.v[2] = gf_angle_wrap(q->mu.v[2]);
    if (!gf_vec3_is_finite_n(&q->mu, N_STATE) ||
        !gf_mat3_is_finite(&q->sigma)) {
        return GF_ERR_NONFINITE;
    }
    const gf_status st = gf_mat3_check_psd(&q->sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    ukf->mu = q->mu;
    ukf->sigma = q->sigma;
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
    st = gf_mat3_check_psd(&ukf->sigma, N_STATE);
    if (st != GF_OK) {
        return st;
    }
    const unsigned m = meas->m;
    const unsigned mask = meas->angle_mask;

    // chi_bar = (mu_bar, mu_bar +- gamma sqrt(Sigma_bar)), Z_j = h(chi_bar_j),
    // twice over the points: pass 0 for z_hat = sum_j w_m,j Z_j (in y; the
    // residuals about Z_0 are summed in s, not yet in use), pass 1 for the
    // moments about it, with dz_j = Z_j - z_hat (angles wrapped):
    //   S = sum_j w_c,j dz_j dz_j^T + Q   (m x m, lower triangle packed),
    //   Sigma^xz = sum_j w_c,j (chi_bar_j - mu_bar) dz_j^T   (3 x m).
    gf_real s[6];
    gf_mat3 Pxz;
    gf_vec3 y;
    {
        ukf3_point p;
        gf_sqrt_psd_packed(&ukf->sigma, N_STATE, p.l);
        for (unsigned pass = 0; pass < 2u; pass++) {
            for (unsigned j = 0; j < N_SIGMA; j++) {
                st = measure(ukf, meas, j, &p);
                if (st != GF_OK) {
                    return st;
                }
                if (pass == 0u && j == 0u) {
                    y = p.Z;
                    s[0] = s[1] = s[2] = 0;
                } else if (pass == 0u) {
                    residual(&p.Z, &y, m, mask, &p.Z);
                    for (unsigned k = 0; k < N_STATE; k++) {
                        s[k] += ukf->wi * p.Z.v[k];
                    }
                } else {
                    residual(&p.Z, &y, m, mask, &p.Z);
                    accumulate(ukf, j, &p, s, &Pxz);
                }
            }
            if (pass == 0u) {
                for (unsigned k = 0; k < N_STATE; k++) {
                    y.v[k] = y.v[k] + s[k];
                }
                wrap_flagged(&y, m, mask);
                moments_init(meas, s, &Pxz);
            }
        }
        // y = z - z_hat, angle residuals wrapped
        residual(z, &y, m, mask, &y);
    }
    // S = L_S L_S^T in place (a non-finite entry fails it too)
    for (unsigned k = 0; k < GF_TRI(m, 0u); k++) {
        if (!GF_ISFINITE(s[k])) {
            return GF_ERR_NONFINITE;
        }
    }
    st = gf_chol_packed(s, m);
    if (st != GF_OK) {
        return st;
    }
    {
        // u = L_S^-1 y, NIS = y^T S^-1 y = u^T u
        ukf3_post q;
        q.in.m = m;
        q.in.nis = 0;
        for (unsigned i = 0; i < N_STATE; i++) {
            q.in.y[i] = y.v[i];
            q.u.v[i] = y.v[i];
        }
        for (unsigned i = 0; i < m; i++) {
            for (unsigned k = 0; k < i; k++) {
                q.u.v[i] -= s[GF_TRI(i, k)] * q.u.v[k];
            }
            q.u.v[i] /= s[GF_TRI(i, i)];
            q.in.nis += q.u.v[i] * q.u.v[i];
        }
        if (!GF_ISFINITE(q.in.nis)) {
            return GF_ERR_NONFINITE;
        }
        if (gf_gated(&q.in, meas->gate, info)) {
            return GF_ERR_GATED;
        }
        st = posterior(ukf, s, &Pxz, &q);
        if (st != GF_OK) {
            return st;
        }
        if (info) {
            *info = q.in;
        }
    }
    return GF_OK;
}
