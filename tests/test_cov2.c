// SPDX-License-Identifier: MIT
// Correlation and uncertainty ellipses of 2-D covariances (Figures 1.1,
// 1.2, 2.1 and 4.1 of the worked solutions, docs/exercises.md, draw 68%
// ellipses).
#include "gf_test.h"

// k^2 = -2 ln(1 - p) for the worked solutions' p = 0.68.
static const double K2_68 = 2.2788685663767296; // -2 ln 0.32

static void correlation(void **state)
{
    (void)state;
    gf_real rho = GF_R(7.0);
    const gf_mat2 t2 = {{{2.5, 2}, {2, 2}}};
    assert_int_equal(gf_cov2_correlation(&t2, &rho), GF_OK);
    CHECK_CLOSE(rho, 2 / sqrt(5.0));
    const gf_mat2 neg = {{{4, -3}, {-3, 9}}};
    assert_int_equal(gf_cov2_correlation(&neg, &rho), GF_OK);
    CHECK_CLOSE(rho, -0.5);
    // Rank one (Table 1.1, t = 1): exactly 1.
    const gf_mat2 t1 = {{{0.25, 0.5}, {0.5, 1}}};
    assert_int_equal(gf_cov2_correlation(&t1, &rho), GF_OK);
    CHECK_CLOSE(rho, 1);
    // Rounding can push |rho| past 1; it is clamped.
    const gf_mat2 over = {{{1, 1.0000001}, {1.0000001, 1}}};
    assert_int_equal(gf_cov2_correlation(&over, &rho), GF_OK);
    CHECK_CLOSE(rho, 1);
    // Large variances whose product overflows a float still work.
    const gf_mat2 big = {{{1e30, 5e29}, {5e29, 1e30}}};
    assert_int_equal(gf_cov2_correlation(&big, &rho), GF_OK);
    CHECK_CLOSE(rho, 0.5);

    // Undefined when a variance is zero (t = 0 of Table 1.1), or negative.
    const gf_mat2 zero = {{{0, 0}, {0, 0}}};
    const gf_mat2 one_zero = {{{1, 0}, {0, 0}}};
    const gf_mat2 negvar = {{{-1, 0}, {0, 1}}};
    const gf_mat2 nan = {{{1, (gf_real)NAN}, {(gf_real)NAN, 1}}};
    gf_real keep = GF_R(7.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_UNDEFINED, &keep,
                          gf_cov2_correlation(&zero, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_UNDEFINED, &keep,
                          gf_cov2_correlation(&one_zero, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_UNDEFINED, &keep,
                          gf_cov2_correlation(&negvar, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &keep,
                          gf_cov2_correlation(&nan, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_cov2_correlation(NULL, &keep));
    assert_int_equal(gf_cov2_correlation(&t2, NULL), GF_ERR_ARG);
}

static void ellipse(void **state)
{
    (void)state;
    gf_ellipse e;
    const gf_mat2 s = {{{3, 1}, {1, 3}}}; // eigenvalues 4 (at 45 deg) and 2
    assert_int_equal(gf_cov2_ellipse(&s, GF_R(0.68), &e), GF_OK);
    CHECK_CLOSE(e.a, sqrt(K2_68 * 4));
    CHECK_CLOSE(e.b, sqrt(K2_68 * 2));
    CHECK_CLOSE(e.angle, GF_PI / 4);

    // Table 1.1, t = 1: a degenerate ellipse, a segment along (0.5, 1).
    const gf_mat2 t1 = {{{0.25, 0.5}, {0.5, 1}}};
    assert_int_equal(gf_cov2_ellipse(&t1, GF_R(0.68), &e), GF_OK);
    CHECK_CLOSE(e.a, sqrt(K2_68 * 1.25));
    CHECK_CLOSE(e.b, 0);
    CHECK_CLOSE(e.angle, atan2(1.0, 0.5));

    // t = 0: a point.
    const gf_mat2 zero = {{{0, 0}, {0, 0}}};
    assert_int_equal(gf_cov2_ellipse(&zero, GF_R(0.68), &e), GF_OK);
    CHECK_CLOSE(e.a, 0);
    CHECK_CLOSE(e.b, 0);

    // Table 4.1, (x, y) marginal of the predicted belief: the heading's
    // uncertainty went to y alone, so the major axis is vertical.
    const gf_mat3 pred = {
        {{0.01, 0, 0}, {0, 10000.01, 10000}, {0, 10000, 10000}}};
    gf_mat2 xy;
    assert_int_equal(gf_cov2_marginal(&pred, 0, 1, &xy), GF_OK);
    CHECK_CLOSE(xy.m[1][1], 10000.01);
    assert_int_equal(gf_cov2_ellipse(&xy, GF_R(0.68), &e), GF_OK);
    CHECK_CLOSE(e.a, sqrt(K2_68 * 10000.01));
    CHECK_CLOSE(e.b, sqrt(K2_68 * 0.01));
    CHECK_CLOSE(e.angle, GF_PI / 2);

    // 39.35% is the 1-sigma ellipse in 2-D: k = 1.
    const gf_real p1 = (gf_real)(1 - exp(-0.5));
    assert_int_equal(gf_cov2_ellipse(&s, p1, &e), GF_OK);
    CHECK_CLOSE(e.a, 2);

    // Bad input: p out of (0, 1), not PSD, NaN, NULL.
    gf_ellipse keep = {1, 2, 3};
    const gf_mat2 indef = {{{1, 2}, {2, 1}}};
    const gf_mat2 nan = {{{(gf_real)NAN, 0}, {0, 1}}};
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_cov2_ellipse(&s, 0, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_cov2_ellipse(&s, 1, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep,
                          gf_cov2_ellipse(&s, (gf_real)NAN, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep,
                          gf_cov2_ellipse(NULL, GF_R(0.5), &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &keep,
                          gf_cov2_ellipse(&indef, GF_R(0.5), &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &keep,
                          gf_cov2_ellipse(&nan, GF_R(0.5), &keep));
    assert_int_equal(gf_cov2_ellipse(&s, GF_R(0.5), NULL), GF_ERR_ARG);
}

static void marginal(void **state)
{
    (void)state;
    const gf_mat3 s = {{{1, 2, 3}, {2, 5, 6}, {3, 6, 9}}};
    gf_mat2 m;
    assert_int_equal(gf_cov2_marginal(&s, 0, 2, &m), GF_OK);
    CHECK_CLOSE(m.m[0][0], 1);
    CHECK_CLOSE(m.m[0][1], 3);
    CHECK_CLOSE(m.m[1][0], 3);
    CHECK_CLOSE(m.m[1][1], 9);
    gf_mat2 keep = m;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_cov2_marginal(&s, 3, 0, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_cov2_marginal(&s, 0, 3, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep,
                          gf_cov2_marginal(NULL, 0, 1, &keep));
    assert_int_equal(gf_cov2_marginal(&s, 0, 1, NULL), GF_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(correlation),
        cmocka_unit_test(ellipse),
        cmocka_unit_test(marginal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
