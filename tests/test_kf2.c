// SPDX-License-Identifier: MIT
// KF2 against exercises 1, 2 and 5 of Probabilistic Robotics chapter 3
// (docs/exercises.md): Table 1.1, Figure 1.2,
// Table 2.1, and the additive constants of exercise 5.
#include "gf_test.h"

// Exercise 1: A = ((1, 1), (0, 1)), no control, and the process noise
// R = G G^T with G = (0.5, 1)^T. (The worked solutions' equation 1.8 prints
// diag(0.25, 1), but its own Table 1.1 needs the full R; the tables are
// the truth.)
static const gf_kf2_model CAR = {
    .A = {{{1, 1}, {0, 1}}},
    .B = {{{0, 0}, {0, 0}}},
    .R = {{{0.25, 0.5}, {0.5, 1}}},
    .c = {{0, 0}},
};

// Exercise 2: the position is measured, C = (1, 0), Q = 10.
static const gf_kf2_meas GPS = {
    .m = 1,
    .C = {{{1, 0}, {0, 0}}},
    .Q = {{{10, 0}, {0, 0}}},
    .c = {{0, 0}},
    .gate = 0,
};

static const gf_vec2 ZERO2 = {{0, 0}};
static const gf_mat2 ZERO22 = {{{0, 0}, {0, 0}}};

// Table 1.1: Sigma_t for t = 0..5 (every entry exact in binary).
static const gf_mat2 TABLE_1_1[6] = {
    {{{0, 0}, {0, 0}}},   {{{0.25, 0.5}, {0.5, 1}}},
    {{{2.5, 2}, {2, 2}}}, {{{8.75, 4.5}, {4.5, 3}}},
    {{{21, 8}, {8, 4}}},  {{{41.25, 12.5}, {12.5, 5}}},
};

static void check_belief(const gf_kf2 *kf, const gf_vec2 *mu,
                         const gf_mat2 *sigma)
{
    CHECK_CLOSE(kf->mu.v[0], mu->v[0]);
    CHECK_CLOSE(kf->mu.v[1], mu->v[1]);
    const gf_mat2 got = gf_test_kf2_sigma(kf);
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 2; j++) {
            CHECK_CLOSE(got.m[i][j], sigma->m[i][j]);
        }
    }
}

static void car_at_t5(gf_kf2 *kf)
{
    assert_int_equal(gf_kf2_init(kf, &ZERO2, &ZERO22), GF_OK);
    for (int t = 1; t <= 5; t++) {
        assert_int_equal(gf_kf2_predict(kf, &CAR, NULL), GF_OK);
    }
}

static void table_1_1(void **state)
{
    (void)state;
    gf_kf2 kf;
    assert_int_equal(gf_kf2_init(&kf, &ZERO2, &ZERO22), GF_OK);
    check_belief(&kf, &ZERO2, &TABLE_1_1[0]);
    for (int t = 1; t <= 5; t++) {
        assert_int_equal(gf_kf2_predict(&kf, &CAR, NULL), GF_OK);
        // Without measurements or control the mean stays at 0.
        check_belief(&kf, &ZERO2, &TABLE_1_1[t]);
    }
    // A zero control is the same as no control.
    gf_kf2 a, b;
    car_at_t5(&a);
    assert_int_equal(gf_kf2_init(&b, &ZERO2, &ZERO22), GF_OK);
    for (int t = 1; t <= 5; t++) {
        assert_int_equal(gf_kf2_predict(&b, &CAR, &ZERO2), GF_OK);
    }
    assert_memory_equal(&a, &b, sizeof a);
}

// Figure 1.2: rho_t = Sigma_xv / sqrt(Sigma_xx Sigma_vv) for t = 1..10,
// from the exact rationals of Sigma_t (Sigma_t = ((t(2t^2+1)/12... ))
// evaluated offline in double.
static const double RHO[11] = {
    0, /* t = 0: undefined */
    1.0,
    0.8944271909999159,
    0.8783100656536799,
    0.8728715609439696,
    0.8703882797784892,
    0.8690481892534816,
    0.8682431421244592,
    0.8677218312746247,
    0.8673649643743680,
    0.8671099695241200,
};
// The values the worked solutions' Figure 1.2 shows, to three decimals.
static const double RHO_PRINTED[4] = {0, 1.0, 0.894, 0.878};

