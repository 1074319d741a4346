// SPDX-License-Identifier: MIT
// UKF3: exact on linear models (where it must equal the Kalman filter, for
// any scaling), angle-aware across +-pi, and every bad input refused with
// the belief unchanged. Exercise 4 is in test_ex4.c.
#include "gf_test.h"

// UKF against EKF3 on models where both are exact: agreement to UKF_TOL
// (sums of seven weighted outer products against one sandwich).
#ifdef GF_SINGLE_PRECISION
#define UKF_TOL 1e-4
#else
#define UKF_TOL 1e-9
#endif
#define CHECK_UKF(got, want)                                                   \
    gf_check_close_((double)(got), (double)(want), UKF_TOL, #got, __FILE__,    \
                    __LINE__)

// A linear motion x' = A x + b, with its Jacobian A, for both filters.
static const gf_mat3 lin_A = {
    {{1, GF_R(0.5), 0}, {GF_R(-0.2), 1, GF_R(0.3)}, {GF_R(0.05), 0, 1}}};
static gf_status linear_motion(void *ctx, const gf_vec3 *mu, const gf_real *u,
                               gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)ctx;
    gf_mat3_mulv(&lin_A, mu, mu_bar);
    mu_bar->v[0] += u[0];
    mu_bar->v[1] += u[1];
    *G = lin_A;
    return GF_OK;
}

// Measures the heading alone (an angle, m = 1).
static gf_status meas_theta(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    (void)ctx;
    z_hat->v[0] = gf_angle_wrap(mu_bar->v[2]); // as a real sensor would
    H->m[0][0] = 0;
    H->m[0][1] = 0;
    H->m[0][2] = 1;
    return GF_OK;
}

// Exercise 4's motion, returning the heading wrapped as a real model might:
// sigma points near pi come back on both sides of the cut.
static gf_status wrapped_turn(void *ctx, const gf_vec3 *mu, const gf_real *u,
                              gf_vec3 *mu_bar, gf_mat3 *G)
{
    gf_status st = gf_ekf3_motion_forward_turn(ctx, mu, u, mu_bar, G);
    mu_bar->v[2] = gf_angle_wrap(mu_bar->v[2]);
    return st;
}

// A motion model that fails, with a status the filter does not know.
static gf_status broken_motion(void *ctx, const gf_vec3 *mu, const gf_real *u,
                               gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)ctx;
    (void)mu;
    (void)u;
    (void)mu_bar;
    (void)G;
    return (gf_status)42;
}

// A measurement model that returns NaN.
static gf_status nan_meas(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                          gf_mat3 *H)
{
    (void)ctx;
    (void)mu_bar;
    (void)H;
    z_hat->v[0] = (gf_real)NAN;
    return GF_OK;
}

// Measures x and counts its calls; fails (GF_ERR_MODEL) on call number
// fail_at (1-based; 0: never).
typedef struct counting {
    unsigned calls;
    unsigned fail_at;
} counting;
static gf_status counting_meas_x(void *ctx, const gf_vec3 *mu_bar,
                                 gf_vec3 *z_hat, gf_mat3 *H)
{
    counting *c = ctx;
    c->calls++;
    if (c->calls == c->fail_at) {
        return GF_ERR_MODEL;
    }
    return gf_ekf3_meas_x(NULL, mu_bar, z_hat, H);
}

static void check_same(const gf_ukf3 *ukf, const gf_ekf3 *ekf)
{
    const gf_mat3 ekf_sigma = gf_test_ekf3_sigma(ekf);
    for (int i = 0; i < 3; i++) {
        CHECK_UKF(ukf->mu.v[i], ekf->mu.v[i]);
        for (int j = 0; j < 3; j++) {
            CHECK_UKF(ukf->sigma.m[i][j], ekf_sigma.m[i][j]);
        }
    }
}

static const gf_vec3 mu_a = {{1, -2, GF_R(0.3)}};
static const gf_mat3 sig_a = {{{GF_R(0.5), GF_R(0.1), GF_R(0.02)},
                               {GF_R(0.1), GF_R(0.4), GF_R(-0.05)},
                               {GF_R(0.02), GF_R(-0.05), GF_R(0.1)}}};

