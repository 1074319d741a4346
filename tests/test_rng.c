// SPDX-License-Identifier: MIT
// gf_rng and gf_mat3_sqrt_psd: the generator's known answers and
// determinism, the moments of its uniform and normal draws, and the
// semidefinite square root that sigma points and samples are made with.
#include "gf_test.h"

// Sampling checks: a sample statistic lies within SAMPLING_K standard
// errors of its expectation. 4.5 standard errors: a correct generator
// fails one such check with probability 6.8e-6; the seeds are fixed, so a
// run is reproducible and a failure is a real change.
#define SAMPLING_K 4.5

// xoshiro128** from the state (1, 2, 3, 4): the first three outputs, worked
// by hand from the reference algorithm (rotl(s1 * 5, 7) * 9, then the
// state update): 1280 * 9, then s1 = 0, then rotl(1029 * 5, 7) * 9.
static void test_known_answer(void **state)
{
    (void)state;
    gf_rng rng;
    assert_int_equal(gf_rng_seed(&rng, 0), GF_OK);
    rng.s[0] = 1;
    rng.s[1] = 2;
    rng.s[2] = 3;
    rng.s[3] = 4;
    assert_int_equal(gf_rng_u32(&rng), 11520u);
    assert_int_equal(gf_rng_u32(&rng), 0u);
    assert_int_equal(gf_rng_u32(&rng), 5927040u);
}

static void test_seeding(void **state)
{
    (void)state;
    gf_rng a, b, c;
    assert_int_equal(gf_rng_seed(NULL, 1), GF_ERR_ARG);
    assert_int_equal(gf_rng_seed(&a, 42), GF_OK);
    assert_int_equal(gf_rng_seed(&b, 42), GF_OK);
    assert_int_equal(gf_rng_seed(&c, 43), GF_OK);
    int same = 0;
    for (int i = 0; i < 1000; i++) {
        uint32_t x = gf_rng_u32(&a);
        assert_int_equal(x, gf_rng_u32(&b));
        same += x == gf_rng_u32(&c);
    }
    assert_true(same < 2);
    // Seed 0 is a valid seed too: a non-zero state.
    assert_int_equal(gf_rng_seed(&a, 0), GF_OK);
    assert_true((a.s[0] | a.s[1] | a.s[2] | a.s[3]) != 0);
}

static void test_uniform_moments(void **state)
{
    (void)state;
    gf_rng rng;
    assert_int_equal(gf_rng_seed(&rng, 7), GF_OK);
    const int n = 200000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; i++) {
        gf_real u = gf_rng_uniform(&rng);
        assert_true(u >= 0 && u < 1);
        s += (double)u;
        s2 += (double)u * (double)u;
    }
    double mean = s / n, var = s2 / n - mean * mean;
    // mean 1/2 with standard error sqrt(1/12 / n); variance 1/12 with
    // standard error sqrt((1/80 - 1/144) / n) (fourth central moment 1/80).
    assert_true(fabs(mean - 0.5) < SAMPLING_K * sqrt(1.0 / 12 / n));
    assert_true(fabs(var - 1.0 / 12) <
                SAMPLING_K * sqrt((1.0 / 80 - 1.0 / 144) / n));
}

static void test_normal_moments(void **state)
{
    (void)state;
    gf_rng rng;
    assert_int_equal(gf_rng_seed(&rng, 11), GF_OK);
    const int n = 200000;
    double s = 0, s2 = 0;
    int inside = 0;
    for (int i = 0; i < n; i++) {
        double x = (double)gf_rng_normal(&rng);
        s += x;
        s2 += x * x;
        inside += fabs(x) < 1;
    }
    double mean = s / n, var = s2 / n - mean * mean;
    double p = inside / (double)n, p1 = 0.682689492137; // P(|x| < 1)
    // standard errors: 1/sqrt(n), sqrt(2/n), sqrt(p1 (1 - p1) / n)
    assert_true(fabs(mean) < SAMPLING_K / sqrt(n));
    assert_true(fabs(var - 1) < SAMPLING_K * sqrt(2.0 / n));
    assert_true(fabs(p - p1) < SAMPLING_K * sqrt(p1 * (1 - p1) / n));
}

