// gaussfilt benchmark: per-step cost of the two workloads peers are
// compared on. Not a test: it prints figures and fails only if a filter call
// fails (so the smoke stage catches a rotted benchmark).
//
//   W1, KF2:  the car of exercises 1 and 2: A = ((1,1),(0,1)), no control,
//             R = ((0.25,0.5),(0.5,1)); one step = predict + update with a
//             scalar position measurement, C = (1,0), Q = 10.
//   W2, EKF3: the robot of exercise 4: predict with "move 1 forward, then
//             turn phi" (gf_ekf3_motion_forward_turn), update with an x
//             measurement of variance 0.01 (gf_ekf3_meas_x). The turn phi is
//             drawn in [-0.6, 0.6] each step, so the heading wanders over the
//             whole circle (theta = 0 would let sin/cos take a fast path).
//
// Usage:
//   gf_bench count WL PART N   runs N loop iterations once (under
//                              callgrind: the loop function is bench_loop_*)
//   gf_bench time WL PART N R  R timed runs of N iterations; prints the
//                              median, min and max ns per iteration
//   gf_bench floor WL PART     prints the hand-counted flop floor
// WL is w1, w1p (W1 through the prepared models: gf_kf2_prepare_model and
// _meas once, then gf_kf2_predict_prepared and _update_prepared), w2, or
// w2c (W2 with the caller's own copies of the two models, which take the
// core's general path); PART is step, predict, update or ref (the step done by
// the no-checks reference of bench/ref.c). The inputs (measurements,
// turns, and for the part loops the beliefs they start from) come from a
// simulated truth of TAB steps computed before the loop; the step loop
// replays those TAB steps from the same initial belief again and again.
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gaussfilt/gaussfilt.h"
#include "ref.h"

#define TAB 1024u // steps of simulated truth; a power of two

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

// ---- the workloads -------------------------------------------------------

// A deterministic xorshift64* generator and Box-Muller normals, for the
// simulated truth only.
static unsigned long long rng_state = 0x9E3779B97F4A7C15ull;

static double uniform01(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    unsigned long long r = rng_state * 2685821657736338717ull;
    return ((double)(r >> 11) + 0.5) / 9007199254740992.0;
}

static double normal01(void)
{
    return sqrt(-2.0 * log(uniform01())) * cos(6.283185307179586 * uniform01());
}

static const gf_kf2_model W1_MODEL = {
    {{{1, 1}, {0, 1}}},
    {{{0, 0}, {0, 0}}},
    {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), 1}}},
    {{0, 0}},
};

static const gf_kf2_meas W1_MEAS = {
    1, {{{1, 0}, {0, 0}}}, {{{10, 0}, {0, 0}}}, {{0, 0}}, 0,
};

static gf_kf2_pmodel w1_pmodel; // W1_MODEL and W1_MEAS, prepared
static gf_kf2_pmeas w1_pmeas;
static gf_kf2 w1_init;         // belief at the start of each replay
static gf_vec2 w1_z[TAB];      // measurement of step i
static gf_kf2 w1_post[TAB];    // belief before step i's predict
static gf_kf2 w1_prior[TAB];   // belief before step i's update

static gf_ekf3_motion w2_motion;
static gf_ekf3_meas w2_meas;
static gf_ekf3 w2_init;
static gf_real w2_u[TAB][2];   // control of step i: (1, phi_i)
static gf_vec3 w2_z[TAB];
static gf_ekf3 w2_post[TAB];
static gf_ekf3 w2_prior[TAB];

static void die(const char *what, int i, gf_status st)
{
    fprintf(stderr, "gf_bench: %s failed at step %d: %s\n", what, i,
            gf_status_str(st));
    exit(1);
}

