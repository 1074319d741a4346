// SPDX-License-Identifier: MIT
// Statistical consistency of KF2 and EKF3 (Bar-Shalom, Li, Kirubarajan,
// "Estimation with Applications to Tracking and Navigation", 5.4): on data
// drawn from the very model the filter assumes, the normalised estimation
// error squared NEES = e^T Sigma^-1 e (e = truth - mu) and the normalised
// innovation squared NIS = y^T S^-1 y are chi-square with n and m degrees
// of freedom. Averaged over M independent Monte-Carlo runs, M times the
// average at a step is chi-square with M n degrees of freedom, so the
// average must lie in [chi2inv(0.025, M n) / M, chi2inv(0.975, M n) / M]
// at 95% of the steps.
//
// Allowance for the other 5%: the number of steps outside is taken as
// Binomial(T, 0.05) (steps are treated as independent trials; they are
// mildly correlated through the state, which widens the spread a little)
// and the test allows up to its 99.9% quantile.
//
// The average over all runs and steps must in addition lie in two-sided
// 99.9% bounds (wider than the per-step 95%: this check is one sample per
// test, and a fixed seed should not sit on a 1-in-20 edge). For NIS these have M T m degrees of freedom: the innovations
// of a consistent filter are white (Bar-Shalom 5.4.2), so the steps are
// independent and a filter off by a few percent everywhere fails there
// even if each step passes. Estimation errors are not white (the error at
// t carries into t + 1), so for NEES the overall bounds are those of a
// single step (M n degrees of freedom): the variance of an average of
// equally distributed, correlated samples is at most that of one sample,
// so these bounds are conservative.
//
// Seeds are fixed, so every run of this test sees the same numbers; the
// mistuned-filter cases show that the checker can fail.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gaussfilt/gaussfilt.h"
#include "trust.h"

#define RUNS 100      // Monte-Carlo runs M
#define STEPS 200     // steps T per run
#define EX4_RUNS 2000 // exercise 4 is one step; more runs instead

// ---- the verdict -----------------------------------------------------------

typedef struct verdict {
    const char *what;
    int dof;               // n (NEES) or m (NIS) of one sample
    int runs;              // M
    int steps;             // steps judged
    double lo, hi;         // two-sided 95% bounds on a step's average
    int outside;           // steps whose average fell outside [lo, hi]
    int allowed;           // binomial 99.9% quantile of steps * 0.05
    double mean;           // average over all runs and steps
    double all_lo, all_hi; // 99.9% bounds on that, see the top
    double min, max;       // smallest and largest step average
} verdict;

// Judges per-step sums over the runs: sum[t] for t = first..last.
// white: the samples are independent over time (NIS), see the top.
static verdict judge(const char *what, const double *sum, int first, int last,
                     int runs, int dof, int white)
{
    verdict v;
    v.what = what;
    v.dof = dof;
    v.runs = runs;
    v.steps = last - first + 1;
    double k = (double)runs * dof;
    v.lo = trust_chi2_inv(0.025, k) / runs;
    v.hi = trust_chi2_inv(0.975, k) / runs;
    v.allowed = trust_binom_quantile(v.steps, 0.05, 0.999);
    v.outside = 0;
    v.min = (double)INFINITY;
    v.max = -(double)INFINITY;
    double total = 0.0;
    for (int t = first; t <= last; t++) {
        double avg = sum[t] / runs;
        total += sum[t];
        v.outside += !(avg >= v.lo && avg <= v.hi);
        v.min = avg < v.min ? avg : v.min;
        v.max = avg > v.max ? avg : v.max;
    }
    double kk = white ? k * v.steps : k;
    double nk = white ? (double)runs * v.steps : runs;
    v.mean = total / ((double)runs * v.steps);
    v.all_lo = trust_chi2_inv(0.0005, kk) / nk;
    v.all_hi = trust_chi2_inv(0.9995, kk) / nk;
    printf("  %-34s M=%d T=%d dof=%d: avg %.3f (99.9%% [%.3f, %.3f]); "
           "steps outside [%.3f, %.3f]: %d (allowed %d); step avg %.3f..%.3f\n",
           what, runs, v.steps, dof, v.mean, v.all_lo, v.all_hi, v.lo, v.hi,
           v.outside, v.allowed, v.min, v.max);
    return v;
}