static void check_square_root(const gf_mat3 *s)
{
    gf_mat3 l, llt;
    assert_int_equal(gf_mat3_sqrt_psd(s, 3, &l), GF_OK);
    for (int i = 0; i < 3; i++) {
        for (int j = i + 1; j < 3; j++) {
            assert_true(l.m[i][j] == 0); // lower triangular
        }
        for (int j = 0; j < 3; j++) {
            llt.m[i][j] = l.m[i][0] * l.m[j][0] + l.m[i][1] * l.m[j][1] +
                          l.m[i][2] * l.m[j][2];
            CHECK_CLOSE(llt.m[i][j], s->m[i][j]);
        }
    }
}

// l l^T = s for definite and semidefinite s: exercise 4's prior, exercise
// 1's rank-one R (as a 3x3 block), a zero matrix, a zero leading entry.
static void test_sqrt_psd(void **state)
{
    (void)state;
    const gf_mat3 ex4 = {
        {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, 10000}}};
    const gf_mat3 full = {{{4, 2, 1}, {2, 3, GF_R(0.5)}, {1, GF_R(0.5), 2}}};
    const gf_mat3 rank1 = {
        {{GF_R(0.25), GF_R(0.5), 0}, {GF_R(0.5), 1, 0}, {0, 0, 0}}};
    const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    const gf_mat3 lead0 = {{{0, 0, 0}, {0, 2, 1}, {0, 1, 3}}};
    check_square_root(&ex4);
    check_square_root(&full);
    check_square_root(&rank1);
    check_square_root(&zero);
    check_square_root(&lead0);

    // Bad input: status, and l untouched.
    const gf_mat3 indef = {{{1, 2, 0}, {2, 1, 0}, {0, 0, 1}}};
    gf_mat3 nanm = full;
    nanm.m[2][1] = (gf_real)NAN;
    gf_mat3 l = full;
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &l, gf_mat3_sqrt_psd(&indef, 3, &l));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &l, gf_mat3_sqrt_psd(&nanm, 3, &l));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &l, gf_mat3_sqrt_psd(&full, 0, &l));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &l, gf_mat3_sqrt_psd(&full, 4, &l));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &l, gf_mat3_sqrt_psd(NULL, 3, &l));
    assert_int_equal(gf_mat3_sqrt_psd(&full, 3, NULL), GF_ERR_ARG);
    // n = 2: only the leading block, the rest zero.
    assert_int_equal(gf_mat3_sqrt_psd(&full, 2, &l), GF_OK);
    CHECK_CLOSE(l.m[0][0], 2.0);
    CHECK_CLOSE(l.m[1][0], 1.0);
    CHECK_CLOSE(l.m[1][1], sqrt(2.0));
    assert_true(l.m[2][0] == 0 && l.m[2][1] == 0 && l.m[2][2] == 0);
}

// gf_rng_mvn3 draws have the mean and covariance asked for.
static void test_mvn3_moments(void **state)
{
    (void)state;
    const gf_vec3 mu = {{1, -2, GF_R(0.5)}};
    const gf_mat3 s = {{{4, 2, 1}, {2, 3, GF_R(0.5)}, {1, GF_R(0.5), 2}}};
    gf_mat3 l;
    gf_rng rng;
    assert_int_equal(gf_mat3_sqrt_psd(&s, 3, &l), GF_OK);
    assert_int_equal(gf_rng_seed(&rng, 3), GF_OK);
    const int n = 100000;
    double m[3] = {0, 0, 0}, c[3][3] = {{0}};
    for (int k = 0; k < n; k++) {
        gf_vec3 x;
        gf_rng_mvn3(&rng, &mu, &l, &x);
        for (int i = 0; i < 3; i++) {
            double d = (double)x.v[i] - (double)mu.v[i];
            m[i] += d;
            for (int j = 0; j < 3; j++) {
                c[i][j] += d * ((double)x.v[j] - (double)mu.v[j]);
            }
        }
    }
    for (int i = 0; i < 3; i++) {
        double sii = (double)s.m[i][i];
        assert_true(fabs(m[i] / n) < SAMPLING_K * sqrt(sii / n));
        for (int j = 0; j < 3; j++) {
            double sij = (double)s.m[i][j], sjj = (double)s.m[j][j];
            // about the true mean: var(d_i d_j) = s_ij^2 + s_ii s_jj
            assert_true(fabs(c[i][j] / n - sij) <
                        SAMPLING_K * sqrt((sij * sij + sii * sjj) / n));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_answer),
        cmocka_unit_test(test_seeding),
        cmocka_unit_test(test_uniform_moments),
        cmocka_unit_test(test_normal_moments),
        cmocka_unit_test(test_sqrt_psd),
        cmocka_unit_test(test_mvn3_moments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
