// SPDX-License-Identifier: MIT
// The Cortex-M4F benchmark image: the workloads of workloads.h, run once
// each on QEMU's mps2-an386 under the insncount plugin (bench/qemu/), which
// counts the instructions executed between bench_mark_start and
// bench_mark_stop and prints its totals at each bench_mark_report. Each
// measured call (or predict + update pair) is one region, so the set-up,
// the loop and the copies of the stored beliefs are outside; the empty
// region ("empty"), run first, is what the markers themselves cost.
//
// After each report the image prints, over semihosting, one line
//   bench WL PART N
// naming the report (the i-th line names the plugin's i-th report), and
// "bench done" at the end; a failing filter call ends it with exit code 1.
#include <stdio.h>

#include "gaussfilt/gaussfilt.h"
#include "ref.h"
#include "workloads.h"

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
                             const gf_vec3 *) =
        m == 1 ? ref_ekf3_update
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
}

int main(void)
{
    empty();
    w1();
    w2("w2", 1);
    w2("w2m2", 2);
    w2("w2m3", 3);
    printf("bench done\n");
    return 0;
}