static void figure_1_2(void **state)
{
    (void)state;
    gf_kf2 kf;
    gf_real rho = GF_R(42.0);
    assert_int_equal(gf_kf2_init(&kf, &ZERO2, &ZERO22), GF_OK);
    // t = 0: both variances are zero, the correlation is undefined.
    gf_mat2 sigma = gf_test_kf2_sigma(&kf);
    assert_int_equal(gf_cov2_correlation(&sigma, &rho), GF_ERR_UNDEFINED);
    CHECK_CLOSE(rho, 42.0);

    gf_real prev = GF_R(2.0);
    for (int t = 1; t <= 10; t++) {
        assert_int_equal(gf_kf2_predict(&kf, &CAR, NULL), GF_OK);
        sigma = gf_test_kf2_sigma(&kf);
        assert_int_equal(gf_cov2_correlation(&sigma, &rho), GF_OK);
        CHECK_CLOSE(rho, RHO[t]);
        if (t < 4) {
            assert_true(fabs((double)rho - RHO_PRINTED[t]) <= 0.0005);
        }
        // Falling towards sqrt(3)/2, the worked solutions' 0.87, from above.
        assert_true(rho < prev);
        assert_true((double)rho > 0.8660254037844386);
        prev = rho;
    }
    assert_true(fabs((double)rho - 0.867) <= 0.0005);
}

static void table_2_1(void **state)
{
    (void)state;
    gf_kf2 kf;
    car_at_t5(&kf);
    // Before: Table 2.1's first row.
    check_belief(&kf, &ZERO2, &TABLE_1_1[5]);

    const gf_vec2 z = {{5, 0}};
    gf_innovation info;
    assert_int_equal(gf_kf2_update(&kf, &GPS, &z, &info), GF_OK);

    // After, against the exact fractions: S = 41.25 + 10 = 51.25,
    // K = (41.25, 12.5) / 51.25.
    const double s = 51.25;
    const gf_vec2 mu = {{(gf_real)(5 * 41.25 / s), (gf_real)(5 * 12.5 / s)}};
    const gf_mat2 sigma = {
        {{(gf_real)(41.25 * 10 / s), (gf_real)(12.5 * 10 / s)},
         {(gf_real)(12.5 * 10 / s), (gf_real)(5 - 12.5 * 12.5 / s)}}};
    check_belief(&kf, &mu, &sigma);
    // ... and to the digits the worked solutions print.
    const gf_mat2 got = gf_test_kf2_sigma(&kf);
    CHECK_PRINTED(kf.mu.v[0], 4.02);
    CHECK_PRINTED(kf.mu.v[1], 1.22);
    CHECK_PRINTED(got.m[0][0], 8.05);
    CHECK_PRINTED(got.m[0][1], 2.44);
    CHECK_PRINTED(got.m[1][0], 2.44);
    CHECK_PRINTED(got.m[1][1], 1.95);
    // ... and to four digits (the long-double values, 4.0244, 1.2195, ...).
    assert_true(fabs((double)kf.mu.v[0] - 4.0244) < 0.00005);
    assert_true(fabs((double)kf.mu.v[1] - 1.2195) < 0.00005);
    assert_true(fabs((double)got.m[0][0] - 8.0488) < 0.00005);
    assert_true(fabs((double)got.m[0][1] - 2.4390) < 0.00005);
    assert_true(fabs((double)got.m[1][1] - 1.9512) < 0.00005);
    // Exactly symmetric, as gf_kf2_cov promises.
    assert_memory_equal(&got.m[0][1], &got.m[1][0], sizeof(gf_real));

    // The innovation and its NIS: y = 5, NIS = 25 / 51.25.
    assert_int_equal(info.m, 1);
    CHECK_CLOSE(info.y[0], 5);
    CHECK_CLOSE(info.nis, 25 / s);
}

