// SPDX-License-Identifier: MIT
// libFuzzer target for the core API: the input is a little program of
// calls (init, predict, update of KF2 and EKF3 with arbitrary models,
// beliefs and measurements, and the matrix and covariance helpers), each
// with its arguments taken from the input. After every call it asserts the
// contract of include/gaussfilt:
//
//  - the status is GF_OK or one of the named error codes;
//  - on GF_OK the belief is finite and its covariance (as gf_kf2_cov and
//    gf_ekf3_cov read it from the factors) finite and exactly symmetric,
//    and the innovation's NIS is finite;
//  - on any error the belief is bit-for-bit unchanged, and so are the
//    outputs a failing call must not write (info unless gated, inverses,
//    factors, eigenvalues, ellipses).
//
// Built with clang -fsanitize=fuzzer,address,undefined (scripts/fuzz), once
// with gf_real = double and once with -DGF_SINGLE_PRECISION. A broken
// contract calls abort(), which libFuzzer reports with the input.
//
// Argument encoding: a real is one selector byte s, then
//   s <  200: (s - 100) / 4, the grid -25 .. 24.75 in steps of 0.25;
//   s <  240: an entry of `special` below (scales, extremes, -0, pi);
//   s >= 240: the next sizeof(gf_real) bytes as raw bits (NaN, inf,
//             subnormals, anything).
// A missing byte reads as 0.
#include <float.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gaussfilt/gaussfilt.h"

#ifdef GF_SINGLE_PRECISION
#define REAL_MAX FLT_MAX
#define REAL_MIN FLT_MIN

#else
#define REAL_MAX DBL_MAX
#define REAL_MIN DBL_MIN

#endif

typedef struct cursor {
    const uint8_t *p;
    size_t n;
} cursor;

static uint8_t byte(cursor *c)
{
    if (c->n == 0) {
        return 0;
    }
    c->n--;
    return *c->p++;
}

static const gf_real special[] = {
    GF_R(0.0),
    -GF_R(0.0),
    GF_R(1e-3),
    GF_R(0.01),
    GF_R(0.1),
    GF_R(100.0),
    GF_R(1e4),
    GF_R(1e6),
    GF_R(1e-6),
    GF_R(1e-12),
    GF_R(1e12),
    GF_R(1e-30),
    GF_R(1e30),
    REAL_MAX,
    -REAL_MAX,
    REAL_MIN,
    REAL_MIN *GF_REAL_EPSILON,
    GF_PI,
    -GF_PI,
    GF_R(0.5) * GF_PI,
    GF_R(2.0) * GF_PI,
    GF_REAL_EPSILON,
    GF_R(1.0) + GF_REAL_EPSILON,
    GF_R(1.0) - GF_REAL_EPSILON,
    GF_R(0.25),
    GF_R(10.0),
    GF_R(-0.7),
    GF_R(0.68),
};

static gf_real real(cursor *c)
{
    uint8_t s = byte(c);
    if (s < 200) {
        return (gf_real)((int)s - 100) / GF_R(4.0);
    }
    if (s < 240) {
        return special[(size_t)(s - 200) %
                       (sizeof special / sizeof special[0])];
    }
    unsigned char raw[sizeof(gf_real)];
    for (size_t i = 0; i < sizeof raw; i++) {
        raw[i] = byte(c);
    }
    gf_real x;
    memcpy(&x, raw, sizeof x);
    return x;
}

static void vec2(cursor *c, gf_vec2 *v)
{
    v->v[0] = real(c);
    v->v[1] = real(c);
}

static void vec3(cursor *c, gf_vec3 *v)
{
    for (int i = 0; i < 3; i++) {
        v->v[i] = real(c);
    }
}

static void mat2(cursor *c, gf_mat2 *a)
{
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 2; j++) {
            a->m[i][j] = real(c);
        }
    }
}

