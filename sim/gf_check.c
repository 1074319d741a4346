// SPDX-License-Identifier: MIT
// gf_check: listens to one track's beliefs on the wire and checks them
// against a table of the worked solutions (docs/exercises.md).
// Prints the beliefs beside the worked solutions' values; exit 0 only if they agree.
//
//   gf_check --table 1.1|2.1|4.2 --track N [--url URL] [--timeout-ms MS]
//   gf_check --count N --track N [--url URL] [--timeout-ms MS]
//
// 1.1: track running `gf_sim --exercise 1`: Sigma_t for t = 0..5 (and the
//      correlation rho_t of Figure 1.2 up to t = 10, falling to 0.87);
// 2.1: `gf_sim --exercise 2`: the belief at t = 5 before and after z = 5;
// 4.2: `gf_sim --exercise 4`: init, predicted, corrected.
// --count N only waits for N beliefs of the track and prints them.
//
// Tolerance: 1e-12 relative to max(1, |value|) against the exact values of
// the tables (2e-5 when the node is built in float); the worked solutions' printed
// values are shown beside them.
// Prints "gf_check: ready" once subscribed.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "book.h"
#include "gaussfilt/gaussfilt.h"
#include "gf_channels.h"
#include "gf_help.h"
#include "gf_route.h"
#include "gf_wire.h"

#define MAX_BELIEFS 64
// The node's filter runs in gf_real: exact to 1e-12 in double, a few float
// ulps (as in the core's tests) in the float build.
#ifdef GF_SINGLE_PRECISION
#define TOL 2e-5
#else
#define TOL 1e-12
#endif

typedef struct check {
    gf_wire_belief b[MAX_BELIEFS];
    int have[MAX_BELIEFS];
    int count;
    int bad;
} check;

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    check *c = (check *)user;
    gf_wire_belief b;
    (void)channel;
    if (gf_wire_belief_decode(rbuf->data, rbuf->data_size, &b) != 0) {
        c->bad++;
        return;
    }
    if (b.seq >= 0 && b.seq < MAX_BELIEFS && !c->have[b.seq]) {
        c->b[b.seq] = b;
        c->have[b.seq] = 1;
        c->count++;
    }
}

// ---- the worked solutions' tables, in exact form -------------------------

typedef struct want {
    const char *label;
    int stage;
    int n;
    double mean[3];
    double cov[3][3];
    const char *worked; // as the worked solutions print it
} want;

static int close_to(double got, double want_v, double tol)
{
    double scale = fabs(want_v) > 1.0 ? fabs(want_v) : 1.0;
    return fabs(got - want_v) <= tol * scale;
}

static void print_belief(const gf_wire_belief *b)
{
    int i, j;
    printf("mu = (");
    for (i = 0; i < b->n; i++) {
        printf("%s%9.4f", i ? " " : "", b->mean[i]);
    }
    printf(")  Sigma = (");
    for (i = 0; i < b->n; i++) {
        for (j = 0; j < b->n; j++) {
            printf("%s%10.4f", j ? " " : (i ? "; " : ""), b->cov[i][j]);
        }
    }
    printf(")");
}

// Compares belief b with w within TOL, and its status and stage.
static int compare(const gf_wire_belief *b, const want *w)
{
    int i, j, ok = b->status == 0 && b->stage == w->stage && b->n == w->n;
    for (i = 0; i < w->n; i++) {
        ok &= close_to(b->mean[i], w->mean[i], TOL);
        for (j = 0; j < w->n; j++) {
            ok &= close_to(b->cov[i][j], w->cov[i][j], TOL);
        }
    }
    return ok;
}

// The options that make the table being checked differ from the book's
// (examples/book.h), "" if none: then each row is checked against what
// those numbers give, and the book's printed row is not shown.
static char g_differs[256];

static int run_rows(const check *c, const want *w, const int *seq, int rows)
{
    int r, fails = 0;
    for (r = 0; r < rows; r++) {
        const gf_wire_belief *b = &c->b[seq[r]];
        int ok = compare(b, &w[r]);
        fails += !ok;
        printf("  %-9s wire: ", w[r].label);
        print_belief(b);
        if (g_differs[0] == '\0') {
            printf("\n  %-7s worked: %s  %s\n", "", w[r].worked,
                   ok ? "[match]" : "[MISMATCH]");
        } else {
            printf("\n  %-9s want: ", "");
            {
                gf_wire_belief x;
                int i, j;
                memset(&x, 0, sizeof x);
                x.n = (int8_t)w[r].n;
                for (i = 0; i < w[r].n; i++) {
                    x.mean[i] = w[r].mean[i];
                    for (j = 0; j < w[r].n; j++) {
                        x.cov[i][j] = w[r].cov[i][j];
                    }
                }
                print_belief(&x);
            }
            printf("  %s\n", ok ? "[match]" : "[MISMATCH]");
        }
    }
    return fails;
}

