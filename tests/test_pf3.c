// SPDX-License-Identifier: MIT
// PF3: sampling, weighting, low-variance resampling in place, summaries,
// determinism, and the promise that a failing call leaves the belief (the
// struct, its generator and every particle) as it was. Exercise 4 is in
// test_ex4.c.
#include <stdlib.h>

#include "gf_test.h"

#define N 4
#define N_BIG 1000

static gf_pf3_particle small[N];
static gf_pf3_particle big[N_BIG], big2[N_BIG];

static const gf_vec3 origin = {{0, 0, 0}};
static const gf_mat3 zero3 = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
static const gf_mat3 prior = {
    {{1, GF_R(0.2), 0}, {GF_R(0.2), 2, 0}, {0, 0, GF_R(0.5)}}};

// A 4-particle filter with particles at x = 0, 0.1, 0.3, 0.7, heading 0.
static void four(gf_pf3 *pf)
{
    static const gf_real xs[N] = {0, GF_R(0.1), GF_R(0.3), GF_R(0.7)};
    assert_int_equal(gf_pf3_init(pf, small, N, 1, &origin, &zero3), GF_OK);
    for (int k = 0; k < N; k++) {
        small[k].x.v[0] = xs[k];
    }
}

// Fails for a particle beyond x = 0.5: the last of four().
static gf_status fails_far(void *ctx, const gf_vec3 *mu, const gf_real *u,
                           gf_vec3 *mu_bar, gf_mat3 *G)
{
    if (mu->v[0] > GF_R(0.5)) {
        return GF_ERR_MODEL;
    }
    return gf_ekf3_motion_forward_turn(ctx, mu, u, mu_bar, G);
}

static gf_status meas_fails_far(void *ctx, const gf_vec3 *mu_bar,
                                gf_vec3 *z_hat, gf_mat3 *H)
{
    if (mu_bar->v[0] > GF_R(0.5)) {
        return (gf_status)-100; // unknown: reported as GF_ERR_MODEL
    }
    return gf_ekf3_meas_x(ctx, mu_bar, z_hat, H);
}

static void test_init_deterministic(void **state)
{
    (void)state;
    gf_pf3 a, b;
    assert_int_equal(gf_pf3_init(&a, big, N_BIG, 99, &origin, &prior), GF_OK);
    assert_int_equal(gf_pf3_init(&b, big2, N_BIG, 99, &origin, &prior), GF_OK);
    assert_memory_equal(big, big2, sizeof big); // same seed, same particles
    assert_memory_equal(a.rng.s, b.rng.s, sizeof a.rng.s); // (not padding)
    assert_int_equal(a.rng.has_spare, b.rng.has_spare);
    for (int k = 0; k < N_BIG; k++) {
        CHECK_CLOSE(big[k].w, 1.0 / N_BIG);
    }
    assert_int_equal(gf_pf3_init(&b, big2, N_BIG, 100, &origin, &prior), GF_OK);
    assert_true(memcmp(big, big2, sizeof big) != 0);
    // sigma = 0: n copies of mu
    const gf_vec3 mu = {{1, 2, 3}};
    assert_int_equal(gf_pf3_init(&a, small, N, 5, &mu, &zero3), GF_OK);
    for (int k = 0; k < N; k++) {
        assert_memory_equal(&small[k].x, &mu, sizeof mu);
    }
}