static int consistent(const verdict *v)
{
    return v->outside <= v->allowed && v->mean >= v->all_lo &&
           v->mean <= v->all_hi;
}

// ---- the quantiles themselves ----------------------------------------------

static void test_quantiles(void **state)
{
    (void)state;
    // k = 2: the chi-square is exponential, quantile -2 ln(1 - p) exactly.
    const double ps[] = {0.001, 0.025, 0.5, 0.68, 0.95, 0.975, 0.999};
    for (size_t i = 0; i < sizeof ps / sizeof ps[0]; i++) {
        double want = -2.0 * log1p(-ps[i]);
        assert_true(fabs(trust_chi2_inv(ps[i], 2) - want) <= 1e-10 * want);
        // k = 1: CDF(x) = erf(sqrt(x / 2)).
        double x = trust_chi2_inv(ps[i], 1);
        assert_true(fabs(erf(sqrt(0.5 * x)) - ps[i]) <= 1e-12);
    }
    // Large k (the continued-fraction branch), against printed tables
    // (NIST/SEMATECH e-Handbook 1.3.6.7.4: 74.222 and 129.561 for k = 100).
    assert_true(fabs(trust_chi2_inv(0.025, 100) - 74.222) < 1e-3);
    assert_true(fabs(trust_chi2_inv(0.975, 100) - 129.561) < 1e-3);
    // Round trip far out in the bulk of the bounds used below.
    for (int k = 1; k <= 2000000; k *= 7) {
        for (size_t i = 0; i < sizeof ps / sizeof ps[0]; i++) {
            double x = trust_chi2_inv(ps[i], k);
            assert_true(fabs(trust_chi2_cdf(x, k) - ps[i]) <= 1e-9);
        }
    }
    // Binomial quantile: the smallest k whose CDF reaches q.
    int k = trust_binom_quantile(199, 0.05, 0.999);
    double below = 0.0, at = 0.0;
    for (int j = 0; j <= k; j++) {
        double pmf = exp(lgamma(200.0) - lgamma(j + 1.0) - lgamma(200.0 - j) +
                         j * log(0.05) + (199 - j) * log(0.95));
        at += pmf;
        below += j < k ? pmf : 0.0;
    }
    assert_true(below < 0.999 && at >= 0.999);
    printf("  chi2inv(0.025, 200)/100 = %.4f, chi2inv(0.975, 200)/100 = %.4f, "
           "binom(199, 0.05) 99.9%% quantile = %d\n",
           trust_chi2_inv(0.025, 200) / 100, trust_chi2_inv(0.975, 200) / 100,
           k);
}

// ---- KF2 on the car of exercises 1 and 2 ----------------------------------

