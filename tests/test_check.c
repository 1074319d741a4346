// SPDX-License-Identifier: MIT
// gf_ekf_check_model: a model's Jacobians against the central differences
// of its functions. Correct models read small, in both precisions; a wrong
// entry is found where it is, with its value and the numeric one; angle
// outputs are differenced across the wrap; a seeded family of random
// smooth models (products, quotients, sin and cos, square roots of sums of
// squares) reads small and finds any one entry perturbed; arguments,
// callbacks' errors and non-finite answers give their statuses and leave
// the report untouched.
#include <math.h>

#include "gf_test.h"

#ifdef GF_SINGLE_PRECISION
#define CORRECT_BELOW 1e-2 // float: eps^(2/3) times the model's curvature
#define RSIN sinf
#define RCOS cosf
#define RATAN2 atan2f
#else
#define CORRECT_BELOW 1e-8
#define RSIN sin
#define RCOS cos
#define RATAN2 atan2
#endif

static gf_kf_work work;

// ---- range and bearing to a landmark, from (x, y, heading) --------------

typedef struct landmark {
    gf_real x, y;
    int wrong; // 1: the sign of H[1][0] flipped
} landmark;

static gf_status range_bearing(void *ctx, unsigned n, unsigned m,
                               const gf_real *mu, gf_real *z, gf_real *H)
{
    const landmark *l = (const landmark *)ctx;
    (void)m;
    const gf_real dx = l->x - mu[0], dy = l->y - mu[1];
    const gf_real q = dx * dx + dy * dy, r = GF_SQRT(q);
    z[0] = r;
    z[1] = gf_angle_wrap(RATAN2(dy, dx) - mu[2]);
    H[0 * n + 0] = -dx / r;
    H[0 * n + 1] = -dy / r;
    H[1 * n + 0] = (l->wrong ? -dy : dy) / q;
    H[1 * n + 1] = -dx / q;
    H[1 * n + 2] = -1;
    return GF_OK;
}

static gf_ekf_meas rb_meas(landmark *l, unsigned mask)
{
    gf_ekf_meas meas = {2, range_bearing, l, NULL, mask, 0};
    return meas;
}

static void correct_range_bearing_reads_small(void **state)
{
    (void)state;
    landmark l = {GF_R(4.0), GF_R(3.0), 0};
    const gf_real mu[3] = {GF_R(1.0), GF_R(-0.5), GF_R(0.3)};
    gf_ekf_meas meas = rb_meas(&l, 2u);
    gf_ekf_check c;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 3, mu, NULL, 0, &c, &work),
                     GF_OK);
    print_message("range-bearing, correct H: worst %.3g at H[%u][%u]\n",
                  (double)c.worst, c.row, c.col);
    assert_true((double)c.worst < CORRECT_BELOW);
    assert_int_equal(c.jacobian, 1);
}

static void a_wrong_entry_is_found(void **state)
{
    (void)state;
    landmark l = {GF_R(4.0), GF_R(3.0), 1};
    const gf_real mu[3] = {GF_R(1.0), GF_R(-0.5), GF_R(0.3)};
    gf_ekf_meas meas = rb_meas(&l, 2u);
    gf_ekf_check c;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 3, mu, NULL, 0, &c, &work),
                     GF_OK);
    print_message("range-bearing, H[1][0] of the wrong sign: worst %.3g at "
                  "H[%u][%u], given %.6g, numeric %.6g\n",
                  (double)c.worst, c.row, c.col, (double)c.given,
                  (double)c.numeric);
    assert_int_equal(c.jacobian, 1);
    assert_int_equal(c.row, 1);
    assert_int_equal(c.col, 0);
    // a sign: |J - D| = 2 |D|, relative to |D|
    assert_true(fabs((double)c.worst - 2.0) < 1e-2);
    assert_true(fabs((double)(c.given + c.numeric)) <
                1e-2 * fabs((double)c.numeric));
}