// With R = 0 every particle moves exactly by g; weights are kept.
static void test_predict_noiseless(void **state)
{
    (void)state;
    gf_pf3 pf;
    const gf_ekf3_motion mo = {
        gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
    const gf_real u[2] = {2, GF_R(0.5)};
    assert_int_equal(gf_pf3_init(&pf, big, N_BIG, 3, &origin, &prior), GF_OK);
    memcpy(big2, big, sizeof big);
    assert_int_equal(gf_pf3_predict(&pf, &mo, u), GF_OK);
    for (int k = 0; k < N_BIG; k++) {
        gf_vec3 want;
        gf_mat3 G;
        gf_ekf3_motion_forward_turn(NULL, &big2[k].x, u, &want, &G);
        CHECK_CLOSE(big[k].x.v[0], want.v[0]);
        CHECK_CLOSE(big[k].x.v[1], want.v[1]);
        CHECK_CLOSE(big[k].x.v[2], gf_angle_wrap(want.v[2]));
        assert_true(big[k].w == big2[k].w);
    }
}

// With R != 0 the motion noise has covariance R: the particles' spread
// about g(x) has R's variances, within 4.5 standard errors.
static void test_predict_noise(void **state)
{
    (void)state;
    gf_pf3 pf;
    const gf_ekf3_motion mo = {
        gf_ekf3_motion_forward_turn,
        NULL,
        {{{GF_R(0.04), 0, 0}, {0, GF_R(0.09), 0}, {0, 0, GF_R(0.01)}}}};
    const gf_real u[2] = {1, 0};
    assert_int_equal(gf_pf3_init(&pf, big, N_BIG, 8, &origin, &zero3), GF_OK);
    assert_int_equal(gf_pf3_predict(&pf, &mo, u), GF_OK);
    for (int i = 0; i < 3; i++) {
        double m = i == 0 ? 1 : 0, s2 = 0, r = (double)mo.R.m[i][i];
        for (int k = 0; k < N_BIG; k++) {
            double d = (double)big[k].x.v[i] - m;
            s2 += d * d / N_BIG;
        }
        assert_true(fabs(s2 - r) < 4.5 * r * sqrt(2.0 / N_BIG));
    }
}

// w <- w N(z; h(x), Q), normalised: particles at 0, 0.1, 0.3, 0.7 seeing
// z = 0 with Q = 0.01 weigh 1 : e^-0.5 : e^-4.5 : e^-24.5.
static void test_update_weights(void **state)
{
    (void)state;
    gf_pf3 pf;
    four(&pf);
    const gf_ekf3_meas me = {1,    gf_ekf3_meas_x,
                             NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                             0,    0};
    const gf_vec3 z = {{0, 0, 0}};
    assert_int_equal(gf_pf3_update(&pf, &me, &z), GF_OK);
    const double w[N] = {1, exp(-0.5), exp(-4.5), exp(-24.5)};
    const double sum = w[0] + w[1] + w[2] + w[3];
    for (int k = 0; k < N; k++) {
        CHECK_CLOSE(small[k].w, w[k] / sum);
    }
    // A second update multiplies in: weights ~ w^2.
    assert_int_equal(gf_pf3_update(&pf, &me, &z), GF_OK);
    const double sum2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3];
    for (int k = 0; k < N; k++) {
        CHECK_CLOSE(small[k].w, w[k] * w[k] / sum2);
    }
}

// z = 1000, far from every particle: e^(-d2/2) underflows for all of
// them, but the log-domain weights give the closest (x = 0.7) all the
// weight, not NaN. With a gate of 9, the same z is refused.
static void test_update_far(void **state)
{
    (void)state;
    gf_pf3 pf;
    four(&pf);
    gf_ekf3_meas me = {1,    gf_ekf3_meas_x,
                       NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                       0,    0};
    const gf_vec3 z = {{1000, 0, 0}};
    me.gate = 9;
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &pf, gf_pf3_update(&pf, &me, &z));
    me.gate = 0;
    assert_int_equal(gf_pf3_update(&pf, &me, &z), GF_OK);
    CHECK_CLOSE(small[0].w, 0.0);
    CHECK_CLOSE(small[1].w, 0.0);
    CHECK_CLOSE(small[2].w, 0.0);
    CHECK_CLOSE(small[3].w, 1.0);
}

