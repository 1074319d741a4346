// SPDX-License-Identifier: MIT
// Exercise 4 (docs/exercises.md) three ways: the robot at the origin, heading
// unknown (variance 10000), moves 1 forward, then observes x = -0.7 (variance
// 0.01). It must be near (-0.7, +0.714) or (-0.7, -0.714).
//
//   EKF3: linearizes at heading 0 and stays at (1, 0), then (0.15, 0, 0)
//         (Tables 4.1 and 4.2): the failure docs/exercises.md shows.
//   UKF3: pushes sigma points through the motion; its predicted mean lies
//         inside the unit circle, but it is still one Gaussian.
//   PF3:  the particles after z = -0.7 have two modes, near
//         (-0.7, +-0.714).
#include "gf_test.h"

#define N_PARTICLES 4000 // chosen at compile time, the array is ours
#define SEED 4u

static gf_pf3_particle particles[N_PARTICLES];

static const gf_vec3 mu0 = {{0, 0, 0}};
static const gf_mat3 sigma0 = {
    {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, 10000}}};
static const gf_ekf3_motion move = {
    gf_ekf3_motion_forward_turn, NULL, {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}};
static const gf_ekf3_meas observe_x = {
    1, gf_ekf3_meas_x, NULL, {{{GF_R(0.01), 0, 0}, {0, 0, 0}, {0, 0, 0}}}, 0,
    0};
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
    const gf_mat3 sigma = gf_test_ekf3_sigma(&ekf);
    CHECK_CLOSE(sigma.m[0][0], 0.005);
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
                  "origin\n",
                  (double)ukf.mu.v[0], (double)ukf.mu.v[1], r);
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

// The particles' weighted kernel density of (x, y): a histogram of 0.01
// cells over [-1.5, 1.5)^2 smoothed by a Gaussian kernel of width 0.05
// (5 cells, cut at 3 widths), separably. Linear in the particle count, so
// it runs in seconds on an emulated Cortex-M4F too.
#define GRID 300
#define CELL 0.01
#define KW 5
static double dens[GRID][GRID], pass1[GRID][GRID];

static int cell(double v)
{
    return (int)floor((v + 1.5) / CELL);
}

static void density_map(const gf_pf3 *pf)
{
    double k[6 * KW + 1];
    for (int d = -3 * KW; d <= 3 * KW; d++) {
        k[d + 3 * KW] = exp(-0.5 * (double)(d * d) / (KW * KW));
    }
    memset(dens, 0, sizeof dens);
    for (unsigned i = 0; i < pf->n; i++) {
        int cx = cell((double)pf->p[i].x.v[0]);
        int cy = cell((double)pf->p[i].x.v[1]);
        if (cx >= 0 && cx < GRID && cy >= 0 && cy < GRID) {
            dens[cx][cy] += (double)pf->p[i].w;
        }
    }
    for (int x = 0; x < GRID; x++) { // along y
        for (int y = 0; y < GRID; y++) {
            double a = 0;
            for (int d = -3 * KW; d <= 3 * KW; d++) {
                if (y + d >= 0 && y + d < GRID) {
                    a += k[d + 3 * KW] * dens[x][y + d];
                }
            }
            pass1[x][y] = a;
        }
    }
    for (int x = 0; x < GRID; x++) { // along x
        for (int y = 0; y < GRID; y++) {
            double a = 0;
            for (int d = -3 * KW; d <= 3 * KW; d++) {
                if (x + d >= 0 && x + d < GRID) {
                    a += k[d + 3 * KW] * pass1[x + d][y];
                }
            }
            dens[x][y] = a;
        }
    }
}

// The smoothed density at (x, y), from density_map().
static double density(double x, double y)
{
    return dens[cell(x)][cell(y)];
}

// The mode in the half plane sign * y > 0: the centre of the densest cell.
static void mode(double sign, double *mx, double *my)
{
    double best = -1;
    for (int x = 0; x < GRID; x++) {
        for (int y = 0; y < GRID; y++) {
            double cy = -1.5 + CELL * (y + 0.5);
            if (sign * cy > 0 && dens[x][y] > best) {
                best = dens[x][y];
                *mx = -1.5 + CELL * (x + 0.5);
                *my = cy;
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
    density_map(pf);
    mode(1, &xp, &yp);
    mode(-1, &xn, &yn);
    print_message("  PF %s: modes (%.2f, %.2f) and (%.2f, %.2f), masses "
                  "%.3f and %.3f\n",
                  when, xp, yp, xn, yn, mass(pf, 1), mass(pf, -1));
    // Each mode within 0.1 of its place (the density's cells are 0.01, its
    // kernel 0.05; the ring the particles lie on is 0.1 wide).
    assert_true(hypot(xp - MODE_X, yp - MODE_Y) < 0.1);
    assert_true(hypot(xn - MODE_X, yn + MODE_Y) < 0.1);
    // Both carry about half the belief (symmetric problem; the split
    // fluctuates with the ~400 effective particles).
    assert_true(fabs(mass(pf, 1) - 0.5) < 0.1);
    assert_true(fabs(mass(pf, -1) - 0.5) < 0.1);
    // Nothing is left near the EKF's (0.15, 0) or the predicted (1, 0).
    assert_true(density(0.15, 0) < 0.01 * density(xp, yp));
    assert_true(density(1, 0) < 0.01 * density(xp, yp));
}

static void test_pf(void **state)
{
    (void)state;
    gf_pf3 pf;
    assert_int_equal(
        gf_pf3_init(&pf, particles, N_PARTICLES, SEED, &mu0, &sigma0), GF_OK);
    assert_int_equal(gf_pf3_predict(&pf, &move, u), GF_OK);
    // Predicted: a ring, every particle about 1 from the origin.
    double r_mean = 0;
    for (unsigned k = 0; k < pf.n; k++) {
        r_mean +=
            hypot((double)particles[k].x.v[0], (double)particles[k].x.v[1]) /
            N_PARTICLES;
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
