// gaussfilt: the compact KF2 and EKF3 steps of GF_SMALL (config.h).
//
// gf_kf2_predict/update and gf_ekf3_predict/update, for flash and stack
// instead of speed: one correction and one prediction routine shared by
// both filters (n = 2 or 3 states, m = 1..3 measured quantities), every
// model called through its pointer, no fast path. Same API, statuses,
// checks and order of checks as kf2.c and ekf3.c (which leave these four
// functions out under GF_SMALL), so the same tests pass.
//
// The routines work on the belief in place, through row-major pointers
// whose rows have n entries: KF2's 2x2 and EKF3's 3x3 matrices (C and H,
// Q, A and G, R) are read as they are, without padded copies. Results go
// to locals (the new Sigma with rows of n, then the new mu) and reach the
// belief only once all are finite.
//
// Stack (issue 4: no public function deeper than 256 bytes on an MCU):
// the update's checks (correct) end in a tail call to the computation
// (update), so the two frames are never on the stack together (but on
// Thumb-1, Cortex-M0+, where gcc makes no tail calls). The computation's
// frame holds H, y, S^-1, K and the new belief (120 B in float); what it
// calls has a small frame of its own (on Cortex-M4F quad and commit 20 B
// each; commit takes the new Sigma and mu in one buffer, a fifth argument
// made its frame larger). commit is a leaf (it tests finiteness itself,
// the caller wraps the heading): on RV32 a call from it cost a 32 B frame
// on top of update's 240 B. The prediction's public functions own the
// new belief's buffer and call predict (the covariance) and commit one
// after the other, so that on Cortex-M0+ neither is on top of the other.
// Compiled in every build; empty (but for the declarations of ekf3.h)
// unless GF_SMALL is 1 (config.h).
#include <stddef.h>

#include "gaussfilt/ekf3.h"

#if GF_SMALL

// 1 if the n entries of x are all finite.
static int all_finite(const gf_real *x, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (!GF_ISFINITE(x[i])) {
            return 0;
        }
    }
    return 1;
}

// sum over i < d of a[i as] b[i bs]: rows, and columns (as or bs = 3).
static gf_real dot(const gf_real *a, size_t as, const gf_real *b,
                         size_t bs, size_t d)
{
    gf_real acc = 0;
    for (size_t i = 0; i < d; i++) {
        acc += a[i * as] * b[i * bs];
    }
    return acc;
}

// u^T A v over the leading d x d block of a (rows of as entries), summed
// as u_i a_ij v_j over i, then j. Walks u and the rows by pointer, the
// rows counted down: on Thumb-1 (Cortex-M0+) gcc then keeps fewer values
// on the stack across the soft-float calls than with i * as + j (frame
// 40 B, not 56).
static gf_real quad(const gf_real *u, const gf_real *a, size_t as,
                          const gf_real *v, size_t d)
{
    gf_real acc = 0;
    const gf_real *ui = u;
    const gf_real *row = a;
    for (size_t i = d; i > 0u; i--) {
        for (size_t j = 0; j < d; j++) {
            acc += *ui * row[j] * v[j];
        }
        ui++;
        row = &row[as];
    }
    return acc;
}

// Writes the new belief from b: the new Sigma (n x n, rows of n, exactly
// symmetric) and after it the new mu (n entries), if all are finite; else
// GF_ERR_NONFINITE and the belief is untouched. EKF3's (n = 3) heading
// has been wrapped to (-pi, pi] in b by its owner (a non-finite heading
// stays non-finite), so that this is a leaf (a call from here gave it a
// 32 B frame on RV32, on top of update's).
// Never inlined: gcc would then see KF2's 2x2 through its first row.
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static gf_status commit(gf_real *mu, gf_real *sigma, size_t n,
                        const gf_real *b)
{
    for (size_t i = 0; &b[i] != &b[n * n + n]; i++) { // all_finite's test
        if (!GF_ISFINITE(b[i])) {
            return GF_ERR_NONFINITE;
        }
    }
    // (up to the new mu's address: a loop over i < n * n takes two more
    // saved registers here, gcc knowing n to be 2 or 3)
    for (size_t i = 0; &b[i] != &b[n * n]; i++) {
        sigma[i] = b[i];
    }
    for (size_t i = 0; i < n; i++) {
        mu[i] = b[n * n + i];
    }
    return GF_OK;
}