// Weights (0.5, 0, 0.25, 0.25): n = 4 points r + k/4 with r in (0, 1/4)
// give particle 0 two copies, 2 and 3 one each, 1 none; whatever r.
static void test_resample_counts(void **state)
{
    (void)state;
    gf_pf3 pf;
    four(&pf);
    const gf_real w[N] = {GF_R(0.5), 0, GF_R(0.25), GF_R(0.25)};
    for (int k = 0; k < N; k++) {
        small[k].w = w[k];
    }
    assert_int_equal(gf_pf3_resample(&pf), GF_OK);
    int seen[N] = {0, 0, 0, 0};
    for (int k = 0; k < N; k++) {
        CHECK_CLOSE(small[k].w, 0.25);
        for (int j = 0; j < N; j++) {
            seen[j] += fabs((double)small[k].x.v[0] - (j == 0   ? 0
                                                       : j == 1 ? 0.1
                                                       : j == 2 ? 0.3
                                                                : 0.7)) < 1e-6;
        }
    }
    assert_int_equal(seen[0], 2);
    assert_int_equal(seen[1], 0);
    assert_int_equal(seen[2], 1);
    assert_int_equal(seen[3], 1);
}

// In place against the book's out-of-place Table 4.4, on 1000 random
// weights with the same r: the same copies of the same particles.
static void test_resample_matches_table_4_4(void **state)
{
    (void)state;
    gf_pf3 pf;
    gf_rng wr;
    assert_int_equal(gf_pf3_init(&pf, big, N_BIG, 21, &origin, &zero3), GF_OK);
    assert_int_equal(gf_rng_seed(&wr, 5), GF_OK);
    gf_real total = 0; // summed as the filter sums it
    for (int k = 0; k < N_BIG; k++) {
        big[k].x.v[0] = (gf_real)k; // the particle's identity
        big[k].w = gf_rng_uniform(&wr) * gf_rng_uniform(&wr) *
                   gf_rng_uniform(&wr); // skewed
        total += big[k].w;
    }
    // Reference, in double: r from a copy of the filter's generator.
    gf_rng copy = pf.rng;
    const gf_real step_f = total / (gf_real)N_BIG;
    const double r = (double)(gf_rng_uniform(&copy) * step_f);
    const double step = (double)step_f;
    static int want[N_BIG];
    memset(want, 0, sizeof want);
    double c = (double)big[0].w;
    int i = 0;
    for (int k = 0; k < N_BIG; k++) {
        double U = r + k * step;
        while (U > c && i + 1 < N_BIG) {
            i++;
            c += (double)big[i].w;
        }
        want[i]++;
    }
    assert_int_equal(gf_pf3_resample(&pf), GF_OK);
    static int got[N_BIG];
    memset(got, 0, sizeof got);
    for (int k = 0; k < N_BIG; k++) {
        got[(int)big[k].x.v[0]]++;
    }
    int differ = 0;
    for (int k = 0; k < N_BIG; k++) {
        differ += abs(got[k] - want[k]);
    }
    // Rounding of the running sum in float may move a boundary point.
#ifdef GF_SINGLE_PRECISION
    assert_true(differ <= 4);
#else
    assert_int_equal(differ, 0);
#endif
}

static void test_neff_and_estimate(void **state)
{
    (void)state;
    gf_pf3 pf;
    gf_real neff;
    four(&pf);
    assert_int_equal(gf_pf3_neff(&pf, &neff), GF_OK);
    CHECK_CLOSE(neff, 4.0);
    small[0].w = 1;
    small[1].w = small[2].w = small[3].w = 0;
    assert_int_equal(gf_pf3_neff(&pf, &neff), GF_OK);
    CHECK_CLOSE(neff, 1.0);

    // Two particles at headings pi - 0.1 and -pi + 0.1: the mean heading
    // is pi (not 0), the heading variance 0.01.
    four(&pf);
    small[0].x.v[2] = GF_PI - GF_R(0.1);
    small[1].x.v[2] = -GF_PI + GF_R(0.1);
    small[2].w = small[3].w = 0;
    gf_vec3 m;
    gf_mat3 s;
    assert_int_equal(gf_pf3_estimate(&pf, &m, &s), GF_OK);
    CHECK_CLOSE(fabs((double)m.v[2]), 3.14159265358979323846);
    CHECK_CLOSE(m.v[0], 0.05);
    CHECK_CLOSE(s.m[0][0], 0.0025);
    CHECK_CLOSE(s.m[2][2], 0.01);
    CHECK_CLOSE(s.m[0][2], s.m[2][0]);
    // Opposite headings have no mean direction.
    small[0].x.v[2] = 0;
    small[1].x.v[2] = GF_PI;
    m.v[0] = 7;
    assert_int_equal(gf_pf3_estimate(&pf, &m, NULL), GF_ERR_UNDEFINED);
    assert_true(m.v[0] > GF_R(6.5));
}