static void setup_w1(void)
{
    // Truth: x += v + 0.5 a, v += a, a ~ N(0, 1) (so R = G G^T), z = x +
    // N(0, 10).
    double x = 0, v = 0;
    gf_vec2 mu = {{0, 0}};
    gf_mat2 sig = {{{0, 0}, {0, 0}}};
    gf_kf2 kf;
    if (gf_kf2_init(&w1_init, &mu, &sig) != GF_OK) {
        die("w1 init", 0, GF_ERR_ARG);
    }
    kf = w1_init;
    if (gf_kf2_prepare_model(&w1_pmodel, &W1_MODEL) != GF_OK ||
        gf_kf2_prepare_meas(&w1_pmeas, &W1_MEAS) != GF_OK) {
        die("w1 prepare", 0, GF_ERR_ARG);
    }
    for (unsigned i = 0; i < TAB; i++) {
        double a = normal01();
        x += v + 0.5 * a;
        v += a;
        w1_z[i].v[0] = (gf_real)(x + sqrt(10.0) * normal01());
        w1_z[i].v[1] = 0;
        w1_post[i] = kf;
        gf_status st = gf_kf2_predict(&kf, &W1_MODEL, NULL);
        if (st != GF_OK) {
            die("w1 predict", (int)i, st);
        }
        w1_prior[i] = kf;
        st = gf_kf2_update(&kf, &W1_MEAS, &w1_z[i], NULL);
        if (st != GF_OK) {
            die("w1 update", (int)i, st);
        }
    }
}

// W2 with the caller's own callbacks ("w2c"): the same models as the
// built-ins, written here, so the core cannot recognise them and takes its
// general path (call through the pointer, G filled and its shape tested).
static gf_status user_forward_turn(void *ctx, const gf_vec3 *mu,
                                   const gf_real *u, gf_vec3 *mu_bar,
                                   gf_mat3 *G)
{
    (void)ctx;
    const gf_real d = u[0], th = mu->v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    mu_bar->v[0] = mu->v[0] + d * c;
    mu_bar->v[1] = mu->v[1] + d * s;
    mu_bar->v[2] = th + u[1];
    G->m[0][2] = -d * s; // the rest of G: identity, preset by the core
    G->m[1][2] = d * c;
    return GF_OK;
}

static gf_status user_meas_x(void *ctx, const gf_vec3 *mu_bar,
                             gf_vec3 *z_hat, gf_mat3 *H)
{
    (void)ctx;
    z_hat->v[0] = mu_bar->v[0];
    H->m[0][0] = 1;
    H->m[0][1] = 0;
    H->m[0][2] = 0;
    return GF_OK;
}

static void setup_w2(int user)
{
    memset(&w2_motion, 0, sizeof w2_motion);
    w2_motion.g = user ? user_forward_turn : gf_ekf3_motion_forward_turn;
    // Process noise: 5 cm along each axis, 0.02 rad of heading per step.
    w2_motion.R.m[0][0] = GF_R(0.0025);
    w2_motion.R.m[1][1] = GF_R(0.0025);
    w2_motion.R.m[2][2] = GF_R(0.0004);
    memset(&w2_meas, 0, sizeof w2_meas);
    w2_meas.m = 1;
    w2_meas.h = user ? user_meas_x : gf_ekf3_meas_x;
    w2_meas.Q.m[0][0] = GF_R(0.01);

    gf_vec3 mu = {{0, 0, 0}};
    gf_mat3 sig = {{{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0},
                    {0, 0, GF_R(0.01)}}};
    if (gf_ekf3_init(&w2_init, &mu, &sig) != GF_OK) {
        die("w2 init", 0, GF_ERR_ARG);
    }
    gf_ekf3 ekf = w2_init;
    double x = 0, y = 0, th = 0;
    for (unsigned i = 0; i < TAB; i++) {
        double phi = 1.2 * uniform01() - 0.6;
        x += cos(th) + 0.05 * normal01();
        y += sin(th) + 0.05 * normal01();
        th += phi + 0.02 * normal01();
        w2_u[i][0] = 1;
        w2_u[i][1] = (gf_real)phi;
        w2_z[i].v[0] = (gf_real)(x + 0.1 * normal01());
        w2_z[i].v[1] = w2_z[i].v[2] = 0;
        w2_post[i] = ekf;
        gf_status st = gf_ekf3_predict(&ekf, &w2_motion, w2_u[i]);
        if (st != GF_OK) {
            die("w2 predict", (int)i, st);
        }
        w2_prior[i] = ekf;
        st = gf_ekf3_update(&ekf, &w2_meas, &w2_z[i], NULL);
        if (st != GF_OK) {
            die("w2 update", (int)i, st);
        }
    }
}