// On a linear motion and a linear measurement the unscented transform is
// exact: the UKF is the Kalman filter, whatever alpha, beta, kappa.
static void test_linear_equals_kalman(void **state)
{
    (void)state;
    const gf_ukf3_params params[] = {
        {1, 2, 0}, {GF_R(0.5), 2, 1}, {GF_R(0.1), 0, 3}};
    const gf_ekf3_motion motion = {linear_motion,
                                   NULL,
                                   {{{GF_R(0.01), 0, 0},
                                     {0, GF_R(0.02), GF_R(0.005)},
                                     {0, GF_R(0.005), GF_R(0.01)}}}};
    const gf_ekf3_meas meas = {
        2,
        gf_ekf3_meas_xy,
        NULL,
        {{{GF_R(0.2), GF_R(0.05), 0}, {GF_R(0.05), GF_R(0.3), 0}, {0, 0, 0}}},
        0,
        0};
    const gf_real u[2] = {GF_R(0.4), GF_R(-0.1)};
    const gf_vec3 z = {{GF_R(1.2), GF_R(-2.5), 0}};
    for (unsigned k = 0; k < sizeof params / sizeof params[0]; k++) {
        gf_ukf3 ukf;
        gf_ekf3 ekf;
        gf_innovation iu, ie;
        assert_int_equal(gf_ukf3_init(&ukf, &mu_a, &sig_a, &params[k]), GF_OK);
        assert_int_equal(gf_ekf3_init(&ekf, &mu_a, &sig_a), GF_OK);
        for (int t = 0; t < 3; t++) {
            assert_int_equal(gf_ukf3_predict(&ukf, &motion, u), GF_OK);
            assert_int_equal(gf_ekf3_predict(&ekf, &motion, u), GF_OK);
            check_same(&ukf, &ekf);
            assert_int_equal(gf_ukf3_update(&ukf, &meas, &z, &iu), GF_OK);
            assert_int_equal(gf_ekf3_update(&ekf, &meas, &z, &ie), GF_OK);
            check_same(&ukf, &ekf);
            assert_int_equal(iu.m, 2u);
            CHECK_UKF(iu.y[0], ie.y[0]);
            CHECK_UKF(iu.y[1], ie.y[1]);
            CHECK_UKF(iu.nis, ie.nis);
        }
    }
}

// The weights of Table 3.4 for alpha = 0.5, beta = 2, kappa = 1, n = 3:
// n + lambda = 0.25 * 4 = 1, lambda = -2; what the centre's weights leave
// once folded in, beta - alpha^2 = 1.75.
static void test_weights(void **state)
{
    (void)state;
    const gf_ukf3_params p = {GF_R(0.5), 2, 1};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &mu_a, &sig_a, &p), GF_OK);
    CHECK_CLOSE(ukf.gamma, 1.0);
    CHECK_CLOSE(ukf.wi, 0.5);
    CHECK_CLOSE(ukf.wfold, 1.75);
}

// ---- small alpha ---------------------------------------------------------
//
// Exercise 4's motion (d forward along theta, then turn by phi) from
// mu = (1, 2, 0.5), Sigma = 0.01 I, u = (1, 0.3), R = 0: near-linear (the
// heading's sigma is 0.1 rad), where the EKF predicts
// (1.8776, 2.4794, 0.8), diag (0.0123, 0.0177, 0.01).
// |got - want| <= tol, absolute (the bounds below carry their own scale).
#define check_abs(got, want, tol, what)                                        \
    check_abs_((got), (want), (tol), (what), __FILE__, __LINE__)
static void check_abs_(double got, double want, double tol, const char *what,
                       const char *file, int line)
{
    if (!(fabs(got - want) <= tol)) {
        print_error("%s: got %.17g, want %.17g (tol %g)\n", what, got, want,
                    tol);
        _fail(file, line);
    }
}

static const gf_vec3 sa_mu = {{1, 2, GF_R(0.5)}};
static const gf_mat3 sa_sig = {
    {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, GF_R(0.01)}}};
static const gf_real sa_u[2] = {1, GF_R(0.3)};
static const gf_ekf3_motion sa_move = {
    gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};

