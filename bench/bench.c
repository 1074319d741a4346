// SPDX-License-Identifier: MIT
// gaussfilt benchmark: per-step cost of the workloads peers are compared on
// (workloads.h). Not a test: it prints figures and fails only if a filter
// call fails (so the smoke stage catches a rotted benchmark).
//
// Usage:
//   gf_bench count WL PART N   runs N loop iterations once (under
//                              callgrind: the loop function is
//                              bench_loop_FILTER_PART, FILTER kf2 for W1,
//                              ekf3 for W2, n for the filters of n states)
//   gf_bench time WL PART N R  R timed runs of N iterations; prints the
//                              median, min and max ns per iteration
//   gf_bench floor WL PART     prints the hand-counted flop floor
// WL is w1, w1p (W1 through the prepared models: gf_kf2_prepare_model and
// _meas once, then gf_kf2_predict_prepared and _update_prepared), w2, w2c
// (W2 with the caller's own copies of the two models, which take the
// core's general path), w2p (W2 through the prepared models), w2m2 or
// w2m3 (W2 with an update of m = 2 or 3), or a workload of the filters of n
// states (workloads_n.h): cv2, cv3, cv4, cv6, cv8, cv12 (gf_kf) or gps
// (gf_ekf), with PART step or ref only (the floor of bench/ref_n.c) and no
// flop floor (floor prints "-");
// PART is step, predict, update or ref (the step done by the textbook
// reference of bench/ref.c, no checks). The inputs (measurements, turns, and for the part loops the beliefs they start from) come from a
// simulated truth of TAB steps computed before the loop; the step loop
// replays those TAB steps from the same initial belief again and again.
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gaussfilt/gaussfilt.h"
#include "ref.h"
#include "ref_n.h"
#include "workloads.h"
#include "workloads_n.h"

#define TAB WL_TAB

// ---- the arithmetic floor ------------------------------------------------
//
// Floating-point operations (+ - * / each count one) that a hand-unrolled
// scalar implementation of one step must do, knowing what the library can
// know: matrices passed as data are general (A; C a general row; R and
// Sigma symmetric, so only their 3 or 6 unique entries are formed), the
// built-in models' structure is known (G = I but for G[0][2] and G[1][2];
// H = (1 0 0)). No Joseph form, no checks, no NIS, no constant terms (zero
// in W1 and W2). sin and cos of the motion are not counted as flops (their
// cost, gf_sincos, is in the instructions). Derivation, and the counts for
// general G and H: docs/performance.md.
//
// W1 predict: mu = A mu (6); T = A Sigma (12); T A^T, 3 entries (9); +R (3)
#define FLOOR_W1_PREDICT 30
// W1 update: p = Sigma C^T (6); s = C p + Q (4); y = z - C mu (4); 1/s (1);
//            K = p/s (2); mu += K y (4); Sigma -= K p^T, 3 entries (6)
#define FLOOR_W1_UPDATE 27
// W2 predict: model: x + d cos, y + d sin, theta + phi, -d sin, d cos (7);
//             G Sigma G^T for that G, 6 entries (16); +R (6)
#define FLOOR_W2_PREDICT 29
// W2 update: p = Sigma's first column (0); s = s00 + Q (1); y = z - x (1);
//            1/s (1); K = p/s (3); mu += K y (6); Sigma -= K p^T, 6 (12)
#define FLOOR_W2_UPDATE 24
// W2 update, m = 2 (H = (I 0), Q general): S = Sigma's 2x2 + Q (3); det
//            (3); 1/det (1); S^-1 (3); K = P S^-1, 3x2 (18); y (2); mu +=
//            K y (12); Sigma -= K P^T, 6 entries (24)
#define FLOOR_W2M2_UPDATE 66
// W2 update, m = 3 (H = I, Q general): S = Sigma + Q (6); cofactors (18);
//            det and 1/det (6); S^-1 (6); K = Sigma S^-1 (45); y (3); mu +=
//            K y (18); Sigma -= K Sigma, 6 entries (36)
#define FLOOR_W2M3_UPDATE 138

// ---- the workloads (workloads.h) -----------------------------------------

