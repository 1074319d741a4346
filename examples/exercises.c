// SPDX-License-Identifier: MIT
// Prints the exercise tables of Probabilistic Robotics chapter 3 as
// gaussfilt computes them, beside the values the worked solutions print
// (docs/exercises.md). Exit status 1 if any value disagrees with the
// worked solutions to the digits they print.
//
//   exercises [--meas-var V] [--z Z] [--steps N] [--heading-var V]
//             [--beliefs FILE]
//
// The numbers come from book.h; the options change exercise 2's and 4's
// (book.h says which), and a table they change is printed as computed and
// named as differing from the book, not compared with it. --beliefs FILE
// writes every belief (tracks 1, 2, 4 as scripts/demo streams them) as
// text for sim/tools/gf_plots.py, which draws the same figures from it.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "book.h"
#include "gaussfilt/gaussfilt.h"

static int mismatches;
static int g_compare = 1; // 0: the table differs from the book's (options)
static FILE *g_beliefs;   // --beliefs, or NULL

// One belief as a line of text (see gf_plots.py): track seq stage n, the
// mean (3), the covariance (9, row by row).
static void put_belief(int track, int seq, int stage, int n, const gf_real *mu,
                       const gf_real *sigma, int stride)
{
    int i, j;
    if (g_beliefs == NULL) {
        return;
    }
    fprintf(g_beliefs, "%d %d %d %d", track, seq, stage, n);
    for (i = 0; i < 3; i++) {
        fprintf(g_beliefs, " %.17g", i < n ? (double)mu[i] : 0.0);
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            fprintf(g_beliefs, " %.17g",
                    i < n && j < n ? (double)sigma[i * stride + j] : 0.0);
        }
    }
    fprintf(g_beliefs, "\n");
}

// A belief's Sigma, read back from its factors (NaN, which shows as a
// disagreement, if it cannot be).
static gf_mat2 sigma2(const gf_kf2 *kf)
{
    gf_mat2 s;
    if (gf_kf2_cov(kf, &s) != GF_OK) {
        s.m[0][0] = s.m[0][1] = s.m[1][0] = s.m[1][1] = (gf_real)NAN;
    }
    return s;
}

static gf_mat3 sigma3(const gf_ekf3 *e)
{
    gf_mat3 s;
    if (gf_ekf3_cov(e, &s) != GF_OK) {
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                s.m[i][j] = (gf_real)NAN;
            }
        }
    }
    return s;
}

static void put_kf2(int track, int seq, int stage, const gf_kf2 *kf)
{
    const gf_mat2 s = sigma2(kf);
    put_belief(track, seq, stage, 2, kf->mu.v, &s.m[0][0], 2);
}

static void put_ekf3(int track, int seq, int stage, const gf_ekf3 *e)
{
    const gf_mat3 s = sigma3(e);
    put_belief(track, seq, stage, 3, e->mu.v, &s.m[0][0], 3);
}

// One number, computed, and printed by the worked solutions with `digits`
// decimals.
static void cell(double got, double worked, int digits)
{
    double half_ulp = 0.5 * pow(10.0, -digits) + 1e-12;
    int ok = !g_compare || fabs(got - worked) <= half_ulp;
    mismatches += !ok;
    printf(" %10.*f%s", digits + 2, got, ok ? " " : "!");
}

static void row2(const char *label, const gf_kf2 *kf, const double worked_mu[2],
                 const double worked_s[3], int digits)
{
    const gf_mat2 s = sigma2(kf);
    printf("  %-8s mu =", label);
    cell((double)kf->mu.v[0], worked_mu[0], digits);
    cell((double)kf->mu.v[1], worked_mu[1], digits);
    printf("   Sigma =");
    cell((double)s.m[0][0], worked_s[0], digits);
    cell((double)s.m[0][1], worked_s[1], digits);
    cell((double)s.m[1][1], worked_s[2], digits);
    printf("\n");
    if (!g_compare) {
        return;
    }
    printf("  %-6s worked  %10.*f  %10.*f           %10.*f  %10.*f  %10.*f\n",
           "", digits, worked_mu[0], digits, worked_mu[1], digits, worked_s[0],
           digits, worked_s[1], digits, worked_s[2]);
}

