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
//   gf_bench agree WL PART     (PART udu, uduc or uducp) the sound floor
//                              held against the library after each of
//                              the TAB steps: the largest differences
// WL is w1, w1p (W1 through the prepared models: gf_kf2_prepare_model and
// _meas once, then gf_kf2_predict_prepared and _update_prepared), w2, w2c
// (W2 with the caller's own copies of the two models, which take the
// core's general path), w2p (W2 through the prepared models), w2m2 or
// w2m3 (W2 with an update of m = 2 or 3), or a workload of the filters of n
// states (workloads_n.h): cv2, cv3, cv4, cv6, cv8, cv12 (gf_kf) or gps
// (gf_ekf), with PART step or ref only (the floor of bench/ref_n.c) and no
// flop floor (floor prints "-");
// PART is step, predict, update or ref (the step done by the no-checks
// reference of bench/ref.c), or the step done by the sound floor of
// bench/ref.c on U D U^T: udu (no checks), uduc (the plain API's checks)
// or uducp (the prepared path's), for w1, w2, w2m2 and w2m3. The inputs
// (measurements,
// turns, and for the part loops the beliefs they start from) come from a
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

// The same step on the sound floor of bench/ref.c (U D U^T by hand):
// unchecked (udu: R's factors made once), with the plain API's checks
// (uduc) and with the prepared path's (uducp: the models prepared once).
static ref_noise2 udu_rn2;
static ref_noise3 udu_rn3;
static ref_kf2_pmodel udu_pm2;
static ref_kf2_pmeas udu_pq2;
static ref_ekf3_pmotion udu_pm3;
static ref_ekf3_pmeas udu_pq3;

// The floors' models made once (outside the measured loops); nonzero if a
// model is refused.
static int udu_setup(int ekf3)
{
    if (!ekf3) {
        udu_rn2 = ref_noise2_from(&wl_w1_model.R);
        return ref_uducp2_prepare_model(&udu_pm2, &wl_w1_model) != GF_OK ||
               ref_uducp2_prepare_meas(&udu_pq2, &wl_w1_meas) != GF_OK;
    }
    udu_rn3 = ref_noise3_from(&wl_w2_motion.R);
    return ref_uducp3_prepare_motion(&udu_pm3, &wl_w2_motion) != GF_OK ||
           ref_uducp3_prepare_meas(&udu_pq3, &wl_w2_meas) != GF_OK;
}

// One step of W1 on floor v (0 udu, 1 uduc, 2 uducp) from step j's inputs.
static inline gf_status kf2_udu_step(int v, ref_udu2 *kf, unsigned j)
{
    gf_status a = GF_OK, b = GF_OK;
    if (v == 0) {
        ref_udu2_predict(kf, &wl_w1_model, &udu_rn2);
        ref_udu2_update(kf, &wl_w1_meas, &wl_w1_z[j]);
    } else if (v == 1) {
        a = ref_uduc2_predict(kf, &wl_w1_model, NULL);
        b = ref_uduc2_update(kf, &wl_w1_meas, &wl_w1_z[j], &info_sink);
    } else {
        a = ref_uducp2_predict(kf, &udu_pm2, NULL);
        b = ref_uducp2_update(kf, &udu_pq2, &wl_w1_z[j], &info_sink);
    }
    return a != GF_OK ? a : b;
}

static inline gf_status ekf3_udu_step(int v, ref_udu3 *ekf, unsigned j)
{
    gf_status a = GF_OK, b = GF_OK;
    if (v == 0) {
        ref_udu3_predict(ekf, &wl_w2_motion, &udu_rn3, wl_w2_u[j]);
        if (wl_w2_meas.m == 1) {
            ref_udu3_update(ekf, &wl_w2_meas, &wl_w2_z[j]);
        } else if (wl_w2_meas.m == 2) {
            ref_udu3_update_xy(ekf, &wl_w2_meas, &wl_w2_z[j]);
        } else {
            ref_udu3_update_xyt(ekf, &wl_w2_meas, &wl_w2_z[j]);
        }
    } else if (v == 1) {
        a = ref_uduc3_predict(ekf, &wl_w2_motion, wl_w2_u[j]);
        b = ref_uduc3_update(ekf, &wl_w2_meas, &wl_w2_z[j], &info_sink);
    } else {
        a = ref_uducp3_predict(ekf, &udu_pm3, wl_w2_u[j]);
        b = ref_uducp3_update(ekf, &udu_pq3, &wl_w2_z[j], &info_sink);
    }
    return a != GF_OK ? a : b;
}

static inline double kf2_udu_loop(int v, unsigned long n)
{
    const ref_udu2 init =
        v == 0 ? ref_udu2_inorder(&wl_w1_init) : ref_udu2_from(&wl_w1_init);
    ref_udu2 kf = init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = init;
        }
        if (kf2_udu_step(v, &kf, j) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)kf.mu.v[0] + (double)kf.ud[1];
}

static inline double ekf3_udu_loop(int v, unsigned long n)
{
    const ref_udu3 init =
        v == 0 ? ref_udu3_inorder(&wl_w2_init) : ref_udu3_from(&wl_w2_init);
    ref_udu3 ekf = init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ekf = init;
        }
        if (ekf3_udu_step(v, &ekf, j) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)ekf.mu.v[0] + (double)ekf.ud[1];
}