typedef struct bench_wl {
    const char *name;
    int ekf3;     // W2's EKF3, else W1's KF2
    int prepared; // through the prepared models
    unsigned m;   // W2's measured quantities
    int user;     // W2 with the caller's own copies of the built-in models
    int floor_predict, floor_update;
} bench_wl;

static const bench_wl WORKLOADS[] = {
    {"w1", 0, 0, 1u, 0, FLOOR_W1_PREDICT, FLOOR_W1_UPDATE},
    {"w1p", 0, 1, 1u, 0, FLOOR_W1_PREDICT, FLOOR_W1_UPDATE},
    {"w2", 1, 0, 1u, 0, FLOOR_W2_PREDICT, FLOOR_W2_UPDATE},
    {"w2c", 1, 0, 1u, 1, FLOOR_W2_PREDICT, FLOOR_W2_UPDATE},
    {"w2p", 1, 1, 1u, 0, FLOOR_W2_PREDICT, FLOOR_W2_UPDATE},
    {"w2m2", 1, 0, 2u, 0, FLOOR_W2_PREDICT, FLOOR_W2M2_UPDATE},
    {"w2m3", 1, 0, 3u, 0, FLOOR_W2_PREDICT, FLOOR_W2M3_UPDATE},
};

// ---- the measured loops --------------------------------------------------
//
// noinline, so that callgrind can attribute to them by name and the
// compiler cannot fold them into main. Each returns a value derived from
// every belief so that nothing is dead, and stops on the first failure.

#define NOINLINE __attribute__((noinline))

static double fail_sink; // set on failure, so the loops have a side exit
static gf_innovation info_sink;

// The chosen workload's steps: through the prepared models or not (each
// loop reads bench_prepared once; the branch is outside the measured calls).
static int bench_prepared;

static inline gf_status kf2_predict(int prepared, gf_kf2 *kf)
{
    return prepared ? gf_kf2_predict_prepared(kf, &wl_w1_pmodel, NULL)
                    : gf_kf2_predict(kf, &wl_w1_model, NULL);
}

static inline gf_status kf2_update(int prepared, gf_kf2 *kf, unsigned j)
{
    return prepared ? gf_kf2_update_prepared(kf, &wl_w1_pmeas, &wl_w1_z[j],
                                             &info_sink)
                    : gf_kf2_update(kf, &wl_w1_meas, &wl_w1_z[j], &info_sink);
}

static inline gf_status ekf3_predict(int prepared, gf_ekf3 *ekf, unsigned j)
{
    return prepared ? gf_ekf3_predict_prepared(ekf, &wl_w2_pmotion, wl_w2_u[j])
                    : gf_ekf3_predict(ekf, &wl_w2_motion, wl_w2_u[j]);
}

static inline gf_status ekf3_update(int prepared, gf_ekf3 *ekf, unsigned j)
{
    return prepared ? gf_ekf3_update_prepared(ekf, &wl_w2_pmeas, &wl_w2_z[j],
                                              &info_sink)
                    : gf_ekf3_update(ekf, &wl_w2_meas, &wl_w2_z[j], &info_sink);
}

// W1 (KF2): the step, the prediction alone, the update alone.
NOINLINE static double bench_loop_kf2_step(unsigned long n)
{
    const int prepared = bench_prepared;
    gf_kf2 kf = wl_w1_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = wl_w1_init;
        }
        if (kf2_predict(prepared, &kf) != GF_OK ||
            kf2_update(prepared, &kf, j) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)kf.mu.v[0] + (double)kf.ud[1];
}

NOINLINE static double bench_loop_kf2_predict(unsigned long n)
{
    const int prepared = bench_prepared;
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        gf_kf2 kf = wl_w1_post[i & (TAB - 1)];
        if (kf2_predict(prepared, &kf) != GF_OK) {
            return -1;
        }
        acc += (double)kf.ud[1];
    }
    return acc;
}

NOINLINE static double bench_loop_kf2_update(unsigned long n)
{
    const int prepared = bench_prepared;
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_kf2 kf = wl_w1_prior[j];
        if (kf2_update(prepared, &kf, j) != GF_OK) {
            return -1;
        }
        acc += (double)kf.ud[1];
    }
    return acc;
}