// The covariance prediction of both filters into s (rows of n):
//   Sigma_bar = G Sigma G^T + R (upper triangle of R, mirrored).
// g, sigma and r have rows of n entries. The caller owns s, with the new
// mu after it (commit's layout), and commits it: on Cortex-M0+ commit's
// finiteness test (soft-float compares, 60 B) is then not on top of this
// frame, and this frame holds no array. quad's sum is written out here
// (Cortex-M0+: this frame + 32 B, where a call to quad cost + 40 + 32 B);
// one loop over the n x n entries keeps fewer values on the stack.
static void predict(gf_real *s, const gf_real *sigma, size_t n,
                    const gf_real *g, const gf_real *r)
{
    // entry k = (i, j), row by row: the upper triangle computed, the
    // lower one mirrored from the rows already done
    size_t i = 0, j = 0;
    for (size_t k = 0; k < n * n; k++) {
        if (j < i) {
            s[k] = s[j * n + i];
        } else {
            gf_real acc = 0; // quad's sum
            const gf_real *ui = &g[i * n];
            const gf_real *row = sigma;
            for (size_t a = n; a > 0u; a--) {
                for (size_t b = 0; b < n; b++) {
                    acc += *ui * row[b] * g[j * n + b];
                }
                ui++;
                row = &row[n];
            }
            s[k] = acc + r[k];
        }
        j++;
        if (j == n) {
            j = 0;
            i++;
        }
    }
}

// gf_mat2_check_psd on the leading m x m block of s, through
// gf_mat3_check_psd (the same tests) on a padded copy, so one PSD test is
// linked, not two. The copy is this function's own, so that its callers
// take no local's address (correct's tail call needs that).
static gf_status check_psd2(const gf_mat2 *s, unsigned m)
{
    const gf_mat3 t = {{{s->m[0][0], s->m[0][1], 0},
                        {s->m[1][0], s->m[1][1], 0},
                        {0, 0, 0}}};
    return gf_mat3_check_psd(&t, m);
}

// S^-1 in place (rows of 3) by Gauss-Jordan elimination, s_diag holding
// S's diagonal. Pivot p is a Schur complement of S, the square of a
// Cholesky pivot: singular unless above GF_PD_RTOL times S_pp, as
// gf_mat3_chol tests it (NaN fails too).
static gf_status spd_inverse(gf_real *l, const gf_real *s_diag, size_t m)
{
    for (size_t p = 0; p < m; p++) {
        const gf_real d = l[p * 3 + p];
        if (!(d > GF_PD_RTOL * s_diag[p])) {
            return GF_ERR_SINGULAR;
        }
        l[p * 3 + p] = 1;
        for (size_t j = 0; j < m; j++) {
            l[p * 3 + j] /= d;
        }
        for (size_t i = 0; i < m; i++) {
            if (i != p) {
                const gf_real f = l[i * 3 + p];
                l[i * 3 + p] = 0;
                for (size_t j = 0; j < m; j++) {
                    l[i * 3 + j] -= f * l[p * 3 + j];
                }
            }
        }
    }
    return GF_OK;
}

