// SPDX-License-Identifier: MIT
// EKF3 against exercise 4 of Probabilistic Robotics chapter 3
// (docs/exercises.md): Tables 4.1 and 4.2.
#include "gf_test.h"

// Tables 4.1 and 4.2: the robot moves one unit forward without noise in
// the motion (R = 0), then observes its x coordinate with variance 0.01.
static const gf_ekf3_motion FORWARD = {
    .g = gf_ekf3_motion_forward_turn,
    .ctx = NULL,
    .R = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
};
static const gf_real MOVE_1[2] = {1, 0};

static const gf_ekf3_meas SEE_X = {
    .m = 1,
    .h = gf_ekf3_meas_x,
    .ctx = NULL,
    .Q = {{{0.01, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
    .angle_mask = 0,
    .gate = 0,
};

static const gf_vec3 INIT_MU = {{0, 0, 0}};
static const gf_mat3 INIT_SIGMA = {{{0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 10000}}};

static void check_belief(const gf_ekf3 *ekf, const gf_vec3 *mu,
                         const gf_mat3 *sigma)
{
    const gf_mat3 got = gf_test_ekf3_sigma(ekf);
    for (int i = 0; i < 3; i++) {
        CHECK_CLOSE(ekf->mu.v[i], mu->v[i]);
        for (int j = 0; j < 3; j++) {
            CHECK_CLOSE(got.m[i][j], sigma->m[i][j]);
        }
    }
}

static void check_printed(const gf_ekf3 *ekf, const gf_real mu[3],
                          const gf_real sigma[3][3])
{
    const gf_mat3 got = gf_test_ekf3_sigma(ekf);
    for (int i = 0; i < 3; i++) {
        CHECK_PRINTED(ekf->mu.v[i], mu[i]);
        for (int j = 0; j < 3; j++) {
            CHECK_PRINTED(got.m[i][j], sigma[i][j]);
        }
    }
}

static void table_4_1(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &INIT_MU, &INIT_SIGMA), GF_OK);
    check_belief(&ekf, &INIT_MU, &INIT_SIGMA);
    assert_int_equal(gf_ekf3_predict(&ekf, &FORWARD, MOVE_1), GF_OK);

    // G = ((1, 0, 0), (0, 1, 1), (0, 0, 1)) at theta = 0 (equation 4.1):
    // the heading's uncertainty goes to y alone.
    const gf_vec3 mu = {{1, 0, 0}};
    const gf_mat3 sigma = {{{0.01, 0, 0},
                            {0, GF_R(0.01) + GF_R(10000.0), 10000},
                            {0, 10000, 10000}}};
    check_belief(&ekf, &mu, &sigma);
    const gf_real pmu[3] = {1, 0, 0};
    const gf_real psig[3][3] = {
        {0.01, 0, 0}, {0, 10000.01, 10000}, {0, 10000, 10000}};
    check_printed(&ekf, pmu, psig);
}

static void table_4_2(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &INIT_MU, &INIT_SIGMA), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &FORWARD, MOVE_1), GF_OK);
    const gf_mat3 predicted = gf_test_ekf3_sigma(&ekf);

    const gf_vec3 z = {{-0.7, 0, 0}};
    gf_innovation info;
    assert_int_equal(gf_ekf3_update(&ekf, &SEE_X, &z, &info), GF_OK);

    // S = 0.01 + 0.01, K = (0.5, 0, 0): x = 1 + 0.5 (-0.7 - 1) = 0.15,
    // Sigma_xx = 0.005; nothing else moves (Sigma_x* stays 0).
    const gf_vec3 mu = {{0.15, 0, 0}};
    gf_mat3 sigma = predicted;
    sigma.m[0][0] = GF_R(0.005);
    check_belief(&ekf, &mu, &sigma);
    const gf_real pmu[3] = {0.15, 0, 0};
    const gf_real psig[3][3] = {
        {0.005, 0, 0}, {0, 10000.01, 10000}, {0, 10000, 10000}};
    check_printed(&ekf, pmu, psig);
    const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
    assert_true(fabs((double)got.m[0][0] - 0.005) < 0.0005); // 3 decimals

    assert_int_equal(info.m, 1);
    CHECK_CLOSE(info.y[0], -1.7);
    CHECK_CLOSE(info.nis, 1.7 * 1.7 / 0.02);
}