// W2 (EKF3): the step, the prediction alone, the update alone.
NOINLINE static double bench_loop_ekf3_step(unsigned long n)
{
    const int prepared = bench_prepared;
    gf_ekf3 ekf = wl_w2_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ekf = wl_w2_init;
        }
        if (ekf3_predict(prepared, &ekf, j) != GF_OK ||
            ekf3_update(prepared, &ekf, j) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)ekf.mu.v[0] + (double)ekf.ud[1];
}

NOINLINE static double bench_loop_ekf3_predict(unsigned long n)
{
    const int prepared = bench_prepared;
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_ekf3 ekf = wl_w2_post[j];
        if (ekf3_predict(prepared, &ekf, j) != GF_OK) {
            return -1;
        }
        acc += (double)ekf.ud[1];
    }
    return acc;
}

NOINLINE static double bench_loop_ekf3_update(unsigned long n)
{
    const int prepared = bench_prepared;
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_ekf3 ekf = wl_w2_prior[j];
        if (ekf3_update(prepared, &ekf, j) != GF_OK) {
            return -1;
        }
        acc += (double)ekf.ud[1];
    }
    return acc;
}

// The same step with the no-checks reference (bench/ref.c).
NOINLINE static double bench_loop_kf2_ref(unsigned long n)
{
    const ref_kf2 init = ref_kf2_from(&wl_w1_init);
    ref_kf2 kf = init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = init;
        }
        ref_kf2_predict(&kf, &wl_w1_model);
        ref_kf2_update(&kf, &wl_w1_meas, &wl_w1_z[j]);
    }
    return (double)kf.mu.v[0] + (double)kf.sigma.m[0][0];
}

NOINLINE static double bench_loop_ekf3_ref(unsigned long n)
{
    const ref_ekf3 init = ref_ekf3_from(&wl_w2_init);
    ref_ekf3 ekf = init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ekf = init;
        }
        ref_ekf3_predict(&ekf, &wl_w2_motion, wl_w2_u[j]);
        if (wl_w2_meas.m == 1) {
            ref_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[j]);
        } else if (wl_w2_meas.m == 2) {
            ref_ekf3_update_xy(&ekf, &wl_w2_meas, &wl_w2_z[j]);
        } else {
            ref_ekf3_update_xyt(&ekf, &wl_w2_meas, &wl_w2_z[j]);
        }
    }
    return (double)ekf.mu.v[0] + (double)ekf.sigma.m[0][0];
}

// The filters of n states (workloads_n.h): the step loop and the floor's
// (bench/ref_n.c), for the workload wl_setup_n set up.
NOINLINE static double bench_loop_n_step(unsigned long n)
{
    gf_kf kf = wl_nw.init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = wl_nw.init;
        }
        gf_status a, b;
        if (wl_nw.ekf) {
            a = gf_ekf_predict(&kf, &wl_nw.motion, NULL, &wl_n_work);
            b = gf_ekf_update(&kf, &wl_nw.emeas, wl_n_z[j], NULL, &wl_n_work);
        } else {
            a = gf_kf_predict(&kf, &wl_nw.model, NULL, &wl_n_work);
            b = gf_kf_update(&kf, &wl_nw.meas, wl_n_z[j], NULL, &wl_n_work);
        }
        if (a != GF_OK || b != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)kf.mu[0] + (double)kf.ud[1];
}

static ref_n ref_n_belief;

NOINLINE static double bench_loop_n_ref(unsigned long n)
{
    ref_n *r = &ref_n_belief;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ref_n_from(r, wl_nw.n, wl_nw.mu0, wl_nw.sigma0);
        }
        if (wl_nw.ekf) {
            ref_ekf_predict(r, &wl_nw.motion, NULL);
            ref_ekf_update(r, &wl_nw.emeas, wl_n_z[j]);
        } else {
            ref_kf_predict(r, &wl_nw.model);
            ref_kf_update(r, &wl_nw.meas, wl_n_z[j]);
        }
    }
    return (double)r->mu[0] + (double)r->P[0];
}

typedef double (*loop_fn)(unsigned long n);

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int usage(void)
{
    fprintf(
        stderr,
        "usage: gf_bench count WL PART N | time WL PART N R | "
        "floor WL PART\n"
        "       WL = w1 | w1p | w2 | w2p | w2c | w2m2 | w2m3, PART = step | "
        "predict | update | ref\n"
        "       WL = cv2 | cv3 | cv4 | cv6 | cv8 | cv12 | gps, PART = step | "
        "ref\n");
    return 2;
}