static void angles_are_differenced_across_the_wrap(void **state)
{
    (void)state;
    // the landmark behind: the bearing is near pi, and mu +- h crosses it
    landmark l = {GF_R(-5.0), GF_R(0.0), 0};
    const gf_real mu[3] = {GF_R(0.0), GF_R(0.0), GF_R(0.0)};
    gf_ekf_meas meas = rb_meas(&l, 2u);
    gf_ekf_check c;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 3, mu, NULL, 0, &c, &work),
                     GF_OK);
    assert_true((double)c.worst < CORRECT_BELOW);
    // without the mask, the bearing's 2 pi jump is read as a derivative
    meas.angle_mask = 0;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 3, mu, NULL, 0, &c, &work),
                     GF_OK);
    assert_true((double)c.worst > 0.5);
    assert_int_equal(c.row, 1);
}

// ---- a kinematic motion over (x, y, heading, speed) ----------------------

static gf_status drive(void *ctx, unsigned n, const gf_real *mu,
                       const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    const int wrong = *(const int *)ctx;
    const gf_real dt = u[0], turn = u[1];
    const gf_real s = RSIN(mu[2]), c = RCOS(mu[2]);
    mu_bar[0] = mu[0] + mu[3] * c * dt;
    mu_bar[1] = mu[1] + mu[3] * s * dt;
    mu_bar[2] = gf_angle_wrap(mu[2] + mu[3] * turn * dt);
    G[0 * n + 2] = wrong ? GF_R(0.0) : -mu[3] * s * dt; // wrong: forgotten
    G[0 * n + 3] = c * dt;
    G[1 * n + 2] = mu[3] * c * dt;
    G[1 * n + 3] = s * dt;
    G[2 * n + 3] = turn * dt;
    return GF_OK;
}

static void motion_checks(void **state)
{
    (void)state;
    int wrong = 0;
    const gf_ekf_motion motion = {drive, &wrong, NULL};
    const gf_real mu[4] = {GF_R(2.0), GF_R(1.0), GF_R(3.0), GF_R(1.5)};
    const gf_real u[2] = {GF_R(0.1), GF_R(0.4)};
    gf_ekf_check c;
    // the heading an angle, near pi: wrapped
    assert_int_equal(gf_ekf_check_model(&motion, NULL, 4, mu, u, 4u, &c, &work),
                     GF_OK);
    print_message("motion, correct G: worst %.3g at G[%u][%u]\n",
                  (double)c.worst, c.row, c.col);
    assert_true((double)c.worst < CORRECT_BELOW);
    wrong = 1;
    assert_int_equal(gf_ekf_check_model(&motion, NULL, 4, mu, u, 4u, &c, &work),
                     GF_OK);
    assert_int_equal(c.jacobian, 0);
    assert_int_equal(c.row, 0);
    assert_int_equal(c.col, 2);
    assert_true(fabs((double)c.worst - 1.0) < 1e-2); // J = 0: |D| / |D|
    assert_true(c.given == 0);
}

// ---- a seeded family of random smooth models ------------------------------

typedef struct family {
    gf_real a[4];
    int bad_row, bad_col; // the entry perturbed (-1: none)
} family;

// z0 = a0 x0 x1 + x2 / (x3 + 3), z1 = a1 sin(x0) cos(x2),
// z2 = sqrt(x0^2 + x1^2 + x3^2) + a2 x1 / x2... (x2 kept away from 0)
static gf_status family_h(void *ctx, unsigned n, unsigned m, const gf_real *x,
                          gf_real *z, gf_real *H)
{
    const family *f = (const family *)ctx;
    (void)m;
    const gf_real d = x[3] + 3,
                  r = GF_SQRT(x[0] * x[0] + x[1] * x[1] + x[3] * x[3]);
    z[0] = f->a[0] * x[0] * x[1] + x[2] / d;
    z[1] = f->a[1] * RSIN(x[0]) * RCOS(x[2]);
    z[2] = r + f->a[2] * x[1] / x[2];
    H[0 * n + 0] = f->a[0] * x[1];
    H[0 * n + 1] = f->a[0] * x[0];
    H[0 * n + 2] = 1 / d;
    H[0 * n + 3] = -x[2] / (d * d);
    H[1 * n + 0] = f->a[1] * RCOS(x[0]) * RCOS(x[2]);
    H[1 * n + 2] = -f->a[1] * RSIN(x[0]) * RSIN(x[2]);
    H[2 * n + 0] = x[0] / r;
    H[2 * n + 1] = x[1] / r + f->a[2] / x[2];
    H[2 * n + 2] = -f->a[2] * x[1] / (x[2] * x[2]);
    H[2 * n + 3] = x[3] / r;
    if (f->bad_row >= 0) {
        gf_real *e = &H[(unsigned)f->bad_row * n + (unsigned)f->bad_col];
        *e += GF_R(0.25) * (GF_FABS(*e) + 1); // off by a fifth or more
    }
    return GF_OK;
}

