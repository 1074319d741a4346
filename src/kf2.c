#include <stddef.h>

#include "gaussfilt/kf2.h"

#include "gf_internal.h"

// gcc's basic-block vectorizer (on at -O2 since gcc 12) packs these scalar
// formulas into SSE2 pairs with more shuffles than it saves: scripts/bench
// counts more instructions and time per step with it. Off for this file.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-tree-slp-vectorize")
#endif

// The checks of a motion model (and of u, if not NULL), in the order of
// gf_kf2_predict's statuses.
static gf_status model_check(const gf_kf2_model *model, const gf_vec2 *u)
{
    if (!gf_mat2_is_finite(&model->A) || !gf_mat2_is_finite(&model->B) ||
        !gf_vec2_is_finite(&model->c) || (u && !gf_vec2_is_finite(u))) {
        return GF_ERR_NONFINITE;
    }
    return gf_mat2_check_psd(&model->R);
}

// The checks of a measurement model with m = 1 or 2 (and of z, if not
// NULL), in the order of gf_kf2_update's statuses.
static gf_status meas_check(const gf_kf2_meas *meas, const gf_vec2 *z)
{
    const unsigned m = meas->m;
    for (unsigned i = 0; i < m; i++) {
        if (!GF_ISFINITE(meas->C.m[i][0]) || !GF_ISFINITE(meas->C.m[i][1]) ||
            !GF_ISFINITE(meas->c.v[i]) || (z && !GF_ISFINITE(z->v[i]))) {
            return GF_ERR_NONFINITE;
        }
    }
    if (!GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    if (m != 1) {
        return gf_mat2_check_psd(&meas->Q);
    }
    if (!GF_ISFINITE(meas->Q.m[0][0])) {
        return GF_ERR_NONFINITE;
    }
    return meas->Q.m[0][0] < 0 ? GF_ERR_NOT_PSD : GF_OK;
}

gf_status gf_kf2_prepare_model(gf_kf2_pmodel *pm, const gf_kf2_model *model)
{
    if (!pm || !model) {
        return GF_ERR_ARG;
    }
    gf_status st = model_check(model, NULL);
    if (st != GF_OK) {
        return st;
    }
    pm->model = *model;
    return GF_OK;
}

gf_status gf_kf2_prepare_meas(gf_kf2_pmeas *pq, const gf_kf2_meas *meas)
{
    if (!pq || !meas || meas->m < 1 || meas->m > 2) {
        return GF_ERR_ARG;
    }
    gf_status st = meas_check(meas, NULL);
    if (st != GF_OK) {
        return st;
    }
    pq->meas = *meas;
    // A gate of zero lets every NIS in: an infinite bound (the NIS itself
    // is tested finite with the result).
    pq->nis_max = meas->gate > 0 ? meas->gate : (gf_real)INFINITY;
    return GF_OK;
}

#if !GF_SMALL // GF_SMALL: init, predict and update are in small.c

gf_status gf_kf2_init(gf_kf2 *kf, const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!kf || !mu || !sigma) {
        return GF_ERR_ARG;
    }
    if (!gf_vec2_is_finite(mu)) {
        return GF_ERR_NONFINITE;
    }
    gf_status st = gf_mat2_check_psd(sigma);
    if (st != GF_OK) {
        return st;
    }
    kf->mu = *mu;
    kf->sigma = *sigma;
    gf_mat2_symmetrize(&kf->sigma);
    return GF_OK;
}

// How the checks stay cheap, here and in update1 (docs/performance.md):
// the step is computed first, from the raw inputs, into locals. A NaN or
// inf among the inputs cannot vanish through + - *, so it reaches the
// outputs; inputs that reach no output (B without u, the gate) are added to
// the same sum. One finiteness test of that sum then stands for all the
// per-entry tests, and it can only err on the safe side (a sum of finite
// values that overflows). It is folded into the sign tests: sum - sum is a
// zero when the sum is finite and NaN when it is not, and added to a
// quantity that must be >= 0 it makes that one comparison fail for both
// reasons. On any doubt the slow path runs the full checks in their
// documented order and then the same (inlined) computation again, so every
// failure reports the status it always did, and the belief is written only
// on success. The fast path then needs no stack frame: the slow one is a
// tail call.