static int run_loop(loop_fn loop, int argc, char **argv);

// gf_bench MODE WL PART ... for the filters of n states.
static int main_n(int argc, char **argv)
{
    const char *mode = argv[1], *wl = argv[2], *part = argv[3];
    const int ref = strcmp(part, "ref") == 0;
    if (!ref && strcmp(part, "step") != 0) {
        return usage();
    }
    if (strcmp(mode, "floor") == 0) {
        printf("-\n");
        return 0;
    }
    if (wl_setup_n(wl) != 0) {
        return usage();
    }
    return run_loop(ref ? bench_loop_n_ref : bench_loop_n_step, argc, argv);
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        return usage();
    }
    const char *mode = argv[1], *wl = argv[2], *part = argv[3];
    if (strncmp(wl, "cv", 2) == 0 || strcmp(wl, "gps") == 0) {
        return main_n(argc, argv);
    }
    const bench_wl *w = NULL;
    for (size_t k = 0; k < sizeof WORKLOADS / sizeof WORKLOADS[0]; k++) {
        if (strcmp(wl, WORKLOADS[k].name) == 0) {
            w = &WORKLOADS[k];
        }
    }
    static const char *const parts[4] = {"step", "predict", "update", "ref"};
    int p = -1; // an index of parts
    for (int k = 0; k < 4; k++) {
        if (strcmp(part, parts[k]) == 0) {
            p = k;
        }
    }
    if (!w || p < 0) {
        return usage();
    }
    if (strcmp(mode, "floor") == 0) {
        const int f[4] = {w->floor_predict + w->floor_update, w->floor_predict,
                          w->floor_update, w->floor_predict + w->floor_update};
        printf("%d\n", f[p]);
        return 0;
    }

    static const loop_fn loops[2][4] = {
        {bench_loop_kf2_step, bench_loop_kf2_predict, bench_loop_kf2_update,
         bench_loop_kf2_ref},
        {bench_loop_ekf3_step, bench_loop_ekf3_predict, bench_loop_ekf3_update,
         bench_loop_ekf3_ref}};
    bench_prepared = w->prepared;
    if (w->ekf3) {
        wl_setup_w2(w->m, w->user);
    } else {
        wl_setup_w1();
    }
    return run_loop(loops[w->ekf3][p], argc, argv);
}

// The count and time modes of main, for the loop chosen.
static int run_loop(loop_fn loop, int argc, char **argv)
{
    const char *mode = argv[1], *wl = argv[2], *part = argv[3];
    if (strcmp(mode, "count") == 0 && argc == 5) {
        unsigned long n = strtoul(argv[4], NULL, 10);
        double r = loop(n);
        if (r == -1) {
            fprintf(stderr, "gf_bench: a filter call failed\n");
            return 1;
        }
        printf("%s %s %s: %lu iterations, checksum %.9g\n", mode, wl, part, n,
               r);
        return 0;
    }
    if (strcmp(mode, "time") == 0 && argc == 6) {
        unsigned long n = strtoul(argv[4], NULL, 10);
        int reps = atoi(argv[5]);
        if (n == 0 || reps < 1 || reps > 1000) {
            return usage();
        }
        double *ns = malloc((size_t)reps * sizeof *ns);
        if (!ns) {
            return 1;
        }
        if (loop(n) == -1) { // warm-up
            fprintf(stderr, "gf_bench: a filter call failed\n");
            return 1;
        }
        for (int r = 0; r < reps; r++) {
            double t0 = now_ns();
            double v = loop(n);
            double t1 = now_ns();
            if (v == -1) {
                fprintf(stderr, "gf_bench: a filter call failed\n");
                return 1;
            }
            ns[r] = (t1 - t0) / (double)n;
        }
        qsort(ns, (size_t)reps, sizeof *ns, cmp_double);
        printf("median %.2f min %.2f max %.2f ns/iter (%d runs of %lu)\n",
               ns[reps / 2], ns[0], ns[reps - 1], reps, n);
        free(ns);
        return 0;
    }
    return usage();
}