// Truth: x_t = A x_{t-1} + g a_t, a_t ~ N(0, 1), g = (0.5, 1): process noise
// R = g g^T = ((0.25, 0.5), (0.5, 1)), as in exercise 1. Position measured
// with variance 10 every step. Start known exactly at 0 (Sigma_0 = 0), as
// in the book. The filter may be told wrong noise (scale factors) to show
// that the test notices.
static void run_kf2(uint64_t seed, double r_scale, double q_filter,
                    double *nees_sum, double *nis_sum)
{
    const gf_kf2_model model = {
        .A = {{{1, 1}, {0, 1}}},
        .B = {{{0, 0}, {0, 0}}},
        .R = {{{(gf_real)(0.25 * r_scale), (gf_real)(0.5 * r_scale)},
               {(gf_real)(0.5 * r_scale), (gf_real)(1.0 * r_scale)}}},
        .c = {{0, 0}},
    };
    const gf_kf2_meas meas = {
        .m = 1,
        .C = {{{1, 0}, {0, 0}}},
        .Q = {{{(gf_real)q_filter, 0}, {0, 0}}},
        .c = {{0, 0}},
        .gate = 0,
    };
    memset(nees_sum, 0, sizeof(double) * (STEPS + 1));
    memset(nis_sum, 0, sizeof(double) * (STEPS + 1));
    trust_rng rng;
    trust_rng_seed(&rng, seed);
    for (int run = 0; run < RUNS; run++) {
        gf_kf2 kf;
        const gf_vec2 mu0 = {{0, 0}};
        const gf_mat2 s0 = {{{0, 0}, {0, 0}}};
        assert_int_equal(gf_kf2_init(&kf, &mu0, &s0), GF_OK);
        double x = 0.0, v = 0.0;
        for (int t = 1; t <= STEPS; t++) {
            double a = trust_normal(&rng);
            x += v + 0.5 * a;
            v += a;
            assert_int_equal(gf_kf2_predict(&kf, &model, NULL), GF_OK);
            gf_vec2 z = {{(gf_real)(x + sqrt(10.0) * trust_normal(&rng)), 0}};
            gf_innovation info;
            assert_int_equal(gf_kf2_update(&kf, &meas, &z, &info), GF_OK);
            nis_sum[t] += (double)info.nis;
            double e[2] = {x - (double)kf.mu.v[0], v - (double)kf.mu.v[1]};
            gf_mat2 sigma;
            assert_int_equal(gf_kf2_cov(&kf, &sigma), GF_OK);
            double s[3][3] = {{(double)sigma.m[0][0], (double)sigma.m[0][1], 0},
                              {(double)sigma.m[1][0], (double)sigma.m[1][1], 0},
                              {0, 0, 0}};
            // Sigma_1 is singular (R has rank 1, all of it along g), so
            // NEES is judged from t = 2 on.
            if (t >= 2) {
                double q = trust_quad_form(s, e, 2);
                assert_true(isfinite(q));
                nees_sum[t] += q;
            }
        }
    }
}

static double nees[STEPS + 1], nis[STEPS + 1];

static void test_kf2_consistent(void **state)
{
    (void)state;
    run_kf2(UINT64_C(0x6b66320001), 1.0, 10.0, nees, nis);
    verdict ne = judge("KF2 car NEES (n=2)", nees, 2, STEPS, RUNS, 2, 0);
    verdict ni = judge("KF2 car NIS (m=1)", nis, 1, STEPS, RUNS, 1, 1);
    assert_true(consistent(&ne));
    assert_true(consistent(&ni));
}

// The checker has power: a filter told half the measurement noise, or a
// quarter of the process noise, is caught.
static void test_kf2_mistuned_is_caught(void **state)
{
    (void)state;
    run_kf2(UINT64_C(0x6b66320002), 1.0, 5.0, nees, nis);
    verdict ni =
        judge("KF2 told Q=5 (truth 10): NIS", nis, 1, STEPS, RUNS, 1, 1);
    assert_false(consistent(&ni));
    assert_true(ni.outside > ni.steps / 2);

    run_kf2(UINT64_C(0x6b66320003), 0.25, 10.0, nees, nis);
    verdict ne = judge("KF2 told R/4: NEES", nees, 2, STEPS, RUNS, 2, 0);
    assert_false(consistent(&ne));
    assert_true(ne.outside > ne.steps / 2);
}

// ---- EKF3 -------------------------------------------------------------------

