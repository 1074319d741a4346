// Prints the exercise tables of Probabilistic Robotics chapter 3 as
// gaussfilt computes them, beside the values the seed prints
// (../shared/seeds/000_da0a77abadc93716.txt). Exit status 1 if any value
// disagrees with the seed to the digits it prints.
#include <math.h>
#include <stdio.h>

#include "gaussfilt/gaussfilt.h"

static int mismatches;

// One number, computed and printed by the seed with `digits` decimals.
static void cell(double got, double seed, int digits)
{
    double half_ulp = 0.5 * pow(10.0, -digits) + 1e-12;
    int ok = fabs(got - seed) <= half_ulp;
    mismatches += !ok;
    printf(" %10.*f%s", digits + 2, got, ok ? " " : "!");
}

static void row2(const char *label, const gf_vec2 *mu, const gf_mat2 *s,
                 const double seed_mu[2], const double seed_s[3], int digits)
{
    printf("  %-8s mu =", label);
    cell((double)mu->v[0], seed_mu[0], digits);
    cell((double)mu->v[1], seed_mu[1], digits);
    printf("   Sigma =");
    cell((double)s->m[0][0], seed_s[0], digits);
    cell((double)s->m[0][1], seed_s[1], digits);
    cell((double)s->m[1][1], seed_s[2], digits);
    printf("\n  %-8s seed  %10.*f  %10.*f           %10.*f  %10.*f  %10.*f\n",
           "", digits, seed_mu[0], digits, seed_mu[1], digits, seed_s[0],
           digits, seed_s[1], digits, seed_s[2]);
}

static void row3(const char *label, const gf_ekf3 *b, const double seed[9])
{
    // mu (3), then Sigma's upper triangle: xx xy xt yy yt tt
    const double got[9] = {
        (double)b->mu.v[0], (double)b->mu.v[1], (double)b->mu.v[2],
        (double)b->sigma.m[0][0], (double)b->sigma.m[0][1],
        (double)b->sigma.m[0][2], (double)b->sigma.m[1][1],
        (double)b->sigma.m[1][2], (double)b->sigma.m[2][2]};
    printf("  %-9s", label);
    for (int i = 0; i < 9; i++) {
        cell(got[i], seed[i], i == 3 ? 3 : 2);
    }
    printf("\n  %-9s", "seed");
    for (int i = 0; i < 9; i++) {
        printf(" %11.*f", i == 3 ? 3 : 2, seed[i]);
    }
    printf("\n");
}

int main(void)
{
    static const gf_kf2_model car = {
        .A = {{{1, 1}, {0, 1}}},
        .R = {{{0.25, 0.5}, {0.5, 1}}},
    };
    static const gf_kf2_meas gps = {.m = 1, .C = {{{1, 0}}}, .Q = {{{10}}}};
    static const double table_1_1[6][3] = {
        {0, 0, 0}, {0.25, 0.5, 1}, {2.5, 2, 2},
        {8.75, 4.5, 3}, {21, 8, 4}, {41.25, 12.5, 5}};
    const double zero_mu[2] = {0, 0};
    const gf_vec2 mu0 = {{0, 0}};
    const gf_mat2 s0 = {{{0, 0}, {0, 0}}};
    gf_kf2 kf;
    char label[16];

    printf("gaussfilt %d.%d.%d (%s), computed value, then the seed's;"
           " '!' marks a disagreement\n\n",
           GF_VERSION_MAJOR, GF_VERSION_MINOR, GF_VERSION_PATCH,
           sizeof(gf_real) == sizeof(float) ? "float" : "double");

    printf("Table 1.1: KF2 prediction, no measurements (Sigma: xx xv vv)\n");
    gf_kf2_init(&kf, &mu0, &s0);
    for (int t = 0; t <= 5; t++) {
        if (t > 0) {
            gf_kf2_predict(&kf, &car, NULL);
        }
        snprintf(label, sizeof label, "t = %d", t);
        row2(label, &kf.mu, &kf.sigma, zero_mu, table_1_1[t], 2);
    }

    printf("\nFigure 1.2: correlation of position and velocity\n");
    static const double rho_seed[4] = {0, 1.0, 0.894, 0.878};
    gf_kf2_init(&kf, &mu0, &s0);
    for (int t = 0; t <= 10; t++) {
        gf_real rho;
        if (t > 0) {
            gf_kf2_predict(&kf, &car, NULL);
        }
        if (gf_cov2_correlation(&kf.sigma, &rho) != GF_OK) {
            printf("  t = %2d  rho undefined (a variance is zero)\n", t);
            continue;
        }
        printf("  t = %2d  rho =", t);
        if (t < 4 || t == 10) {
            double seed = t < 4 ? rho_seed[t] : 0.867;
            cell((double)rho, seed, 3);
            printf("  seed %.3f", seed);
        } else {
            printf(" %10.5f ", (double)rho);
        }
        printf("\n");
    }
    printf("  limit   sqrt(3)/2 = %.5f (the seed: 0.87)\n", sqrt(3.0) / 2);

    printf("\nTable 2.1: the measurement z = 5 (variance 10) at t = 5\n");
    gf_kf2_init(&kf, &mu0, &s0);
    for (int t = 1; t <= 5; t++) {
        gf_kf2_predict(&kf, &car, NULL);
    }
    row2("before", &kf.mu, &kf.sigma, zero_mu, table_1_1[5], 2);
    const gf_vec2 z = {{5, 0}};
    gf_kf2_update(&kf, &gps, &z, NULL);
    const double after_mu[2] = {4.02, 1.22}, after_s[3] = {8.05, 2.44, 1.95};
    row2("after", &kf.mu, &kf.sigma, after_mu, after_s, 2);

    printf("\nTables 4.1 and 4.2: EKF3, move 1 forward, then see x = -0.7\n"
           "  (mu: x y theta, Sigma: xx xy xt yy yt tt)\n");
    static const gf_ekf3_motion fwd = {.g = gf_ekf3_motion_forward_turn};
    static const gf_ekf3_meas see_x = {
        .m = 1, .h = gf_ekf3_meas_x, .Q = {{{0.01}}}};
    const gf_vec3 e_mu0 = {{0, 0, 0}};
    const gf_mat3 e_s0 = {{{0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 10000}}};
    const gf_real move[2] = {1, 0};
    const gf_vec3 zx = {{-0.7, 0, 0}};
    static const double t42[3][9] = {
        {0, 0, 0, 0.01, 0, 0, 0.01, 0, 10000},
        {1, 0, 0, 0.01, 0, 0, 10000.01, 10000, 10000},
        {0.15, 0, 0, 0.005, 0, 0, 10000.01, 10000, 10000}};
    gf_ekf3 ekf;
    gf_ekf3_init(&ekf, &e_mu0, &e_s0);
    row3("init", &ekf, t42[0]);
    gf_ekf3_predict(&ekf, &fwd, move);
    row3("predicted", &ekf, t42[1]);
    gf_ekf3_update(&ekf, &see_x, &zx, NULL);
    row3("corrected", &ekf, t42[2]);

    printf("\n%s: %d value(s) disagree with the seed\n",
           mismatches ? "FAIL" : "OK", mismatches);
    return mismatches ? 1 : 0;
}