// A symmetric matrix most of the time (what a covariance should be), an
// arbitrary one when the flag byte's low bit is set.
static void cov2(cursor *c, gf_mat2 *a)
{
    int any = byte(c) & 1;
    mat2(c, a);
    if (!any) {
        a->m[1][0] = a->m[0][1];
    }
}

static void mat3(cursor *c, gf_mat3 *a)
{
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            a->m[i][j] = real(c);
        }
    }
}

static void cov3(cursor *c, gf_mat3 *a)
{
    int any = byte(c) & 1;
    mat3(c, a);
    if (!any) {
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < i; j++) {
                a->m[i][j] = a->m[j][i];
            }
        }
    }
}

#define REQUIRE(cond)                                                          \
    do {                                                                       \
        if (!(cond)) {                                                         \
            fprintf(stderr, "contract broken: %s (%s:%d)\n", #cond, __FILE__,  \
                    __LINE__);                                                 \
            abort();                                                           \
        }                                                                      \
    } while (0)

static int known_status(gf_status st)
{
    return st <= GF_OK && st >= GF_ERR_MODEL;
}

static int finite_n(const gf_real *x, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (!GF_ISFINITE(x[i])) {
            return 0;
        }
    }
    return 1;
}

static void check_kf2(gf_status st, const gf_kf2 *now, const gf_kf2 *before)
{
    REQUIRE(known_status(st));
    if (st == GF_OK) {
        gf_mat2 sigma;
        REQUIRE(gf_kf2_cov(now, &sigma) == GF_OK);
        REQUIRE(finite_n(now->mu.v, 2));
        REQUIRE(finite_n(&sigma.m[0][0], 4));
        REQUIRE(sigma.m[0][1] == sigma.m[1][0]);
    } else {
        REQUIRE(memcmp(now, before, sizeof *now) == 0);
    }
}

static void check_ekf3(gf_status st, const gf_ekf3 *now, const gf_ekf3 *before)
{
    REQUIRE(known_status(st));
    if (st == GF_OK) {
        gf_mat3 sigma;
        REQUIRE(gf_ekf3_cov(now, &sigma) == GF_OK);
        REQUIRE(finite_n(now->mu.v, 3));
        REQUIRE(finite_n(&sigma.m[0][0], 9));
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < i; j++) {
                REQUIRE(sigma.m[i][j] == sigma.m[j][i]);
            }
        }
        REQUIRE(now->mu.v[2] > -GF_PI && now->mu.v[2] <= GF_PI);
    } else {
        REQUIRE(memcmp(now, before, sizeof *now) == 0);
    }
}

// The innovation after an update: written with a finite NIS on GF_OK and
// GF_ERR_GATED, untouched otherwise.
static void check_info(gf_status st, const gf_innovation *info,
                       const gf_innovation *before, unsigned m)
{
    if (st == GF_OK || st == GF_ERR_GATED) {
        REQUIRE(info->m == m);
        REQUIRE(GF_ISFINITE(info->nis));
        REQUIRE(finite_n(info->y, m));
    } else {
        REQUIRE(memcmp(info, before, sizeof *info) == 0);
    }
}

// A caller-supplied EKF3 model whose outputs (and status) come from the
// input: it may return anything, including NaN Jacobians and bad statuses.
typedef struct fuzz_model {
    gf_vec3 out;
    gf_mat3 jac;
    int status;
    int write; // 0: writes nothing at all
} fuzz_model;

static gf_status fuzz_motion(void *ctx, const gf_vec3 *mu, const gf_real *u,
                             gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)mu;
    (void)u;
    const fuzz_model *fm = ctx;
    if (fm->write) {
        *mu_bar = fm->out;
        *G = fm->jac;
    }
    return (gf_status)fm->status;
}

static gf_status fuzz_meas(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                           gf_mat3 *H)
{
    (void)mu_bar;
    const fuzz_model *fm = ctx;
    if (fm->write) {
        *z_hat = fm->out;
        *H = fm->jac;
    }
    return (gf_status)fm->status;
}

