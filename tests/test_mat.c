// SPDX-License-Identifier: MIT
// Small-matrix math: products, sandwich, symmetrization, PSD checks,
// SPD solves, the closed-form 2x2 eigen-decomposition and angle wrapping.
#include "gf_test.h"

static const gf_mat2 A2 = {{{1, 2}, {3, 4}}};
static const gf_mat2 S2 = {{{4, 1}, {1, 3}}};

static void mat2_products(void **state)
{
    (void)state;
    gf_mat2 out;
    gf_mat2_mul(&A2, &S2, &out);
    CHECK_CLOSE(out.m[0][0], 6);
    CHECK_CLOSE(out.m[0][1], 7);
    CHECK_CLOSE(out.m[1][0], 16);
    CHECK_CLOSE(out.m[1][1], 15);

    gf_mat2 alias = A2; // out may alias a source
    gf_mat2_mul(&alias, &S2, &alias);
    assert_memory_equal(&alias, &out, sizeof out);

    gf_vec2 x = {{1, -1}}, y;
    gf_mat2_mulv(&A2, &x, &y);
    CHECK_CLOSE(y.v[0], -1);
    CHECK_CLOSE(y.v[1], -1);

    // A S A^T = ((20, 46), (46, 108)), exactly symmetric
    gf_mat2_sandwich(&A2, &S2, &out);
    CHECK_CLOSE(out.m[0][0], 20);
    CHECK_CLOSE(out.m[0][1], 46);
    CHECK_CLOSE(out.m[1][1], 108);
    assert_memory_equal(&out.m[0][1], &out.m[1][0], sizeof(gf_real));
}

static void mat2_symmetrize_and_finite(void **state)
{
    (void)state;
    gf_mat2 s = {{{1, 2}, {4, 1}}};
    gf_mat2_symmetrize(&s);
    CHECK_CLOSE(s.m[0][1], 3);
    CHECK_CLOSE(s.m[1][0], 3);
    assert_true(gf_mat2_is_finite(&s));
    s.m[1][0] = (gf_real)NAN;
    assert_false(gf_mat2_is_finite(&s));
    s.m[1][0] = (gf_real)INFINITY;
    assert_false(gf_mat2_is_finite(&s));
}

static void mat2_check_psd(void **state)
{
    (void)state;
    const gf_mat2 zero = {{{0, 0}, {0, 0}}};
    const gf_mat2 line = {{{0.25, 0.5}, {0.5, 1}}}; // rank 1: R of ex. 1
    const gf_mat2 neg = {{{-1, 0}, {0, 1}}};
    const gf_mat2 indef = {{{1, 2}, {2, 1}}};
    const gf_mat2 asym = {{{1, 0.5}, {0.4, 1}}};
    const gf_mat2 nan = {{{1, 0}, {0, (gf_real)NAN}}};
    assert_int_equal(gf_mat2_check_psd(&zero), GF_OK);
    assert_int_equal(gf_mat2_check_psd(&line), GF_OK);
    assert_int_equal(gf_mat2_check_psd(&S2), GF_OK);
    assert_int_equal(gf_mat2_check_psd(&neg), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat2_check_psd(&indef), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat2_check_psd(&asym), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat2_check_psd(&nan), GF_ERR_NONFINITE);
    assert_int_equal(gf_mat2_check_psd(NULL), GF_ERR_ARG);

    // The verdict does not depend on units.
    const gf_real scales[] = {GF_R(1e-15), GF_R(1e15)}; // squares fit a float
    for (unsigned k = 0; k < 2; k++) {
        gf_mat2 a = line, b = indef;
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) {
                a.m[i][j] *= scales[k];
                b.m[i][j] *= scales[k];
            }
        }
        assert_int_equal(gf_mat2_check_psd(&a), GF_OK);
        assert_int_equal(gf_mat2_check_psd(&b), GF_ERR_NOT_PSD);
    }
}

