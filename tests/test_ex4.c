// Exercise 4 three ways: the robot at the origin, heading unknown
// (variance 10000), moves 1 forward, then observes x = -0.7 (variance
// 0.01). It must be near (-0.7, +0.714) or (-0.7, -0.714).
//
//   EKF3: linearizes at heading 0 and stays at (1, 0), then (0.15, 0, 0)
//         (Tables 4.1 and 4.2): the seed's failure.
//   UKF3: pushes sigma points through the motion; its predicted mean lies
//         inside the unit circle, but it is still one Gaussian.
//   PF3:  the particles after z = -0.7 have two modes, near
//         (-0.7, +-0.714).
#include "gf_test.h"

#define N_PARTICLES 4000 // chosen at compile time, the array is ours
#define SEED 4u

static gf_pf3_particle particles[N_PARTICLES];

static const gf_vec3 mu0 = {{0, 0, 0}};
static const gf_mat3 sigma0 = {{{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0},
                                {0, 0, 10000}}};
static const gf_ekf3_motion move = {
    gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
static const gf_ekf3_meas observe_x = {
    1, gf_ekf3_meas_x, NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}},
    0, 0};
static const gf_real u[2] = {1, 0}; // 1 forward, no turn
static const gf_vec3 z = {{GF_R(-0.7), 0, 0}};

// The two places the robot can be: x = -0.7 on the unit circle.
#define MODE_X (-0.7)
#define MODE_Y 0.71414284285428498 // sqrt(1 - 0.49)

static void test_ekf(void **state)
{
    (void)state;
    gf_ekf3 ekf;
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &sigma0), GF_OK);
    assert_int_equal(gf_ekf3_predict(&ekf, &move, u), GF_OK);
    CHECK_CLOSE(ekf.mu.v[0], 1.0); // Table 4.1: predicted at (1, 0)
    CHECK_CLOSE(ekf.mu.v[1], 0.0);
    assert_int_equal(gf_ekf3_update(&ekf, &observe_x, &z, NULL), GF_OK);
    // Table 4.2: (0.15, 0, 0): halfway between 1 and -0.7, on neither mode
    CHECK_CLOSE(ekf.mu.v[0], 0.15);
    CHECK_CLOSE(ekf.mu.v[1], 0.0);
    CHECK_CLOSE(ekf.mu.v[2], 0.0);
    CHECK_CLOSE(ekf.sigma.m[0][0], 0.005);
}

// alpha = 1, beta = 2, kappa = 0: gamma = sqrt(3), the centre weighs 0 in
// the mean and the six others 1/6. Four of them keep heading 0 and land at
// x = 1 +- 0.1 sqrt(3) and x = 1; the two heading ones, at theta =
// +-100 sqrt(3) rad, land at (cos a, +-sin a), a = 100 sqrt(3). So
// mu_bar = ((4 + 2 cos a) / 6, 0, 0), about (0.362, 0, 0).
static void test_ukf(void **state)
{
    (void)state;
    const gf_ukf3_params p = {1, 2, 0};
    gf_ukf3 ukf;
    assert_int_equal(gf_ukf3_init(&ukf, &mu0, &sigma0, &p), GF_OK);
    assert_int_equal(gf_ukf3_predict(&ukf, &move, u), GF_OK);
    const double a = 100 * sqrt(3.0);
    CHECK_CLOSE(ukf.mu.v[0], (4 + 2 * cos(a)) / 6);
    CHECK_CLOSE(ukf.mu.v[1], 0.0);
    CHECK_CLOSE(ukf.mu.v[2], 0.0);
    const double r = hypot((double)ukf.mu.v[0], (double)ukf.mu.v[1]);
    print_message("  UKF predicted mean (%.4f, %.4f), %.3f from the "
                  "origin\n", (double)ukf.mu.v[0], (double)ukf.mu.v[1], r);
    assert_true(r < 0.5);                             // inside the circle
    assert_true(fabs((double)ukf.mu.v[0] - 1) > 0.5); // not the EKF's (1, 0)
    // and the position spread is not all in y, as the EKF's is
    assert_true(ukf.sigma.m[0][0] > GF_R(1.0));

    assert_int_equal(gf_ukf3_update(&ukf, &observe_x, &z, NULL), GF_OK);
    print_message("  UKF after z = -0.7: (%.4f, %.4f, %.4f)\n",
                  (double)ukf.mu.v[0], (double)ukf.mu.v[1],
                  (double)ukf.mu.v[2]);
    // One Gaussian all the same: it goes to x = -0.7, and stays at y = 0.
    assert_true(fabs((double)ukf.mu.v[0] - MODE_X) < 0.02);
    assert_true(fabs((double)ukf.mu.v[1]) < 0.01);
}