static void fuzz_model_read(cursor *c, fuzz_model *fm)
{
    uint8_t flags = byte(c);
    vec3(c, &fm->out);
    mat3(c, &fm->jac);
    fm->write = !(flags & 1);
    // Mostly OK; sometimes a named error; sometimes out of the enum range.
    fm->status = (flags & 6) == 6 ? (int)(int8_t)byte(c)
                                  : ((flags & 6) == 4 ? GF_ERR_MODEL : GF_OK);
}

static void op_kf2(cursor *c, uint8_t op, gf_kf2 *kf)
{
    gf_kf2 before = *kf;
    gf_status st;
    if (op == 0) {
        gf_vec2 mu;
        gf_mat2 s;
        vec2(c, &mu);
        cov2(c, &s);
        st = gf_kf2_init(kf, &mu, &s);
        check_kf2(st, kf, &before);
        if (st == GF_OK) {
            REQUIRE(memcmp(&kf->mu, &mu, sizeof mu) == 0);
        }
    } else if (op == 1) {
        gf_kf2_model model;
        gf_vec2 u;
        mat2(c, &model.A);
        mat2(c, &model.B);
        cov2(c, &model.R);
        vec2(c, &model.c);
        vec2(c, &u);
        int with_u = byte(c) & 1;
        st = gf_kf2_predict(kf, &model, with_u ? &u : NULL);
        check_kf2(st, kf, &before);
    } else {
        gf_kf2_meas meas;
        gf_vec2 z;
        gf_innovation info, info_before;
        meas.m = byte(c) % 4; // 0 and 3 are out of range
        mat2(c, &meas.C);
        cov2(c, &meas.Q);
        vec2(c, &meas.c);
        meas.gate = (byte(c) & 1) ? real(c) : 0;
        vec2(c, &z);
        memset(&info, 0xA5, sizeof info);
        info_before = info;
        st = gf_kf2_update(kf, &meas, &z, &info);
        check_kf2(st, kf, &before);
        check_info(st, &info, &info_before, meas.m);
        if (st == GF_ERR_GATED) {
            REQUIRE(info.nis > meas.gate);
        }
    }
}

static void op_ekf3(cursor *c, uint8_t op, gf_ekf3 *ekf)
{
    gf_ekf3 before = *ekf;
    gf_status st;
    fuzz_model fm;
    if (op == 3) {
        gf_vec3 mu;
        gf_mat3 s;
        vec3(c, &mu);
        cov3(c, &s);
        st = gf_ekf3_init(ekf, &mu, &s);
        check_ekf3(st, ekf, &before);
    } else if (op == 4) {
        gf_ekf3_motion motion;
        gf_real u[2];
        uint8_t which = byte(c);
        u[0] = real(c);
        u[1] = real(c);
        cov3(c, &motion.R);
        motion.ctx = NULL;
        motion.g = gf_ekf3_motion_forward_turn;
        if (which & 1) {
            fuzz_model_read(c, &fm);
            motion.g = fuzz_motion;
            motion.ctx = &fm;
        }
        st = gf_ekf3_predict(ekf, &motion, (which & 2) ? NULL : u);
        check_ekf3(st, ekf, &before);
    } else {
        gf_ekf3_meas meas;
        gf_vec3 z;
        gf_innovation info, info_before;
        uint8_t which = byte(c);
        meas.m = byte(c) % 5; // 0 and 4 are out of range
        meas.h = (which & 1) ? gf_ekf3_meas_xy : gf_ekf3_meas_x;
        meas.ctx = NULL;
        if (which & 2) {
            fuzz_model_read(c, &fm);
            meas.h = fuzz_meas;
            meas.ctx = &fm;
        }
        cov3(c, &meas.Q);
        meas.angle_mask = byte(c);
        meas.gate = (which & 4) ? real(c) : 0;
        vec3(c, &z);
        memset(&info, 0xA5, sizeof info);
        info_before = info;
        st = gf_ekf3_update(ekf, &meas, &z, &info);
        check_ekf3(st, ekf, &before);
        check_info(st, &info, &info_before, meas.m);
        if (st == GF_ERR_GATED) {
            REQUIRE(info.nis > meas.gate);
        }
    }
}