static void mat2_spd_inv(void **state)
{
    (void)state;
    gf_mat2 inv;
    assert_int_equal(gf_mat2_spd_inv(&S2, &inv), GF_OK);
    CHECK_CLOSE(inv.m[0][0], 3.0 / 11.0);
    CHECK_CLOSE(inv.m[0][1], -1.0 / 11.0);
    CHECK_CLOSE(inv.m[1][0], -1.0 / 11.0);
    CHECK_CLOSE(inv.m[1][1], 4.0 / 11.0);

    // Singular, scaled singular, tiny but well conditioned, NaN.
    const gf_mat2 sing = {{{1, 1}, {1, 1}}};
    const gf_mat2 sing_big = {{{1e20, 1e20}, {1e20, 1e20}}};
    const gf_mat2 tiny = {{{1e-18, 0}, {0, 1e-18}}};
    const gf_mat2 nan = {{{(gf_real)NAN, 0}, {0, 1}}};
    const gf_mat2 neg = {{{-1, 0}, {0, -1}}};
    gf_mat2 keep = {{{7, 7}, {7, 7}}};
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep,
                          gf_mat2_spd_inv(&sing, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep,
                          gf_mat2_spd_inv(&sing_big, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep, gf_mat2_spd_inv(&neg, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &keep,
                          gf_mat2_spd_inv(&nan, &keep));
    assert_int_equal(gf_mat2_spd_inv(&tiny, &inv), GF_OK);
    CHECK_CLOSE(inv.m[0][0] * GF_R(1e-18), 1);
}

static void mat2_eig_sym(void **state)
{
    (void)state;
    gf_vec2 l;
    gf_real th;
    const gf_mat2 a = {{{2, 1}, {1, 2}}};
    assert_int_equal(gf_mat2_eig_sym(&a, &l, &th), GF_OK);
    CHECK_CLOSE(l.v[0], 3);
    CHECK_CLOSE(l.v[1], 1);
    CHECK_CLOSE(th, GF_PI / 4);

    const gf_mat2 b = {{{1, 0}, {0, 2}}}; // major axis along the second axis
    assert_int_equal(gf_mat2_eig_sym(&b, &l, &th), GF_OK);
    CHECK_CLOSE(l.v[0], 2);
    CHECK_CLOSE(l.v[1], 1);
    CHECK_CLOSE(th, GF_PI / 2);

    const gf_mat2 c = {{{5, -2}, {-2, 2}}}; // eigenvalues 6 and 1
    assert_int_equal(gf_mat2_eig_sym(&c, &l, &th), GF_OK);
    CHECK_CLOSE(l.v[0], 6);
    CHECK_CLOSE(l.v[1], 1);
    // s v = lambda v for v = (cos th, sin th)
    gf_real vx = (gf_real)cos((double)th), vy = (gf_real)sin((double)th);
    CHECK_CLOSE(5 * vx - 2 * vy, 6 * vx);
    CHECK_CLOSE(-2 * vx + 2 * vy, 6 * vy);

    const gf_mat2 eye = {{{1, 0}, {0, 1}}};
    assert_int_equal(gf_mat2_eig_sym(&eye, &l, &th), GF_OK);
    CHECK_CLOSE(l.v[0], 1);
    CHECK_CLOSE(l.v[1], 1);
    CHECK_CLOSE(th, 0);

    const gf_mat2 inf = {{{(gf_real)INFINITY, 0}, {0, 1}}};
    gf_vec2 keep = {{9, 9}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &keep,
                          gf_mat2_eig_sym(&inf, &keep, &th));
    assert_int_equal(gf_mat2_eig_sym(NULL, &l, &th), GF_ERR_ARG);
    assert_int_equal(gf_mat2_eig_sym(&a, NULL, &th), GF_ERR_ARG);
    assert_int_equal(gf_mat2_eig_sym(&a, &l, NULL), GF_ERR_ARG);
}

static const gf_mat3 A3 = {{{1, 2, 0}, {0, 1, 3}, {4, 0, 1}}};
static const gf_mat3 S3 = {{{4, 2, 0}, {2, 5, 1}, {0, 1, 3}}};

static void mat3_products(void **state)
{
    (void)state;
    gf_mat3 out;
    gf_mat3_mul(&A3, &S3, &out);
    const gf_real want[3][3] = {{8, 12, 2}, {2, 8, 10}, {16, 9, 3}};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            CHECK_CLOSE(out.m[i][j], want[i][j]);
        }
    }
    gf_mat3 alias = A3;
    gf_mat3_mul(&alias, &S3, &alias);
    assert_memory_equal(&alias, &out, sizeof out);

    gf_vec3 x = {{1, 2, 3}}, y;
    gf_mat3_mulv(&A3, &x, &y);
    CHECK_CLOSE(y.v[0], 5);
    CHECK_CLOSE(y.v[1], 11);
    CHECK_CLOSE(y.v[2], 7);

    // A S A^T, computed by hand: (A S) A^T
    gf_mat3_sandwich(&A3, &S3, &out);
    const gf_real w2[3][3] = {{32, 18, 34}, {18, 38, 18}, {34, 18, 67}};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            CHECK_CLOSE(out.m[i][j], w2[i][j]);
        }
    }
}

