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
// W1 and W2 also run on the sound floor of bench/ref.c, the step on
// U D U^T by hand, unchecked ("udu"), with the plain API's checks
// ("uduc") and with the prepared path's ("uducp"): after each step
// (outside the region) its belief is held against the library's at the
// same step, and the image prints the largest difference of each row,
//   agree WL PART cov C mu M
// (C: of Sigma, in the correlation form; M: of the mean, in standard
// deviations), ending with exit code 1 beyond AGREE_TOL. The checked
// floors' updates of m > 1 are held against the library's once more with
// a correlated Q, where the whitening shows (rows w1m2q, w2m2q, w2m3q, not
// measured), and on inputs each status rule refuses.
//
// After each report the image prints, over semihosting, one line
//   bench WL PART N
// naming the report (the i-th line names the plugin's i-th report), and
// "bench done" at the end; a failing filter call ends it with exit code 1.
#include <stdio.h>
#include <stdlib.h>

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

// How far a floor may be from the library (float): rounding gives about
// 1e-6; a wrong formula, differences of order 1.
#define AGREE_TOL GF_R(1e-3)

typedef struct agree {
    gf_real cov, mu;
} agree;

static void agree_add(agree *a, gf_real cov, gf_real mu)
{
    a->cov = cov > a->cov ? cov : a->cov;
    a->mu = mu > a->mu ? mu : a->mu;
}

static void agree_report(const agree *a, const char *wl, const char *part)
{
    printf("agree %s %s cov %.2e mu %.2e\n", wl, part, (double)a->cov,
           (double)a->mu);
    if (!(a->cov <= AGREE_TOL && a->mu <= AGREE_TOL)) {
        printf("gf_bench: %s %s is not the library's step\n", wl, part);
        exit(1);
    }
}

// The library's belief after step i of W1 / W2: the stored table's, the
// step loop's own after the last.
static gf_kf2 w1_end;
static gf_ekf3 w2_end;

static void agree_w1(agree *a, const ref_udu2 *r, unsigned i)
{
    gf_real mu;
    const gf_real cov =
        ref_udu2_dev(r, i + 1u < WL_TAB ? &wl_w1_post[i + 1u] : &w1_end, &mu);
    agree_add(a, cov, mu);
}

static void agree_w2(agree *a, const ref_udu3 *r, unsigned i)
{
    gf_real mu;
    const gf_real cov =
        ref_udu3_dev(r, i + 1u < WL_TAB ? &wl_w2_post[i + 1u] : &w2_end, &mu);
    agree_add(a, cov, mu);
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
    w1_end = kf;
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
    // The sound floor: unchecked (R's factors made once), then checked.
    const ref_noise2 rn = ref_noise2_from(&wl_w1_model.R);
    agree ag = {0, 0};
    ref_udu2 ru = ref_udu2_inorder(&wl_w1_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        ref_udu2_predict(&ru, &wl_w1_model, &rn);
        ref_udu2_update(&ru, &wl_w1_meas, &wl_w1_z[i]);
        bench_mark_stop(&ru);
        agree_w1(&ag, &ru, i);
    }
    report("w1", "udu");
    agree_report(&ag, "w1", "udu");
    ag.cov = ag.mu = 0;
    ru = ref_udu2_from(&wl_w1_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        gf_status a = ref_uduc2_predict(&ru, &wl_w1_model, NULL);
        gf_status b = ref_uduc2_update(&ru, &wl_w1_meas, &wl_w1_z[i], &info);
        bench_mark_stop(&ru);
        check(a != GF_OK ? a : b, "w1 uduc", i);
        agree_w1(&ag, &ru, i);
    }
    report("w1", "uduc");
    agree_report(&ag, "w1", "uduc");
    // The same through the prepared path: the models checked and R
    // factored once, before the loop.
    ref_kf2_pmodel pm;
    ref_kf2_pmeas pq;
    check(ref_uducp2_prepare_model(&pm, &wl_w1_model), "w1 uducp", 0);
    check(ref_uducp2_prepare_meas(&pq, &wl_w1_meas), "w1 uducp", 0);
    ag.cov = ag.mu = 0;
    ru = ref_udu2_from(&wl_w1_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        gf_status a = ref_uducp2_predict(&ru, &pm, NULL);
        gf_status b = ref_uducp2_update(&ru, &pq, &wl_w1_z[i], &info);
        bench_mark_stop(&ru);
        check(a != GF_OK ? a : b, "w1 uducp", i);
        agree_w1(&ag, &ru, i);
    }
    report("w1", "uducp");
    agree_report(&ag, "w1", "uducp");
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
    w2_end = ekf;
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
    // The sound floor: unchecked (R's factors made once), then checked.
    void (*const udu_update)(ref_udu3 *, const gf_ekf3_meas *,
                             const gf_vec3 *) = m == 1   ? ref_udu3_update
                                                : m == 2 ? ref_udu3_update_xy
                                                         : ref_udu3_update_xyt;
    const ref_noise3 rn = ref_noise3_from(&wl_w2_motion.R);
    agree ag = {0, 0};
    ref_udu3 ru = ref_udu3_inorder(&wl_w2_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        ref_udu3_predict(&ru, &wl_w2_motion, &rn, wl_w2_u[i]);
        udu_update(&ru, &wl_w2_meas, &wl_w2_z[i]);
        bench_mark_stop(&ru);
        agree_w2(&ag, &ru, i);
    }
    report(name, "udu");
    agree_report(&ag, name, "udu");
    ag.cov = ag.mu = 0;
    ru = ref_udu3_from(&wl_w2_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        gf_status a = ref_uduc3_predict(&ru, &wl_w2_motion, wl_w2_u[i]);
        gf_status b = ref_uduc3_update(&ru, &wl_w2_meas, &wl_w2_z[i], &info);
        bench_mark_stop(&ru);
        check(a != GF_OK ? a : b, "w2 uduc", i);
        agree_w2(&ag, &ru, i);
    }
    report(name, "uduc");
    agree_report(&ag, name, "uduc");
    ref_ekf3_pmotion pm;
    ref_ekf3_pmeas pq;
    check(ref_uducp3_prepare_motion(&pm, &wl_w2_motion), "w2 uducp", 0);
    check(ref_uducp3_prepare_meas(&pq, &wl_w2_meas), "w2 uducp", 0);
    ag.cov = ag.mu = 0;
    ru = ref_udu3_from(&wl_w2_init);
    for (unsigned i = 0; i < WL_TAB; i++) {
        bench_mark_start(&ru);
        gf_status a = ref_uducp3_predict(&ru, &pm, wl_w2_u[i]);
        gf_status b = ref_uducp3_update(&ru, &pq, &wl_w2_z[i], &info);
        bench_mark_stop(&ru);
        check(a != GF_OK ? a : b, "w2 uducp", i);
        agree_w2(&ag, &ru, i);
    }
    report(name, "uducp");
    agree_report(&ag, name, "uducp");
}