static void exercise_5_constants(void **state)
{
    (void)state;
    // Motion constant: mu_bar = A mu + B u + c. Means shift, Sigma doesn't.
    gf_kf2_model shifted = CAR;
    shifted.c.v[0] = GF_R(0.5);
    shifted.c.v[1] = GF_R(-1.0);
    gf_kf2 plain, moved;
    car_at_t5(&plain);
    assert_int_equal(gf_kf2_init(&moved, &ZERO2, &ZERO22), GF_OK);
    double x = 0, v = 0;
    for (int t = 1; t <= 5; t++) {
        assert_int_equal(gf_kf2_predict(&moved, &shifted, NULL), GF_OK);
        x = x + v + 0.5;
        v = v - 1.0;
    }
    CHECK_CLOSE(moved.mu.v[0], x); // x_5 = -7.5, v_5 = -5
    CHECK_CLOSE(moved.mu.v[1], v);
    CHECK_CLOSE(x, -7.5);
    const gf_mat2 s_moved = gf_test_kf2_sigma(&moved);
    const gf_mat2 s_plain = gf_test_kf2_sigma(&plain);
    assert_memory_equal(&s_moved, &s_plain, sizeof s_plain);

    // Measurement constant: mu = mu_bar + K (z - c - C mu_bar). A reading
    // offset by c gives the same posterior as the plain reading.
    gf_kf2_meas biased = GPS;
    biased.c.v[0] = GF_R(3.0);
    gf_kf2 a = plain, b = plain;
    const gf_vec2 z = {{5, 0}}, zb = {{8, 0}};
    gf_innovation ia, ib;
    assert_int_equal(gf_kf2_update(&a, &GPS, &z, &ia), GF_OK);
    assert_int_equal(gf_kf2_update(&b, &biased, &zb, &ib), GF_OK);
    assert_memory_equal(&a, &b, sizeof a);
    CHECK_CLOSE(ib.y[0], 5);

    // Same reading, with the constant: the mean moves by K (-c), Sigma the
    // same bit for bit.
    gf_kf2 c = plain;
    assert_int_equal(gf_kf2_update(&c, &biased, &z, NULL), GF_OK);
    CHECK_CLOSE(c.mu.v[0], (double)a.mu.v[0] - 3 * 41.25 / 51.25);
    CHECK_CLOSE(c.mu.v[1], (double)a.mu.v[1] - 3 * 12.5 / 51.25);
    const gf_mat2 s_c = gf_test_kf2_sigma(&c);
    const gf_mat2 s_a = gf_test_kf2_sigma(&a);
    assert_memory_equal(&s_c, &s_a, sizeof s_a);
}

static void control_input(void **state)
{
    (void)state;
    // B u with u = acceleration: B = ((0.5, 0), (1, 0)).
    gf_kf2_model m = CAR;
    m.B.m[0][0] = GF_R(0.5);
    m.B.m[1][0] = GF_R(1.0);
    gf_kf2 kf;
    const gf_vec2 mu0 = {{1, 2}}, u = {{2, 0}};
    assert_int_equal(gf_kf2_init(&kf, &mu0, &ZERO22), GF_OK);
    assert_int_equal(gf_kf2_predict(&kf, &m, &u), GF_OK);
    CHECK_CLOSE(kf.mu.v[0], 1 + 2 + 0.5 * 2);
    CHECK_CLOSE(kf.mu.v[1], 2 + 2);
}