// Table 1.1 and Figure 1.2: t = 0..5 against the table, rho_t to t = 10.
static int table_1_1(const check *c)
{
    static const double s[6][3] = {{0, 0, 0},   {0.25, 0.5, 1},
                                   {2.5, 2, 2}, {8.75, 4.5, 3},
                                   {21, 8, 4},  {41.25, 12.5, 5}};
    static const char *worked[6] = {"mu = (0 0)  Sigma = (0 0; 0 0)",
                                    "mu = (0 0)  Sigma = (0.25 0.5; 0.5 1)",
                                    "mu = (0 0)  Sigma = (2.5 2; 2 2)",
                                    "mu = (0 0)  Sigma = (8.75 4.5; 4.5 3)",
                                    "mu = (0 0)  Sigma = (21 8; 8 4)",
                                    "mu = (0 0)  Sigma = (41.25 12.5; 12.5 5)"};
    static const char *label[6] = {"t = 0", "t = 1", "t = 2",
                                   "t = 3", "t = 4", "t = 5"};
    want w[6];
    int seq[6], t, fails;
    memset(w, 0, sizeof(w));
    for (t = 0; t < 6; t++) {
        w[t].label = label[t];
        w[t].stage = t == 0 ? GAUSSFILT_LCM_BELIEF_T_STAGE_INIT
                            : GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
        w[t].n = 2;
        w[t].cov[0][0] = s[t][0];
        w[t].cov[0][1] = w[t].cov[1][0] = s[t][1];
        w[t].cov[1][1] = s[t][2];
        w[t].worked = worked[t];
        seq[t] = t;
    }
    printf("Table 1.1: the car's belief, prediction only (from the wire)\n");
    fails = run_rows(c, w, seq, 6);

    printf("Figure 1.2 / 1.1: correlation rho_t and the 68%% ellipse "
           "(gf_cov2_correlation, gf_cov2_ellipse)\n");
    for (t = 0; t < c->count && t <= 10; t++) {
        gf_mat2 m;
        gf_real rho = GF_R(0.0);
        gf_ellipse e;
        gf_status sr, se;
        m.m[0][0] = (gf_real)c->b[t].cov[0][0];
        m.m[0][1] = (gf_real)c->b[t].cov[0][1];
        m.m[1][0] = (gf_real)c->b[t].cov[1][0];
        m.m[1][1] = (gf_real)c->b[t].cov[1][1];
        sr = gf_cov2_correlation(&m, &rho);
        se = gf_cov2_ellipse(&m, GF_R(0.68), &e);
        printf("  t = %2d  rho = ", t);
        if (sr == GF_OK) {
            printf("%.4f", (double)rho);
        } else {
            printf("%s", gf_status_str(sr));
        }
        if (se == GF_OK) {
            printf("   ellipse a = %.3f b = %.3f angle = %.1f deg\n",
                   (double)e.a, (double)e.b,
                   (double)e.angle * 180.0 / 3.14159265358979323846);
        } else {
            printf("   ellipse %s\n", gf_status_str(se));
        }
        if (t == 0 && sr != GF_ERR_UNDEFINED) {
            fails++; // rho_0 is undefined: both variances are zero
        }
        if (t == 1 && !(sr == GF_OK && close_to((double)rho, 1.0, TOL))) {
            fails++;
        }
        if (t == 10 && !(sr == GF_OK && fabs((double)rho - 0.87) <= 0.005)) {
            fails++;
        }
    }
    if (c->count < 11) {
        fails++;
    }
    printf("  worked: rho starts at 1 (t = 1) and converges to 0.87 "
           "(sqrt(3)/2 = 0.866)\n");
    return fails;
}

