// SPDX-License-Identifier: MIT
#include "gaussfilt/pf3.h"

#include "gf_filter.h"
#include "gf_internal.h"
#include "gf_meas3.h"

// Total weight W; GF_ERR_NONFINITE or GF_ERR_UNDEFINED (a negative weight,
// W not positive) when the weights cannot be used.
static gf_status pf3_total_weight(const gf_pf3 *pf, gf_real *total)
{
    gf_real w = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        if (!GF_ISFINITE(pf->p[k].w)) {
            return GF_ERR_NONFINITE;
        }
        if (pf->p[k].w < 0) {
            return GF_ERR_UNDEFINED;
        }
        w += pf->p[k].w;
    }
    if (!GF_ISFINITE(w)) {
        return GF_ERR_NONFINITE;
    }
    if (!(w > 0)) {
        return GF_ERR_UNDEFINED;
    }
    *total = w;
    return GF_OK;
}

// l = sqrt(s), packed (GF_TRI), for s checked PSD: gf_sqrt_psd_packed in
// a frame of its own (docs/firmware.md, the stack).
#if defined(__GNUC__)
__attribute__((noinline))
#endif
static void
pf3_sqrt_psd(const gf_mat3 *s, gf_real l[6])
{
    gf_sqrt_psd_packed(s, 3, l);
}

// x = mu + L n, n ~ N(0, I), L packed (GF_TRI): gf_rng_mvn3's arithmetic,
// the zero entries of L included, with no 3x3 matrix. x may be mu.
static void pf3_draw(gf_rng *rng, const gf_vec3 *mu, const gf_real l[6],
                     gf_vec3 *x)
{
    gf_real nv[3];
    for (unsigned i = 0; i < 3u; i++) {
        nv[i] = gf_rng_normal(rng);
    }
    const gf_real z = 0; // L's upper entries
    x->v[0] = mu->v[0] + (l[0] * nv[0] + z * nv[1] + z * nv[2]);
    x->v[1] = mu->v[1] + (l[1] * nv[0] + l[2] * nv[1] + z * nv[2]);
    x->v[2] = mu->v[2] + (l[3] * nv[0] + l[4] * nv[1] + l[5] * nv[2]);
}

gf_status gf_pf3_init(gf_pf3 *pf, gf_pf3_particle *particles, unsigned n,
                      uint32_t seed, const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!pf || !particles || !mu || !sigma || n < 1 || n > GF_PF3_MAX_N) {
        return GF_ERR_ARG;
    }
    const gf_status st = gf_prior3_check(mu, sigma);
    if (st != GF_OK) {
        return st;
    }
    gf_real L[6];
    pf3_sqrt_psd(sigma, L);
    // Dry run: every draw mu + L n_k must be finite before anything is
    // written (an enormous sigma could overflow). The generator is then
    // seeded again, so the draws kept are the ones checked.
    gf_rng rng;
    (void)gf_rng_seed(&rng, seed);
    for (unsigned k = 0; k < n; k++) {
        gf_vec3 x;
        pf3_draw(&rng, mu, L, &x);
        if (!gf_vec3_is_finite_n(&x, 3)) {
            return GF_ERR_NONFINITE;
        }
    }
    // x^[k] ~ N(mu, Sigma), then w^[k] = 1/n
    (void)gf_rng_seed(&rng, seed);
    for (unsigned k = 0; k < n; k++) {
        pf3_draw(&rng, mu, L, &particles[k].x);
        particles[k].x.v[2] = gf_angle_wrap(particles[k].x.v[2]);
    }
    const gf_real w = GF_R(1.0) / (gf_real)n;
    for (unsigned k = 0; k < n; k++) {
        particles[k].w = w;
    }
    pf->p = particles;
    pf->n = n;
    pf->rng = rng;
    return GF_OK;
}

// x = g(u, p) through the motion's callback (G discarded), checked
// finite. A call of its own under -Os, inlined otherwise
// (docs/firmware.md, the stack).
#if defined(__GNUC__) && defined(__OPTIMIZE_SIZE__)
__attribute__((noinline))
#endif
static gf_status
pf3_propagate(const gf_ekf3_motion *motion, const gf_vec3 *p, const gf_real *u,
              gf_vec3 *x)
{
    // G is not used, but it arrives as the identity (ekf3.h's promise to
    // every motion callback).
    gf_mat3 G_unused = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    *x = *p;
    gf_status st =
        gf_callback_status(motion->g(motion->ctx, p, u, x, &G_unused));
    if (st == GF_OK && !gf_vec3_is_finite_n(x, 3)) {
        st = GF_ERR_NONFINITE;
    }
    return st;
}

