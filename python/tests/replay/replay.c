// SPDX-License-Identifier: MIT
// gf_replay: runs a scenario file through libgaussfilt.a and writes every
// belief, so that python/tests/test_bitexact.py can compare the Python
// package with the C library built elsewhere, bit for bit: on the host
// (replay IN OUT) and on the Cortex-M4F under QEMU (GF_REPLAY_FIXED_FILES:
// replay.in and replay.out in QEMU's working directory, over
// semihosting).
//
// The scenario (python/tests/scenarios.py writes it; little-endian): the
// 4 bytes "GFRP", a u32 sizeof(gf_real), then operations, each a u32 code
// and its operands (u32 sizes and flags, gf_real numbers), ending with
// code 0. After each operation the driver writes an i32 status, a u32 n,
// the belief's mu (n) and Sigma (n x n, from the _cov accessor), and after
// an update that ran (GF_OK or GF_ERR_GATED) the NIS and the innovation
// (m entries).
//
//   replay IN OUT            the scenario
//   replay --bench-kf2 N     the C loop of the KF2 benchmark (host): the
//                            ns per predict + update, printed
#ifndef GF_REPLAY_FIXED_FILES
#define _POSIX_C_SOURCE 199309L // clock_gettime
#endif
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "gaussfilt/ekf.h"
#include "gaussfilt/ekf3.h"
#include "gaussfilt/kf.h"
#include "gaussfilt/kf2.h"

#ifndef GF_REPLAY_FIXED_FILES
#include <stdlib.h>
#include <time.h>
#endif

enum {
    OP_END = 0,
    OP_KF2_INIT = 1,
    OP_KF2_PREDICT = 2,
    OP_KF2_UPDATE = 3,
    OP_KF_INIT = 4,
    OP_KF_PREDICT = 5,
    OP_KF_UPDATE = 6,
    OP_EKF3_INIT = 7,
    OP_EKF3_PREDICT = 8,
    OP_EKF3_UPDATE = 9,
    OP_EKF_INIT = 10,
    OP_EKF_PREDICT = 11,
    OP_EKF_UPDATE = 12,
};

#define IO_BYTES (1u << 20)
static unsigned char in[IO_BYTES], out[IO_BYTES];
static size_t in_len, in_pos, out_len;
static int malformed;

static uint32_t rd_u32(void)
{
    uint32_t v = 0;
    if (in_pos + 4 > in_len) {
        malformed = 1;
        return 0;
    }
    for (int i = 3; i >= 0; i--) {
        v = (v << 8) | in[in_pos + (size_t)i];
    }
    in_pos += 4;
    return v;
}

static void rd_reals(gf_real *dst, size_t count)
{
    if (in_pos + count * sizeof(gf_real) > in_len) {
        malformed = 1;
        memset(dst, 0, count * sizeof(gf_real));
        return;
    }
    memcpy(dst, in + in_pos, count * sizeof(gf_real));
    in_pos += count * sizeof(gf_real);
}

static void wr(const void *src, size_t bytes)
{
    if (out_len + bytes > IO_BYTES) {
        malformed = 1;
        return;
    }
    memcpy(out + out_len, src, bytes);
    out_len += bytes;
}

static void wr_record(gf_status st, unsigned n, const gf_real *mu,
                      const gf_real *sigma)
{
    int32_t s = (int32_t)st;
    uint32_t nn = n;
    wr(&s, 4);
    wr(&nn, 4);
    wr(mu, n * sizeof(gf_real));
    wr(sigma, (size_t)n * n * sizeof(gf_real));
}

static void wr_info(gf_status st, gf_real nis, const gf_real *y, unsigned m)
{
    if (st == GF_OK || st == GF_ERR_GATED) {
        wr(&nis, sizeof nis);
        wr(y, m * sizeof(gf_real));
    }
}

// ---- the test models of the any-size EKF (python/tests/scenarios.py has
// the same arithmetic, operation for operation) --------------------------

#define DT GF_R(0.1)
#define K3 GF_R(0.01)
#define K3X3 GF_R(0.03)
#define HALF GF_R(0.5)
#define ONE GF_R(1.0)