// The computations are inlined into both paths, so the fast path does not
// pay for a call, and the slow paths stay out of line, so it needs no frame.
// Under -Os all this is left to the compiler (one copy of each computation,
// called), which keeps the flash cost of the slow paths small.
// KF2_FAST: a fast path shared by two public functions, inlined into each
// for speed, but one called copy under -Os.
#if defined(__GNUC__) && !defined(__OPTIMIZE_SIZE__)
#define KF2_INLINE static inline __attribute__((always_inline))
#define KF2_FAST static inline __attribute__((always_inline))
#define KF2_SLOW static __attribute__((noinline, cold))
#elif defined(__GNUC__)
#define KF2_INLINE static inline
#define KF2_FAST static __attribute__((noinline))
#define KF2_SLOW static
#else
#define KF2_INLINE static inline
#define KF2_FAST static
#define KF2_SLOW static
#endif
// update2 (m = 2) is never inlined: its frame (2x2 locals, a call to
// gf_mat2_spd_inv) would otherwise be the frame of gf_kf2_update, for m = 1
// too.
#if defined(__GNUC__)
#define KF2_OUTLINE static __attribute__((noinline))
#else
#define KF2_OUTLINE static
#endif

// mu_bar and Sigma_bar (upper triangle) of a step.
typedef struct kf2_step {
    gf_real m0, m1, s00, s01, s11;
} kf2_step;

static int step_is_finite(const kf2_step *r)
{
    return GF_ISFINITE(r->m0) && GF_ISFINITE(r->m1) && GF_ISFINITE(r->s00) &&
           GF_ISFINITE(r->s01) && GF_ISFINITE(r->s11);
}

// The sum of a step's outputs: finite only if every one of them is.
static inline gf_real step_sum(const kf2_step *r)
{
    return r->m0 + r->m1 + r->s00 + r->s01 + r->s11;
}

// min(a, b), written so that a NaN in b is kept (a NaN in a is dropped:
// pass a NaN to be kept as b). Compiles to one minsd on x86-64.
static inline gf_real min_keep_b(gf_real a, gf_real b)
{
    return a < b ? a : b;
}

// Writes a step's belief; Sigma mirrored, so exactly symmetric.
static inline void step_commit(gf_kf2 *kf, const kf2_step *r)
{
    kf->mu.v[0] = r->m0;
    kf->mu.v[1] = r->m1;
    kf->sigma.m[0][0] = r->s00;
    kf->sigma.m[0][1] = r->s01;
    kf->sigma.m[1][0] = r->s01;
    kf->sigma.m[1][1] = r->s11;
}

// mu_bar = A mu + B u + c, Sigma_bar = A Sigma A^T + R, from the raw inputs.
KF2_INLINE kf2_step predict_compute(const gf_kf2 *kf,
                                    const gf_kf2_model *model,
                                    const gf_vec2 *u)
{
    const gf_mat2 *A = &model->A, *B = &model->B, *R = &model->R;
    const gf_real a00 = A->m[0][0], a01 = A->m[0][1];
    const gf_real a10 = A->m[1][0], a11 = A->m[1][1];
    // Sigma is symmetric (every call writes it so): 3 unique entries.
    const gf_real s00 = kf->sigma.m[0][0], s01 = kf->sigma.m[0][1];
    const gf_real s11 = kf->sigma.m[1][1];
    kf2_step r;

    // mu_bar = A mu + B u + c
    r.m0 = a00 * kf->mu.v[0] + a01 * kf->mu.v[1];
    r.m1 = a10 * kf->mu.v[0] + a11 * kf->mu.v[1];
    if (u) {
        r.m0 += B->m[0][0] * u->v[0] + B->m[0][1] * u->v[1];
        r.m1 += B->m[1][0] * u->v[0] + B->m[1][1] * u->v[1];
    }
    r.m0 += model->c.v[0];
    r.m1 += model->c.v[1];

    // Sigma_bar = A Sigma A^T + R: T = A Sigma, then the upper triangle of
    // T A^T.
    const gf_real t00 = a00 * s00 + a01 * s01, t01 = a00 * s01 + a01 * s11;
    const gf_real t10 = a10 * s00 + a11 * s01, t11 = a10 * s01 + a11 * s11;
    r.s00 = t00 * a00 + t01 * a01 + R->m[0][0];
    r.s01 = t00 * a10 + t01 * a11 + R->m[0][1];
    r.s11 = t10 * a10 + t11 * a11 + R->m[1][1];
    return r;
}