// The Jacobian of the built-in motion against central differences.
static void motion_jacobian(void **state)
{
    (void)state;
    const gf_real u[2] = {GF_R(1.5), GF_R(0.3)};
    for (int k = -6; k <= 6; k++) {
        gf_vec3 x = {{GF_R(0.2), GF_R(-0.4), (gf_real)k * GF_R(0.5)}}, fx;
        gf_mat3 G;
        assert_int_equal(gf_ekf3_motion_forward_turn(NULL, &x, u, &fx, &G),
                         GF_OK);
        CHECK_CLOSE(fx.v[0], 0.2 + 1.5 * cos((double)x.v[2]));
        for (int j = 0; j < 3; j++) {
            const gf_real h = GF_R(1e-3);
            gf_vec3 xp = x, xm = x, fp, fm;
            gf_mat3 dummy;
            xp.v[j] += h;
            xm.v[j] -= h;
            gf_ekf3_motion_forward_turn(NULL, &xp, u, &fp, &dummy);
            gf_ekf3_motion_forward_turn(NULL, &xm, u, &fm, &dummy);
            for (int i = 0; i < 3; i++) {
                double fd =
                    ((double)fp.v[i] - (double)fm.v[i]) / (2 * (double)h);
                assert_true(fabs(fd - (double)G.m[i][j]) < 1e-3);
            }
        }
    }
}

// Heading is wrapped after predict; an angle residual is wrapped before it
// is used.
static gf_status meas_heading(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                              gf_mat3 *H)
{
    int *calls = ctx;
    (*calls)++;
    z_hat->v[0] = mu_bar->v[2];
    H->m[0][0] = 0;
    H->m[0][1] = 0;
    H->m[0][2] = 1;
    return GF_OK;
}