NOINLINE static double bench_loop_kf2_udu(unsigned long n)
{
    return kf2_udu_loop(0, n);
}

NOINLINE static double bench_loop_kf2_uduc(unsigned long n)
{
    return kf2_udu_loop(1, n);
}

NOINLINE static double bench_loop_kf2_uducp(unsigned long n)
{
    return kf2_udu_loop(2, n);
}

NOINLINE static double bench_loop_ekf3_udu(unsigned long n)
{
    return ekf3_udu_loop(0, n);
}

NOINLINE static double bench_loop_ekf3_uduc(unsigned long n)
{
    return ekf3_udu_loop(1, n);
}

NOINLINE static double bench_loop_ekf3_uducp(unsigned long n)
{
    return ekf3_udu_loop(2, n);
}

// gf_bench agree WL PART: the floor's belief held against the library's
// after each of the TAB steps (wl_*_post, the last one the step loop's
// own); prints the largest differences as ref_udu2_dev / ref_udu3_dev
// give them.
static int udu_agree(int ekf3, int v, const char *wl, const char *part)
{
    gf_real worst = 0, worst_mu = 0, mu;
    if (!ekf3) {
        ref_udu2 kf =
            v == 0 ? ref_udu2_inorder(&wl_w1_init) : ref_udu2_from(&wl_w1_init);
        gf_kf2 lib = wl_w1_init;
        for (unsigned j = 0; j < TAB; j++) {
            if (kf2_udu_step(v, &kf, j) != GF_OK ||
                gf_kf2_predict(&lib, &wl_w1_model, NULL) != GF_OK ||
                gf_kf2_update(&lib, &wl_w1_meas, &wl_w1_z[j], NULL) != GF_OK) {
                return 1;
            }
            const gf_real c = ref_udu2_dev(&kf, &lib, &mu);
            worst = c > worst ? c : worst;
            worst_mu = mu > worst_mu ? mu : worst_mu;
        }
    } else {
        ref_udu3 ekf =
            v == 0 ? ref_udu3_inorder(&wl_w2_init) : ref_udu3_from(&wl_w2_init);
        gf_ekf3 lib = wl_w2_init;
        for (unsigned j = 0; j < TAB; j++) {
            if (ekf3_udu_step(v, &ekf, j) != GF_OK ||
                gf_ekf3_predict(&lib, &wl_w2_motion, wl_w2_u[j]) != GF_OK ||
                gf_ekf3_update(&lib, &wl_w2_meas, &wl_w2_z[j], NULL) != GF_OK) {
                return 1;
            }
            const gf_real c = ref_udu3_dev(&ekf, &lib, &mu);
            worst = c > worst ? c : worst;
            worst_mu = mu > worst_mu ? mu : worst_mu;
        }
    }
    printf("agree %s %s cov %.2e mu %.2e\n", wl, part, (double)worst,
           (double)worst_mu);
    return 0;
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
        "floor WL PART | agree WL PART\n"
        "       WL = w1 | w1p | w2 | w2p | w2c | w2m2 | w2m3, PART = step | "
        "predict | update | ref | udu | uduc | uducp\n"
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
    static const char *const parts[7] = {"step", "predict", "update", "ref",
                                         "udu",  "uduc",    "uducp"};
    int p = -1; // an index of parts
    for (int k = 0; k < 7; k++) {
        if (strcmp(part, parts[k]) == 0) {
            p = k;
        }
    }
    // The sound floors run the workload's own models (not w1p, w2p, w2c).
    if (!w || p < 0 || (p >= 4 && (w->prepared || w->user))) {
        return usage();
    }
    if (strcmp(mode, "floor") == 0) {
        const int f[4] = {w->floor_predict + w->floor_update, w->floor_predict,
                          w->floor_update, w->floor_predict + w->floor_update};
        printf("%d\n", f[p < 4 ? p : 3]);
        return 0;
    }

    static const loop_fn loops[2][7] = {
        {bench_loop_kf2_step, bench_loop_kf2_predict, bench_loop_kf2_update,
         bench_loop_kf2_ref, bench_loop_kf2_udu, bench_loop_kf2_uduc,
         bench_loop_kf2_uducp},
        {bench_loop_ekf3_step, bench_loop_ekf3_predict, bench_loop_ekf3_update,
         bench_loop_ekf3_ref, bench_loop_ekf3_udu, bench_loop_ekf3_uduc,
         bench_loop_ekf3_uducp}};
    bench_prepared = w->prepared;
    if (w->ekf3) {
        wl_setup_w2(w->m, w->user);
    } else {
        wl_setup_w1();
    }
    if (p >= 4 && udu_setup(w->ekf3) != 0) {
        fprintf(stderr, "gf_bench: the floor's models were refused\n");
        return 1;
    }
    if (strcmp(mode, "agree") == 0) {
        if (p < 4 || udu_agree(w->ekf3, p - 4, wl, part) != 0) {
            return p < 4 ? usage() : 1;
        }
        return 0;
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