// The quick tests of a prediction with an unchecked model: fin (the sum of
// the outputs and of B when u is NULL) finite, and R a covariance: exactly
// symmetric (within the tolerance only: slow path; a NaN fails both
// comparisons, so R's lower entry needs no other test), variances and
// determinant non-negative as gf_mat2_check_psd judges them. The last three
// and fin are one comparison: det + tol r00 r11 >= 0 is exactly the
// rounded det >= -tol r00 r11 of gf_mat2_check_psd (a rounded sum has the
// sign of the exact one), fin - fin makes it NaN for a fin that is not
// finite, and the minimum with the variances (NaN kept) makes it negative
// for a negative variance.
KF2_INLINE int predict_model_ok(const gf_mat2 *R, gf_real fin)
{
    const gf_real r00 = R->m[0][0], r01 = R->m[0][1], r11 = R->m[1][1];
    const gf_real r10 = R->m[1][0];
    const gf_real rdp = r00 * r11;
    gf_real v = (rdp - r01 * r01) + GF_PD_RTOL * rdp + (fin - fin);
    v = min_keep_b(r00, v);
    v = min_keep_b(r11, v);
    return r01 <= r10 && r01 >= r10 && v >= 0;
}

KF2_SLOW gf_status predict_slow(gf_kf2 *kf, const gf_kf2_model *model,
                                const gf_vec2 *u)
{
    gf_status st = model_check(model, u);
    if (st != GF_OK) {
        return st;
    }
    kf2_step r = predict_compute(kf, model, u);
    if (!step_is_finite(&r)) {
        return GF_ERR_NONFINITE; // overflow: keep the last good belief
    }
    step_commit(kf, &r);
    return GF_OK;
}

gf_status gf_kf2_predict(gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    if (!kf || !model) {
        return GF_ERR_ARG;
    }
    kf2_step r = predict_compute(kf, model, u);
    gf_real fin = step_sum(&r);
    if (!u) { // B reaches no output
        const gf_mat2 *B = &model->B;
        fin += B->m[0][0] + B->m[0][1] + B->m[1][0] + B->m[1][1];
    }
    if (!predict_model_ok(&model->R, fin)) {
        return predict_slow(kf, model, u);
    }
    step_commit(kf, &r);
    return GF_OK;
}

// A scalar update: the new belief, the innovation and NIS, s and 1/s.
typedef struct kf2_update1 {
    kf2_step b;
    gf_real s, si, y, nis;
} kf2_update1;