static void row3(const char *label, const gf_ekf3 *b, const double worked[9])
{
    // mu (3), then Sigma's upper triangle: xx xy xt yy yt tt
    const gf_mat3 s = sigma3(b);
    const double got[9] = {
        (double)b->mu.v[0], (double)b->mu.v[1], (double)b->mu.v[2],
        (double)s.m[0][0],  (double)s.m[0][1],  (double)s.m[0][2],
        (double)s.m[1][1],  (double)s.m[1][2],  (double)s.m[2][2]};
    printf("  %-9s", label);
    for (int i = 0; i < 9; i++) {
        cell(got[i], worked[i], i == 3 ? 3 : 2);
    }
    printf("\n");
    if (!g_compare) {
        return;
    }
    printf("  %-9s", "worked");
    for (int i = 0; i < 9; i++) {
        printf(" %11.*f", i == 3 ? 3 : 2, worked[i]);
    }
    printf("\n");
}

int main(int argc, char **argv)
{
    // x += v dt, R = accel_var G G^T, G = (dt^2/2, dt)^T (book.h)
    const gf_kf2_model car = {
        .A = {{{1, (gf_real)GF_BOOK_CAR_DT}, {0, 1}}},
        .R = {{{(gf_real)(GF_BOOK_CAR_ACCEL_VAR * 0.25),
                (gf_real)(GF_BOOK_CAR_ACCEL_VAR * 0.5)},
               {(gf_real)(GF_BOOK_CAR_ACCEL_VAR * 0.5),
                (gf_real)GF_BOOK_CAR_ACCEL_VAR}}},
    };
    gf_book book = GF_BOOK_DEFAULTS;
    char differs[256];
    const char *beliefs_path = NULL;
    for (int i = 1; i < argc;) {
        int r = gf_book_option(&book, argc, argv, &i);
        if (r < 0) {
            return 2;
        }
        if (r == 0 && strcmp(argv[i], "--beliefs") == 0 && i + 1 < argc) {
            beliefs_path = argv[i + 1];
            i += 2;
        } else if (r == 0) {
            fprintf(stderr, "usage: exercises %s [--beliefs FILE]\n",
                    GF_BOOK_USAGE);
            return 2;
        }
    }
    if (beliefs_path != NULL) {
        g_beliefs = fopen(beliefs_path, "w");
        if (g_beliefs == NULL) {
            perror(beliefs_path);
            return 2;
        }
        fprintf(g_beliefs, "# gaussfilt beliefs: track seq stage n mu[3] "
                           "sigma[3][3]\n");
        fprintf(g_beliefs, "# meas 2 %.17g %.17g\n# meas 4 %.17g %.17g\n",
                book.ex2_z, book.ex2_q, GF_BOOK_EX4_Z, GF_BOOK_EX4_Q);
    }
    const gf_kf2_meas gps = {
        .m = 1, .C = {{{1, 0}}}, .Q = {{{(gf_real)book.ex2_q}}}};
    static const double table_1_1[6][3] = {{0, 0, 0},   {0.25, 0.5, 1},
                                           {2.5, 2, 2}, {8.75, 4.5, 3},
                                           {21, 8, 4},  {41.25, 12.5, 5}};
    const double zero_mu[2] = {0, 0};
    const gf_vec2 mu0 = {{0, 0}};
    const gf_mat2 s0 = {{{0, 0}, {0, 0}}};
    gf_kf2 kf;
    char label[16];

    printf(
        "gaussfilt %d.%d.%d (%s), computed value, then the worked solutions';"
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
        row2(label, &kf, zero_mu, table_1_1[t], 2);
    }

    printf("\nFigure 1.2: correlation of position and velocity\n");
    static const double rho_worked[4] = {0, 1.0, 0.894, 0.878};
    gf_kf2_init(&kf, &mu0, &s0);
    for (int t = 0; t <= GF_BOOK_EX1_STEPS; t++) {
        gf_real rho;
        if (t > 0) {
            gf_kf2_predict(&kf, &car, NULL);
        }
        put_kf2(1, t, t == 0 ? 0 : 1, &kf);
        const gf_mat2 s = sigma2(&kf);
        if (gf_cov2_correlation(&s, &rho) != GF_OK) {
            printf("  t = %2d  rho undefined (a variance is zero)\n", t);
            continue;
        }
        printf("  t = %2d  rho =", t);
        if (t < 4 || t == 10) {
            double worked = t < 4 ? rho_worked[t] : 0.867;
            cell((double)rho, worked, 3);
            printf("  worked %.3f", worked);
        } else {
            printf(" %10.5f ", (double)rho);
        }
        printf("\n");
    }
    printf("  limit   sqrt(3)/2 = %.5f (the worked solutions: 0.87)\n",
           sqrt(3.0) / 2);

    printf("\nTable 2.1: the measurement z = %g (variance %g) at t = %d\n",
           book.ex2_z, book.ex2_q, book.ex2_steps);
    int ex2_differs = gf_book_differs(&book, "2.1", differs, sizeof differs);
    if (ex2_differs) {
        printf("  (differs from the book because of %s: not compared)\n",
               differs);
    }
    gf_kf2_init(&kf, &mu0, &s0);
    put_kf2(2, 0, 0, &kf);
    for (int t = 1; t <= book.ex2_steps; t++) {
        gf_kf2_predict(&kf, &car, NULL);
        put_kf2(2, t, 1, &kf);
    }
    const double after_mu[2] = {4.02, 1.22}, after_s[3] = {8.05, 2.44, 1.95};
    g_compare = !ex2_differs;
    row2("before", &kf, zero_mu, table_1_1[5], 2);
    const gf_vec2 z = {{(gf_real)book.ex2_z, 0}};
    gf_kf2_update(&kf, &gps, &z, NULL);
    put_kf2(2, book.ex2_steps + 1, 2, &kf);
    row2("after", &kf, after_mu, after_s, 2);
    g_compare = 1;

    printf("\nTables 4.1 and 4.2: EKF3, move 1 forward, then see x = -0.7\n"
           "  (mu: x y theta, Sigma: xx xy xt yy yt tt)\n");
    static const gf_ekf3_motion fwd = {.g = gf_ekf3_motion_forward_turn};
    static const gf_ekf3_meas see_x = {
        .m = 1, .h = gf_ekf3_meas_x, .Q = {{{(gf_real)GF_BOOK_EX4_Q}}}};
    const gf_vec3 e_mu0 = {{0, 0, 0}};
    const gf_real xy = (gf_real)GF_BOOK_EX4_XY_VAR;
    const gf_mat3 e_s0 = {
        {{xy, 0, 0}, {0, xy, 0}, {0, 0, (gf_real)book.ex4_heading_var}}};
    const gf_real move[2] = {(gf_real)GF_BOOK_EX4_D, (gf_real)GF_BOOK_EX4_PHI};
    const gf_vec3 zx = {{(gf_real)GF_BOOK_EX4_Z, 0, 0}};
    static const double t42[3][9] = {
        {0, 0, 0, 0.01, 0, 0, 0.01, 0, 10000},
        {1, 0, 0, 0.01, 0, 0, 10000.01, 10000, 10000},
        {0.15, 0, 0, 0.005, 0, 0, 10000.01, 10000, 10000}};
    gf_ekf3 ekf;
    int ex4_differs = gf_book_differs(&book, "4.2", differs, sizeof differs);
    g_compare = !ex4_differs;
    if (ex4_differs) {
        printf("  (differs from the book because of %s: not compared)\n",
               differs);
    }
    gf_ekf3_init(&ekf, &e_mu0, &e_s0);
    put_ekf3(4, 0, 0, &ekf);
    row3("init", &ekf, t42[0]);
    gf_ekf3_predict(&ekf, &fwd, move);
    put_ekf3(4, 1, 1, &ekf);
    row3("predicted", &ekf, t42[1]);
    gf_ekf3_update(&ekf, &see_x, &zx, NULL);
    put_ekf3(4, 2, 2, &ekf);
    row3("corrected", &ekf, t42[2]);
    g_compare = 1;
    if (g_beliefs != NULL) {
        fclose(g_beliefs);
        printf("\nbeliefs written to %s\n", beliefs_path);
    }

    printf("\n%s: %d value(s) disagree with the worked solutions%s%s%s\n",
           mismatches ? "FAIL" : "OK", mismatches,
           ex2_differs || ex4_differs
               ? "; not compared (changed by an option): "
               : "",
           ex2_differs ? "Table 2.1" : "",
           ex4_differs ? (ex2_differs ? ", Table 4.2" : "Table 4.2") : "");
    return mismatches ? 1 : 0;
}