// The truth moves exactly as the EKF's model says: x_t = g(u, x_{t-1}) +
// eps, eps ~ N(0, R), with g the built-in "move d forward, then turn phi".
typedef struct ekf3_case {
    double sigma0[3]; // initial variances of x, y, theta (truth drawn from it)
    double r[3];      // process noise variances
    unsigned m;       // 1: x measured, 2: (x, y)
    double q;         // measurement variance of each measured quantity
    double d, phi;    // the control, every step
    int steps;
    int runs;
} ekf3_case;

static void run_ekf3(const ekf3_case *c, uint64_t seed, double *nees_sum,
                     double *nis_sum)
{
    gf_ekf3_motion motion;
    memset(&motion, 0, sizeof motion);
    motion.g = gf_ekf3_motion_forward_turn;
    gf_ekf3_meas meas;
    memset(&meas, 0, sizeof meas);
    meas.m = c->m;
    meas.h = c->m == 1 ? gf_ekf3_meas_x : gf_ekf3_meas_xy;
    for (int i = 0; i < 3; i++) {
        motion.R.m[i][i] = (gf_real)c->r[i];
    }
    for (unsigned i = 0; i < c->m; i++) {
        meas.Q.m[i][i] = (gf_real)c->q;
    }
    const gf_real u[2] = {(gf_real)c->d, (gf_real)c->phi};
    memset(nees_sum, 0, sizeof(double) * (size_t)(c->steps + 1));
    memset(nis_sum, 0, sizeof(double) * (size_t)(c->steps + 1));
    trust_rng rng;
    trust_rng_seed(&rng, seed);
    for (int run = 0; run < c->runs; run++) {
        double x[3];
        gf_vec3 mu0 = {{0, 0, 0}};
        gf_mat3 s0 = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
        for (int i = 0; i < 3; i++) {
            x[i] = sqrt(c->sigma0[i]) * trust_normal(&rng);
            s0.m[i][i] = (gf_real)c->sigma0[i];
        }
        gf_ekf3 ekf;
        assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
        for (int t = 1; t <= c->steps; t++) {
            double th = x[2];
            x[0] += c->d * cos(th) + sqrt(c->r[0]) * trust_normal(&rng);
            x[1] += c->d * sin(th) + sqrt(c->r[1]) * trust_normal(&rng);
            x[2] += c->phi + sqrt(c->r[2]) * trust_normal(&rng);
            assert_int_equal(gf_ekf3_predict(&ekf, &motion, u), GF_OK);
            gf_vec3 z = {{0, 0, 0}};
            for (unsigned i = 0; i < c->m; i++) {
                z.v[i] = (gf_real)(x[i] + sqrt(c->q) * trust_normal(&rng));
            }
            gf_innovation info;
            assert_int_equal(gf_ekf3_update(&ekf, &meas, &z, &info), GF_OK);
            nis_sum[t] += (double)info.nis;
            double e[3] = {x[0] - (double)ekf.mu.v[0],
                           x[1] - (double)ekf.mu.v[1],
                           trust_wrap(x[2] - (double)ekf.mu.v[2])};
            gf_mat3 sigma;
            assert_int_equal(gf_ekf3_cov(&ekf, &sigma), GF_OK);
            double s[3][3];
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++) {
                    s[i][j] = (double)sigma.m[i][j];
                }
            }
            double q = trust_quad_form(s, e, 3);
            assert_true(isfinite(q));
            nees_sum[t] += q;
        }
    }
}

// Small heading uncertainty (standard deviation 0.1 rad at the start, 0.03
// rad of heading noise per step), driving a circle of radius 20 with (x, y)
// measured: the linearisation error d sigma_theta^2 / 2 is tiny against
// the position noise, so the EKF must pass as a linear filter would.
static void test_ekf3_small_heading_consistent(void **state)
{
    (void)state;
    const ekf3_case c = {
        .sigma0 = {0.01, 0.01, 0.01},
        .r = {0.005, 0.005, 0.001},
        .m = 2,
        .q = 0.01,
        .d = 1.0,
        .phi = 0.05,
        .steps = STEPS,
        .runs = RUNS,
    };
    run_ekf3(&c, UINT64_C(0x656b66330001), nees, nis);
    verdict ne =
        judge("EKF3 small heading NEES (n=3)", nees, 1, STEPS, RUNS, 3, 0);
    verdict ni =
        judge("EKF3 small heading NIS (m=2)", nis, 1, STEPS, RUNS, 2, 1);
    assert_true(consistent(&ne));
    assert_true(consistent(&ni));
}