// The helpers: outputs written only on success, and sane when written.
static void op_helpers(cursor *c, uint8_t op)
{
    gf_mat2 s2;
    gf_mat3 s3;
    unsigned char sentinel[sizeof(gf_mat3) + sizeof(gf_real)];
    memset(sentinel, 0x5A, sizeof sentinel);
    switch (op % 6) {
    case 0: {
        cov2(c, &s2);
        gf_real rho;
        memcpy(&rho, sentinel, sizeof rho);
        gf_status st = gf_cov2_correlation(&s2, &rho);
        REQUIRE(known_status(st));
        if (st == GF_OK) {
            REQUIRE(rho >= -1 && rho <= 1);
        } else {
            REQUIRE(memcmp(&rho, sentinel, sizeof rho) == 0);
        }
        break;
    }
    case 1: {
        cov2(c, &s2);
        gf_real p = real(c);
        gf_ellipse e;
        memcpy(&e, sentinel, sizeof e);
        gf_status st = gf_cov2_ellipse(&s2, p, &e);
        REQUIRE(known_status(st));
        if (st == GF_OK) {
            REQUIRE(finite_n(&e.a, 3));
            REQUIRE(e.a >= e.b && e.b >= 0);
            REQUIRE(e.angle > -GF_R(0.5) * GF_PI - GF_REAL_EPSILON &&
                    e.angle <= GF_R(0.5) * GF_PI + GF_REAL_EPSILON);
        } else {
            REQUIRE(memcmp(&e, sentinel, sizeof e) == 0);
        }
        break;
    }
    case 2: {
        cov2(c, &s2);
        gf_mat2 inv;
        memcpy(&inv, sentinel, sizeof inv);
        gf_status st = gf_mat2_spd_inv(&s2, &inv);
        REQUIRE(known_status(st));
        if (st == GF_OK) {
            REQUIRE(finite_n(&inv.m[0][0], 4));
            REQUIRE(inv.m[0][0] > 0 && inv.m[1][1] > 0);
        } else {
            REQUIRE(memcmp(&inv, sentinel, sizeof inv) == 0);
        }
        (void)gf_mat2_check_psd(&s2);
        break;
    }
    case 3: {
        cov2(c, &s2);
        gf_vec2 lambda;
        gf_real angle;
        memcpy(&lambda, sentinel, sizeof lambda);
        memcpy(&angle, sentinel, sizeof angle);
        gf_status st = gf_mat2_eig_sym(&s2, &lambda, &angle);
        REQUIRE(known_status(st));
        if (st != GF_OK) {
            REQUIRE(memcmp(&lambda, sentinel, sizeof lambda) == 0);
            REQUIRE(memcmp(&angle, sentinel, sizeof angle) == 0);
        }
        break;
    }
    case 4: {
        cov3(c, &s3);
        unsigned n = byte(c) % 5;
        gf_mat3 l;
        memcpy(&l, sentinel, sizeof l);
        gf_status st = gf_mat3_chol(&s3, n, &l);
        REQUIRE(known_status(st));
        if (st == GF_OK) {
            REQUIRE(n >= 1 && n <= 3);
            REQUIRE(finite_n(&l.m[0][0], 9));
            for (unsigned i = 0; i < n; i++) {
                REQUIRE(l.m[i][i] > 0);
            }
            gf_vec3 b, x;
            vec3(c, &b);
            gf_mat3_chol_solve(&l, n, &b, &x);
        } else {
            REQUIRE(memcmp(&l, sentinel, sizeof l) == 0);
        }
        (void)gf_mat3_check_psd(&s3, n);
        unsigned i = byte(c) % 4, j = byte(c) % 4;
        gf_mat2 marg;
        memcpy(&marg, sentinel, sizeof marg);
        st = gf_cov2_marginal(&s3, i, j, &marg);
        REQUIRE(st == ((i > 2 || j > 2) ? GF_ERR_ARG : GF_OK));
        if (st != GF_OK) {
            REQUIRE(memcmp(&marg, sentinel, sizeof marg) == 0);
        }
        break;
    }
    default: {
        gf_real a = real(c);
        gf_real w = gf_angle_wrap(a);
        if (GF_ISFINITE(a)) {
            REQUIRE(w > -GF_PI && w <= GF_PI);
        }
        break;
    }
    }
}

