// SPDX-License-Identifier: MIT
// gps8_count: what gps8's model (gps8.h) costs on the Cortex-M4F, counted
// by QEMU's insncount plugin (bench/qemu/). An image of this file and one
// model (gps8_hand.c, or the gps8_model.c gaussfilt.codegen writes from
// examples/gps8_model.py), float, runs under the plugin as the benchmark
// image bench/m4f.c does, with its markers and report lines (read by
// bench/qemu/m4f.sh's gf_m4f_count): the motion (g and G), the four
// pseudoranges (z_hat and H), and gf_ekf's predict and update with them,
// each N times, one region a call (a step: both calls), on states and
// satellites made here without libm. It prints, after each report,
//
//   bench empty - N / bench gps8 g N / bench gps8 h N / bench gps8 step N
//
// and "bench done" at the end; a failing call ends it with exit code 1.
#include <stdio.h>
#include <string.h>

#include "gps8.h"
#include "gaussfilt/ekf.h"

#define N 16u
#define NOINLINE __attribute__((noinline, used))

// The markers (as bench/m4f.c's): the plugin is given their addresses.
NOINLINE void bench_mark_start(const void *p);
NOINLINE void bench_mark_stop(const void *p);
NOINLINE void bench_mark_report(void);

NOINLINE void bench_mark_start(const void *p)
{
    __asm__ volatile("" : : "r"(p) : "memory");
}

NOINLINE void bench_mark_stop(const void *p)
{
    __asm__ volatile("" : : "r"(p) : "memory");
}

NOINLINE void bench_mark_report(void)
{
    __asm__ volatile("" : : : "memory");
}

static void report(const char *wl, const char *part)
{
    bench_mark_report();
    printf("bench %s %s %u\n", wl, part, N);
}

// Four satellites at about 2.66e7 m from the Earth's centre, above a
// receiver near (4.5e6, 0.55e6, 4.5e6) m (45 N, 7 E).
static gf_real sats[12] = {GF_R(1.88e7), GF_R(0.23e7),  GF_R(1.87e7),
                           GF_R(2.41e7), GF_R(-0.62e7), GF_R(0.93e7),
                           GF_R(0.47e7), GF_R(1.95e7),  GF_R(1.75e7),
                           GF_R(0.69e7), GF_R(-1.02e7), GF_R(2.36e7)};

// State i: the receiver a few hundred metres from its start, moving.
static void state(unsigned i, gf_real mu[8])
{
    const gf_real k = (gf_real)i;
    mu[0] = GF_R(4.5e6) + GF_R(37.0) * k;
    mu[1] = GF_R(0.55e6) - GF_R(11.0) * k;
    mu[2] = GF_R(4.5e6) + GF_R(23.0) * k;
    mu[3] = GF_R(-2.4) + GF_R(0.1) * k;
    mu[4] = GF_R(19.8);
    mu[5] = GF_R(0.3) * k;
    mu[6] = GF_R(3.0e4) + GF_R(2.0) * k;
    mu[7] = GF_R(2.0);
}

static gf_kf ekf;
static gf_kf_work work;
static gf_ekf_pmotion pmotion;
static gf_ekf_pmeas pmeas;

static int fail(const char *what, unsigned i)
{
    printf("gps8_count: %s failed at %u\n", what, i);
    return 1;
}

int main(void)
{
    const gf_real dt[1] = {GF_R(1.0)};
    gf_real mu[8], mu_bar[8], G[64], z[4], H[32];
    for (unsigned i = 0; i < N; i++) {
        bench_mark_start(mu);
        bench_mark_stop(mu);
    }
    report("empty", "-");
    for (unsigned i = 0; i < N; i++) {
        state(i, mu);
        memcpy(mu_bar, mu, sizeof mu_bar);
        memset(G, 0, sizeof G);
        bench_mark_start(mu_bar);
        gf_status st = gps8_g(NULL, 8u, mu, dt, mu_bar, G);
        bench_mark_stop(mu_bar);
        if (st != GF_OK) {
            return fail("g", i);
        }
    }
    report("gps8", "g");
    for (unsigned i = 0; i < N; i++) {
        state(i, mu);
        memset(H, 0, sizeof H);
        bench_mark_start(z);
        gf_status st = gps8_h_rho(sats, 8u, 4u, mu, z, H);
        bench_mark_stop(z);
        if (st != GF_OK) {
            return fail("h", i);
        }
    }
    report("gps8", "h");
    // The filter: gps8.c's R and Q (dt = 1 s), a prior of 100 m, 5 m/s,
    // 1e5 m and 10 m/s, and pseudoranges of the states above.
    gf_real R[64] = {0}, Q[16] = {0}, S0[64] = {0};
    for (unsigned i = 0; i < 3u; i++) {
        R[i * 8u + i] = GF_R(0.1) / GF_R(3.0);
        R[i * 8u + i + 3u] = R[(i + 3u) * 8u + i] = GF_R(0.05);
        R[(i + 3u) * 8u + i + 3u] = GF_R(0.1);
        S0[i * 8u + i] = GF_R(1.0e4);
        S0[(i + 3u) * 8u + i + 3u] = GF_R(25.0);
    }
    R[6u * 8u + 6u] = GF_R(0.1) + GF_R(0.01) / GF_R(3.0);
    R[6u * 8u + 7u] = R[7u * 8u + 6u] = GF_R(0.005);
    R[7u * 8u + 7u] = GF_R(0.01);
    S0[6u * 8u + 6u] = GF_R(1.0e10);
    S0[7u * 8u + 7u] = GF_R(100.0);
    for (unsigned k = 0; k < 4u; k++) {
        Q[k * 4u + k] = GF_R(36.0);
    }
    const gf_ekf_motion mo = {gps8_g, NULL, R};
    const gf_ekf_meas me = {4u, gps8_h_rho, sats, Q, 0, 0};
    state(0u, mu);
    mu[0] += GF_R(60.0);
    mu[6] -= GF_R(500.0);
    if (gf_ekf_init(&ekf, 8u, mu, S0, 0u, &work) != GF_OK ||
        gf_ekf_prepare_motion(&pmotion, 8u, &mo, &work) != GF_OK ||
        gf_ekf_prepare_meas(&pmeas, 8u, &me, &work) != GF_OK) {
        return fail("set-up", 0u);
    }
    for (unsigned i = 0; i < N; i++) {
        gf_kf_innovation info;
        state(i + 1u, mu);
        if (gps8_h_rho(sats, 8u, 4u, mu, z, H) != GF_OK) {
            return fail("truth", i);
        }
        z[i % 4u] += GF_R(5.0);
        bench_mark_start(&ekf);
        gf_status a = gf_ekf_predict_prepared(&ekf, &pmotion, dt, &work);
        gf_status b = gf_ekf_update_prepared(&ekf, &pmeas, z, &info, &work);
        bench_mark_stop(&ekf);
        if (a != GF_OK || b != GF_OK) {
            return fail("step", i);
        }
    }
    report("gps8", "step");
    printf("bench done\n");
    return 0;
}