// The unscented transform of Table 3.4 in exact arithmetic, for this
// motion and a diagonal Sigma = s I (kappa = 0), in long double and in a
// form with nothing to cancel. The points are mu +- h e_k, h^2 = 3 alpha^2 s,
// w_i = 1 / (6 alpha^2); only the two heading points move off the line:
// cos(th +- h) - cos th = -+2 sin(th +- h/2) sin(h/2), likewise for sin,
// so with s2 = sin(h/2), about the centre's image:
//   m = -(4 d s2^2 w_i) (cos th, sin th, 0),  mu_bar = g(mu) + m,
//   Sigma_bar = sum_{i>0} w_i e_i e_i^T + (beta - alpha^2) m m^T
// (the book's sums, exactly: see ukf3.h).
typedef struct exact_ut {
    long double mu[3];
    long double sig[3][3];
} exact_ut;

static exact_ut exact_turn(long double alpha, long double beta)
{
    const long double x = 1, y = 2, th = 0.5L, s = 0.01L, d = 1, phi = 0.3L;
    const long double h = sqrtl(3 * alpha * alpha * s);
    const long double wi = 1 / (6 * alpha * alpha);
    const long double s2 = sinl(h / 2);
    const long double sp = sinl(th + h / 2), sm = sinl(th - h / 2);
    const long double cp = cosl(th + h / 2), cm = cosl(th - h / 2);
    const long double m[3] = {-4 * d * s2 * s2 * wi * cosl(th),
                              -4 * d * s2 * s2 * wi * sinl(th), 0};
    const long double f = beta - alpha * alpha;
    exact_ut r;
    r.mu[0] = x + d * cosl(th) + m[0];
    r.mu[1] = y + d * sinl(th) + m[1];
    r.mu[2] = th + phi;
    // the position points: e = (+-h, 0, 0) and (0, +-h, 0)
    r.sig[0][0] =
        2 * wi * h * h + wi * 4 * d * d * s2 * s2 * (sp * sp + sm * sm);
    r.sig[1][1] =
        2 * wi * h * h + wi * 4 * d * d * s2 * s2 * (cp * cp + cm * cm);
    r.sig[2][2] = 2 * wi * h * h;
    r.sig[0][1] = -wi * 4 * d * d * s2 * s2 * (sp * cp + sm * cm);
    r.sig[0][2] = -wi * 4 * d * h * s2 * sinl(th) * cosl(h / 2);
    r.sig[1][2] = wi * 4 * d * h * s2 * cosl(th) * cosl(h / 2);
    for (int a = 0; a < 3; a++) {
        for (int b = a; b < 3; b++) {
            r.sig[a][b] += f * m[a] * m[b];
            r.sig[b][a] = r.sig[a][b];
        }
    }
    return r;
}

// The rounding the sums cannot avoid (ukf3.h): the images' own, u |g| with
// |g| <= 3 here, divided by alpha^2 in the mean, by alpha sigma (sigma =
// 0.1) in the covariance's first-order sum, plus a few ulps of the entries
// themselves. Measured: under a twentieth of these bounds, float and double.
#ifdef GF_SINGLE_PRECISION
#define SA_U 5.96e-8
#else
#define SA_U 1.11e-16
#endif
static double sa_tol_mu(double alpha)
{
    return 16 * SA_U * 3 / (alpha * alpha) + 16 * SA_U * 3;
}
static double sa_tol_sig(double alpha)
{
    return 16 * SA_U * 3 * 0.1 / alpha + 16 * SA_U * 0.02 +
           2 * sa_tol_mu(alpha) * 0.01;
}