// Table 2.1: before and after z = 5 at t = 5 (the book), or z after N
// predictions with variance Q (--z, --steps, --meas-var): Sigma_t =
// A Sigma A^T + R from 0, then S = Sigma_xx + Q, K = Sigma e_x / S.
static int table_2_1(const check *c, const gf_book *bk)
{
    want w[2];
    int seq[2], t, n = bk->ex2_steps;
    double sx = 0.0, sxv = 0.0, sv = 0.0, s, q = bk->ex2_q, z = bk->ex2_z;
    for (t = 0; t < n; t++) { // A = ((1, 1), (0, 1)), R = ((.25 .5)(.5 1))
        double nx = sx + 2.0 * sxv + sv + 0.25 * GF_BOOK_CAR_ACCEL_VAR;
        double nxv = sxv + sv + 0.5 * GF_BOOK_CAR_ACCEL_VAR;
        double nv = sv + GF_BOOK_CAR_ACCEL_VAR;
        sx = nx;
        sxv = nxv;
        sv = nv;
    }
    s = sx + q; // S = C Sigma_bar C^T + Q
    seq[0] = n;
    seq[1] = n + 1;
    memset(w, 0, sizeof(w));
    w[0].label = "Before";
    w[0].stage = GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
    w[0].n = 2;
    w[0].cov[0][0] = sx;
    w[0].cov[0][1] = w[0].cov[1][0] = sxv;
    w[0].cov[1][1] = sv;
    w[0].worked = "mu = (0 0)  cov = (41.25 12.5; 12.5 5)";
    w[1].label = "After";
    w[1].stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
    w[1].n = 2;
    w[1].mean[0] = sx * z / s;
    w[1].mean[1] = sxv * z / s;
    w[1].cov[0][0] = sx * q / s;
    w[1].cov[0][1] = w[1].cov[1][0] = sxv * q / s;
    w[1].cov[1][1] = sv - sxv * sxv / s;
    w[1].worked = "mu = (4.02 1.22)  cov = (8.05 2.44; 2.44 1.95)";
    printf("Table 2.1: the car at t = %d before and after z = %g "
           "(variance %g, from the wire)\n",
           n, z, q);
    return run_rows(c, w, seq, 2) + (c->count < n + 2);
}

// Table 4.2: init, predicted (move 1 forward), corrected (x = -0.7); the
// heading variance H of the prior (--heading-var) moves to y on the move:
// Sigma_bar = G Sigma G^T, G = ((1 0 0) (0 1 d) (0 0 1)) at theta = 0.
static int table_4_2(const check *c, const gf_book *bk)
{
    want w[3];
    int seq[3] = {0, 1, 2}, r;
    const double h = bk->ex4_heading_var, d = GF_BOOK_EX4_D;
    const double xy = GF_BOOK_EX4_XY_VAR, q = GF_BOOK_EX4_Q;
    memset(w, 0, sizeof(w));
    for (r = 0; r < 3; r++) {
        w[r].n = 3;
        w[r].stage = r;
        w[r].cov[0][0] = xy;
        w[r].cov[1][1] = r == 0 ? xy : xy + d * d * h;
        w[r].cov[2][2] = h;
        w[r].cov[1][2] = w[r].cov[2][1] = r == 0 ? 0.0 : d * h;
    }
    w[0].label = "Init";
    w[0].worked = "mu = (0 0 0)  cov = (0.01 0 0; 0 0.01 0; 0 0 10000)";
    w[1].label = "Predicted";
    w[1].worked = "mu = (1 0 0)  cov = (0.01 0 0; 0 10000.01 10000; "
                  "0 10000 10000)";
    w[2].label = "Corrected";
    w[1].mean[0] = d;
    {
        double k = xy / (xy + q); // K for x: Sigma_bar_xx / S
        w[2].mean[0] = d + k * (GF_BOOK_EX4_Z - d);
        w[2].cov[0][0] = (1 - k) * (1 - k) * xy + k * k * q; // Joseph form
    }
    w[2].worked = "mu = (0.15 0 0)  cov = (0.005 0 0; 0 10000.01 10000; "
                  "0 10000 10000)";
    printf("Table 4.2: the robot, EKF (from the wire)\n");
    return run_rows(c, w, seq, 3) + (c->count < 3);
}

static long elapsed_ms(const struct timespec *t0)
{
    struct timespec t1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (long)(t1.tv_sec - t0->tv_sec) * 1000L +
           (t1.tv_nsec - t0->tv_nsec) / 1000000L;
}