// gf_kf2_update for a scalar measurement, from the raw inputs: S is a
// number, so no inverse and no 2x2 algebra.
KF2_INLINE kf2_update1 update1_compute(const gf_kf2 *kf,
                                       const gf_kf2_meas *meas,
                                       const gf_vec2 *z)
{
    const gf_real c0 = meas->C.m[0][0], c1 = meas->C.m[0][1];
    const gf_real mu0 = kf->mu.v[0], mu1 = kf->mu.v[1];
    const gf_real s00 = kf->sigma.m[0][0], s01 = kf->sigma.m[0][1];
    const gf_real s11 = kf->sigma.m[1][1];
    kf2_update1 r;

    // p = Sigma_bar C^T, s = C Sigma_bar C^T + Q
    const gf_real p0 = s00 * c0 + s01 * c1, p1 = s01 * c0 + s11 * c1;
    const gf_real s = meas->Q.m[0][0] + (c0 * p0 + c1 * p1);
    const gf_real si = GF_R(1.0) / s;
    // y = z - c - C mu_bar, NIS = y s^-1 y
    r.s = s;
    r.si = si;
    r.y = z->v[0] - meas->c.v[0] - (c0 * mu0 + c1 * mu1);
    r.nis = r.y * si * r.y;
    // K = p s^-1; mu = mu_bar + K y
    const gf_real k0 = p0 * si, k1 = p1 * si;
    r.b.m0 = mu0 + k0 * r.y;
    r.b.m1 = mu1 + k1 * r.y;
    // Joseph form, (I - K C) Sigma_bar (I - K C)^T + K Q K^T, multiplied
    // out for a scalar measurement: Sigma_bar - K p^T - p K^T + s K K^T.
    // That holds for any gain K, so a rounding error dK in K adds only
    // s dK dK^T (positive semidefinite, second order): the property the
    // Joseph form is used for. With w = s K - p (zero but for rounding):
    // Sigma = Sigma_bar - p K^T + K w^T, whose diagonal is Sigma_bar_ii +
    // k_i (w_i - p_i); the upper triangle, mirrored on commit (so exactly
    // symmetric).
    const gf_real w0 = s * k0 - p0, w1 = s * k1 - p1;
    r.b.s00 = s00 + k0 * (w0 - p0);
    r.b.s01 = s01 - p0 * k1 + k0 * w1;
    r.b.s11 = s11 + k1 * (w1 - p1);
    return r;
}

// The sum of a scalar update's outputs and NIS: finite only if all are.
// C, c, z and Q reach s or the NIS, and s is tested through s^-1 > 0,
// which fails for s = inf or NaN.
static inline gf_real update1_sum(const kf2_update1 *r)
{
    return r->nis + step_sum(&r->b);
}

// The info of a scalar update (y and NIS in its first entry).
static inline void update1_info(gf_innovation *info, const kf2_update1 *r)
{
    info->m = 1;
    info->y[0] = r->y;
    info->y[1] = 0;
    info->y[2] = 0;
    info->nis = r->nis;
}

// A scalar update that passed its checks: the commit and the info.
KF2_INLINE gf_status update1_commit(gf_kf2 *kf, const kf2_update1 *r,
                                    gf_innovation *info)
{
    step_commit(kf, &r->b);
    if (info) {
        update1_info(info, r);
    }
    return GF_OK;
}

// Every check of a scalar update, in the order gf_kf2_update reports them,
// then the gate, then the commit.
KF2_SLOW gf_status update1_slow(gf_kf2 *kf, const gf_kf2_meas *meas,
                                const gf_vec2 *z, gf_innovation *info)
{
    gf_status st = meas_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    kf2_update1 r = update1_compute(kf, meas, z);
    if (!GF_ISFINITE(r.s)) {
        return GF_ERR_NONFINITE;
    }
    if (!(r.s > 0)) {
        return GF_ERR_SINGULAR;
    }
    if (!GF_ISFINITE(r.nis)) {
        return GF_ERR_NONFINITE;
    }
    gf_innovation in;
    update1_info(&in, &r);
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }
    if (!step_is_finite(&r.b)) {
        return GF_ERR_NONFINITE;
    }
    return update1_commit(kf, &r, info);
}