// Two measured quantities against the information form
// Sigma = (Sigma_bar^-1 + C^T Q^-1 C)^-1, mu = Sigma (Sigma_bar^-1 mu_bar +
// C^T Q^-1 z), computed here independently in double.
static void two_measurements(void **state)
{
    (void)state;
    gf_kf2 kf;
    car_at_t5(&kf);
    const gf_kf2_meas both = {
        .m = 2,
        .C = {{{1, 0}, {0, 1}}},
        .Q = {{{10, 1}, {1, 2}}},
        .c = {{0, 0}},
        .gate = 0,
    };
    const gf_vec2 z = {{5, 1}};
    gf_innovation info;
    assert_int_equal(gf_kf2_update(&kf, &both, &z, &info), GF_OK);

    const double P[2][2] = {{41.25, 12.5}, {12.5, 5}};
    const double Q[2][2] = {{10, 1}, {1, 2}};
    double dp = P[0][0] * P[1][1] - P[0][1] * P[0][1];
    double dq = Q[0][0] * Q[1][1] - Q[0][1] * Q[0][1];
    double Pi[2][2] = {{P[1][1] / dp, -P[0][1] / dp},
                       {-P[0][1] / dp, P[0][0] / dp}};
    double Qi[2][2] = {{Q[1][1] / dq, -Q[0][1] / dq},
                       {-Q[0][1] / dq, Q[0][0] / dq}};
    double O[2][2], xi[2];
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 2; j++) {
            O[i][j] = Pi[i][j] + Qi[i][j];
        }
        xi[i] = Qi[i][0] * 5 + Qi[i][1] * 1; // Pi mu_bar = 0
    }
    double d = O[0][0] * O[1][1] - O[0][1] * O[1][0];
    double Sg[2][2] = {{O[1][1] / d, -O[0][1] / d},
                       {-O[1][0] / d, O[0][0] / d}};
    const gf_mat2 got = gf_test_kf2_sigma(&kf);
    CHECK_CLOSE(got.m[0][0], Sg[0][0]);
    CHECK_CLOSE(got.m[0][1], Sg[0][1]);
    CHECK_CLOSE(got.m[1][1], Sg[1][1]);
    CHECK_CLOSE(kf.mu.v[0], Sg[0][0] * xi[0] + Sg[0][1] * xi[1]);
    CHECK_CLOSE(kf.mu.v[1], Sg[1][0] * xi[0] + Sg[1][1] * xi[1]);

    // NIS = y^T S^-1 y with S = P + Q, y = z.
    double S[2][2] = {{51.25, 13.5}, {13.5, 7}};
    double ds = S[0][0] * S[1][1] - S[0][1] * S[0][1];
    double nis = (S[1][1] * 25 - 2 * S[0][1] * 5 + S[0][0] * 1) / ds;
    assert_int_equal(info.m, 2);
    CHECK_CLOSE(info.nis, nis);
}

static void gate(void **state)
{
    (void)state;
    gf_kf2 kf;
    car_at_t5(&kf);
    gf_kf2_meas gated = GPS;
    gated.gate = GF_R(3.84); // chi-square 95%, 1 dof
    // z = 5: NIS = 0.49, accepted.
    gf_kf2 ok = kf;
    const gf_vec2 near = {{5, 0}}, far = {{50, 0}};
    gf_innovation info;
    assert_int_equal(gf_kf2_update(&ok, &gated, &near, &info), GF_OK);
    // z = 50: NIS = 2500 / 51.25 = 48.8, gated: nothing changes, but the
    // caller learns the innovation and NIS.
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &kf,
                          gf_kf2_update(&kf, &gated, &far, &info));
    CHECK_CLOSE(info.y[0], 50);
    CHECK_CLOSE(info.nis, 2500 / 51.25);
}