static void mat3_symmetrize_and_finite(void **state)
{
    (void)state;
    gf_mat3 s = {{{1, 2, 3}, {0, 1, 5}, {1, 1, 1}}};
    gf_mat3_symmetrize(&s);
    CHECK_CLOSE(s.m[0][1], 1);
    CHECK_CLOSE(s.m[1][0], 1);
    CHECK_CLOSE(s.m[0][2], 2);
    CHECK_CLOSE(s.m[2][0], 2);
    CHECK_CLOSE(s.m[1][2], 3);
    CHECK_CLOSE(s.m[2][1], 3);
    assert_true(gf_mat3_is_finite(&s));
    s.m[2][2] = (gf_real) - (gf_real)INFINITY;
    assert_false(gf_mat3_is_finite(&s));
}

static void mat3_check_psd(void **state)
{
    (void)state;
    // Table 4.1's predicted covariance: PSD, nearly singular in (y, theta).
    const gf_mat3 ex4 = {
        {{0.01, 0, 0}, {0, 10000.01, 10000}, {0, 10000, 10000}}};
    // Zero leading entry but an indefinite trailing block: only a test of
    // every principal minor sees it.
    const gf_mat3 trail = {{{0, 0, 0}, {0, 1, 2}, {0, 2, 1}}};
    const gf_mat3 indef3 = {{{1, 0.9, 0.9}, {0.9, 1, -0.9}, {0.9, -0.9, 1}}};
    const gf_mat3 asym = {{{1, 0, 0}, {0, 1, 0.1}, {0, 0, 1}}};
    gf_mat3 nan = S3;
    nan.m[1][2] = (gf_real)NAN;
    assert_int_equal(gf_mat3_check_psd(&S3, 3), GF_OK);
    assert_int_equal(gf_mat3_check_psd(&ex4, 3), GF_OK);
    assert_int_equal(gf_mat3_check_psd(&trail, 3), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat3_check_psd(&trail, 1), GF_OK);
    assert_int_equal(gf_mat3_check_psd(&indef3, 3), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat3_check_psd(&indef3, 2), GF_OK);
    assert_int_equal(gf_mat3_check_psd(&asym, 3), GF_ERR_NOT_PSD);
    assert_int_equal(gf_mat3_check_psd(&nan, 3), GF_ERR_NONFINITE);
    assert_int_equal(gf_mat3_check_psd(&nan, 1), GF_OK); // only the block
    assert_int_equal(gf_mat3_check_psd(&S3, 0), GF_ERR_ARG);
    assert_int_equal(gf_mat3_check_psd(&S3, 4), GF_ERR_ARG);
    assert_int_equal(gf_mat3_check_psd(NULL, 3), GF_ERR_ARG);
}

static void mat3_cholesky(void **state)
{
    (void)state;
    gf_mat3 l;
    assert_int_equal(gf_mat3_chol(&S3, 3, &l), GF_OK);
    // l l^T == S3, l lower triangular
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            gf_real s = 0;
            for (int k = 0; k < 3; k++) {
                s += l.m[i][k] * l.m[j][k];
            }
            CHECK_CLOSE(s, S3.m[i][j]);
            if (j > i) {
                CHECK_CLOSE(l.m[i][j], 0);
            }
        }
    }
    // Solve S3 x = b for b = S3 (1, -2, 3)
    gf_vec3 b = {{0, -5, 7}}, x;
    gf_mat3_chol_solve(&l, 3, &b, &x);
    CHECK_CLOSE(x.v[0], 1);
    CHECK_CLOSE(x.v[1], -2);
    CHECK_CLOSE(x.v[2], 3);

    // Leading blocks
    assert_int_equal(gf_mat3_chol(&S3, 1, &l), GF_OK);
    CHECK_CLOSE(l.m[0][0], 2);
    CHECK_CLOSE(l.m[1][1], 0);
    gf_vec3 b1 = {{8, 99, 99}};
    gf_mat3_chol_solve(&l, 1, &b1, &x);
    CHECK_CLOSE(x.v[0], 2);

    // Singular (rank 2), scaled singular, NaN, bad n: l untouched.
    const gf_mat3 sing = {{{1, 1, 0}, {1, 1, 0}, {0, 0, 1}}};
    const gf_mat3 sing_small = {
        {{1e-20, 1e-20, 0}, {1e-20, 1e-20, 0}, {0, 0, 1e-20}}};
    gf_mat3 nan = S3;
    nan.m[2][2] = (gf_real)NAN;
    gf_mat3 keep = S3;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep,
                          gf_mat3_chol(&sing, 3, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep,
                          gf_mat3_chol(&sing_small, 2, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &keep, gf_mat3_chol(&nan, 3, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_mat3_chol(&S3, 0, &keep));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &keep, gf_mat3_chol(&S3, 4, &keep));
    // A well-conditioned but tiny matrix is not singular.
    const gf_mat3 tiny = {{{1e-20, 0, 0}, {0, 1e-20, 0}, {0, 0, 1e-20}}};
    assert_int_equal(gf_mat3_chol(&tiny, 3, &l), GF_OK);
}