// NULL where the API promises GF_ERR_ARG.
static void op_nulls(cursor *c, gf_kf2 *kf, gf_ekf3 *ekf)
{
    gf_kf2 kb = *kf;
    gf_ekf3 eb = *ekf;
    const gf_vec2 mu2 = {{0, 0}};
    const gf_mat2 s2 = {{{1, 0}, {0, 1}}};
    const gf_vec3 mu3 = {{0, 0, 0}};
    const gf_mat3 s3 = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    gf_real r;
    switch (byte(c) % 10) {
    case 0:
        REQUIRE(gf_kf2_init(kf, NULL, &s2) == GF_ERR_ARG);
        break;
    case 1:
        REQUIRE(gf_kf2_init(kf, &mu2, NULL) == GF_ERR_ARG);
        break;
    case 2:
        REQUIRE(gf_kf2_predict(kf, NULL, NULL) == GF_ERR_ARG);
        break;
    case 3:
        REQUIRE(gf_kf2_update(kf, NULL, &mu2, NULL) == GF_ERR_ARG);
        break;
    case 4:
        REQUIRE(gf_ekf3_init(ekf, NULL, &s3) == GF_ERR_ARG);
        break;
    case 5:
        REQUIRE(gf_ekf3_init(ekf, &mu3, NULL) == GF_ERR_ARG);
        break;
    case 6:
        REQUIRE(gf_ekf3_predict(ekf, NULL, NULL) == GF_ERR_ARG);
        break;
    case 7:
        REQUIRE(gf_ekf3_update(ekf, NULL, &mu3, NULL) == GF_ERR_ARG);
        break;
    case 8:
        REQUIRE(gf_cov2_correlation(NULL, &r) == GF_ERR_ARG);
        break;
    default:
        REQUIRE(gf_kf2_init(NULL, &mu2, &s2) == GF_ERR_ARG);
        break;
    }
    REQUIRE(memcmp(kf, &kb, sizeof kb) == 0);
    REQUIRE(memcmp(ekf, &eb, sizeof eb) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cursor c = {data, size};
    // Start from the books' beliefs: the car at rest, the robot of
    // exercise 4.
    gf_kf2 kf;
    gf_ekf3 ekf;
    const gf_vec2 mu2 = {{0, 0}};
    const gf_mat2 s2 = {{{0, 0}, {0, 0}}};
    const gf_vec3 mu3 = {{0, 0, 0}};
    const gf_mat3 s3 = {
        {{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, 10000}}};
    REQUIRE(gf_kf2_init(&kf, &mu2, &s2) == GF_OK);
    REQUIRE(gf_ekf3_init(&ekf, &mu3, &s3) == GF_OK);
    const char *st = gf_status_str(GF_OK);
    REQUIRE(st != NULL);
    for (int ops = 0; ops < 256 && c.n > 0; ops++) {
        uint8_t op = byte(&c);
        REQUIRE(gf_status_str((gf_status)(int8_t)op) != NULL);
        switch (op % 8) {
        case 0:
        case 1:
        case 2:
            op_kf2(&c, op % 8, &kf);
            break;
        case 3:
        case 4:
        case 5:
            op_ekf3(&c, op % 8, &ekf);
            break;
        case 6:
            op_helpers(&c, (uint8_t)(op / 8));
            break;
        default:
            op_nulls(&c, &kf, &ekf);
            break;
        }
    }
    return 0;
}