// From alpha = 1 down to GF_UKF3_ALPHA_MIN, every accepted alpha predicts
// the exact transform within the rounding above, and the EKF within what
// separates them on this near-linear step: the heading's curvature,
// d sigma_th^2 / 2 = 0.005 in the mean, 1e-4 in Sigma (1% of its entries).
static void test_small_alpha_predict(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &sa_mu, &sa_sig), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &sa_move, sa_u), GF_OK);
    const gf_mat3 ekf_sigma = gf_test_ekf3_sigma(&ekf);
    double worst_mu = 0, worst_sig = 0;
    for (double alpha = 1; alpha >= (double)GF_UKF3_ALPHA_MIN; alpha *= 0.5) {
        const gf_ukf3_params p = {(gf_real)alpha, 2, 0};
        gf_ukf3 ukf;
        assert_int_equal(gf_ukf3_init(&ukf, &sa_mu, &sa_sig, &p), GF_OK);
        assert_int_equal(gf_ukf3_predict(&ukf, &sa_move, sa_u), GF_OK);
        const exact_ut ex = exact_turn((long double)p.alpha, 2);
        for (int a = 0; a < 3; a++) {
            const double em = fabs((double)ukf.mu.v[a] - (double)ex.mu[a]);
            worst_mu = em / sa_tol_mu(alpha) > worst_mu ? em / sa_tol_mu(alpha)
                                                        : worst_mu;
            check_abs((double)ukf.mu.v[a], (double)ex.mu[a], sa_tol_mu(alpha),
                      "mu_bar vs exact UT");
            check_abs((double)ukf.mu.v[a], (double)ekf.mu.v[a], 0.01,
                      "mu_bar vs EKF");
            for (int b = 0; b < 3; b++) {
                const double es =
                    fabs((double)ukf.sigma.m[a][b] - (double)ex.sig[a][b]);
                worst_sig = es / sa_tol_sig(alpha) > worst_sig
                                ? es / sa_tol_sig(alpha)
                                : worst_sig;
                check_abs((double)ukf.sigma.m[a][b], (double)ex.sig[a][b],
                          sa_tol_sig(alpha), "Sigma_bar vs exact UT");
                check_abs((double)ukf.sigma.m[a][b], (double)ekf_sigma.m[a][b],
                          1e-4, "Sigma_bar vs EKF");
            }
        }
    }
    print_message("  small alpha: worst error / bound: mu %.3f, Sigma %.3f\n",
                  worst_mu, worst_sig);
}

// The update at every accepted alpha, after the prediction above, with
// (x, y) measured: against the EKF's Joseph update from the same predicted
// belief (exact for a linear h: the UKF's only difference is the
// rounding), within the same bounds.
static void test_small_alpha_update(void **state)
{
    (void)state;
    const gf_ekf3_meas xy = {
        2,
        gf_ekf3_meas_xy,
        NULL,
        {{{GF_R(0.02), GF_R(0.005), 0}, {GF_R(0.005), GF_R(0.03), 0}, {0, 0, 0}}},
        0,
        0};
    const gf_vec3 z = {{GF_R(1.8), GF_R(2.6), 0}};
    for (double alpha = 1; alpha >= (double)GF_UKF3_ALPHA_MIN; alpha *= 0.5) {
        const gf_ukf3_params p = {(gf_real)alpha, 2, 0};
        gf_ukf3 ukf;
        gf_ekf3 ekf;
        gf_innovation iu, ie;
        assert_int_equal(gf_ukf3_init(&ukf, &sa_mu, &sa_sig, &p), GF_OK);
        assert_int_equal(gf_ukf3_predict(&ukf, &sa_move, sa_u), GF_OK);
        assert_int_equal(gf_ekf3_init(&ekf, &ukf.mu, &ukf.sigma), GF_OK);
        assert_int_equal(gf_ukf3_update(&ukf, &xy, &z, &iu), GF_OK);
        assert_int_equal(gf_ekf3_update(&ekf, &xy, &z, &ie), GF_OK);
        const gf_mat3 ekf_sigma = gf_test_ekf3_sigma(&ekf);
        for (int a = 0; a < 3; a++) {
            check_abs((double)ukf.mu.v[a], (double)ekf.mu.v[a],
                      sa_tol_mu(alpha), "mu vs EKF");
            for (int b = 0; b < 3; b++) {
                check_abs((double)ukf.sigma.m[a][b], (double)ekf_sigma.m[a][b],
                          sa_tol_sig(alpha), "Sigma vs EKF");
            }
        }
        check_abs((double)iu.nis, (double)ie.nis, 100 * sa_tol_mu(alpha),
                  "NIS vs EKF");
    }
}