// mu_bar_i = mu_i + DT mu_j - K3 mu_i^3 + u_i, j = (i + 1) mod n;
// G_ii = 1 - 3 K3 mu_i^2, G_ij = DT.
static gf_status cubic(void *ctx, unsigned n, const gf_real *mu,
                       const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    (void)ctx;
    for (unsigned i = 0; i < n; i++) {
        unsigned j = (i + 1u) % n;
        mu_bar[i] = mu[i] + DT * mu[j] - K3 * mu[i] * mu[i] * mu[i] + u[i];
        G[i * n + i] = ONE - K3X3 * mu[i] * mu[i];
        G[i * n + j] = DT;
    }
    return GF_OK;
}

// z_k = mu_k + HALF mu_k mu_j, j = (k + 1) mod n; H_kk = 1 + HALF mu_j,
// H_kj = HALF mu_k.
static gf_status bilinear(void *ctx, unsigned n, unsigned m, const gf_real *mu,
                          gf_real *z_hat, gf_real *H)
{
    (void)ctx;
    for (unsigned k = 0; k < m; k++) {
        unsigned j = (k + 1u) % n;
        z_hat[k] = mu[k] + HALF * mu[k] * mu[j];
        H[k * n + k] = ONE + HALF * mu[j];
        H[k * n + j] = HALF * mu[k];
    }
    return GF_OK;
}

// ---- the replay -----------------------------------------------------------

static gf_kf2 kf2;
static gf_ekf3 ekf3;
static gf_kf kf;
static gf_kf_work work;
static gf_real A[GF_KF_NMAX * GF_KF_NMAX], B[GF_KF_NMAX * GF_KF_NMAX],
    R[GF_KF_NMAX * GF_KF_NMAX], C[GF_KF_NMAX * GF_KF_NMAX],
    Q[GF_KF_NMAX * GF_KF_NMAX], S[GF_KF_NMAX * GF_KF_NMAX], c[GF_KF_NMAX],
    v[GF_KF_NMAX], z[GF_KF_NMAX];

static void kf2_record(gf_status st)
{
    gf_mat2 s;
    (void)gf_kf2_cov(&kf2, &s);
    wr_record(st, 2, kf2.mu.v, &s.m[0][0]);
}

static void ekf3_record(gf_status st)
{
    gf_mat3 s;
    (void)gf_ekf3_cov(&ekf3, &s);
    wr_record(st, 3, ekf3.mu.v, &s.m[0][0]);
}

static void kf_record(gf_status st)
{
    (void)gf_kf_cov(&kf, S);
    wr_record(st, kf.n, kf.mu, S);
}