// How far a checked floor's innovation is from the library's: the largest
// |y_i - y'_i| / (1 + |y'_i|) and |nis - nis'| / (1 + nis') (y', nis' the
// library's), 1 if m differs.
static gf_real info_dev(const gf_innovation *f, const gf_innovation *l)
{
    gf_real worst = f->m == l->m ? GF_R(0.0) : GF_R(1.0);
    for (unsigned i = 0; i < 3u; i++) {
        const gf_real e =
            GF_FABS(f->y[i] - l->y[i]) / (GF_R(1.0) + GF_FABS(l->y[i]));
        worst = e > worst ? e : worst;
    }
    const gf_real e = GF_FABS(f->nis - l->nis) / (GF_R(1.0) + l->nis);
    return e > worst ? e : worst;
}

static void info_report(gf_real dev, const char *wl)
{
    printf("innovation %s uduc/uducp %.2e\n", wl, (double)dev);
    if (!(dev <= AGREE_TOL)) {
        printf("gf_bench: %s's innovation is not the library's\n", wl);
        exit(1);
    }
}

// KF2 with m = 2 and a correlated Q over W1's table, the library, uduc and
// uducp side by side: C's rows (1, 0) and (0.5, 1), Q = ((10, 2), (2, 3))
// (rho = 0.37), c = (0.1, -0.2); z_1 is half the car's position
// measurement plus its change from the last (numbers all three take
// alike).
static const gf_kf2_meas w1m2q_meas = {
    2u,
    {{{GF_R(1.0), GF_R(0.0)}, {GF_R(0.5), GF_R(1.0)}}},
    {{{GF_R(10.0), GF_R(2.0)}, {GF_R(2.0), GF_R(3.0)}}},
    {{GF_R(0.1), GF_R(-0.2)}},
    GF_R(0.0),
};