static void angle_wrapping(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    const gf_vec3 mu0 = {{0, 0, GF_R(3.0)}};
    const gf_mat3 s0 = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 0.1}}};
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
    const gf_real turn[2] = {0, GF_R(0.5)}; // 3.5 rad -> 3.5 - 2 pi
    assert_int_equal(gf_ekf3_predict(&ekf, &FORWARD, turn), GF_OK);
    CHECK_CLOSE(ekf.mu.v[2], 3.5 - 2 * (double)GF_PI);

    // Predicted heading 3.5 - 2 pi = -2.78; measured 3.0: the residual is
    // 3.0 - (3.5 - 2 pi) - 2 pi = -0.5, not 5.78.
    int calls = 0;
    gf_ekf3_meas head = {
        .m = 1,
        .h = meas_heading,
        .ctx = &calls,
        .Q = {{{0.1, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
        .angle_mask = 1u,
        .gate = 0,
    };
    const gf_vec3 z = {{3.0, 0, 0}};
    gf_innovation info;
    assert_int_equal(gf_ekf3_update(&ekf, &head, &z, &info), GF_OK);
    assert_int_equal(calls, 1); // the context reached the callback
    CHECK_CLOSE(info.y[0], -0.5);
    // K = 0.1 / 0.2 = 0.5: theta = -2.78 - 0.25 = -3.03, inside (-pi, pi].
    CHECK_CLOSE(ekf.mu.v[2], 3.25 - 2 * (double)GF_PI);
    const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
    CHECK_CLOSE(got.m[2][2], 0.05);
    assert_true(ekf.mu.v[2] > -GF_PI && ekf.mu.v[2] <= GF_PI);

    // Without the mask, the same reading is a 5.78 rad residual.
    gf_ekf3 raw;
    assert_int_equal(gf_ekf3_init(&raw, &mu0, &s0), GF_OK);
    assert_int_equal(gf_ekf3_predict(&raw, &FORWARD, turn), GF_OK);
    head.angle_mask = 0;
    assert_int_equal(gf_ekf3_update(&raw, &head, &z, &info), GF_OK);
    CHECK_CLOSE(info.y[0], 3.0 - (3.5 - 2 * (double)GF_PI));
}

// With a linear measurement the EKF update is the Kalman update: a correlated
// (x, y) measurement checked against K = P H^T S^-1, computed in double.
static void xy_measurement(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    const gf_vec3 mu0 = {{1, 2, 0.5}};
    const gf_mat3 s0 = {{{4, 2, 0}, {2, 5, 1}, {0, 1, 3}}};
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
    gf_ekf3_meas xy = {
        .m = 2,
        .h = gf_ekf3_meas_xy,
        .ctx = NULL,
        .Q = {{{1, 0.5, 0}, {0.5, 2, 0}, {0, 0, 0}}},
        .angle_mask = 0,
        .gate = 0,
    };
    const gf_vec3 z = {{2, 1, 0}};
    gf_innovation info;
    assert_int_equal(gf_ekf3_update(&ekf, &xy, &z, &info), GF_OK);

    // Reference: K = P H^T (H P H^T + Q)^-1 with H = rows x, y.
    const double P[3][3] = {{4, 2, 0}, {2, 5, 1}, {0, 1, 3}};
    const double S[2][2] = {{5, 2.5}, {2.5, 7}};
    double ds = S[0][0] * S[1][1] - S[0][1] * S[1][0];
    double Si[2][2] = {{S[1][1] / ds, -S[0][1] / ds},
                       {-S[1][0] / ds, S[0][0] / ds}};
    double K[3][2], y[2] = {1, -1}, mu[3], post[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 2; j++) {
            K[i][j] = P[i][0] * Si[0][j] + P[i][1] * Si[1][j];
        }
        mu[i] = (double)mu0.v[i] + K[i][0] * y[0] + K[i][1] * y[1];
    }
    for (int i = 0; i < 3; i++) { // (I - K H) P
        for (int j = 0; j < 3; j++) {
            post[i][j] = P[i][j] - K[i][0] * P[0][j] - K[i][1] * P[1][j];
        }
    }
    const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
    for (int i = 0; i < 3; i++) {
        CHECK_CLOSE(ekf.mu.v[i], mu[i]);
        for (int j = 0; j < 3; j++) {
            CHECK_CLOSE(got.m[i][j], post[i][j]);
        }
    }
    CHECK_CLOSE(info.nis, Si[0][0] * 1 - 2 * Si[0][1] + Si[1][1]);
}

static gf_status meas_full(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                           gf_mat3 *H)
{
    (void)ctx;
    for (int i = 0; i < 3; i++) {
        z_hat->v[i] = mu_bar->v[i];
        for (int j = 0; j < 3; j++) {
            H->m[i][j] = i == j ? 1 : 0;
        }
    }
    return GF_OK;
}

// 3x3 inverse by cofactors, in double, for the reference below.
static void inv3(double a[3][3], double out[3][3])
{
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3;
            int c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            out[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
    }
}

// Three measured quantities (the whole state, correlated noise): the
// posterior is the information-form fusion Sigma = (P^-1 + Q^-1)^-1,
// mu = Sigma (P^-1 mu_bar + Q^-1 z), computed here in double.
static void full_state_measurement(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    const gf_vec3 mu0 = {{1, 2, 0.5}};
    const gf_mat3 s0 = {{{4, 2, 0}, {2, 5, 1}, {0, 1, 3}}};
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
    const gf_ekf3_meas all = {
        .m = 3,
        .h = meas_full,
        .ctx = NULL,
        .Q = {{{1, 0.5, 0}, {0.5, 2, 0.2}, {0, 0.2, 0.5}}},
        .angle_mask = 4u,
        .gate = 0,
    };
    const gf_vec3 z = {{2, 1, 0.25}};
    gf_innovation info;
    assert_int_equal(gf_ekf3_update(&ekf, &all, &z, &info), GF_OK);

    double P[3][3] = {{4, 2, 0}, {2, 5, 1}, {0, 1, 3}};
    double Q[3][3] = {{1, 0.5, 0}, {0.5, 2, 0.2}, {0, 0.2, 0.5}};
    const double m0[3] = {1, 2, 0.5}, zz[3] = {2, 1, 0.25};
    double Pi[3][3], Qi[3][3], O[3][3], Sg[3][3], xi[3];
    inv3(P, Pi);
    inv3(Q, Qi);
    for (int i = 0; i < 3; i++) {
        xi[i] = 0;
        for (int j = 0; j < 3; j++) {
            O[i][j] = Pi[i][j] + Qi[i][j];
            xi[i] += Pi[i][j] * m0[j] + Qi[i][j] * zz[j];
        }
    }
    inv3(O, Sg);
    const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
    for (int i = 0; i < 3; i++) {
        double mu = Sg[i][0] * xi[0] + Sg[i][1] * xi[1] + Sg[i][2] * xi[2];
        CHECK_CLOSE(ekf.mu.v[i], mu);
        for (int j = 0; j < 3; j++) {
            CHECK_CLOSE(got.m[i][j], Sg[i][j]);
        }
    }
    // NIS = y^T (P + Q)^-1 y
    double S[3][3], Si[3][3], y[3] = {1, -1, -0.25}, nis = 0;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            S[i][j] = P[i][j] + Q[i][j];
        }
    }
    inv3(S, Si);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            nis += y[i] * Si[i][j] * y[j];
        }
    }
    assert_int_equal(info.m, 3);
    CHECK_CLOSE(info.y[2], -0.25);
    CHECK_CLOSE(info.nis, nis);
}