static void bad_input(void **state)
{
    (void)state;
    gf_kf2 kf;
    car_at_t5(&kf);
    const gf_vec2 z = {{5, 0}};
    gf_innovation info = {0, {0, 0, 0}, 0};

    // init
    const gf_vec2 nan_mu = {{(gf_real)NAN, 0}};
    const gf_mat2 neg = {{{-1, 0}, {0, 1}}};
    const gf_mat2 asym = {{{1, 0.5}, {0, 1}}};
    const gf_mat2 inf = {{{(gf_real)INFINITY, 0}, {0, 1}}};
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_init(NULL, &ZERO2, &ZERO22));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_init(&kf, NULL, &ZERO22));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_init(&kf, &ZERO2, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_init(&kf, &nan_mu, &ZERO22));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_init(&kf, &ZERO2, &inf));
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf, gf_kf2_init(&kf, &ZERO2, &neg));
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf, gf_kf2_init(&kf, &ZERO2, &asym));

    // predict
    gf_kf2_model m = CAR;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_predict(NULL, &CAR, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_predict(&kf, NULL, NULL));
    m.A.m[0][1] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf, gf_kf2_predict(&kf, &m, NULL));
    m = CAR;
    m.B.m[1][1] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf, gf_kf2_predict(&kf, &m, NULL));
    m = CAR;
    m.c.v[1] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf, gf_kf2_predict(&kf, &m, NULL));
    m = CAR;
    m.R.m[1][1] = GF_R(-1.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf, gf_kf2_predict(&kf, &m, NULL));
    m = CAR;
    m.R.m[0][1] = GF_R(0.6); // asymmetric
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf, gf_kf2_predict(&kf, &m, NULL));
    const gf_vec2 u_nan = {{0, (gf_real)NAN}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_predict(&kf, &CAR, &u_nan));
    // Overflow: a finite model whose result is not finite.
    m = CAR;
    const gf_real huge = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e200);
    m.A.m[0][0] = huge; // huge^2 overflows
    m.A.m[0][1] = huge;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf, gf_kf2_predict(&kf, &m, NULL));

    // update
    gf_kf2_meas q = GPS;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_update(NULL, &GPS, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_update(&kf, NULL, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_update(&kf, &GPS, NULL, &info));
    q.m = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_update(&kf, &q, &z, &info));
    q.m = 3;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_update(&kf, &q, &z, &info));
    q = GPS;
    q.Q.m[0][0] = GF_R(-10.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf,
                          gf_kf2_update(&kf, &q, &z, &info));
    q = GPS;
    q.Q.m[0][0] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update(&kf, &q, &z, &info));
    q = GPS;
    q.C.m[0][1] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update(&kf, &q, &z, &info));
    q = GPS;
    q.c.v[0] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update(&kf, &q, &z, &info));
    q = GPS;
    q.gate = GF_R(-1.0);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf, gf_kf2_update(&kf, &q, &z, &info));
    q.gate = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update(&kf, &q, &z, &info));
    const gf_vec2 z_inf = {{(gf_real)INFINITY, 0}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update(&kf, &GPS, &z_inf, &info));
    // m = 2: Q indefinite; S singular.
    gf_kf2_meas two = {.m = 2,
                       .C = {{{1, 0}, {1, 0}}},
                       .Q = {{{1, 2}, {2, 1}}},
                       .c = {{0, 0}},
                       .gate = 0};
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &kf,
                          gf_kf2_update(&kf, &two, &z, &info));
    two.Q = ZERO22; // two copies of the position, no noise: S is singular
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &kf,
                          gf_kf2_update(&kf, &two, &z, &info));
    // m = 1: known state and noiseless sensor: S = 0.
    gf_kf2 known;
    assert_int_equal(gf_kf2_init(&known, &ZERO2, &ZERO22), GF_OK);
    q = GPS;
    q.Q.m[0][0] = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &known,
                          gf_kf2_update(&known, &q, &z, &info));
    // None of these touched the info either.
    assert_int_equal(info.m, 0);
}

// ---- prepared models (gf_kf2_prepare_model/_meas, *_prepared) ----------

// One predict with the plain and the prepared API from the same belief:
// the same status, and the same belief bit for bit (changed or not).
static void same_predict(const gf_kf2 *kf, const gf_kf2_model *model,
                         const gf_vec2 *u)
{
    gf_kf2_pmodel pm;
    assert_int_equal(gf_kf2_prepare_model(&pm, model), GF_OK);
    gf_kf2 a = *kf, b = *kf;
    assert_int_equal(gf_kf2_predict_prepared(&b, &pm, u),
                     gf_kf2_predict(&a, model, u));
    assert_memory_equal(&a, &b, sizeof a);
}