// ---- the measured loops --------------------------------------------------
//
// noinline, so that callgrind can attribute to them by name and the
// compiler cannot fold them into main. Each returns a value derived from
// every belief so that nothing is dead, and stops on the first failure.

#define NOINLINE __attribute__((noinline))

static double fail_sink; // set on failure, so the loops have a side exit
static gf_innovation info_sink;

NOINLINE static double bench_loop_w1_step(unsigned long n)
{
    gf_kf2 kf = w1_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = w1_init;
        }
        if (gf_kf2_predict(&kf, &W1_MODEL, NULL) != GF_OK ||
            gf_kf2_update(&kf, &W1_MEAS, &w1_z[j], &info_sink) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)kf.mu.v[0] + (double)kf.sigma.m[0][0];
}

NOINLINE static double bench_loop_w1_predict(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        gf_kf2 kf = w1_post[i & (TAB - 1)];
        if (gf_kf2_predict(&kf, &W1_MODEL, NULL) != GF_OK) {
            return -1;
        }
        acc += (double)kf.sigma.m[0][0];
    }
    return acc;
}

NOINLINE static double bench_loop_w1_update(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_kf2 kf = w1_prior[j];
        if (gf_kf2_update(&kf, &W1_MEAS, &w1_z[j], &info_sink) != GF_OK) {
            return -1;
        }
        acc += (double)kf.sigma.m[0][0];
    }
    return acc;
}

// W1 through the prepared models.
NOINLINE static double bench_loop_w1p_step(unsigned long n)
{
    gf_kf2 kf = w1_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = w1_init;
        }
        if (gf_kf2_predict_prepared(&kf, &w1_pmodel, NULL) != GF_OK ||
            gf_kf2_update_prepared(&kf, &w1_pmeas, &w1_z[j], &info_sink) !=
                GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)kf.mu.v[0] + (double)kf.sigma.m[0][0];
}

NOINLINE static double bench_loop_w1p_predict(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        gf_kf2 kf = w1_post[i & (TAB - 1)];
        if (gf_kf2_predict_prepared(&kf, &w1_pmodel, NULL) != GF_OK) {
            return -1;
        }
        acc += (double)kf.sigma.m[0][0];
    }
    return acc;
}

NOINLINE static double bench_loop_w1p_update(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_kf2 kf = w1_prior[j];
        if (gf_kf2_update_prepared(&kf, &w1_pmeas, &w1_z[j], &info_sink) !=
            GF_OK) {
            return -1;
        }
        acc += (double)kf.sigma.m[0][0];
    }
    return acc;
}

NOINLINE static double bench_loop_w2_step(unsigned long n)
{
    gf_ekf3 ekf = w2_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ekf = w2_init;
        }
        if (gf_ekf3_predict(&ekf, &w2_motion, w2_u[j]) != GF_OK ||
            gf_ekf3_update(&ekf, &w2_meas, &w2_z[j], &info_sink) != GF_OK) {
            fail_sink = (double)i;
            return -1;
        }
    }
    return (double)ekf.mu.v[0] + (double)ekf.sigma.m[0][0];
}

NOINLINE static double bench_loop_w2_predict(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_ekf3 ekf = w2_post[j];
        if (gf_ekf3_predict(&ekf, &w2_motion, w2_u[j]) != GF_OK) {
            return -1;
        }
        acc += (double)ekf.sigma.m[0][0];
    }
    return acc;
}