static gf_status meas_fails(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    (void)mu_bar;
    (void)H;
    z_hat->v[0] = (gf_real)NAN;
    return ctx ? (gf_status)7 : GF_OK; // 7: a status the library doesn't know
}

static gf_status meas_gated(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    (void)ctx;
    (void)mu_bar;
    (void)z_hat;
    (void)H;
    return GF_ERR_GATED;
}

static gf_status motion_nan(void *ctx, const gf_vec3 *mu, const gf_real *u,
                            gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)mu;
    (void)u;
    (void)G;
    if (ctx) {
        return GF_ERR_ARG;
    }
    mu_bar->v[1] = (gf_real)NAN;
    return GF_OK;
}

static void gate(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &INIT_MU, &INIT_SIGMA), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &FORWARD, MOVE_1), GF_OK);
    // z = -0.7 is a 12-sigma surprise (NIS = 144.5): a 99% gate drops it.
    gf_ekf3_meas gated = SEE_X;
    gated.gate = GF_R(6.63);
    const gf_vec3 z = {{-0.7, 0, 0}};
    gf_innovation info;
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &ekf,
                          gf_ekf3_update(&ekf, &gated, &z, &info));
    CHECK_CLOSE(info.nis, 144.5);
    const gf_vec3 near = {{1.1, 0, 0}};
    assert_int_equal(gf_ekf3_update(&ekf, &gated, &near, &info), GF_OK);
}