// One operation; 0 at the end, -1 on a malformed scenario.
static int replay_op(void)
{
    uint32_t op = rd_u32(), m, nu, flag, flag2;
    gf_status st;
    unsigned n = kf.n;
    switch (op) {
    case OP_END:
        return 0;
    case OP_KF2_INIT: {
        gf_vec2 mu;
        gf_mat2 s;
        rd_reals(mu.v, 2);
        rd_reals(&s.m[0][0], 4);
        kf2_record(gf_kf2_init(&kf2, &mu, &s));
        break;
    }
    case OP_KF2_PREDICT: {
        gf_kf2_model mo;
        gf_vec2 u;
        rd_reals(&mo.A.m[0][0], 4);
        rd_reals(&mo.B.m[0][0], 4);
        rd_reals(&mo.R.m[0][0], 4);
        rd_reals(mo.c.v, 2);
        flag = rd_u32();
        rd_reals(u.v, 2);
        kf2_record(gf_kf2_predict(&kf2, &mo, flag ? &u : NULL));
        break;
    }
    case OP_KF2_UPDATE: {
        gf_kf2_meas me;
        gf_vec2 zz = {{0, 0}};
        gf_innovation info;
        memset(&me, 0, sizeof me);
        me.m = m = rd_u32();
        if (m < 1 || m > 2) {
            return -1;
        }
        for (unsigned i = 0; i < m; i++) {
            rd_reals(me.C.m[i], 2);
        }
        for (unsigned i = 0; i < m; i++) {
            rd_reals(me.Q.m[i], m);
        }
        rd_reals(me.c.v, m);
        rd_reals(&me.gate, 1);
        rd_reals(zz.v, m);
        st = gf_kf2_update(&kf2, &me, &zz, &info);
        kf2_record(st);
        wr_info(st, info.nis, info.y, m);
        break;
    }
    case OP_KF_INIT:
        n = rd_u32();
        if (n < 1 || n > GF_KF_NMAX) {
            return -1;
        }
        rd_reals(v, n);
        rd_reals(S, (size_t)n * n);
        st = gf_kf_init(&kf, n, v, S, &work);
        kf_record(st);
        break;
    case OP_KF_PREDICT: {
        gf_kf_model mo;
        nu = rd_u32();
        flag = rd_u32();
        if (nu > GF_KF_NMAX) {
            return -1;
        }
        rd_reals(A, (size_t)n * n);
        rd_reals(B, (size_t)n * nu);
        rd_reals(R, (size_t)n * n);
        if (flag) {
            rd_reals(c, n);
        }
        flag2 = rd_u32();
        if (flag2) {
            rd_reals(v, nu);
        }
        mo.nu = nu;
        mo.A = A;
        mo.B = nu ? B : NULL;
        mo.R = R;
        mo.c = flag ? c : NULL;
        kf_record(gf_kf_predict(&kf, &mo, flag2 ? v : NULL, &work));
        break;
    }
    case OP_KF_UPDATE: {
        gf_kf_meas me;
        gf_kf_innovation info;
        m = rd_u32();
        flag = rd_u32();
        if (m < 1 || m > n) {
            return -1;
        }
        rd_reals(C, (size_t)m * n);
        rd_reals(Q, (size_t)m * m);
        if (flag) {
            rd_reals(c, m);
        }
        me.m = m;
        me.C = C;
        me.Q = Q;
        me.c = flag ? c : NULL;
        rd_reals(&me.gate, 1);
        rd_reals(z, m);
        st = gf_kf_update(&kf, &me, z, &info, &work);
        kf_record(st);
        wr_info(st, info.nis, info.y, m);
        break;
    }
    case OP_EKF3_INIT: {
        gf_vec3 mu;
        gf_mat3 s;
        rd_reals(mu.v, 3);
        rd_reals(&s.m[0][0], 9);
        ekf3_record(gf_ekf3_init(&ekf3, &mu, &s));
        break;
    }
    case OP_EKF3_PREDICT: {
        gf_ekf3_motion mo;
        gf_real u[2];
        mo.g = gf_ekf3_motion_forward_turn;
        mo.ctx = NULL;
        rd_reals(&mo.R.m[0][0], 9);
        rd_reals(u, 2);
        ekf3_record(gf_ekf3_predict(&ekf3, &mo, u));
        break;
    }
    case OP_EKF3_UPDATE: {
        gf_ekf3_meas me;
        gf_vec3 zz = {{0, 0, 0}};
        gf_innovation info;
        memset(&me, 0, sizeof me);
        flag = rd_u32();
        if (flag != 1 && flag != 2) {
            return -1;
        }
        me.m = m = flag;
        me.h = flag == 1 ? gf_ekf3_meas_x : gf_ekf3_meas_xy;
        me.angle_mask = rd_u32();
        for (unsigned i = 0; i < m; i++) {
            rd_reals(me.Q.m[i], m);
        }
        rd_reals(&me.gate, 1);
        rd_reals(zz.v, m);
        st = gf_ekf3_update(&ekf3, &me, &zz, &info);
        ekf3_record(st);
        wr_info(st, info.nis, info.y, m);
        break;
    }
    case OP_EKF_INIT:
        n = rd_u32();
        flag = rd_u32();
        if (n < 1 || n > GF_KF_NMAX) {
            return -1;
        }
        rd_reals(v, n);
        rd_reals(S, (size_t)n * n);
        kf_record(gf_ekf_init(&kf, n, v, S, flag, &work));
        break;
    case OP_EKF_PREDICT: {
        gf_ekf_motion mo;
        mo.g = cubic;
        mo.ctx = NULL;
        mo.R = R;
        rd_reals(R, (size_t)n * n);
        rd_reals(v, n);
        kf_record(gf_ekf_predict(&kf, &mo, v, &work));
        break;
    }
    case OP_EKF_UPDATE: {
        gf_ekf_meas me;
        gf_kf_innovation info;
        m = rd_u32();
        if (m < 1 || m > n) {
            return -1;
        }
        rd_reals(Q, (size_t)m * m);
        me.m = m;
        me.h = bilinear;
        me.ctx = NULL;
        me.Q = Q;
        me.angle_mask = 0;
        rd_reals(&me.gate, 1);
        rd_reals(z, m);
        st = gf_ekf_update(&kf, &me, z, &info, &work);
        kf_record(st);
        wr_info(st, info.nis, info.y, m);
        break;
    }
    default:
        return -1;
    }
    return malformed ? -1 : 1;
}