// gf_kf2_update for m = 2: S inverted in closed form, the factored Joseph
// form. Out of line and with few 2x2 locals, each in the narrowest scope
// (the compiler may then share their stack slots): its frame plus
// gf_mat2_spd_inv's is gf_kf2_update's deepest stack on an MCU.
KF2_OUTLINE gf_status update2(gf_kf2 *kf, const gf_kf2_meas *meas,
                              const gf_vec2 *z, gf_innovation *info)
{
    if (!z || meas->m != 2) {
        return GF_ERR_ARG;
    }
    gf_status st = meas_check(meas, z);
    if (st != GF_OK) {
        return st;
    }
    const gf_mat2 *C = &meas->C, *Q = &meas->Q, *sig = &kf->sigma;
    const gf_vec2 *mu = &kf->mu;

    // PCt = Sigma_bar C^T; S = C Sigma_bar C^T + Q, and its inverse
    gf_mat2 PCt, Si;
    for (unsigned j = 0; j < 2; j++) {
        PCt.m[0][j] = sig->m[0][0] * C->m[j][0] + sig->m[0][1] * C->m[j][1];
        PCt.m[1][j] = sig->m[1][0] * C->m[j][0] + sig->m[1][1] * C->m[j][1];
    }
    {
        gf_mat2 S;
        for (unsigned i = 0; i < 2; i++) {
            for (unsigned j = 0; j < 2; j++) {
                S.m[i][j] = Q->m[i][j] + (C->m[i][0] * PCt.m[0][j] +
                                          C->m[i][1] * PCt.m[1][j]);
            }
        }
        st = gf_mat2_spd_inv(&S, &Si);
        if (st != GF_OK) {
            return st;
        }
    }

    // y = z - c - C mu_bar, NIS = y^T S^-1 y
    gf_innovation in;
    in.m = 2;
    in.y[2] = 0;
    for (unsigned i = 0; i < 2; i++) {
        in.y[i] = z->v[i] - meas->c.v[i] -
                  (C->m[i][0] * mu->v[0] + C->m[i][1] * mu->v[1]);
    }
    in.nis = 0;
    for (unsigned i = 0; i < 2; i++) {
        for (unsigned j = 0; j < 2; j++) {
            in.nis += in.y[i] * Si.m[i][j] * in.y[j];
        }
    }
    if (!GF_ISFINITE(in.nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gf_gated(&in, meas->gate, info)) {
        return GF_ERR_GATED;
    }

    // K = Sigma_bar C^T S^-1, into PCt's place (row by row: a row of K
    // needs only the same row of PCt)
    gf_mat2 *K = &PCt;
    for (unsigned i = 0; i < 2; i++) {
        const gf_real p0 = PCt.m[i][0], p1 = PCt.m[i][1];
        K->m[i][0] = p0 * Si.m[0][0] + p1 * Si.m[1][0];
        K->m[i][1] = p0 * Si.m[0][1] + p1 * Si.m[1][1];
    }

    // mu = mu_bar + K y
    kf2_step r;
    r.m0 = mu->v[0] + K->m[0][0] * in.y[0] + K->m[0][1] * in.y[1];
    r.m1 = mu->v[1] + K->m[1][0] * in.y[0] + K->m[1][1] * in.y[1];

    // Sigma = (I - K C) Sigma_bar (I - K C)^T + K Q K^T, then symmetrized
    gf_mat2 sig_new;
    {
        gf_mat2 IKC;
        for (unsigned i = 0; i < 2; i++) {
            for (unsigned k = 0; k < 2; k++) {
                IKC.m[i][k] = (i == k ? GF_R(1.0) : GF_R(0.0)) -
                              K->m[i][0] * C->m[0][k] -
                              K->m[i][1] * C->m[1][k];
            }
        }
        gf_mat2_sandwich(&IKC, sig, &sig_new);
    }
    for (unsigned i = 0; i < 2; i++) {
        const gf_real kq0 = K->m[i][0] * Q->m[0][0] + K->m[i][1] * Q->m[1][0];
        const gf_real kq1 = K->m[i][0] * Q->m[0][1] + K->m[i][1] * Q->m[1][1];
        for (unsigned k = 0; k < 2; k++) {
            sig_new.m[i][k] += kq0 * K->m[k][0];
            sig_new.m[i][k] += kq1 * K->m[k][1];
        }
    }
    r.s00 = sig_new.m[0][0];
    r.s01 = GF_R(0.5) * (sig_new.m[0][1] + sig_new.m[1][0]);
    r.s11 = sig_new.m[1][1];

    if (!step_is_finite(&r)) {
        return GF_ERR_NONFINITE;
    }
    step_commit(kf, &r);
    if (info) {
        *info = in;
    }
    return GF_OK;
}

// The m = 1 update of gf_kf2_update (nis_max NULL: the model unchecked)
// and of gf_kf2_update_prepared (nis_max: the prepared gate's bound).
// Inlined into each at -O2, where the test of nis_max folds away; one copy,
// called, under -Os, so that gf_kf2_update's own frame stays small on an
// MCU (its deepest path is update2's).
KF2_FAST gf_status update1(gf_kf2 *kf, const gf_kf2_meas *meas,
                           const gf_vec2 *z, gf_innovation *info,
                           const gf_real *nis_max)
{
    if (!z) {
        return GF_ERR_ARG;
    }
    kf2_update1 r = update1_compute(kf, meas, z);
    int ok;
    if (nis_max) {
        // A prepared model: the result finite, s > 0, the gate.
        ok = GF_ISFINITE(update1_sum(&r)) && r.si > 0 && r.nis <= *nis_max;
    } else {
        // Q >= 0 and the sum (with the gate, which reaches no output)
        // finite, folded into one comparison; s > 0 and finite; the gate
        // lets the measurement in: the NIS is >= 0 (or NaN), so NIS <= gate
        // is a gate >= 0 that passes it, and the other way in is a gate of
        // zero (disabled), tested without ==.
        const gf_real gate = meas->gate;
        const gf_real fin = update1_sum(&r) + gate;
        ok = meas->Q.m[0][0] + (fin - fin) >= 0 &&
             r.si > 0 && ((gate <= 0 && gate >= 0) || r.nis <= gate);
    }
    if (!ok) {
        return update1_slow(kf, meas, z, info);
    }
    return update1_commit(kf, &r, info);
}

gf_status gf_kf2_update(gf_kf2 *kf, const gf_kf2_meas *meas,
                        const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !meas) {
        return GF_ERR_ARG;
    }
    if (meas->m != 1) {
        return update2(kf, meas, z, info); // m = 2, or GF_ERR_ARG
    }
    return update1(kf, meas, z, info, NULL);
}