// The same for an update, info included (written or not).
static gf_status same_update(const gf_kf2 *kf, const gf_kf2_meas *meas,
                             const gf_vec2 *z)
{
    gf_kf2_pmeas pq;
    assert_int_equal(gf_kf2_prepare_meas(&pq, meas), GF_OK);
    gf_kf2 a = *kf, b = *kf;
    gf_innovation ia, ib;
    memset(&ia, 0xA5, sizeof ia);
    memset(&ib, 0xA5, sizeof ib);
    gf_status st = gf_kf2_update(&a, meas, z, &ia);
    assert_int_equal(gf_kf2_update_prepared(&b, &pq, z, &ib), st);
    assert_memory_equal(&a, &b, sizeof a);
    assert_memory_equal(&ia, &ib, sizeof ia);
    return st;
}

// The prepared steps equal the plain ones bit for bit: exercises 1 and 2
// (Table 2.1's run), with u, the constants of exercise 5, a gate, m = 2.
static void prepared_equals_plain(void **state)
{
    (void)state;
    gf_kf2_model ctl = CAR;
    ctl.B.m[0][0] = GF_R(0.5);
    ctl.B.m[1][0] = GF_R(1.0);
    ctl.c.v[0] = GF_R(0.25);
    gf_kf2_meas gated = GPS;
    gated.gate = GF_R(3.84);
    gated.c.v[0] = GF_R(-0.5);
    const gf_kf2_meas two = {.m = 2,
                             .C = {{{1, 0}, {0, 1}}},
                             .Q = {{{10, 1}, {1, 4}}},
                             .c = {{0, 0}},
                             .gate = 0};
    gf_kf2_pmodel pcar, pctl;
    gf_kf2_pmeas pgps, pgated, ptwo;
    assert_int_equal(gf_kf2_prepare_model(&pcar, &CAR), GF_OK);
    assert_int_equal(gf_kf2_prepare_model(&pctl, &ctl), GF_OK);
    assert_int_equal(gf_kf2_prepare_meas(&pgps, &GPS), GF_OK);
    assert_int_equal(gf_kf2_prepare_meas(&pgated, &gated), GF_OK);
    assert_int_equal(gf_kf2_prepare_meas(&ptwo, &two), GF_OK);

    gf_kf2 a, b;
    assert_int_equal(gf_kf2_init(&a, &ZERO2, &ZERO22), GF_OK);
    b = a;
    int gated_seen = 0;
    for (int t = 1; t <= 60; t++) {
        const gf_vec2 u = {{(gf_real)(t % 5) - 2, 0}};
        const gf_vec2 z = {
            {(gf_real)(3 * t % 17) - GF_R(8.5), (gf_real)(t % 7) - 3}};
        gf_innovation ia, ib;
        const int k = t % 3;
        const gf_kf2_model *m = k ? &CAR : &ctl;
        const gf_kf2_pmodel *pm = k ? &pcar : &pctl;
        assert_int_equal(gf_kf2_predict(&a, m, k ? NULL : &u), GF_OK);
        assert_int_equal(gf_kf2_predict_prepared(&b, pm, k ? NULL : &u), GF_OK);
        assert_memory_equal(&a, &b, sizeof a);
        const gf_kf2_meas *q = k == 0 ? &GPS : k == 1 ? &gated : &two;
        const gf_kf2_pmeas *pq = k == 0 ? &pgps : k == 1 ? &pgated : &ptwo;
        memset(&ia, 0, sizeof ia);
        memset(&ib, 0, sizeof ib);
        gf_status st = gf_kf2_update(&a, q, &z, &ia);
        assert_true(st == GF_OK || st == GF_ERR_GATED);
        gated_seen += st == GF_ERR_GATED;
        assert_int_equal(gf_kf2_update_prepared(&b, pq, &z, &ib), st);
        assert_memory_equal(&a, &b, sizeof a);
        assert_memory_equal(&ia, &ib, sizeof ia);
    }
    assert_true(gated_seen > 0); // the gate was exercised both ways
    assert_true(gated_seen < 20);

    // Table 1.1 through the prepared predict.
    assert_int_equal(gf_kf2_init(&b, &ZERO2, &ZERO22), GF_OK);
    for (int t = 1; t <= 5; t++) {
        assert_int_equal(gf_kf2_predict_prepared(&b, &pcar, NULL), GF_OK);
        check_belief(&b, &ZERO2, &TABLE_1_1[t]);
    }
}