static void bad_input(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &INIT_MU, &INIT_SIGMA), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &FORWARD, MOVE_1), GF_OK);
    const gf_vec3 z = {{-0.7, 0, 0}};
    gf_innovation info = {0, {0, 0, 0}, 0};
    int flag = 1;

    // init
    const gf_vec3 nan_mu = {{0, (gf_real)NAN, 0}};
    gf_mat3 bad = INIT_SIGMA;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_init(NULL, &INIT_MU, &INIT_SIGMA));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_init(&ekf, NULL, &INIT_SIGMA));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf, gf_ekf3_init(&ekf, &INIT_MU, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_init(&ekf, &nan_mu, &INIT_SIGMA));
    bad.m[2][2] = GF_R(-1.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ekf,
                          gf_ekf3_init(&ekf, &INIT_MU, &bad));
    bad = INIT_SIGMA;
    bad.m[0][1] = GF_R(1.0); // asymmetric (and indefinite)
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ekf,
                          gf_ekf3_init(&ekf, &INIT_MU, &bad));

    // predict
    gf_ekf3_motion mo = FORWARD;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_predict(NULL, &FORWARD, MOVE_1));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_predict(&ekf, NULL, MOVE_1));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_predict(&ekf, &FORWARD, NULL));
    mo.g = NULL;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf, gf_ekf3_predict(&ekf, &mo, MOVE_1));
    mo = FORWARD;
    mo.R.m[1][1] = GF_R(-0.1);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ekf,
                          gf_ekf3_predict(&ekf, &mo, MOVE_1));
    mo = FORWARD;
    mo.R.m[2][0] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_predict(&ekf, &mo, MOVE_1));
    const gf_real u_nan[2] = {(gf_real)NAN, 0};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_predict(&ekf, &FORWARD, u_nan));
    mo = FORWARD;
    mo.g = motion_nan;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_predict(&ekf, &mo, MOVE_1));
    mo.ctx = &flag; // the callback's own error is passed on
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf, gf_ekf3_predict(&ekf, &mo, MOVE_1));

    // update
    gf_ekf3_meas q = SEE_X;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(NULL, &SEE_X, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, NULL, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, &SEE_X, NULL, &info));
    q.h = NULL;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q = SEE_X;
    q.m = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q.m = 4;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q = SEE_X;
    q.Q.m[0][0] = GF_R(-0.01);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q = SEE_X;
    q.gate = GF_R(-2.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q.gate = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    const gf_vec3 z_nan = {{(gf_real)NAN, 0, 0}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &SEE_X, &z_nan, &info));
    q = SEE_X;
    q.h = meas_fails;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q.ctx = &flag; // an unknown status from a callback becomes GF_ERR_MODEL
    CHECK_FAILS_UNCHANGED(GF_ERR_MODEL, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    q.h = meas_gated; // and so does GF_ERR_GATED, which only the gate reports
    CHECK_FAILS_UNCHANGED(GF_ERR_MODEL, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    // Singular innovation: known x and a noiseless x sensor.
    gf_ekf3 known;
    const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    assert_int_equal(gf_ekf3_init(&known, &INIT_MU, &zero), GF_OK);
    q = SEE_X;
    q.Q.m[0][0] = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &known,
                          gf_ekf3_update(&known, &q, &z, &info));
    // Overflow in the result.
    gf_ekf3 big;
    const gf_real huge = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e200);
    const gf_mat3 hs = {{{huge, 0, 0}, {0, huge, 0}, {0, 0, huge}}};
    assert_int_equal(gf_ekf3_init(&big, &INIT_MU, &hs), GF_OK);
    const gf_real far[2] = {huge, 0};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &big,
                          gf_ekf3_predict(&big, &FORWARD, far));
    assert_int_equal(info.m, 0);
}

// ---- m = 2 and 3 (the general update) against a double reference ----------

// A linear measurement with a random H: z_hat = H mu_bar (first m rows).
static gf_status meas_linear(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                             gf_mat3 *H)
{
    const gf_mat3 *h = ctx;
    for (int i = 0; i < 3; i++) {
        z_hat->v[i] = h->m[i][0] * mu_bar->v[0] + h->m[i][1] * mu_bar->v[1] +
                      h->m[i][2] * mu_bar->v[2];
        for (int j = 0; j < 3; j++) {
            H->m[i][j] = h->m[i][j];
        }
    }
    return GF_OK;
}

// A random symmetric positive-definite n x n block (A A^T + d I).
static void random_spd(gf_rng *rng, int n, double d, double out[3][3])
{
    double a[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            a[i][j] = gf_test_uniform(rng, -1, 1);
            out[i][j] = 0;
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            for (int k = 0; k < n; k++) {
                out[i][j] += a[i][k] * a[j][k];
            }
        }
        out[i][i] += d;
    }
}