// Below the floor init refuses alpha, the belief untouched: among them the
// reproducers that returned GF_OK with a wrong covariance (float 3e-6:
// diagonal (0.011, 5e10, 8192); 1e-9: Sigma_bar = 0; double 1e-8:
// sigma_xx 0.5 where the exact transform gives 0.0123).
static void test_small_alpha_refused(void **state)
{
    (void)state;
    const gf_ukf3_params ok = {1, 2, 0};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &sa_mu, &sa_sig, &ok), GF_OK);
    const gf_real below[] = {GF_UKF3_ALPHA_MIN * (1 - GF_REAL_EPSILON),
                             GF_R(1e-3),
                             GF_R(3e-6),
                             GF_R(1e-8),
                             GF_R(1e-9),
                             GF_R(1e-30),
                             GF_REAL_EPSILON * GF_R(1e-30)};
    for (unsigned k = 0; k < sizeof below / sizeof below[0]; k++) {
        if (below[k] >= GF_UKF3_ALPHA_MIN) {
            continue; // 1e-3 in double: accepted (the predict test covers it)
        }
        const gf_ukf3_params p = {below[k], 2, 0};
        CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                              gf_ukf3_init(&ukf, &sa_mu, &sa_sig, &p));
    }
    const gf_ukf3_params at = {GF_UKF3_ALPHA_MIN, 2, 0};
    assert_int_equal(gf_ukf3_init(&ukf, &sa_mu, &sa_sig, &at), GF_OK);
}

// Far from the origin the images' rounding grows with |g| / sigma: at
// mu = (1e4, 2e4) with sigma 0.1, alpha at the floor would put Sigma_bar
// 12 times off in float and the mean 3 sigma off. Predict and update
// refuse that with GF_ERR_UNDEFINED, the belief untouched; a larger alpha
// is accepted there and agrees with the exact transform (translated: the
// motion does not depend on the position).
static void test_small_alpha_far(void **state)
{
    (void)state;
#ifdef GF_SINGLE_PRECISION
    const gf_real far = GF_R(1e4), ok_alpha = 1;
    const double tol_mu = 2e-3, tol_sig = 2e-4;
#else
    const gf_real far = GF_R(1e5), ok_alpha = GF_R(1e-4);
    const double tol_mu = 2e-3, tol_sig = 2e-4;
#endif
    const gf_vec3 mu = {{far, 2 * far, GF_R(0.5)}};
    const gf_ukf3_params at_floor = {GF_UKF3_ALPHA_MIN, 2, 0};
    const gf_ukf3_params wide = {ok_alpha, 2, 0};
    const gf_ekf3_meas xy = {
        2,    gf_ekf3_meas_xy,
        NULL, {{{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, 0}}},
        0,    0};
    const gf_vec3 z = {{far, 2 * far, 0}};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &mu, &sa_sig, &at_floor), GF_OK);
    CHECK_FAILS_UNCHANGED(GF_ERR_UNDEFINED, &ukf,
                          gf_ukf3_predict(&ukf, &sa_move, sa_u));
    CHECK_FAILS_UNCHANGED(GF_ERR_UNDEFINED, &ukf,
                          gf_ukf3_update(&ukf, &xy, &z, NULL));

    assert_int_equal(gf_ukf3_init(&ukf, &mu, &sa_sig, &wide), GF_OK);
    assert_int_equal(gf_ukf3_predict(&ukf, &sa_move, sa_u), GF_OK);
    const exact_ut ex = exact_turn((long double)wide.alpha, 2);
    const double shift[3] = {(double)far - 1, 2 * (double)far - 2, 0};
    for (int a = 0; a < 3; a++) {
        check_abs((double)ukf.mu.v[a], (double)ex.mu[a] + shift[a], tol_mu,
                  "far mu_bar vs exact UT");
        for (int b = 0; b < 3; b++) {
            check_abs((double)ukf.sigma.m[a][b], (double)ex.sig[a][b], tol_sig,
                      "far Sigma_bar vs exact UT");
        }
    }
    assert_int_equal(gf_ukf3_update(&ukf, &xy, &z, NULL), GF_OK);
}