static void w1m2q(void)
{
    ref_kf2_pmodel pm;
    ref_kf2_pmeas pq;
    wl_setup_w1();
    check(ref_uducp2_prepare_model(&pm, &wl_w1_model), "w1m2q uducp", 0);
    check(ref_uducp2_prepare_meas(&pq, &w1m2q_meas), "w1m2q uducp", 0);
    gf_kf2 lib = wl_w1_init;
    ref_udu2 fc = ref_udu2_from(&wl_w1_init), fp = fc;
    agree ac = {0, 0}, ap = {0, 0};
    gf_real idev = 0;
    for (unsigned i = 0; i < WL_TAB; i++) {
        const gf_real z0 = wl_w1_z[i].v[0];
        const gf_real dz = z0 - wl_w1_z[i > 0u ? i - 1u : 0u].v[0];
        const gf_vec2 z = {{z0, GF_R(0.5) * z0 + dz}};
        gf_innovation li, ci, pi;
        check(gf_kf2_predict(&lib, &wl_w1_model, NULL), "w1m2q", i);
        check(gf_kf2_update(&lib, &w1m2q_meas, &z, &li), "w1m2q", i);
        check(ref_uduc2_predict(&fc, &wl_w1_model, NULL), "w1m2q uduc", i);
        check(ref_uduc2_update(&fc, &w1m2q_meas, &z, &ci), "w1m2q uduc", i);
        check(ref_uducp2_predict(&fp, &pm, NULL), "w1m2q uducp", i);
        check(ref_uducp2_update(&fp, &pq, &z, &pi), "w1m2q uducp", i);
        gf_real mu;
        gf_real cov = ref_udu2_dev(&fc, &lib, &mu);
        agree_add(&ac, cov, mu);
        cov = ref_udu2_dev(&fp, &lib, &mu);
        agree_add(&ap, cov, mu);
        const gf_real e = info_dev(&ci, &li), ep = info_dev(&pi, &li);
        idev = e > idev ? e : idev;
        idev = ep > idev ? ep : idev;
    }
    agree_report(&ac, "w1m2q", "uduc");
    agree_report(&ap, "w1m2q", "uducp");
    info_report(idev, "w1m2q");
}

// EKF3 with m = 2 (gf_ekf3_meas_xy) and m = 3 (wl_meas_xyt, the heading's
// residual wrapped) and a correlated Q over W2's table (wl_setup_w2's
// motion and measurements), as w1m2q: Q = ((0.01, 0.006), (0.006, 0.02))
// for m = 2, and for m = 3 its 3 x 3 with the heading's variance 0.0025
// coupled to x and y (0.001, -0.002).
static void w2q(const char *name, unsigned m)
{
    wl_setup_w2(m, 0);
    gf_ekf3_meas meas = wl_w2_meas;
    meas.Q.m[0][0] = GF_R(0.01);
    meas.Q.m[0][1] = meas.Q.m[1][0] = GF_R(0.006);
    meas.Q.m[1][1] = GF_R(0.02);
    if (m == 3u) {
        meas.Q.m[0][2] = meas.Q.m[2][0] = GF_R(0.001);
        meas.Q.m[1][2] = meas.Q.m[2][1] = GF_R(-0.002);
        meas.Q.m[2][2] = GF_R(0.0025);
    }
    ref_ekf3_pmotion pm;
    ref_ekf3_pmeas pq;
    check(ref_uducp3_prepare_motion(&pm, &wl_w2_motion), name, 0);
    check(ref_uducp3_prepare_meas(&pq, &meas), name, 0);
    gf_ekf3 lib = wl_w2_init;
    ref_udu3 fc = ref_udu3_from(&wl_w2_init), fp = fc;
    agree ac = {0, 0}, ap = {0, 0};
    gf_real idev = 0;
    for (unsigned i = 0; i < WL_TAB; i++) {
        const gf_real *u = wl_w2_u[i];
        const gf_vec3 *z = &wl_w2_z[i];
        gf_innovation li, ci, pi;
        check(gf_ekf3_predict(&lib, &wl_w2_motion, u), name, i);
        check(gf_ekf3_update(&lib, &meas, z, &li), name, i);
        check(ref_uduc3_predict(&fc, &wl_w2_motion, u), name, i);
        check(ref_uduc3_update(&fc, &meas, z, &ci), name, i);
        check(ref_uducp3_predict(&fp, &pm, u), name, i);
        check(ref_uducp3_update(&fp, &pq, z, &pi), name, i);
        gf_real mu;
        gf_real cov = ref_udu3_dev(&fc, &lib, &mu);
        agree_add(&ac, cov, mu);
        cov = ref_udu3_dev(&fp, &lib, &mu);
        agree_add(&ap, cov, mu);
        const gf_real e = info_dev(&ci, &li), ep = info_dev(&pi, &li);
        idev = e > idev ? e : idev;
        idev = ep > idev ? ep : idev;
    }
    agree_report(&ac, name, "uduc");
    agree_report(&ap, name, "uducp");
    info_report(idev, name);
}

// The checked floors' updates against the library's on inputs each status
// rule refuses, from one stored prior (W1's, with w1m2q's model; W2's,
// with w2q's m = 3 model): the statuses equal, and info on GF_ERR_GATED.
static void status_case(const char *what, gf_status lib, gf_status fl,
                        const gf_innovation *li, const gf_innovation *fi)
{
    if (lib != fl ||
        (lib == GF_ERR_GATED && !(info_dev(fi, li) <= AGREE_TOL))) {
        printf("gf_bench: %s: the library returns %d, the floor %d\n", what,
               (int)lib, (int)fl);
        exit(1);
    }
}