// Random beliefs, correlated noise and general H for m = 2 and 3: the
// update against K = P H^T S^-1 (S inverted in double by cofactors) and the
// factored Joseph form (I - K H) P (I - K H)^T + K Q K^T, written out here.
static void general_random(void **state)
{
    (void)state;
    gf_rng rng;
    (void)gf_rng_seed(&rng, 1u);
#ifdef GF_SINGLE_PRECISION
    const double tol = 2e-4;
#else
    const double tol = 1e-10;
#endif
    for (int trial = 0; trial < 200; trial++) {
        const int m = 2 + trial % 2;
        double P[3][3], Q[3][3], Hd[3][3] = {{0}}, mu[3], z[3];
        random_spd(&rng, 3, 0.05, P);
        random_spd(&rng, m, 0.1, Q);
        gf_mat3 hm = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < 3; j++) {
                hm.m[i][j] = (gf_real)gf_test_uniform(&rng, -1.5, 1.5);
                Hd[i][j] = (double)hm.m[i][j];
            }
        }
        gf_ekf3 ekf;
        gf_vec3 mu0;
        gf_mat3 s0;
        gf_ekf3_meas meas = {
            .m = (unsigned)m,
            .h = meas_linear,
            .ctx = &hm,
            .Q = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}},
            .angle_mask = 0,
            .gate = 0,
        };
        gf_vec3 zv = {{0, 0, 0}};
        for (int i = 0; i < 3; i++) {
            mu0.v[i] = (gf_real)gf_test_uniform(&rng, -0.5, 0.5);
            for (int j = 0; j < 3; j++) {
                s0.m[i][j] = (gf_real)P[i][j];
                meas.Q.m[i][j] = (gf_real)Q[i][j];
            }
        }
        assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
        // The reference starts from the belief as stored: mu, and Sigma as
        // gf_ekf3_cov gives it back from its factors.
        const gf_mat3 prior = gf_test_ekf3_sigma(&ekf);
        for (int i = 0; i < 3; i++) {
            mu[i] = (double)ekf.mu.v[i];
            for (int j = 0; j < 3; j++) {
                P[i][j] = (double)prior.m[i][j];
                Q[i][j] = i < m && j < m ? (double)meas.Q.m[i][j] : 0;
            }
        }
        for (int i = 0; i < m; i++) {
            zv.v[i] = (gf_real)gf_test_uniform(&rng, -1, 1);
            z[i] = (double)zv.v[i];
        }
        gf_innovation info;
        assert_int_equal(gf_ekf3_update(&ekf, &meas, &zv, &info), GF_OK);

        // Reference: S, S^-1 (identity padded to 3x3 for m = 2), K, y.
        double PHt[3][3] = {{0}}, S[3][3], Si[3][3], K[3][3] = {{0}};
        double y[3] = {0, 0, 0}, nis = 0;
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < m; j++) {
                for (int k = 0; k < 3; k++) {
                    PHt[i][j] += P[i][k] * Hd[j][k];
                }
            }
        }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                S[i][j] = i == j ? 1 : 0;
                if (i < m && j < m) {
                    S[i][j] = Q[i][j];
                    for (int k = 0; k < 3; k++) {
                        S[i][j] += Hd[i][k] * PHt[k][j];
                    }
                }
            }
        }
        inv3(S, Si);
        for (int i = 0; i < m; i++) {
            y[i] =
                z[i] - (Hd[i][0] * mu[0] + Hd[i][1] * mu[1] + Hd[i][2] * mu[2]);
        }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < m; j++) {
                for (int k = 0; k < m; k++) {
                    K[i][j] += PHt[i][k] * Si[k][j];
                }
            }
        }
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++) {
                nis += y[i] * Si[i][j] * y[j];
            }
        }
        double A[3][3], T[3][3] = {{0}}, post[3][3];
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                A[i][j] = i == j ? 1 : 0;
                for (int k = 0; k < m; k++) {
                    A[i][j] -= K[i][k] * Hd[k][j];
                }
            }
        }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                for (int k = 0; k < 3; k++) {
                    T[i][j] += A[i][k] * P[k][j];
                }
            }
        }
        double scale = 1;
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                post[i][j] = 0;
                for (int k = 0; k < 3; k++) {
                    post[i][j] += T[i][k] * A[j][k];
                }
                for (int a = 0; a < m; a++) {
                    for (int b = 0; b < m; b++) {
                        post[i][j] += K[i][a] * Q[a][b] * K[j][b];
                    }
                }
                scale = fabs(P[i][j]) > scale ? fabs(P[i][j]) : scale;
            }
        }
        const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
        for (int i = 0; i < 3; i++) {
            double want = mu[i];
            for (int k = 0; k < m; k++) {
                want += K[i][k] * y[k];
            }
            assert_true(fabs((double)ekf.mu.v[i] - want) <= tol * scale);
            for (int j = 0; j < 3; j++) {
                assert_true(fabs((double)got.m[i][j] - post[i][j]) <=
                            tol * scale);
                // exactly symmetric
                assert_true(got.m[i][j] == got.m[j][i]); // NOLINT
            }
        }
        assert_int_equal(info.m, (unsigned)m);
        assert_true(fabs((double)info.nis - nis) <= tol * (nis > 1 ? nis : 1));
        for (int i = 0; i < m; i++) {
            assert_true(fabs((double)info.y[i] - y[i]) <= tol * scale);
        }
    }
}