// Everything gf_kf2_predict/update refuse in a model, prepare refuses with
// the same status, and leaves the prepared struct untouched.
static void prepare_bad_input(void **state)
{
    (void)state;
    gf_kf2 kf;
    car_at_t5(&kf);
    const gf_vec2 z = {{5, 0}};
    gf_kf2_pmodel pm;
    gf_kf2_pmeas pq;
    memset(&pm, 0x5A, sizeof pm);
    memset(&pq, 0x5A, sizeof pq);
    const gf_real huge = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e200);

    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &pm, gf_kf2_prepare_model(NULL, &CAR));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &pm, gf_kf2_prepare_model(&pm, NULL));
    gf_kf2_model bad[6];
    for (int i = 0; i < 6; i++) {
        bad[i] = CAR;
    }
    bad[0].A.m[1][0] = (gf_real)NAN;
    bad[1].B.m[0][1] = (gf_real)INFINITY; // reaches no output without u
    bad[2].c.v[0] = (gf_real)-INFINITY;
    bad[3].R.m[0][0] = GF_R(-0.25);
    bad[4].R.m[1][0] = GF_R(0.6);                     // asymmetric
    bad[5].R.m[0][1] = bad[5].R.m[1][0] = GF_R(0.75); // indefinite
    const gf_status want_model[6] = {GF_ERR_NONFINITE, GF_ERR_NONFINITE,
                                     GF_ERR_NONFINITE, GF_ERR_NOT_PSD,
                                     GF_ERR_NOT_PSD,   GF_ERR_NOT_PSD};
    for (int i = 0; i < 6; i++) {
        gf_kf2 k2 = kf;
        CHECK_FAILS_UNCHANGED(want_model[i], &k2,
                              gf_kf2_predict(&k2, &bad[i], NULL));
        CHECK_FAILS_UNCHANGED(want_model[i], &pm,
                              gf_kf2_prepare_model(&pm, &bad[i]));
    }

    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &pq, gf_kf2_prepare_meas(NULL, &GPS));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &pq, gf_kf2_prepare_meas(&pq, NULL));
    gf_kf2_meas badq[10];
    for (int i = 0; i < 10; i++) {
        badq[i] = GPS;
    }
    badq[0].m = 0;
    badq[1].m = 3;
    badq[2].C.m[0][1] = (gf_real)NAN;
    badq[3].c.v[0] = (gf_real)INFINITY;
    badq[4].gate = (gf_real)NAN;
    badq[5].gate = GF_R(-1.0);
    badq[6].Q.m[0][0] = (gf_real)INFINITY;
    badq[7].Q.m[0][0] = GF_R(-10.0);
    badq[8].m = 2; // Q indefinite
    badq[8].C.m[1][1] = 1;
    badq[8].Q.m[0][1] = badq[8].Q.m[1][0] = 5;
    badq[8].Q.m[1][1] = 1;
    badq[9].C.m[0][0] = huge; // finite: prepares; S overflows in the step
    const gf_status want_meas[9] = {
        GF_ERR_ARG,       GF_ERR_ARG,       GF_ERR_NONFINITE,
        GF_ERR_NONFINITE, GF_ERR_NONFINITE, GF_ERR_ARG,
        GF_ERR_NONFINITE, GF_ERR_NOT_PSD,   GF_ERR_NOT_PSD};
    for (int i = 0; i < 9; i++) {
        gf_kf2 k2 = kf;
        CHECK_FAILS_UNCHANGED(want_meas[i], &k2,
                              gf_kf2_update(&k2, &badq[i], &z, NULL));
        CHECK_FAILS_UNCHANGED(want_meas[i], &pq,
                              gf_kf2_prepare_meas(&pq, &badq[i]));
    }
    assert_int_equal(gf_kf2_prepare_meas(&pq, &badq[9]), GF_OK);
    assert_int_equal(same_update(&kf, &badq[9], &z), GF_ERR_NONFINITE);
}

