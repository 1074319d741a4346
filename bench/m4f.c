// SPDX-License-Identifier: MIT
// The Cortex-M4F benchmark image: the workloads of workloads.h, run once
// each on QEMU's mps2-an386 under the insncount plugin (bench/qemu/), which
// counts the instructions executed between bench_mark_start and
// bench_mark_stop and prints its totals at each bench_mark_report. Each
// measured call (or predict + update pair) is one region, so the set-up,
// the loop and the copies of the stored beliefs are outside; the empty
// region ("empty"), run first, is what the markers themselves cost.
//
// The filters of n states (workloads_n.h): each row's step through gf_kf
// (gf_ekf for gps), the same through the prepared path, and the same step
// by the floor of bench/ref_n.c, named "cvN step" / "cvN prep" / "cvN ref"
// (and "gps ...").
//
// After each report the image prints, over semihosting, one line
//   bench WL PART N
// naming the report (the i-th line names the plugin's i-th report), and
// "bench done" at the end; a failing filter call ends it with exit code 1.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "floor.h"
#include "gaussfilt/gaussfilt.h"
#include "ref.h"
#include "ref_n.h"
#include "workloads.h"
#include "workloads_n.h"

#define NOINLINE __attribute__((noinline, used))

// The markers: the plugin is given their entry addresses. Each takes the
// belief the region works on, so the compiler has finished writing it
// before the region opens and cannot start on it before; the asm keeps
// them from being judged pure.
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

static gf_innovation info;

static void report(const char *wl, const char *part)
{
    bench_mark_report();
    printf("bench %s %s %u\n", wl, part, WL_TAB);
}

static void check(gf_status st, const char *what, unsigned i)
{
    if (st != GF_OK) {
        wl_die(what, (int)i, st);
    }
}

static void empty(void)
{
    gf_kf2 kf = wl_w1_init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&kf);
        bench_mark_stop(&kf);
    }
    report("empty", "-");
}

static void w1(void)
{
    wl_setup_w1();
    gf_kf2 kf = wl_w1_init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&kf);
        gf_status a = gf_kf2_predict(&kf, &wl_w1_model, NULL);
        gf_status b = gf_kf2_update(&kf, &wl_w1_meas, &wl_w1_z[i], &info);
        bench_mark_stop(&kf);
        check(a != GF_OK ? a : b, "w1 step", i);
    }
    report("w1", "step");
    for (unsigned i = 0; i < WL_TAB; i++) {
        kf = wl_w1_prior[i];
        bench_mark_start(&kf);
        gf_status a = gf_kf2_update(&kf, &wl_w1_meas, &wl_w1_z[i], &info);
        bench_mark_stop(&kf);
        check(a, "w1 update", i);
    }
    report("w1", "update");
    kf = wl_w1_init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&kf);
        gf_status a = gf_kf2_predict_prepared(&kf, &wl_w1_pmodel, NULL);
        gf_status b =
            gf_kf2_update_prepared(&kf, &wl_w1_pmeas, &wl_w1_z[i], &info);
        bench_mark_stop(&kf);
        check(a != GF_OK ? a : b, "w1p step", i);
    }
    report("w1p", "step");
    ref_kf2 rk = ref_kf2_from(&wl_w1_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&rk);
        ref_kf2_predict(&rk, &wl_w1_model);
        ref_kf2_update(&rk, &wl_w1_meas, &wl_w1_z[i]);
        bench_mark_stop(&rk);
    }
    report("w1", "ref");
    // The loop floor (floor.h), checked against the library's belief at
    // the end of the replay: the same filter, so within float's rounding.
    floor_kf2 fk;
    gf_mat2 s0, s1, s2;
    (void)gf_kf2_cov(&wl_w1_init, &s0);
    check(floor_kf2_init(&fk, &wl_w1_init.mu, &s0), "w1 floor init", 0);
    for (unsigned i = 0; i < WL_TAB; i++) {
        gf_real nis;
        bench_mark_start(&fk);
        gf_status a = floor_kf2_predict(&fk, &wl_w1_model, NULL);
        gf_status b = floor_kf2_update(&fk, &wl_w1_meas, &wl_w1_z[i], &nis);
        bench_mark_stop(&fk);
        check(a != GF_OK ? a : b, "w1 floor", i);
    }
    floor_kf2_cov(&fk, &s1);
    (void)gf_kf2_cov(&kf, &s2);
    for (unsigned i = 0; i < 4u; i++) {
        const gf_real e = s1.m[i / 2u][i % 2u] - s2.m[i / 2u][i % 2u];
        const gf_real t = GF_R(1e-3) * (s2.m[0][0] + s2.m[1][1]);
        check((e > t || -e > t) ? GF_ERR_ARG : GF_OK, "w1 floor's Sigma", i);
    }
    report("w1", "floor");
}