static void kf2_case(const char *what, const gf_kf2_meas *meas, gf_vec2 z)
{
    gf_kf2 lib = wl_w1_prior[100];
    ref_udu2 fl = ref_udu2_from(&lib);
    gf_innovation li = {0, {0, 0, 0}, 0}, fi = li;
    const gf_status a = gf_kf2_update(&lib, meas, &z, &li);
    const gf_status b = ref_uduc2_update(&fl, meas, &z, &fi);
    status_case(what, a, b, &li, &fi);
}

static void ekf3_case(const char *what, const gf_ekf3_meas *meas, gf_vec3 z)
{
    gf_ekf3 lib = wl_w2_prior[100];
    ref_udu3 fl = ref_udu3_from(&lib);
    gf_innovation li = {0, {0, 0, 0}, 0}, fi = li;
    const gf_status a = gf_ekf3_update(&lib, meas, &z, &li);
    const gf_status b = ref_uduc3_update(&fl, meas, &z, &fi);
    status_case(what, a, b, &li, &fi);
}

static void statuses(void)
{
    const gf_real qnan = GF_R(0.0) / GF_R(0.0);
    wl_setup_w1();
    const gf_vec2 z2 = wl_w1_z[100];
    gf_kf2_meas k = w1m2q_meas;
    k.m = 3u;
    kf2_case("kf2 m = 3", &k, z2);
    k = w1m2q_meas;
    k.Q.m[0][1] = qnan;
    kf2_case("kf2 Q NaN", &k, z2);
    k = w1m2q_meas;
    k.Q.m[0][1] = k.Q.m[1][0] = GF_R(6.0);
    kf2_case("kf2 Q indefinite", &k, z2);
    k = w1m2q_meas;
    k.Q.m[1][0] = GF_R(2.5);
    kf2_case("kf2 Q not symmetric", &k, z2);
    k = w1m2q_meas;
    k.C.m[1][0] = GF_R(1.0) / GF_R(0.0);
    kf2_case("kf2 C inf", &k, z2);
    k = w1m2q_meas;
    gf_vec2 zn = z2;
    zn.v[1] = qnan;
    kf2_case("kf2 z NaN", &k, zn);
    k.gate = GF_R(-1.0);
    kf2_case("kf2 gate < 0", &k, z2);
    k.gate = GF_R(1e-6);
    kf2_case("kf2 gated", &k, z2);
    k = w1m2q_meas;
    k.C.m[1][0] = GF_R(1.0);
    k.C.m[1][1] = GF_R(0.0);
    k.Q.m[0][0] = k.Q.m[0][1] = k.Q.m[1][0] = k.Q.m[1][1] = GF_R(1.0);
    kf2_case("kf2 one quantity twice, Q singular", &k, z2);
    k.Q.m[0][0] = k.Q.m[0][1] = k.Q.m[1][0] = k.Q.m[1][1] = GF_R(0.0);
    kf2_case("kf2 one quantity twice, exact", &k, z2);

    wl_setup_w2(3, 0);
    const gf_vec3 z3 = wl_w2_z[100];
    gf_ekf3_meas e = wl_w2_meas;
    e.m = 4u;
    ekf3_case("ekf3 m = 4", &e, z3);
    e = wl_w2_meas;
    e.Q.m[2][1] = qnan;
    ekf3_case("ekf3 Q NaN", &e, z3);
    e = wl_w2_meas;
    e.Q.m[0][2] = e.Q.m[2][0] = GF_R(0.01);
    ekf3_case("ekf3 Q indefinite", &e, z3);
    e = wl_w2_meas;
    gf_vec3 zn3 = z3;
    zn3.v[2] = qnan;
    ekf3_case("ekf3 z NaN", &e, zn3);
    e.gate = GF_R(1e-6);
    ekf3_case("ekf3 gated", &e, z3);
    e = wl_w2_meas;
    e.m = 2u;
    e.h = gf_ekf3_meas_xy;
    e.Q.m[0][1] = e.Q.m[1][0] = GF_R(0.02);
    ekf3_case("ekf3 m = 2, Q indefinite", &e, z3);
    e.Q.m[0][1] = GF_R(0.0);
    e.Q.m[1][0] = GF_R(0.0);
    e.gate = GF_R(1e-6);
    ekf3_case("ekf3 m = 2, gated", &e, z3);
    printf("statuses: the checked floor's m > 1 statuses are the library's\n");
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

int main(void)
{
    empty();
    w1();
    w2("w2", 1);
    w2("w2m2", 2);
    w2("w2m3", 3);
    w1m2q();
    w2q("w2m2q", 2);
    w2q("w2m3q", 3);
    statuses();
    for (unsigned k = 0; k < WL_N_ROWS; k++) {
        n_rows(wl_n_names[k]);
    }
    printf("bench done\n");
    return 0;
}