// Heading near pi: the sigma points straddle +-pi. The heading's mean and
// variance must be those of theta' = theta + phi (linear in theta), as in
// the EKF, not an average of +3 and -3.
static void test_heading_across_pi(void **state)
{
    (void)state;
    const gf_vec3 mu = {{0, 0, GF_PI - GF_R(0.05)}};
    const gf_mat3 sig = {
        {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, GF_R(0.04)}}};
    const gf_ekf3_motion turn = {
        wrapped_turn,
        NULL,
        {{{GF_R(0.001), 0, 0}, {0, GF_R(0.001), 0}, {0, 0, GF_R(0.002)}}}};
    const gf_real u[2] = {GF_R(0.5), GF_R(0.1)};
    const gf_ukf3_params p = {1, 2, 0};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &mu, &sig, &p), GF_OK);
    assert_int_equal(gf_ukf3_predict(&ukf, &turn, u), GF_OK);
    CHECK_UKF(ukf.mu.v[2], -GF_PI + GF_R(0.05)); // pi + 0.05, wrapped
    CHECK_UKF(ukf.sigma.m[2][2], 0.04 + 0.002);
    assert_true(ukf.mu.v[0] < GF_R(-0.45)); // moved along heading ~pi

    // Observe the heading at -pi + 0.02 (so 0.03 from the mean, across the
    // cut): the linear measurement of an angle, where UKF and EKF agree.
    const gf_ekf3_meas head = {
        1,  meas_theta, NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
        1u, 0};
    const gf_vec3 z = {{-GF_PI + GF_R(0.02), 0, 0}};
    gf_ekf3 ekf;
    gf_innovation iu, ie;
    assert_int_equal(gf_ekf3_init(&ekf, &ukf.mu, &ukf.sigma), GF_OK);
    assert_int_equal(gf_ukf3_update(&ukf, &head, &z, &iu), GF_OK);
    assert_int_equal(gf_ekf3_update(&ekf, &head, &z, &ie), GF_OK);
    CHECK_UKF(iu.y[0], -0.03);
    CHECK_UKF(iu.nis, ie.nis);
    check_same(&ukf, &ekf);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    const gf_ukf3_params p = {1, 2, 0};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &mu_a, &sig_a, &p), GF_OK);

    // init
    gf_ukf3_params bp = p;
    gf_vec3 nanv = mu_a;
    nanv.v[1] = (gf_real)NAN;
    gf_mat3 indef = sig_a;
    indef.m[2][2] = -1;
    assert_int_equal(gf_ukf3_init(NULL, &mu_a, &sig_a, &p), GF_ERR_ARG);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, NULL, &sig_a, &p));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, NULL, &p));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_init(&ukf, &nanv, &sig_a, &p));
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &indef, &p));
    bp.alpha = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, &bp));
    bp.alpha = GF_R(1.5);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, &bp));
    bp = p;
    bp.beta = -1;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, &bp));
    bp = p;
    bp.kappa = -1;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, &bp));
    bp.kappa = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_init(&ukf, &mu_a, &sig_a, &bp));

    // predict
    const gf_real u[2] = {1, 0};
    gf_ekf3_motion mo = {
        gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
    assert_int_equal(gf_ukf3_predict(NULL, &mo, u), GF_ERR_ARG);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf, gf_ukf3_predict(&ukf, NULL, u));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf, gf_ukf3_predict(&ukf, &mo, NULL));
    mo.R.m[0][0] = -1;
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ukf, gf_ukf3_predict(&ukf, &mo, u));
    mo.R.m[0][0] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_predict(&ukf, &mo, u));
    mo.R.m[0][0] = 0;
    // A step so long that its square overflows in the covariance.
#ifdef GF_SINGLE_PRECISION
    const gf_real huge = GF_R(1e30);
#else
    const gf_real huge = 1e200;