static void w2(const char *name, unsigned m)
{
    wl_setup_w2(m, 0);
    gf_ekf3 ekf = wl_w2_init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ekf);
        gf_status a = gf_ekf3_predict(&ekf, &wl_w2_motion, wl_w2_u[i]);
        gf_status b = gf_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[i], &info);
        bench_mark_stop(&ekf);
        check(a != GF_OK ? a : b, "w2 step", i);
    }
    report(name, "step");
    for (unsigned i = 0; i < WL_TAB; i++) {
        ekf = wl_w2_prior[i];
        bench_mark_start(&ekf);
        gf_status a = gf_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[i], &info);
        bench_mark_stop(&ekf);
        check(a, "w2 update", i);
    }
    report(name, "update");
    if (m == 1) {
        ekf = wl_w2_init;
        for (unsigned i = 0; i < WL_TAB; i++) {
            bench_mark_start(&ekf);
            gf_status a =
                gf_ekf3_predict_prepared(&ekf, &wl_w2_pmotion, wl_w2_u[i]);
            gf_status b =
                gf_ekf3_update_prepared(&ekf, &wl_w2_pmeas, &wl_w2_z[i], &info);
            bench_mark_stop(&ekf);
            check(a != GF_OK ? a : b, "w2p step", i);
        }
        report("w2p", "step");
    }
    void (*const ref_update)(ref_ekf3 *, const gf_ekf3_meas *,
                             const gf_vec3 *) = m == 1   ? ref_ekf3_update
                                                : m == 2 ? ref_ekf3_update_xy
                                                         : ref_ekf3_update_xyt;
    ref_ekf3 re = ref_ekf3_from(&wl_w2_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&re);
        ref_ekf3_predict(&re, &wl_w2_motion, wl_w2_u[i]);
        ref_update(&re, &wl_w2_meas, &wl_w2_z[i]);
        bench_mark_stop(&re);
    }
    report(name, "ref");
    if (m != 1u) {
        return;
    }
    // The loop floor, checked as W1's.
    floor_ekf3 fe;
    gf_mat3 s0, s1, s2;
    (void)gf_ekf3_cov(&wl_w2_init, &s0);
    check(floor_ekf3_init(&fe, &wl_w2_init.mu, &s0), "w2 floor init", 0);
    for (unsigned i = 0; i < WL_TAB; i++) {
        gf_real nis;
        bench_mark_start(&fe);
        gf_status a = floor_ekf3_predict(&fe, &wl_w2_motion, wl_w2_u[i]);
        gf_status b = floor_ekf3_update(&fe, &wl_w2_meas, &wl_w2_z[i], &nis);
        bench_mark_stop(&fe);
        check(a != GF_OK ? a : b, "w2 floor", i);
    }
    floor_ekf3_cov(&fe, &s1);
    ekf = wl_w2_init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        check(gf_ekf3_predict(&ekf, &wl_w2_motion, wl_w2_u[i]), "w2", i);
        check(gf_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[i], &info), "w2", i);
    }
    (void)gf_ekf3_cov(&ekf, &s2);
    for (unsigned i = 0; i < 9u; i++) {
        const gf_real e = s1.m[i / 3u][i % 3u] - s2.m[i / 3u][i % 3u];
        const gf_real t = GF_R(1e-3) * (s2.m[0][0] + s2.m[1][1] + s2.m[2][2]);
        check((e > t || -e > t) ? GF_ERR_ARG : GF_OK, "w2 floor's Sigma", i);
    }
    report(name, "floor");
}