// What the prepared steps still check at every step (u, z, overflow, S,
// the NIS and its gate, NULL): the plain API's status, belief and info
// untouched (info written when gated), bit for bit the same.
static void prepared_failures(void **state)
{
    (void)state;
    gf_kf2 kf, known;
    car_at_t5(&kf);
    assert_int_equal(gf_kf2_init(&known, &ZERO2, &ZERO22), GF_OK);
    const gf_real huge = (gf_real)(sizeof(gf_real) == 4 ? 1e30 : 1e200);
    gf_kf2_pmodel pm;
    gf_kf2_pmeas pq;
    assert_int_equal(gf_kf2_prepare_model(&pm, &CAR), GF_OK);
    assert_int_equal(gf_kf2_prepare_meas(&pq, &GPS), GF_OK);
    const gf_vec2 z = {{5, 0}};

    // predict: NULL, u not finite, a finite model whose result overflows
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_predict_prepared(NULL, &pm, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_predict_prepared(&kf, NULL, NULL));
    gf_kf2_model m = CAR;
    m.B.m[0][0] = 1;
    const gf_vec2 u_nan = {{0, (gf_real)NAN}}, u_inf = {{(gf_real)INFINITY, 0}};
    same_predict(&kf, &m, &u_nan);
    same_predict(&kf, &m, &u_inf);
    assert_int_equal(gf_kf2_prepare_model(&pm, &m), GF_OK);
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_predict_prepared(&kf, &pm, &u_nan));
    m = CAR;
    m.A.m[0][0] = m.A.m[0][1] = huge;
    same_predict(&kf, &m, NULL);
    assert_int_equal(gf_kf2_prepare_model(&pm, &m), GF_OK);
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_predict_prepared(&kf, &pm, NULL));

    // update: NULL, z not finite, S = 0, gated, a NIS that overflows
    gf_innovation info = {0, {0, 0, 0}, 0};
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_update_prepared(NULL, &pq, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_update_prepared(&kf, NULL, &z, &info));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &kf,
                          gf_kf2_update_prepared(&kf, &pq, NULL, &info));
    const gf_vec2 z_inf = {{(gf_real)INFINITY, 0}}, z_nan = {{(gf_real)NAN, 0}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &kf,
                          gf_kf2_update_prepared(&kf, &pq, &z_inf, &info));
    assert_int_equal(info.m, 0); // info untouched
    assert_int_equal(same_update(&kf, &GPS, &z_nan), GF_ERR_NONFINITE);
    gf_kf2_meas q = GPS;
    q.Q.m[0][0] = 0; // known state, noiseless sensor: S = 0
    assert_int_equal(same_update(&known, &q, &z), GF_ERR_SINGULAR);
    q = GPS;
    q.gate = GF_R(3.84);
    const gf_vec2 far = {{50, 0}};
    assert_int_equal(same_update(&kf, &q, &far), GF_ERR_GATED);
    assert_int_equal(same_update(&kf, &q, &z), GF_OK);
    const gf_vec2 z_huge = {{huge, 0}}; // y^2 overflows: NIS = inf
    assert_int_equal(same_update(&kf, &GPS, &z_huge), GF_ERR_NONFINITE);
    // m = 2 through the prepared update: S singular, z not finite
    gf_kf2_meas two = {.m = 2,
                       .C = {{{1, 0}, {1, 0}}},
                       .Q = {{{0, 0}, {0, 0}}},
                       .c = {{0, 0}},
                       .gate = 0};
    assert_int_equal(same_update(&kf, &two, &z), GF_ERR_SINGULAR);
    two.Q.m[0][0] = two.Q.m[1][1] = 1;
    assert_int_equal(same_update(&kf, &two, &z_inf), GF_ERR_NONFINITE);
    assert_int_equal(same_update(&kf, &two, &z), GF_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(table_1_1),
        cmocka_unit_test(figure_1_2),
        cmocka_unit_test(table_2_1),
        cmocka_unit_test(exercise_5_constants),
        cmocka_unit_test(control_input),
        cmocka_unit_test(two_measurements),
        cmocka_unit_test(gate),
        cmocka_unit_test(bad_input),
        cmocka_unit_test(prepared_equals_plain),
        cmocka_unit_test(prepare_bad_input),
        cmocka_unit_test(prepared_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