static void random_models(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 7);
    double worst_ok = 0, least_bad = 1e300;
    for (int t = 0; t < 300; t++) {
        family f;
        gf_real x[4];
        for (unsigned i = 0; i < 4u; i++) {
            f.a[i] = (gf_real)gf_test_uniform(&rng, -2, 2);
            x[i] = (gf_real)gf_test_uniform(&rng, -2, 2);
        }
        x[2] = (gf_real)gf_test_uniform(&rng, 0.5, 2); // away from 0
        f.bad_row = -1;
        f.bad_col = 0;
        const gf_ekf_meas meas = {3, family_h, &f, NULL, 0, 0};
        gf_ekf_check c;
        assert_int_equal(
            gf_ekf_check_model(NULL, &meas, 4, x, NULL, 0, &c, &work), GF_OK);
        worst_ok = fmax(worst_ok, (double)c.worst);
        // one entry perturbed, among those the model has (not a true zero)
        static const int entries[][2] = {{0, 0}, {0, 1}, {0, 2}, {0, 3},
                                         {1, 0}, {1, 2}, {2, 0}, {2, 1},
                                         {2, 2}, {2, 3}};
        const int k = t % 10;
        f.bad_row = entries[k][0];
        f.bad_col = entries[k][1];
        assert_int_equal(
            gf_ekf_check_model(NULL, &meas, 4, x, NULL, 0, &c, &work), GF_OK);
        assert_int_equal(c.row, (unsigned)f.bad_row);
        assert_int_equal(c.col, (unsigned)f.bad_col);
        least_bad = fmin(least_bad, (double)c.worst);
    }
    print_message("300 random models: correct worst %.3g, a perturbed entry "
                  "at least %.3g, always the one found\n",
                  worst_ok, least_bad);
    assert_true(worst_ok < CORRECT_BELOW);
    assert_true(least_bad > 0.05);
}

// ---- statuses --------------------------------------------------------------

static gf_status h_fails(void *ctx, unsigned n, unsigned m, const gf_real *x,
                         gf_real *z, gf_real *H)
{
    (void)n, (void)m, (void)H;
    const int nan = *(const int *)ctx;
    if (!nan) {
        return GF_ERR_UNDEFINED;
    }
    z[0] = x[0] > 0 ? (gf_real)NAN : GF_R(0.0);
    return GF_OK;
}

static void statuses(void **state)
{
    (void)state;
    int nan = 0;
    const gf_real mu[2] = {GF_R(1.0), GF_R(2.0)};
    gf_ekf_meas meas = {1, h_fails, &nan, NULL, 0, 0};
    gf_ekf_check c = {GF_R(9.0), 9, 9, 9, GF_R(9.0), GF_R(9.0)};
    const gf_ekf_check kept = c;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 2, mu, NULL, 0, &c, &work),
                     GF_ERR_UNDEFINED);
    nan = 1;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 2, mu, NULL, 0, &c, &work),
                     GF_ERR_NONFINITE);
    const gf_real bad_mu[2] = {(gf_real)INFINITY, GF_R(0.0)};
    assert_int_equal(
        gf_ekf_check_model(NULL, &meas, 2, bad_mu, NULL, 0, &c, &work),
        GF_ERR_NONFINITE);
    meas.m = 3; // more quantities than states
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 2, mu, NULL, 0, &c, &work),
                     GF_ERR_ARG);
    meas.m = 1;
    assert_int_equal(gf_ekf_check_model(NULL, &meas, 0, mu, NULL, 0, &c, &work),
                     GF_ERR_ARG);
    assert_int_equal(gf_ekf_check_model(NULL, &meas, GF_KF_NMAX + 1u, mu, NULL,
                                        0, &c, &work),
                     GF_ERR_ARG);
    assert_memory_equal(&c, &kept, sizeof c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(correct_range_bearing_reads_small),
        cmocka_unit_test(a_wrong_entry_is_found),
        cmocka_unit_test(angles_are_differenced_across_the_wrap),
        cmocka_unit_test(motion_checks),
        cmocka_unit_test(random_models),
        cmocka_unit_test(statuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