static ref_n ref_belief;
static union {
    gf_kf_pmodel k;
    gf_ekf_pmotion e;
} n_pmotion;
static union {
    gf_kf_pmeas k;
    gf_ekf_pmeas e;
} n_pmeas;

static void n_rows(const char *name)
{
    if (wl_setup_n(name) != 0) {
        wl_die(name, -1, GF_ERR_ARG);
    }
    gf_kf kf = wl_nw.init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        gf_status a, b;
        if (wl_nw.ekf) {
            bench_mark_start(&kf);
            a = gf_ekf_predict(&kf, &wl_nw.motion, NULL, &wl_n_work);
            b = gf_ekf_update(&kf, &wl_nw.emeas, wl_n_z[i], NULL, &wl_n_work);
            bench_mark_stop(&kf);
        } else {
            bench_mark_start(&kf);
            a = gf_kf_predict(&kf, &wl_nw.model, NULL, &wl_n_work);
            b = gf_kf_update(&kf, &wl_nw.meas, wl_n_z[i], NULL, &wl_n_work);
            bench_mark_stop(&kf);
        }
        check(a != GF_OK ? a : b, name, i);
    }
    report(name, "step");
    // The same steps through the prepared path: the models judged and
    // factored once, before the loop.
    kf = wl_nw.init;
    if (wl_nw.ekf) {
        check(gf_ekf_prepare_motion(&n_pmotion.e, wl_nw.n, &wl_nw.motion,
                                    &wl_n_work),
              name, 0);
        check(
            gf_ekf_prepare_meas(&n_pmeas.e, wl_nw.n, &wl_nw.emeas, &wl_n_work),
            name, 0);
    } else {
        check(gf_kf_prepare_model(&n_pmotion.k, wl_nw.n, &wl_nw.model,
                                  &wl_n_work),
              name, 0);
        check(gf_kf_prepare_meas(&n_pmeas.k, wl_nw.n, &wl_nw.meas, &wl_n_work),
              name, 0);
    }
    for (unsigned i = 0; i < WL_TAB; i++) {
        gf_status a, b;
        if (wl_nw.ekf) {
            bench_mark_start(&kf);
            a = gf_ekf_predict_prepared(&kf, &n_pmotion.e, NULL, &wl_n_work);
            b = gf_ekf_update_prepared(&kf, &n_pmeas.e, wl_n_z[i], NULL,
                                       &wl_n_work);
            bench_mark_stop(&kf);
        } else {
            bench_mark_start(&kf);
            a = gf_kf_predict_prepared(&kf, &n_pmotion.k, NULL, &wl_n_work);
            b = gf_kf_update_prepared(&kf, &n_pmeas.k, wl_n_z[i], NULL,
                                      &wl_n_work);
            bench_mark_stop(&kf);
        }
        check(a != GF_OK ? a : b, name, i);
    }
    report(name, "prep");
    ref_n *r = &ref_belief;
    ref_n_from(r, wl_nw.n, wl_nw.mu0, wl_nw.sigma0);
    for (unsigned i = 0; i < WL_TAB; i++) {
        if (wl_nw.ekf) {
            bench_mark_start(r);
            ref_ekf_predict(r, &wl_nw.motion, NULL);
            ref_ekf_update(r, &wl_nw.emeas, wl_n_z[i]);
            bench_mark_stop(r);
        } else {
            bench_mark_start(r);
            ref_kf_predict(r, &wl_nw.model);
            ref_kf_update(r, &wl_nw.meas, wl_n_z[i]);
            bench_mark_stop(r);
        }
    }
    report(name, "ref");
}

// 1 if a and b (n entries) agree within tol times scale.
static int near(const gf_real *a, const gf_real *b, unsigned n, gf_real scale)
{
    for (unsigned i = 0; i < n; i++) {
        const gf_real e = a[i] - b[i], t = GF_R(1e-3) * scale;
        if (e > t || -e > t) {
            return 0;
        }
    }
    return 1;
}