NOINLINE static double bench_loop_w2_update(unsigned long n)
{
    double acc = 0;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        gf_ekf3 ekf = w2_prior[j];
        if (gf_ekf3_update(&ekf, &w2_meas, &w2_z[j], &info_sink) != GF_OK) {
            return -1;
        }
        acc += (double)ekf.sigma.m[0][0];
    }
    return acc;
}

// The same step with the no-checks reference (bench/ref.c).
NOINLINE static double bench_loop_w1_ref(unsigned long n)
{
    gf_kf2 kf = w1_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            kf = w1_init;
        }
        ref_kf2_predict(&kf, &W1_MODEL);
        ref_kf2_update(&kf, &W1_MEAS, &w1_z[j]);
    }
    return (double)kf.mu.v[0] + (double)kf.sigma.m[0][0];
}

NOINLINE static double bench_loop_w2_ref(unsigned long n)
{
    gf_ekf3 ekf = w2_init;
    for (unsigned long i = 0; i < n; i++) {
        unsigned j = (unsigned)(i & (TAB - 1));
        if (j == 0) {
            ekf = w2_init;
        }
        ref_ekf3_predict(&ekf, &w2_motion, w2_u[j]);
        ref_ekf3_update(&ekf, &w2_meas, &w2_z[j]);
    }
    return (double)ekf.mu.v[0] + (double)ekf.sigma.m[0][0];
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
    fprintf(stderr,
            "usage: gf_bench count WL PART N | time WL PART N R | "
            "floor WL PART\n"
            "       WL = w1 | w1p | w2 | w2c, PART = step | predict | update | "
            "ref\n");
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        return usage();
    }
    const char *mode = argv[1], *wl = argv[2], *part = argv[3];
    int user = strcmp(wl, "w2c") == 0;
    int w2 = user || strcmp(wl, "w2") == 0;
    int prepared = strcmp(wl, "w1p") == 0;
    if (!w2 && !prepared && strcmp(wl, "w1") != 0) {
        return usage();
    }
    int p; // 0 step, 1 predict, 2 update, 3 reference step
    if (strcmp(part, "step") == 0) {
        p = 0;
    } else if (strcmp(part, "ref") == 0) {
        p = 3;
    } else if (strcmp(part, "predict") == 0) {
        p = 1;
    } else if (strcmp(part, "update") == 0) {
        p = 2;
    } else {
        return usage();
    }

    if (strcmp(mode, "floor") == 0) {
        static const int floors[2][4] = {
            {FLOOR_W1_PREDICT + FLOOR_W1_UPDATE, FLOOR_W1_PREDICT,
             FLOOR_W1_UPDATE, FLOOR_W1_PREDICT + FLOOR_W1_UPDATE},
            {FLOOR_W2_PREDICT + FLOOR_W2_UPDATE, FLOOR_W2_PREDICT,
             FLOOR_W2_UPDATE, FLOOR_W2_PREDICT + FLOOR_W2_UPDATE}};
        printf("%d\n", floors[w2][p]);
        return 0;
    }

    static const loop_fn loops[3][4] = {
        {bench_loop_w1_step, bench_loop_w1_predict, bench_loop_w1_update,
         bench_loop_w1_ref},
        {bench_loop_w2_step, bench_loop_w2_predict, bench_loop_w2_update,
         bench_loop_w2_ref},
        {bench_loop_w1p_step, bench_loop_w1p_predict, bench_loop_w1p_update,
         bench_loop_w1_ref}};
    loop_fn loop = loops[prepared ? 2 : w2][p];
    if (w2) {
        setup_w2(user);
    } else {
        setup_w1();
    }

    if (strcmp(mode, "count") == 0 && argc == 5) {
        unsigned long n = strtoul(argv[4], NULL, 10);
        double r = loop(n);
        if (r == -1) {
            fprintf(stderr, "gf_bench: a filter call failed\n");
            return 1;
        }
        printf("%s %s %s: %lu iterations, checksum %.9g\n", mode, wl, part,
               n, r);
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