gf_status gf_pf3_predict(gf_pf3 *pf, const gf_ekf3_motion *motion,
                         const gf_real *u)
{
    if (!pf || !pf->p || !motion || !motion->g) {
        return GF_ERR_ARG;
    }
    gf_status st = gf_mat3_check_psd(&motion->R, 3);
    if (st != GF_OK) {
        return st;
    }
    gf_real L[6];
    pf3_sqrt_psd(&motion->R, L);
    // x_t^[k] = g(u, x_{t-1}^[k]) + L n^[k], n^[k] ~ N(0, I), heading
    // wrapped (G discarded). Pass 0 is a dry run on a copy of the
    // generator that writes nothing and stops at the first failure; pass 1
    // repeats exactly its computations on the filter's own generator and
    // writes each particle, so it cannot fail half-way.
    gf_rng dry = pf->rng;
    for (unsigned pass = 0; pass < 2u; pass++) {
        gf_rng *rng = (pass == 0u) ? &dry : &pf->rng;
        for (unsigned k = 0; k < pf->n; k++) {
            gf_vec3 x;
            st = pf3_propagate(motion, &pf->p[k].x, u, &x);
            if (st == GF_OK) {
                pf3_draw(rng, &x, L, &x);
                x.v[2] = gf_angle_wrap(x.v[2]);
                if (!gf_vec3_is_finite_n(&x, 3)) {
                    st = GF_ERR_NONFINITE;
                }
            }
            if (pass == 0u && st != GF_OK) {
                return st;
            }
            if (pass != 0u && st == GF_OK) {
                pf->p[k].x = x;
            }
        }
    }
    return GF_OK;
}

// d2 = r^T Q^-1 r, r = z - h(x) (flagged entries wrapped), l = chol(Q)
// packed as GF_TRI. H goes to a scratch matrix that is gone before the
// solve.
static gf_status pf3_mahalanobis(const gf_ekf3_meas *meas, const gf_real l[6],
                                 const gf_vec3 *z, const gf_vec3 *x,
                                 gf_real *d2)
{
    const unsigned m = meas->m;
    gf_vec3 r = {{0, 0, 0}};
    {
        gf_mat3 H_unused;
        const gf_status st = meas->h(meas->ctx, x, &r, &H_unused);
        if (st != GF_OK) {
            return gf_callback_status(st);
        }
    }
    if (!gf_vec3_is_finite_n(&r, m)) {
        return GF_ERR_NONFINITE;
    }
    gf_real qr[3] = {0, 0, 0};
    for (unsigned i = 0; i < m; i++) {
        r.v[i] = z->v[i] - r.v[i];
        if ((meas->angle_mask >> i) & 1u) {
            r.v[i] = gf_angle_wrap(r.v[i]);
        }
        qr[i] = r.v[i];
    }
    gf_chol_solve_packed(l, m, qr);
    gf_real d = 0;
    for (unsigned i = 0; i < m; i++) {
        d += r.v[i] * qr[i];
    }
    if (!GF_ISFINITE(d)) {
        return GF_ERR_NONFINITE;
    }
    *d2 = d;
    return GF_OK;
}

gf_status gf_pf3_update(gf_pf3 *pf, const gf_ekf3_meas *meas, const gf_vec3 *z)
{
    if (!pf || !pf->p) {
        return GF_ERR_ARG;
    }
    gf_status st = z ? gf_meas3_verdict(meas, z) : GF_ERR_ARG;
    if (st != GF_OK) {
        return st;
    }
    // z copied: it may point into the particles this call rewrites
    const gf_vec3 zc = *z;
    // chol(Q), packed: gf_mat3_chol's arithmetic in 6 entries
    gf_real L[6];
    for (unsigned i = 0; i < meas->m; i++) {
        for (unsigned j = 0; j <= i; j++) {
            L[GF_TRI(i, j)] = meas->Q.m[i][j];
        }
    }
    st = gf_chol_packed(L, meas->m);
    if (st != GF_OK) {
        return st;
    }
    gf_real total;
    st = pf3_total_weight(pf, &total);
    if (st != GF_OK) {
        return st;
    }

    // Dry run: the best log-weight ln w - d2 / 2 and the smallest d2 over
    // the particles that have weight.
    int seen = 0;
    gf_real best = 0, d2min = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        gf_real d2;
        st = pf3_mahalanobis(meas, L, &zc, &pf->p[k].x, &d2);
        if (st != GF_OK) {
            return st;
        }
        if (!(pf->p[k].w > 0)) {
            continue;
        }
        const gf_real lw = gf_log(pf->p[k].w) - GF_R(0.5) * d2;
        if (!seen || lw > best) {
            best = lw;
        }
        if (!seen || d2 < d2min) {
            d2min = d2;
        }
        seen = 1;
    }
    if (meas->gate > 0 && d2min > meas->gate) {
        return GF_ERR_GATED;
    }

    // w^[k] = exp(ln w^[k] - d2_k / 2 - best): the best particle gets 1,
    // so the sum is at least 1; then normalised.
    gf_real sum = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        gf_real d2 = 0;
        (void)pf3_mahalanobis(meas, L, &zc, &pf->p[k].x, &d2);
        gf_real w = 0;
        if (pf->p[k].w > 0) {
            w = gf_exp(gf_log(pf->p[k].w) - GF_R(0.5) * d2 - best);
        }
        pf->p[k].w = w;
        sum += w;
    }
    const gf_real inv = GF_R(1.0) / sum;
    for (unsigned k = 0; k < pf->n; k++) {
        pf->p[k].w *= inv;
    }
    return GF_OK;
}