// The floors of the updates with what the API holds (floor.h's
// *_update_api), whose stack scripts/footprint counts, checked against
// the library outside any region: W1's prior updated with two correlated
// quantities (the same mean, Sigma and NIS within float's rounding) and
// with two exact quantities along one direction (both singular, the
// floor's belief unchanged); W2's prior with its three quantities.
static void api_floors(void)
{
    wl_setup_w1();
    gf_kf2_meas meas = wl_w1_meas;
    meas.m = 2;
    meas.C = (gf_mat2){{{1, 0}, {1, 1}}};
    meas.Q = (gf_mat2){{{GF_R(0.5), GF_R(0.2)}, {GF_R(0.2), GF_R(0.4)}}};
    const gf_vec2 z = {{GF_R(1.0), GF_R(2.0)}};
    gf_kf2 kf = wl_w1_prior[5];
    gf_mat2 s0, s1, s2;
    (void)gf_kf2_cov(&kf, &s0);
    floor_kf2 fk, fk0;
    check(floor_kf2_init(&fk, &kf.mu, &s0), "kf2 api floor init", 0);
    fk0 = fk;
    gf_innovation a, b;
    check(gf_kf2_update(&kf, &meas, &z, &a), "kf2 api update", 0);
    check(floor_kf2_update_api(&fk, &meas, &z, &b), "kf2 api floor", 0);
    (void)gf_kf2_cov(&kf, &s1);
    floor_kf2_cov(&fk, &s2);
    const gf_real tr = s0.m[0][0] + s0.m[1][1];
    check(near(s1.m[0], s2.m[0], 4, tr) && near(kf.mu.v, fk.mu.v, 2, tr) &&
                  near(&a.nis, &b.nis, 1, a.nis)
              ? GF_OK
              : GF_ERR_ARG,
          "kf2 api floor's belief", 0);
    meas.C = (gf_mat2){{{1, 0}, {2, 0}}};
    meas.Q = (gf_mat2){{{0, 0}, {0, 0}}};
    fk = fk0;
    kf = wl_w1_prior[5];
    const gf_status st = gf_kf2_update(&kf, &meas, &z, &a);
    const gf_status fst = floor_kf2_update_api(&fk, &meas, &z, &b);
    check(st == GF_ERR_SINGULAR && fst == GF_ERR_SINGULAR &&
                  memcmp(&fk, &fk0, sizeof fk) == 0
              ? GF_OK
              : GF_ERR_ARG,
          "kf2 api floor's exact duplicate", 0);

    wl_setup_w2(3, 0);
    gf_ekf3 ekf = wl_w2_prior[5];
    gf_mat3 t0, t1, t2;
    (void)gf_ekf3_cov(&ekf, &t0);
    floor_ekf3 fe;
    check(floor_ekf3_init(&fe, &ekf.mu, &t0), "ekf3 api floor init", 0);
    check(gf_ekf3_update(&ekf, &wl_w2_meas, &wl_w2_z[5], &a), "ekf3 api", 0);
    check(floor_ekf3_update_api(&fe, &wl_w2_meas, &wl_w2_z[5], &b),
          "ekf3 api floor", 0);
    (void)gf_ekf3_cov(&ekf, &t1);
    floor_ekf3_cov(&fe, &t2);
    const gf_real tr3 = t0.m[0][0] + t0.m[1][1] + t0.m[2][2];
    check(near(t1.m[0], t2.m[0], 9, tr3) && near(ekf.mu.v, fe.mu.v, 3, tr3) &&
                  near(&a.nis, &b.nis, 1, a.nis)
              ? GF_OK
              : GF_ERR_ARG,
          "ekf3 api floor's belief", 0);
}

int main(void)
{
    empty();
    w1();
    w2("w2", 1);
    w2("w2m2", 2);
    w2("w2m3", 3);
    api_floors();
    for (unsigned k = 0; k < WL_N_ROWS; k++) {
        n_rows(wl_n_names[k]);
    }
    printf("bench done\n");
    return 0;
}