#endif
    const gf_real big[2] = {huge, 0};
    gf_ukf3 far = ukf;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &far,
                          gf_ukf3_predict(&far, &mo, big));
    mo.g = NULL;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf, gf_ukf3_predict(&ukf, &mo, u));
    mo.g = broken_motion;
    CHECK_FAILS_UNCHANGED(GF_ERR_MODEL, &ukf, gf_ukf3_predict(&ukf, &mo, u));

    // update
    gf_ekf3_meas me = {1,    gf_ekf3_meas_x,
                       NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                       0,    0};
    const gf_vec3 z = {{5, 0, 0}};
    gf_vec3 zn = z;
    zn.v[0] = (gf_real)NAN;
    gf_innovation info;
    memset(&info, 0x77, sizeof info);
    assert_int_equal(gf_ukf3_update(NULL, &me, &z, NULL), GF_ERR_ARG);
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, NULL, &z, NULL));
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, &me, NULL, NULL));
    me.m = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.m = 4;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.m = 1;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_update(&ukf, &me, &zn, NULL));
    me.gate = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.gate = -1;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.gate = 0;
    me.Q.m[0][0] = -1;
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.Q.m[0][0] = GF_R(0.01);
    me.h = NULL;
    CHECK_FAILS_UNCHANGED(GF_ERR_ARG, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    me.h = nan_meas;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, NULL));
    // S singular: the state known exactly and a noiseless measurement.
    gf_ukf3 exact;
    const gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    assert_int_equal(gf_ukf3_init(&exact, &mu_a, &zero, &p), GF_OK);
    me.h = gf_ekf3_meas_x;
    me.Q.m[0][0] = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &exact,
                          gf_ukf3_update(&exact, &me, &z, &info));
    // Gated: z = 5 against x = 1 with S = 0.51: NIS = 16 / 0.51 > 9.
    me.Q.m[0][0] = GF_R(0.01);
    me.gate = 9;
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &ukf,
                          gf_ukf3_update(&ukf, &me, &z, &info));
    CHECK_UKF(info.y[0], 4.0);
    CHECK_UKF(info.nis, 16 / 0.51);
}

// The update calls h once per sigma point: 7 calls; a failure at any of
// them, the last included, leaves the belief and info untouched. The
// result does not depend on the counting.
static void test_update_calls(void **state)
{
    (void)state;
    const gf_ukf3_params p = {1, 2, 0};
    counting c = {0, 0};
    gf_ekf3_meas me = {1,  counting_meas_x,
                       &c, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
                       0,  0};
    const gf_ekf3_meas plain = {
        1,    gf_ekf3_meas_x,
        NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
        0,    0};
    const gf_vec3 z = {{GF_R(1.3), 0, 0}};
    gf_ukf3 ukf, ref;
    gf_innovation info, info_ref;
    assert_int_equal(gf_ukf3_init(&ukf, &mu_a, &sig_a, &p), GF_OK);
    ref = ukf;
    assert_int_equal(gf_ukf3_update(&ukf, &me, &z, &info), GF_OK);
    assert_int_equal(c.calls, 7u);
    assert_int_equal(gf_ukf3_update(&ref, &plain, &z, &info_ref), GF_OK);
    assert_memory_equal(&ukf, &ref, sizeof ukf); // gf_reals only
    assert_int_equal(info.m, info_ref.m);
    assert_memory_equal(info.y, info_ref.y, sizeof info.y);
    assert_memory_equal(&info.nis, &info_ref.nis, sizeof info.nis);
    for (unsigned fail = 1; fail <= 7u; fail++) {
        gf_ukf3 f;
        assert_int_equal(gf_ukf3_init(&f, &mu_a, &sig_a, &p), GF_OK);
        unsigned char untouched[sizeof info];
        memset(&info, 0x5a, sizeof info);
        memcpy(untouched, &info, sizeof info);
        c.calls = 0;
        c.fail_at = fail;
        CHECK_FAILS_UNCHANGED(GF_ERR_MODEL, &f,
                              gf_ukf3_update(&f, &me, &z, &info));
        assert_int_equal(c.calls, fail);
        assert_memory_equal(&info, untouched, sizeof info);
    }
}

// Every sigma point's call of g gets mu_bar = its point and G = I.
static void test_motion_args(void **state)
{
    (void)state;
    unsigned broken = 0;
    const gf_test_args a = gf_test_args_make(&broken);
    const gf_ukf3_params p = {1, 2, 0};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &a.mu, &a.sig, &p), GF_OK);
    assert_int_equal(gf_ukf3_predict(&ukf, &a.mo, a.u), GF_OK);
    assert_int_equal(broken, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_equals_kalman),
        cmocka_unit_test(test_weights),
        cmocka_unit_test(test_small_alpha_predict),
        cmocka_unit_test(test_small_alpha_update),
        cmocka_unit_test(test_small_alpha_refused),
        cmocka_unit_test(test_small_alpha_far),
        cmocka_unit_test(test_heading_across_pi),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_update_calls),
        cmocka_unit_test(test_motion_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