static void angle_wrap(void **state)
{
    (void)state;
    CHECK_CLOSE(gf_angle_wrap(0), 0);
    CHECK_CLOSE(gf_angle_wrap(GF_R(0.5)), 0.5);
    CHECK_CLOSE(gf_angle_wrap(GF_R(-0.5)), -0.5);
    assert_true(gf_angle_wrap(GF_PI) == GF_PI);  // pi stays pi
    assert_true(gf_angle_wrap(-GF_PI) == GF_PI); // -pi is outside
    // +-3 pi in floating point lie a rounding error either side of the odd
    // multiple of pi: either end of the interval is right.
    CHECK_CLOSE(fabs((double)gf_angle_wrap(3 * GF_PI)), GF_PI);
    CHECK_CLOSE(fabs((double)gf_angle_wrap(-3 * GF_PI)), GF_PI);
    CHECK_CLOSE(gf_angle_wrap(2 * GF_PI + GF_R(0.25)), 0.25);
    CHECK_CLOSE(gf_angle_wrap(-2 * GF_PI - GF_R(0.25)), -0.25);
    for (int k = -50; k <= 50; k++) {
        gf_real w = gf_angle_wrap((gf_real)k * GF_R(0.7));
        assert_true(w > -GF_PI && w <= GF_PI);
        CHECK_CLOSE(sin((double)w), sin((double)((gf_real)k * GF_R(0.7))));
    }
}

static void angle_wrap_edges(void **state)
{
    (void)state;
    assert_true(isnan(gf_angle_wrap((gf_real)NAN)));
    assert_true(isnan(gf_angle_wrap((gf_real)INFINITY)));
    assert_true(isnan(gf_angle_wrap(-(gf_real)INFINITY)));
    // Beyond 2^22 turns (float) or 2^51 (double) there is no direction left.
    const gf_real huge = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e300);
    CHECK_CLOSE(gf_angle_wrap(huge), 0);
    // Ten turns and a bit (the input itself is rounded to the precision).
    CHECK_CLOSE(gf_angle_wrap(GF_R(20.0) * GF_PI + GF_R(0.5)), 0.5);
}

// The core's own sin/cos against the C library's, in double, over several
// turns: within a few ulp of the build's precision.
static void sincos_accuracy(void **state)
{
    (void)state;
    const double tol = 4.0 * (double)GF_REAL_EPSILON;
    double worst = 0;
    for (int i = -20000; i <= 20000; i++) {
        gf_real a = (gf_real)i * GF_R(0.00093);
        gf_real s, c;
        gf_sincos(a, &s, &c);
        double es = fabs((double)s - sin((double)a));
        double ec = fabs((double)c - cos((double)a));
        worst = es > worst ? es : worst;
        worst = ec > worst ? ec : worst;
        if (!(es <= tol && ec <= tol)) {
            print_error("a = %.17g: sin err %g, cos err %g\n", (double)a, es,
                        ec);
            fail();
        }
    }
    print_message("gf_sincos: worst error %.3g over 40001 angles (tol %.3g)\n",
                  worst, tol);
    gf_real s, c;
    gf_sincos(0, &s, &c);
    assert_true(s == 0 && c == 1); // exact at theta = 0 (exercise 4)
    gf_sincos((gf_real)NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
}

static void status_names(void **state)
{
    (void)state;
    assert_string_equal(gf_status_str(GF_OK), "ok");
    assert_string_equal(gf_status_str(GF_ERR_GATED), "gated");
    assert_string_equal(gf_status_str(GF_ERR_SINGULAR),
                        "singular innovation covariance");
    assert_string_equal(gf_status_str((gf_status)-99), "unknown");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mat2_products),
        cmocka_unit_test(mat2_symmetrize_and_finite),
        cmocka_unit_test(mat2_check_psd),
        cmocka_unit_test(mat2_spd_inv),
        cmocka_unit_test(mat2_eig_sym),
        cmocka_unit_test(mat3_products),
        cmocka_unit_test(mat3_symmetrize_and_finite),
        cmocka_unit_test(mat3_check_psd),
        cmocka_unit_test(mat3_cholesky),
        cmocka_unit_test(angle_wrap),
        cmocka_unit_test(angle_wrap_edges),
        cmocka_unit_test(sincos_accuracy),
        cmocka_unit_test(status_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