static double ex4_nees[2], ex4_nis[2];

// Exercise 4 exactly (Sigma_0 = diag(0.01, 0.01, theta variance), move 1
// forward, x measured with variance 0.01), with the truth drawn from the
// prior: with a heading variance of 0.01 the one-step EKF is consistent...
static void test_ekf3_exercise4_small_heading_consistent(void **state)
{
    (void)state;
    const ekf3_case c = {
        .sigma0 = {0.01, 0.01, 0.01},
        .r = {0, 0, 0},
        .m = 1,
        .q = 0.01,
        .d = 1.0,
        .phi = 0.0,
        .steps = 1,
        .runs = EX4_RUNS,
    };
    run_ekf3(&c, UINT64_C(0x657834000001), ex4_nees, ex4_nis);
    verdict ne = judge("exercise 4, theta var 0.01: NEES", ex4_nees, 1, 1,
                       EX4_RUNS, 3, 0);
    verdict ni =
        judge("exercise 4, theta var 0.01: NIS", ex4_nis, 1, 1, EX4_RUNS, 1, 1);
    assert_true(consistent(&ne));
    assert_true(consistent(&ni));
}

// ...but with the exercise's heading variance of 10000 (the heading is unknown,
// the robot is somewhere on the unit circle) it is badly inconsistent, the
// point of exercise 4 (docs/exercises.md): the linearisation puts all of the
// heading's uncertainty into y (y = theta, true only for small theta), and the
// x-variance 0.01 it predicts ignores that x = cos(theta) spans [-1, 1].
// "Badly": both averages above 10 times their 95% upper bound.
static void test_ekf3_exercise4_inconsistent(void **state)
{
    (void)state;
    const ekf3_case c = {
        .sigma0 = {0.01, 0.01, 10000.0},
        .r = {0, 0, 0},
        .m = 1,
        .q = 0.01,
        .d = 1.0,
        .phi = 0.0,
        .steps = 1,
        .runs = EX4_RUNS,
    };
    run_ekf3(&c, UINT64_C(0x657834000002), ex4_nees, ex4_nis);
    verdict ne = judge("exercise 4, theta var 10000: NEES", ex4_nees, 1, 1,
                       EX4_RUNS, 3, 0);
    verdict ni = judge("exercise 4, theta var 10000: NIS", ex4_nis, 1, 1,
                       EX4_RUNS, 1, 1);
    assert_false(consistent(&ne));
    assert_false(consistent(&ni));
    assert_true(ne.mean > 10.0 * ne.hi);
    assert_true(ni.mean > 10.0 * ni.hi);
    // Expected NIS: E[(cos theta - 1)^2] / S with theta uniform on the
    // circle and S = 0.02: (1/2 + 1) / 0.02 = 75 (+1 from the noise terms
    // scaled by S, which is what a consistent filter would show alone).
    printf("  exercise 4: NIS %.1f times, NEES %.1f times the consistent "
           "value (1 and 3)\n",
           ni.mean, ne.mean / 3.0);
    assert_true(ni.mean > 60.0 && ni.mean < 90.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quantiles),
        cmocka_unit_test(test_kf2_consistent),
        cmocka_unit_test(test_kf2_mistuned_is_caught),
        cmocka_unit_test(test_ekf3_small_heading_consistent),
        cmocka_unit_test(test_ekf3_exercise4_small_heading_consistent),
        cmocka_unit_test(test_ekf3_exercise4_inconsistent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