// Checks that a call fails with st and leaves pf and its particles as
// they were.
#define CHECK_PF_UNCHANGED(st, pf, call)                                       \
    do {                                                                       \
        gf_pf3_particle keep_[N];                                              \
        memcpy(keep_, small, sizeof small);                                    \
        CHECK_FAILS_UNCHANGED(st, pf, call);                                   \
        assert_memory_equal(keep_, small, sizeof small);                       \
    } while (0)

// z may point into the particles an update rewrites: a z whose first
// entry is particle 0's weight gives the same particles, bit for bit, as
// a copy of it.
static void test_update_z_aliasing_weight(void **state)
{
    (void)state;
    gf_ekf3_meas meas;
    memset(&meas, 0, sizeof meas);
    meas.m = 1;
    meas.h = gf_ekf3_meas_x;
    meas.Q.m[0][0] = GF_R(0.01);
    gf_pf3 pf;
    four(&pf);
    const gf_vec3 zc = {{small[0].w, 0, 0}};
    assert_int_equal(gf_pf3_update(&pf, &meas, &zc), GF_OK);
    gf_pf3_particle want[N];
    memcpy(want, small, sizeof want);
    four(&pf);
    const gf_vec3 *alias = (const gf_vec3 *)(const void *)&small[0].w;
    assert_int_equal(gf_pf3_update(&pf, &meas, alias), GF_OK);
    assert_memory_equal(want, small, sizeof want);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    gf_pf3 pf;
    four(&pf);
    gf_vec3 nanv = origin;
    nanv.v[0] = (gf_real)NAN;
    gf_mat3 indef = prior;
    indef.m[1][1] = -1;

    // init
    assert_int_equal(gf_pf3_init(NULL, small, N, 1, &origin, &prior),
                     GF_ERR_ARG);
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf,
                       gf_pf3_init(&pf, NULL, N, 1, &origin, &prior));
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf,
                       gf_pf3_init(&pf, small, 0, 1, &origin, &prior));
    CHECK_PF_UNCHANGED(
        GF_ERR_ARG, &pf,
        gf_pf3_init(&pf, small, GF_PF3_MAX_N + 1u, 1, &origin, &prior));
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf,
                       gf_pf3_init(&pf, small, N, 1, NULL, &prior));
    CHECK_PF_UNCHANGED(GF_ERR_NONFINITE, &pf,
                       gf_pf3_init(&pf, small, N, 1, &nanv, &prior));
    CHECK_PF_UNCHANGED(GF_ERR_NOT_PSD, &pf,
                       gf_pf3_init(&pf, small, N, 1, &origin, &indef));

    // predict: the model fails on the last particle, after the first three
    // went through: nothing moved, the generator did not advance.
    const gf_real u[2] = {1, 0};
    gf_ekf3_motion mo = {
        fails_far,
        NULL,
        {{{GF_R(0.1), 0, 0}, {0, GF_R(0.1), 0}, {0, 0, GF_R(0.1)}}}};
    CHECK_PF_UNCHANGED(GF_ERR_MODEL, &pf, gf_pf3_predict(&pf, &mo, u));
    assert_int_equal(gf_pf3_predict(NULL, &mo, u), GF_ERR_ARG);
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_predict(&pf, NULL, u));
    mo.g = gf_ekf3_motion_forward_turn;
    mo.R.m[1][1] = -1;
    CHECK_PF_UNCHANGED(GF_ERR_NOT_PSD, &pf, gf_pf3_predict(&pf, &mo, u));
    mo.R.m[1][1] = (gf_real)NAN;
    CHECK_PF_UNCHANGED(GF_ERR_NONFINITE, &pf, gf_pf3_predict(&pf, &mo, u));
    mo.R.m[1][1] = GF_R(0.1);
    mo.g = NULL;
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_predict(&pf, &mo, u));

    // update
    gf_ekf3_meas me = {1,    meas_fails_far,
                       NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                       0,    0};
    const gf_vec3 z = {{0, 0, 0}};
    CHECK_PF_UNCHANGED(GF_ERR_MODEL, &pf, gf_pf3_update(&pf, &me, &z));
    me.h = gf_ekf3_meas_x;
    assert_int_equal(gf_pf3_update(NULL, &me, &z), GF_ERR_ARG);
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_update(&pf, NULL, &z));
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_update(&pf, &me, NULL));
    me.m = 4;
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_update(&pf, &me, &z));
    me.m = 1;
    CHECK_PF_UNCHANGED(GF_ERR_NONFINITE, &pf, gf_pf3_update(&pf, &me, &nanv));
    me.gate = -1;
    CHECK_PF_UNCHANGED(GF_ERR_ARG, &pf, gf_pf3_update(&pf, &me, &z));
    me.gate = 0;
    me.Q.m[0][0] = -1;
    CHECK_PF_UNCHANGED(GF_ERR_NOT_PSD, &pf, gf_pf3_update(&pf, &me, &z));
    me.Q.m[0][0] = 0;
    CHECK_PF_UNCHANGED(GF_ERR_SINGULAR, &pf, gf_pf3_update(&pf, &me, &z));
    me.Q.m[0][0] = GF_R(0.01);

    // weights the filter cannot use
    small[2].w = -GF_R(0.1);
    gf_real neff = 0;
    CHECK_PF_UNCHANGED(GF_ERR_UNDEFINED, &pf, gf_pf3_resample(&pf));
    CHECK_PF_UNCHANGED(GF_ERR_UNDEFINED, &pf, gf_pf3_update(&pf, &me, &z));
    assert_int_equal(gf_pf3_neff(&pf, &neff), GF_ERR_UNDEFINED);
    small[2].w = (gf_real)NAN;
    CHECK_PF_UNCHANGED(GF_ERR_NONFINITE, &pf, gf_pf3_resample(&pf));
    small[0].w = small[1].w = small[2].w = small[3].w = 0;
    CHECK_PF_UNCHANGED(GF_ERR_UNDEFINED, &pf, gf_pf3_resample(&pf));
    assert_int_equal(gf_pf3_estimate(&pf, &nanv, NULL), GF_ERR_UNDEFINED);
    assert_int_equal(gf_pf3_resample(NULL), GF_ERR_ARG);
    assert_int_equal(gf_pf3_neff(&pf, NULL), GF_ERR_ARG);
    assert_int_equal(gf_pf3_estimate(&pf, NULL, NULL), GF_ERR_ARG);
    assert_true(neff == 0);
}

// Every particle's call of g, in both passes, gets mu_bar = its particle
// and G = I.
static void test_motion_args(void **state)
{
    (void)state;
    unsigned broken = 0;
    const gf_test_args a = gf_test_args_make(&broken);
    gf_pf3 pf;
    assert_int_equal(gf_pf3_init(&pf, big, N_BIG, 5, &a.mu, &a.sig), GF_OK);
    assert_int_equal(gf_pf3_predict(&pf, &a.mo, a.u), GF_OK);
    assert_int_equal(broken, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_deterministic),
        cmocka_unit_test(test_predict_noiseless),
        cmocka_unit_test(test_predict_noise),
        cmocka_unit_test(test_update_weights),
        cmocka_unit_test(test_update_far),
        cmocka_unit_test(test_resample_counts),
        cmocka_unit_test(test_resample_matches_table_4_4),
        cmocka_unit_test(test_neff_and_estimate),
        cmocka_unit_test(test_update_z_aliasing_weight),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_motion_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