gf_status gf_pf3_resample(gf_pf3 *pf)
{
    if (!pf || !pf->p || pf->n < 1) {
        return GF_ERR_ARG;
    }
    gf_real total;
    gf_status st = pf3_total_weight(pf, &total);
    if (st != GF_OK) {
        return st;
    }
    gf_pf3_particle *p = pf->p;
    const unsigned n = pf->n;

    // Table 4.4: r = rand(0; W/n), c = w^[0], i = 0; for each k:
    //   U = r + k W/n; while U > c: i = i + 1, c = c + w^[i]; copy x^[i].
    // The copy count of particle i replaces w^[i] once c has moved past it
    // (w^[i] is never read again).
    const gf_real step = total / (gf_real)n;
    const gf_real r = gf_rng_uniform(&pf->rng) * step;
    unsigned i = 0, count = 0;
    gf_real c = p[0].w;
    for (unsigned k = 0; k < n; k++) {
        const gf_real U = r + (gf_real)k * step;
        while (i + 1u < n) { // integer-controlled (MISRA 14.1)
            if (!(U > c)) {
                break;
            }
            p[i].w = (gf_real)count;
            count = 0;
            i++;
            c += p[i].w;
        }
        count++;
    }
    p[i].w = (gf_real)count;
    for (unsigned j = i + 1; j < n; j++) {
        p[j].w = 0;
    }

    // Copies of particles drawn more than once go to the slots of those
    // drawn none; there are exactly as many such slots as extra copies.
    unsigned hole = 0;
    for (unsigned j = 0; j < n; j++) {
        const unsigned copies = (unsigned)p[j].w; // an exact count
        for (unsigned e = 1; e < copies; e++) {
            while (p[hole].w > GF_R(0.5)) {
                hole++;
            }
            p[hole].x = p[j].x;
            p[hole].w = 1;
        }
        if (copies > 1u) {
            p[j].w = 1;
        }
    }
    const gf_real w = GF_R(1.0) / (gf_real)n;
    for (unsigned j = 0; j < n; j++) {
        p[j].w = w;
    }
    return GF_OK;
}

gf_status gf_pf3_neff(const gf_pf3 *pf, gf_real *neff)
{
    if (!pf || !pf->p || !neff) {
        return GF_ERR_ARG;
    }
    gf_real total;
    gf_status st = pf3_total_weight(pf, &total);
    if (st != GF_OK) {
        return st;
    }
    // 1 / sum (w / W)^2
    gf_real s2 = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        const gf_real w = pf->p[k].w / total;
        s2 += w * w;
    }
    *neff = GF_R(1.0) / s2;
    return GF_OK;
}

gf_status gf_pf3_estimate(const gf_pf3 *pf, gf_vec3 *mu, gf_mat3 *sigma)
{
    if (!pf || !pf->p || (!mu && !sigma)) {
        return GF_ERR_ARG;
    }
    gf_real total;
    gf_status st = pf3_total_weight(pf, &total);
    if (st != GF_OK) {
        return st;
    }
    // mean: sum w x / W for x and y; atan2(sum w sin, sum w cos) for theta
    gf_real sx = 0, sy = 0, ss = 0, sc = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        const gf_pf3_particle *q = &pf->p[k];
        sx += q->w * q->x.v[0];
        sy += q->w * q->x.v[1];
        gf_real sn, cs;
        gf_sincos(q->x.v[2], &sn, &cs);
        ss += q->w * sn;
        sc += q->w * cs;
    }
    if (!(GF_SQRT(ss * ss + sc * sc) > GF_R(64.0) * GF_REAL_EPSILON * total)) {
        return GF_ERR_UNDEFINED;
    }
    gf_vec3 m = {{sx / total, sy / total, gf_atan2(ss, sc)}};
    m.v[2] = gf_angle_wrap(m.v[2]);
    // Sigma = sum w d d^T / W, d = x - mean with the heading wrapped
    gf_mat3 s = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    for (unsigned k = 0; k < pf->n; k++) {
        const gf_pf3_particle *q = &pf->p[k];
        gf_vec3 d = {{q->x.v[0] - m.v[0], q->x.v[1] - m.v[1],
                      gf_angle_wrap(q->x.v[2] - m.v[2])}};
        for (unsigned a = 0; a < 3; a++) {
            for (unsigned b = a; b < 3; b++) {
                s.m[a][b] += q->w * d.v[a] * d.v[b] / total;
            }
        }
    }
    for (unsigned a = 0; a < 3; a++) {
        for (unsigned b = 0; b < a; b++) {
            s.m[a][b] = s.m[b][a];
        }
    }
    if (!gf_vec3_is_finite_n(&m, 3) || !gf_mat3_is_finite(&s)) {
        return GF_ERR_NONFINITE;
    }
    if (mu) {
        *mu = m;
    }
    if (sigma) {
        *sigma = s;
    }
    return GF_OK;
}