// A failing m = 2 or 3 update leaves the belief (and info) as they were.
static void general_fails_unchanged(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    const gf_vec3 mu0 = {{1, 2, 0.5}};
    const gf_mat3 s0 = {{{4, 2, 0}, {2, 5, 1}, {0, 1, 3}}};
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
    gf_ekf3_meas xy = {
        .m = 2,
        .h = gf_ekf3_meas_xy,
        .ctx = NULL,
        .Q = {{{1, 0.5, 0}, {0.5, 2, 0}, {0, 0, 0}}},
        .angle_mask = 0,
        .gate = 0,
    };
    const gf_vec3 z = {{2, 1, 0}};
    gf_innovation info = {0, {0, 0, 0}, 0};

    // Gated: the innovation is written, the belief is not.
    gf_ekf3_meas q = xy;
    q.gate = GF_R(0.01);
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    assert_int_equal(info.m, 2);
    CHECK_CLOSE(info.y[0], 1);
    CHECK_CLOSE(info.y[1], -1);
    // Q not PSD, z not finite, a model that returns NaN in H.
    gf_innovation keep = info;
    q = xy;
    q.Q.m[1][1] = GF_R(-2.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    const gf_vec3 z_nan = {{2, (gf_real)NAN, 0}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &xy, &z_nan, &info));
    gf_mat3 hn = {{{1, 0, 0}, {0, (gf_real)NAN, 0}, {0, 0, 0}}};
    q = xy;
    q.h = meas_linear;
    q.ctx = &hn;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    // S singular: a state known exactly, a noiseless sensor; and S with an
    // infinite entry (a huge H row squared).
    gf_ekf3 known;
    const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    assert_int_equal(gf_ekf3_init(&known, &mu0, &zero), GF_OK);
    q = xy;
    q.Q = zero;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &known,
                          gf_ekf3_update(&known, &q, &z, &info));
    const gf_real big = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e200);
    gf_mat3 hb = {{{big, 0, 0}, {0, 1, 0}, {0, 0, 0}}};
    q = xy;
    q.h = meas_linear;
    q.ctx = &hb;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ekf,
                          gf_ekf3_update(&ekf, &q, &z, &info));
    assert_memory_equal(&keep, &info, sizeof info);
}

// The motion callback gets mu_bar = mu and G = I (ekf3.h), on the fast
// paths and in the compact steps alike.
static void motion_args(void **state)
{
    (void)state;
    unsigned broken = 0;
    const gf_test_args a = gf_test_args_make(&broken);
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &a.mu, &a.sig), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &a.mo, a.u), GF_OK);
    assert_int_equal(broken, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_4_1),
        cmocka_unit_test(table_4_2),
        cmocka_unit_test(motion_jacobian),
        cmocka_unit_test(motion_args),
        cmocka_unit_test(angle_wrapping),
        cmocka_unit_test(xy_measurement),
        cmocka_unit_test(full_state_measurement),
        cmocka_unit_test(gate),
        cmocka_unit_test(bad_input),
        cmocka_unit_test(general_random),
        cmocka_unit_test(general_fails_unchanged),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