// Weighted kernel density of the particles' (x, y), Gaussian kernel of
// width h, at (x, y).
static double density(const gf_pf3 *pf, double x, double y, double h)
{
    double d = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        double dx = (double)pf->p[k].x.v[0] - x;
        double dy = (double)pf->p[k].x.v[1] - y;
        d += (double)pf->p[k].w * exp(-0.5 * (dx * dx + dy * dy) / (h * h));
    }
    return d;
}

// The mode of the particles in the half plane sign * y > 0: the peak of
// their kernel density (width 0.05), found on a 0.05 grid over
// x in [-1.5, 1.5], |y| in [0, 1.5], then refined on a 0.01 grid around it.
static void mode(const gf_pf3 *pf, double sign, double *mx, double *my)
{
    double best = -1, cx = 0, cy = 0;
    for (int i = 0; i <= 60; i++) {
        for (int j = 0; j <= 30; j++) {
            double x = -1.5 + 0.05 * i, y = sign * 0.05 * j;
            double d = density(pf, x, y, 0.05);
            if (d > best) {
                best = d;
                cx = x;
                cy = y;
            }
        }
    }
    *mx = cx;
    *my = cy;
    for (int i = -5; i <= 5; i++) {
        for (int j = -5; j <= 5; j++) {
            double x = cx + 0.01 * i, y = cy + 0.01 * j;
            double d = density(pf, x, y, 0.05);
            if (d > best) {
                best = d;
                *mx = x;
                *my = y;
            }
        }
    }
}

// Weight in the half plane sign * y > 0.
static double mass(const gf_pf3 *pf, double sign)
{
    double w = 0;
    for (unsigned k = 0; k < pf->n; k++) {
        w += sign * (double)pf->p[k].x.v[1] > 0 ? (double)pf->p[k].w : 0;
    }
    return w;
}

static void check_two_modes(const gf_pf3 *pf, const char *when)
{
    double xp = 0, yp = 0, xn = 0, yn = 0;
    mode(pf, 1, &xp, &yp);
    mode(pf, -1, &xn, &yn);
    print_message("  PF %s: modes (%.2f, %.2f) and (%.2f, %.2f), masses "
                  "%.3f and %.3f\n", when, xp, yp, xn, yn, mass(pf, 1),
                  mass(pf, -1));
    // Each mode within 0.1 of its place (the density's grid is 0.01, its
    // kernel 0.05; the ring the particles lie on is 0.1 wide).
    assert_true(hypot(xp - MODE_X, yp - MODE_Y) < 0.1);
    assert_true(hypot(xn - MODE_X, yn + MODE_Y) < 0.1);
    // Both carry about half the belief (symmetric problem; the split
    // fluctuates with the ~400 effective particles).
    assert_true(fabs(mass(pf, 1) - 0.5) < 0.1);
    assert_true(fabs(mass(pf, -1) - 0.5) < 0.1);
    // Nothing is left near the EKF's (0.15, 0) or the predicted (1, 0).
    assert_true(density(pf, 0.15, 0, 0.05) < 0.01 * density(pf, xp, yp, 0.05));
    assert_true(density(pf, 1, 0, 0.05) < 0.01 * density(pf, xp, yp, 0.05));
}

static void test_pf(void **state)
{
    (void)state;
    gf_pf3 pf;
    assert_int_equal(gf_pf3_init(&pf, particles, N_PARTICLES, SEED, &mu0,
                                 &sigma0), GF_OK);
    assert_int_equal(gf_pf3_predict(&pf, &move, u), GF_OK);
    // Predicted: a ring, every particle about 1 from the origin.
    double r_mean = 0;
    for (unsigned k = 0; k < pf.n; k++) {
        r_mean += hypot((double)particles[k].x.v[0],
                        (double)particles[k].x.v[1]) / N_PARTICLES;
    }
    assert_true(fabs(r_mean - 1) < 0.02);

    assert_int_equal(gf_pf3_update(&pf, &observe_x, &z), GF_OK);
    gf_real neff;
    assert_int_equal(gf_pf3_neff(&pf, &neff), GF_OK);
    print_message("  PF effective sample size after z: %.0f of %d\n",
                  (double)neff, N_PARTICLES);
    check_two_modes(&pf, "weighted");
    assert_int_equal(gf_pf3_resample(&pf), GF_OK);
    check_two_modes(&pf, "resampled");

    // The Gaussian summary of this belief sits between the modes, at
    // y ~ 0, where no particle is: the mean is not the belief.
    gf_vec3 m;
    assert_int_equal(gf_pf3_estimate(&pf, &m, NULL), GF_OK);
    assert_true(fabs((double)m.v[1]) < 0.15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ekf),
        cmocka_unit_test(test_ukf),
        cmocka_unit_test(test_pf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