// The computation of the update of both filters (Table 3.1/3.3, lines
// 4-6), once correct has checked its inputs: KF2's (kf, km: z_hat = C
// mu_bar + c, H = C) or EKF3's (ekf, em: its model called through the
// pointer, km and kf 0). With n = 2 or 3 states (KF2's 2x2 and EKF3's 3x3
// belief read in place):
//   S = H Sigma_bar H^T + Q,  K = Sigma_bar H^T S^-1,  mu = mu_bar + K y,
//   Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T, exactly symmetric.
// S is inverted by Gauss-Jordan elimination: its pivots are those of a
// Cholesky factorisation, tested as gf_mat3_chol tests them.
// Never inlined into correct, which tail-calls it: the checks' frame is
// gone before the computation's is set up.
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static gf_status update(gf_kf2 *kf, const gf_kf2_meas *km, gf_ekf3 *ekf,
                        const gf_ekf3_meas *em, const gf_real *z,
                        gf_innovation *info)
{
    // w[0]: H (rows of 3), then the new Sigma (rows of n) and after it the
    // new mu (commit's layout; for n = 3 the mu spills into w[1]'s first
    // row). w[1]: S, S^-1, I - K H.
    gf_mat3 w[2] = {{{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                    {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
    gf_vec3 y = {{0, 0, 0}};
    gf_real k[9]; // S's diagonal, then K (n x m, rows of 3)
    gf_real *h = w[0].m[0];
    gf_real *l = w[1].m[0];
    gf_real *mu, *sigma; // rows of n
    const gf_real *q;    // rows of n
    size_t n, m;
    gf_real gate;
    gf_status st;
    if (em) {
        mu = ekf->mu.v;
        sigma = ekf->sigma.m[0];
        q = em->Q.m[0];
        n = 3;
        m = em->m;
        gate = em->gate;
        // z_hat = h(mu_bar), H = dh/dx at mu_bar (first m rows read)
        st = em->h(em->ctx, &ekf->mu, &y, &w[0]);
        if (st != GF_OK) { // a status the enum lacks, or GATED: MODEL
            return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
                       ? GF_ERR_MODEL : st;
        }
    } else {
        mu = kf->mu.v;
        sigma = kf->sigma.m[0];
        q = km->Q.m[0];
        n = 2;
        m = km->m;
        gate = km->gate;
        // z_hat = C mu_bar + c, H = C
        for (size_t i = 0; i < m; i++) {
            h[i * 3] = km->C.m[i][0];
            h[i * 3 + 1] = km->C.m[i][1];
            y.v[i] = km->c.v[i] + dot(&h[i * 3], 1, mu, 1, 2);
        }
    }
    // y = z - z_hat, angle residuals wrapped
    for (size_t i = 0; i < m; i++) {
        if (!GF_ISFINITE(y.v[i]) || !all_finite(&h[i * 3], 3)) {
            return GF_ERR_NONFINITE;
        }
        y.v[i] = z[i] - y.v[i];
        if (em && (em->angle_mask & (1u << i))) {
            y.v[i] = gf_angle_wrap(y.v[i]);
        }
    }

    // S = H Sigma_bar H^T + Q (upper triangle of Q, mirrored)
    for (size_t i = 0; i < m; i++) {
        for (size_t j = i; j < m; j++) {
            l[i * 3 + j] = quad(&h[i * 3], sigma, n, &h[j * 3], n) +
                           q[i * n + j];
            l[j * 3 + i] = l[i * 3 + j];
        }
        if (!all_finite(&l[i * 3], m)) {
            return GF_ERR_NONFINITE;
        }
        k[i] = l[i * 3 + i];
    }
    // S^-1
    st = spd_inverse(l, k, m);
    if (st != GF_OK) {
        return st;
    }

    // NIS = y^T S^-1 y
    const gf_real nis = quad(y.v, l, 3, y.v, m);
    if (!GF_ISFINITE(nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gate > 0 && nis > gate) {
        st = GF_ERR_GATED;
    } else {
        // K = Sigma_bar H^T S^-1
        for (size_t i = 0; i < n; i++) {
            for (size_t j = 0; j < m; j++) {
                gf_real v = 0;
                for (size_t a = 0; a < m; a++) {
                    v += dot(&sigma[i * n], 1, &h[a * 3], 1, n) *
                         l[a * 3 + j];
                }
                k[i * 3 + j] = v;
            }
        }
        // I - K H over S^-1
        for (size_t i = 0; i < n; i++) {
            for (size_t c = 0; c < n; c++) {
                l[i * 3 + c] = ((i == c) ? GF_R(1.0) : GF_R(0.0)) -
                               dot(&k[i * 3], 1, &h[c], 3, m);
            }
        }
        // Sigma = (I - K H) Sigma_bar (I - K H)^T + K Q K^T over H
        // (upper triangle, mirrored; rows of n)
        for (size_t i = 0; i < n; i++) {
            for (size_t j = i; j < n; j++) {
                h[i * n + j] =
                    quad(&l[i * 3], sigma, n, &l[j * 3], n) +
                    quad(&k[i * 3], q, n, &k[j * 3], m);
                h[j * n + i] = h[i * n + j];
            }
        }
        // mu = mu_bar + K y after it (over I - K H's first row if n = 3)
        for (size_t i = 0; i < n; i++) {
            h[n * n + i] = mu[i] + dot(&k[i * 3], 1, y.v, 1, m);
        }
        if (n == 3u) {
            h[11] = gf_angle_wrap(h[11]);
        }
        st = commit(mu, sigma, n, h);
    }
    if (st != GF_ERR_NONFINITE && info) {
        info->m = (unsigned)m;
        for (size_t i = 0; i < 3; i++) {
            info->y[i] = (i < m) ? y.v[i] : GF_R(0.0);
        }
        info->nis = nis;
    }
    return st;
}

// The update of both filters once the caller has checked for NULL: KF2's
// (kf, km; ekf and em 0) or EKF3's (ekf, em; kf and km 0). Checks the
// measurement, z and Q in the order of kf2.c and ekf3.c, then hands over
// to update by a tail call (nothing of this frame is needed there).
static gf_status correct(gf_kf2 *kf, const gf_kf2_meas *km, gf_ekf3 *ekf,
                         const gf_ekf3_meas *em, const gf_real *z,
                         gf_innovation *info)
{
    size_t n, m;
    gf_real gate;
    if (em) {
        n = 3;
        m = em->m;
        gate = em->gate;
    } else if (km) {
        n = 2;
        m = km->m;
        gate = km->gate;
    } else {
        return GF_ERR_ARG; // not reached: the callers pass km or em
    }
    if ((em && !em->h) || m < 1 || m > n) {
        return GF_ERR_ARG;
    }
    if ((!em && (!all_finite(km->C.m[0], 2 * m) ||
                !all_finite(km->c.v, m))) ||
        !all_finite(z, m) || !GF_ISFINITE(gate)) {
        return GF_ERR_NONFINITE;
    }
    if (gate < 0) {
        return GF_ERR_ARG;
    }
    const gf_status st = em ? gf_mat3_check_psd(&em->Q, (unsigned)m)
                            : check_psd2(&km->Q, (unsigned)m);
    if (st != GF_OK) {
        return st;
    }
    return update(kf, km, ekf, em, z, info);
}

gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!all_finite(mu->v, 2)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = check_psd2(sigma, 2);
    if (st != GF_OK) {
        return st;
    }
    // Sigma symmetrized: (Sigma + Sigma^T) / 2
    const gf_real o = GF_R(0.5) * (sigma->m[0][1] + sigma->m[1][0]);
    kf->mu = *mu;
    kf->sigma = *sigma;
    kf->sigma.m[0][1] = o;
    kf->sigma.m[1][0] = o;
    return GF_OK;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    if (!all_finite(model->A.m[0], 4) || !all_finite(model->B.m[0], 4) ||
        !all_finite(model->c.v, 2) || (u && !all_finite(u->v, 2))) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = check_psd2(&model->R, 2);
    if (st != GF_OK) {
        return st;
    }
    // b: Sigma_bar (rows of 2), then mu_bar = A mu + B u + c
    gf_real b[6];
    for (size_t i = 0; i < 2u; i++) {
        gf_real m = dot(model->A.m[i], 1, kf->mu.v, 1, 2);
        if (u) {
            m += dot(model->B.m[i], 1, u->v, 1, 2);
        }
        b[4u + i] = m + model->c.v[i];
    }
    // Sigma_bar = A Sigma A^T + R
    predict(b, kf->sigma.m[0], 2, model->A.m[0], model->R.m[0]);
    return commit(kf->mu.v, kf->sigma.m[0], 2, b);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas || !z) {
        return GF_ERR_ARG;
    }
    return correct(kf, meas, 0, 0, z->v, info);
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
    // mu_bar = g(u, mu), G = dg/dx at mu. w[0]: Sigma_bar, then (in w[1]'s
    // first row, once G is done with) mu_bar: commit's layout. w[1]: G.
    gf_mat3 w[2] = {{{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                    {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};
    gf_vec3 mu = ekf->mu;
    st = motion->g(motion->ctx, &ekf->mu, u, &mu, &w[1]);
    if (st != GF_OK) { // a status the enum lacks, or GATED: MODEL
        return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
                   ? GF_ERR_MODEL : st;
    }
    // Sigma_bar = G Sigma G^T + R (a non-finite G reaches the diagonal)
    predict(w[0].m[0], ekf->sigma.m[0], 3, w[1].m[0], motion->R.m[0]);
    w[1].m[0][0] = mu.v[0];
    w[1].m[0][1] = mu.v[1];
    w[1].m[0][2] = gf_angle_wrap(mu.v[2]);
    return commit(ekf->mu.v, ekf->sigma.m[0], 3, w[0].m[0]);
}

gf_status gf_ekf3_update(gf_ekf3 *ekf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info)
{
    if (!ekf || !meas || !z) {
        return GF_ERR_ARG;
    }
    return correct(0, 0, ekf, meas, z->v, info);
}

#endif