// The prepared steps: the model's checks were done by prepare, so the
// quick test is only the finiteness of the result (u and z reach it), and
// for an update s > 0 and the gate. On any doubt the same slow paths as
// above, on the stored model, which find the status gf_kf2_predict/update
// report.
gf_status gf_kf2_predict_prepared(gf_kf2 *kf, const gf_kf2_pmodel *pm,
                                  const gf_vec2 *u)
{
    if (!kf || !pm) {
        return GF_ERR_ARG;
    }
    kf2_step r = predict_compute(kf, &pm->model, u);
    if (!GF_ISFINITE(step_sum(&r))) {
        return predict_slow(kf, &pm->model, u);
    }
    step_commit(kf, &r);
    return GF_OK;
}

gf_status gf_kf2_update_prepared(gf_kf2 *kf, const gf_kf2_pmeas *pq,
                                 const gf_vec2 *z, gf_innovation *info)
{
    if (!kf || !pq) {
        return GF_ERR_ARG;
    }
    if (pq->meas.m != 1) {
        return update2(kf, &pq->meas, z, info);
    }
    return update1(kf, &pq->meas, z, info, &pq->nis_max);
}

#else // GF_SMALL: the plain steps of small.c on the stored model

gf_status gf_kf2_predict_prepared(gf_kf2 *kf, const gf_kf2_pmodel *pm,
                                  const gf_vec2 *u)
{
    return pm ? gf_kf2_predict(kf, &pm->model, u) : GF_ERR_ARG;
}

gf_status gf_kf2_update_prepared(gf_kf2 *kf, const gf_kf2_pmeas *pq,
                                 const gf_vec2 *z, gf_innovation *info)
{
    return pq ? gf_kf2_update(kf, &pq->meas, z, info) : GF_ERR_ARG;
}

#endif // GF_SMALL