static int replay(const char *in_path, const char *out_path)
{
    FILE *f = fopen(in_path, "rb");
    int r;
    if (!f) {
        printf("replay: cannot open %s\n", in_path);
        return 2;
    }
    in_len = fread(in, 1, sizeof in, f);
    fclose(f);
    if (in_len < 8 || memcmp(in, "GFRP", 4) != 0) {
        printf("replay: %s is not a scenario\n", in_path);
        return 2;
    }
    in_pos = 4;
    if (rd_u32() != sizeof(gf_real)) {
        printf("replay: %s is for the other precision\n", in_path);
        return 2;
    }
    unsigned ops = 0;
    while ((r = replay_op()) > 0) {
        ops++;
    }
    if (r < 0) {
        printf("replay: malformed scenario at byte %lu\n",
               (unsigned long)in_pos);
        return 2;
    }
    f = fopen(out_path, "wb");
    if (!f || fwrite(out, 1, out_len, f) != out_len) {
        printf("replay: cannot write %s\n", out_path);
        if (f) {
            fclose(f);
        }
        return 2;
    }
    fclose(f);
    printf("replay: %u operations, %lu bytes of beliefs (gf_real: %u bytes)\n",
           ops, (unsigned long)out_len, (unsigned)sizeof(gf_real));
    return 0;
}

#ifdef GF_REPLAY_FIXED_FILES
int main(void)
{
    return replay("replay.in", "replay.out");
}
#else
// The KF2 benchmark's C loop (python/bench.py runs the same workload from
// Python): Table 1.1's car, a position measurement of variance 10 at
// every step, z from a fixed sequence; prepared models, as the package
// uses.
static double bench_kf2(long steps)
{
    static const gf_kf2_model car = {{{{1, 1}, {0, 1}}},
                                     {{{0, 0}, {0, 0}}},
                                     {{{0.25, 0.5}, {0.5, 1}}},
                                     {{0, 0}}};
    static const gf_kf2_meas gps = {
        1, {{{1, 0}, {0, 0}}}, {{{10, 0}, {0, 0}}}, {{0, 0}}, 0};
    gf_kf2_pmodel pm;
    gf_kf2_pmeas pq;
    const gf_vec2 mu0 = {{0, 0}};
    const gf_mat2 s0 = {{{1, 0}, {0, 1}}};
    struct timespec t0, t1;
    gf_real sink = 0;
    if (gf_kf2_prepare_model(&pm, &car) != GF_OK ||
        gf_kf2_prepare_meas(&pq, &gps) != GF_OK ||
        gf_kf2_init(&kf2, &mu0, &s0) != GF_OK) {
        return -1;
    }
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (long k = 0; k < steps; k++) {
        gf_vec2 zz = {{(gf_real)(k % 17) - GF_R(8.0), 0}};
        gf_innovation info;
        if (gf_kf2_predict_prepared(&kf2, &pm, NULL) != GF_OK ||
            gf_kf2_update_prepared(&kf2, &pq, &zz, &info) != GF_OK) {
            return -1;
        }
        sink += info.nis;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (!(sink >= 0)) {
        return -1;
    }
    return ((double)(t1.tv_sec - t0.tv_sec) * 1e9 +
            (double)(t1.tv_nsec - t0.tv_nsec)) /
           (double)steps;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--bench-kf2") == 0) {
        double ns = bench_kf2(atol(argv[2]));
        if (ns < 0) {
            printf("bench: a step failed\n");
            return 1;
        }
        printf("kf2 C loop: %.1f ns per predict + update\n", ns);
        return 0;
    }
    if (argc != 3) {
        printf("usage: replay IN OUT | replay --bench-kf2 STEPS\n");
        return 2;
    }
    return replay(argv[1], argv[2]);
}
#endif