static const char help_text[] =
    "gf_check: listens to one track's beliefs and checks them against a table\n"
    "of Probabilistic Robotics ch. 3's worked exercises; exit 0 if they "
    "agree.\n\n"
    "usage: gf_check --table 1.1|2.1|4.2 --track N [--url URL] [--timeout-ms "
    "MS]\n"
    "                [--meas-var V] [--z Z] [--steps N] [--heading-var V]\n"
    "       gf_check --count N --track N [--url URL] [--timeout-ms MS]\n\n"
    "  --table T       1.1 (gf_sim --exercise 1), 2.1 (2) or 4.2 (4)\n"
    "  --count N       only wait for N beliefs and print them\n"
    "  --track N       the track; --url URL (default LCM's); --timeout-ms\n"
    "  --meas-var V, --z Z, --steps N   exercise 2's numbers (book: 10, 5, 5)\n"
    "  --heading-var V exercise 4's initial heading variance (book: 10000);\n"
    "                  a table they change is checked against what they give\n"
    "                  and named as differing from the book "
    "(examples/book.h)\n\n"
    "example:\n"
    "  gf_check --table 2.1 --track 2 & gf_node & gf_sim --exercise 2 --track "
    "2\n";

int main(int argc, char **argv)
{
    const char *url = NULL, *table = NULL;
    long track = 1, timeout_ms = 10000;
    gf_book book = GF_BOOK_DEFAULTS;
    int need = 0, i, fails;
    char channel[GF_CHANNEL_MAX];
    static check c; // ~11 kB
    struct timespec t0;
    lcm_t *lcm;

    gf_help(argc, argv, help_text);
    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0) {
            url = argv[i + 1];
        } else if (strcmp(argv[i], "--table") == 0) {
            table = argv[i + 1];
        } else if (strcmp(argv[i], "--track") == 0) {
            track = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--count") == 0) {
            need = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--timeout-ms") == 0) {
            timeout_ms = atol(argv[i + 1]);
        } else {
            int k = i, r = gf_book_option(&book, argc, argv, &k);
            if (r < 0) {
                return 2;
            }
            if (r == 0) {
                break;
            }
        }
    }
    if (i != argc || (table == NULL) == (need <= 0)) {
        fprintf(stderr, "usage: gf_check --table 1.1|2.1|4.2 | --count N  "
                        "--track N [--url URL] [--timeout-ms MS]\n");
        return 2;
    }
    if (table != NULL) {
        if (strcmp(table, "1.1") == 0) {
            need = 11;
        } else if (strcmp(table, "2.1") == 0) {
            need = book.ex2_steps + 2;
        } else if (strcmp(table, "4.2") == 0) {
            need = 3;
        } else {
            fprintf(stderr, "gf_check: no table %s\n", table);
            return 2;
        }
    }
    if (need > MAX_BELIEFS) {
        need = MAX_BELIEFS;
    }

    lcm = gf_lcm_open("gf_check", url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_check: cannot open LCM at %s\n",
                url ? url : "(default URL)");
        return 1;
    }
    snprintf(channel, sizeof(channel), "%s%ld", GF_CHANNEL_BELIEF, track);
    lcm_subscription_set_queue_capacity(
        lcm_subscribe(lcm, channel, on_belief, &c), 1024);
    printf("gf_check: ready channel=%s\n", channel);
    fflush(stdout);

    clock_gettime(CLOCK_MONOTONIC, &t0);
    while (c.count < need && elapsed_ms(&t0) < timeout_ms) {
        lcm_handle_timeout(lcm, 50);
    }
    lcm_destroy(lcm);

    if (c.count < need) {
        fprintf(stderr, "gf_check: %s: only %d of %d beliefs in %ld ms\n",
                channel, c.count, need, timeout_ms);
        return 1;
    }
    if (table == NULL) {
        for (i = 0; i < MAX_BELIEFS; i++) {
            if (!c.have[i]) {
                continue;
            }
            printf("  seq %d stage %d status %d: ", i, c.b[i].stage,
                   c.b[i].status);
            print_belief(&c.b[i]);
            printf("\n");
        }
        printf("gf_check: %d beliefs on %s\n", c.count, channel);
        return 0;
    }
    gf_book_differs(&book, table, g_differs, sizeof g_differs);
    if (g_differs[0] != '\0') {
        printf("Table %s differs from the book because of %s: checked "
               "against what these numbers give\n",
               table, g_differs);
    }
    if (strcmp(table, "1.1") == 0) {
        fails = table_1_1(&c);
    } else if (strcmp(table, "2.1") == 0) {
        fails = table_2_1(&c, &book);
    } else {
        fails = table_4_2(&c, &book);
    }
    printf("gf_check: Table %s %s (%d mismatches)%s%s\n", table,
           fails ? "FAILED" : "reproduced from the wire", fails,
           g_differs[0] ? "; differs from the book because of " : "",
           g_differs);
    return fails ? 1 : 0;
}
