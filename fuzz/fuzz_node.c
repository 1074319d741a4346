// SPDX-License-Identifier: MIT
// libFuzzer target for the filter node's message handling
// (sim/node_core.c, gf_node_handle): arbitrary channels and bytes, exactly
// as LCM would deliver them, through one node. After every message it
// asserts the node's contract (sim/node_core.h):
//
//  - the result is one of gf_node_result; received grows by exactly 1 and
//    so does exactly the by_result entry of that result;
//  - a message that is not applied leaves every track's belief bit-for-bit
//    unchanged (but a gated measurement of a linear track in time, which
//    keeps the prediction to its utime); an applied one leaves a finite
//    belief;
//  - every published belief goes to GF_BELIEF_<track>, decodes as a
//    belief_t with the node's own decoder and has finite numbers;
//  - the number of tracks never exceeds GF_NODE_MAX_TRACKS.
//
// Input: records of [kind][track][len lo][len hi][len bytes of payload].
// kind & 3: 0 GF_MEAS_<track>, 1 GF_CTRL_<track>, 2 GF_BELIEF_<track>
// (not the node's), 3 a raw channel name of (track % 40) bytes taken from
// the input. track is a signed byte. A measurement with kind & 8 goes to a
// sensor's channel, GF_MEAS_<track>_<name>, the name by (kind >> 4) & 3:
// wheel, gyro, gnss (the vehicle's, below) or compass (the rover's). The
// node runs a configuration: tracks 100..127 a linear vehicle in time with
// those three sensors, 80..99 a robot with a compass; others the presets. Built with scripts/fuzz (node target),
// which also writes the seeds: this file with -DFUZZ_NODE_MAKE_SEEDS is a
// program that encodes valid messages with the generated types.
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gf_wire.h"
#include "gaussfilt_lcm_model_t.h"
#include "node_core.h"

#define REQUIRE(cond)                                                          \
    do {                                                                       \
        if (!(cond)) {                                                         \
            fprintf(stderr, "contract broken: %s (%s:%d)\n", #cond, __FILE__,  \
                    __LINE__);                                                 \
            abort();                                                           \
        }                                                                      \
    } while (0)

#ifndef FUZZ_NODE_MAKE_SEEDS

typedef struct pub_log {
    uint64_t n;
} pub_log;

static int on_publish(void *ctx, const char *channel, const void *data,
                      size_t len)
{
    pub_log *log = ctx;
    gaussfilt_lcm_belief_t b;
    REQUIRE(strncmp(channel, GF_CHANNEL_BELIEF, strlen(GF_CHANNEL_BELIEF)) ==
            0);
    REQUIRE(gaussfilt_lcm_belief_t_decode(data, 0, (int)len, &b) == (int)len);
    char want[GF_CHANNEL_MAX];
    snprintf(want, sizeof want, "%s%d", GF_CHANNEL_BELIEF, (int)b.track);
    REQUIRE(strcmp(channel, want) == 0);
    REQUIRE(b.n >= 2 && b.n <= GF_NODE_NMAX);
    for (int i = 0; i < b.n; i++) {
        REQUIRE(isfinite(b.mean[i]));
        for (int j = 0; j < b.n; j++) {
            REQUIRE(isfinite(b.cov[i][j]));
        }
    }
    REQUIRE(b.m >= 0 && b.m <= GF_NODE_NMAX);
    REQUIRE(isfinite(b.nis));
    gaussfilt_lcm_belief_t_decode_cleanup(&b);
    log->n++;
    return 0;
}

static const char fuzz_conf[] =
    "[model vehicle]\ntype = linear\nchannels = GF_(MEAS|CTRL|MODEL)_1[0-2]"
    "[0-9]\nmotion = cv cv\ndt = 0.01\naccel_var = 0.5 0.1\n"
    "prior_mean = 0 10 0 0\nprior_cov = 1 1 0.01 0.01\nlate_window = 0.2\n"
    "[sensor wheel]\nC = 0 1 0 0\nQ = 0.0025\ngate = 9\n"
    "[sensor gyro]\nC = 0 0 0 1\nQ = 0.0001\n"
    "[sensor gnss]\nC = 1 0 0 0 ; 0 0 1 0\nQ = 1 0.0025\nangles = 1\n"
    "[model rover]\ntype = robot\nchannels = GF_(MEAS|CTRL|MODEL)_(8|9)"
    "[0-9]\nodometry = 0.01 0 0 0.001\nprior_cov = 0.1 0.1 0.05\n"
    "[sensor compass]\nmeasure = heading\nQ = 0.0004\n";

static const gf_node_model *lookup(const void *ctx, int32_t id, int8_t kind)
{
    return gf_node_config_named((const gf_node_config *)ctx, id, kind);
}

static int belief_finite(const gf_node_track *t)
{
    if (t->model == GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR) {
        unsigned n = t->f.kf.n;
        for (unsigned i = 0; i < n; i++) {
            if (!isfinite(t->f.kf.mu[i])) {
                return 0;
            }
        }
        for (unsigned i = 0; i < GF_KF_TRI(n); i++) {
            if (!isfinite(t->f.kf.ud[i])) {
                return 0;
            }
        }
        return 1;
    }
    {
        const gf_real *p = t->model == GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
                               ? &t->f.kf2.mu.v[0]
                               : &t->f.ekf3.mu.v[0];
        size_t n = t->model == GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
                       ? sizeof(gf_kf2) / sizeof(gf_real)
                       : sizeof(gf_ekf3) / sizeof(gf_real);
        for (size_t i = 0; i < n; i++) {
            if (!isfinite(p[i])) {
                return 0;
            }
        }
        return 1;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gf_node node; // ~17 kB; reinitialised for every input
    static gf_node before;
    static gf_node_config cfg;
    static int have_cfg;
    pub_log log = {0};
    if (!have_cfg) {
        char err[200];
        REQUIRE(gf_node_config_parse(&cfg, fuzz_conf, err, sizeof err) == 0);
        have_cfg = 1;
    }
    REQUIRE(gf_node_init(&node, on_publish, &log) == 0);
    REQUIRE(gf_node_set_models(&node, lookup, &cfg) == 0);
    size_t i = 0;
    int64_t now = 1000000;
    while (i < size) {
        uint8_t kind = data[i++];
        int8_t track = i < size ? (int8_t)data[i++] : 0;
        char channel[64];
        if ((kind & 3) == 3) {
            size_t n = (size_t)(uint8_t)track % 40;
            n = n < size - i ? n : size - i;
            memcpy(channel, data + i, n);
            channel[n] = '\0';
            i += n;
        } else {
            // kind & 3: MEAS, CTRL, BELIEF (or MODEL with kind & 4)
            static const char *const prefix[4] = {
                GF_CHANNEL_MEAS, GF_CHANNEL_CTRL, GF_CHANNEL_BELIEF,
                GF_CHANNEL_MODEL};
            static const char *const sensor[4] = {"wheel", "gyro", "gnss",
                                                  "compass"};
            unsigned k = (kind & 3) == 2 && (kind & 4) ? 3u : kind & 3u;
            if (k == 0 && (kind & 8)) {
                snprintf(channel, sizeof channel, "%s%d_%s", prefix[k],
                         (int)track, sensor[(kind >> 4) & 3]);
            } else {
                snprintf(channel, sizeof channel, "%s%d", prefix[k],
                         (int)track);
            }
        }
        size_t len = 0;
        if (i < size) {
            len = data[i++];
        }
        if (i < size) {
            len |= (size_t)data[i++] << 8;
        }
        len = len < size - i ? len : size - i;
        // A private copy of exactly len bytes, so ASan sees any over-read.
        uint8_t *msg = len ? malloc(len) : NULL;
        if (len) {
            REQUIRE(msg != NULL);
            memcpy(msg, data + i, len);
        }
        i += len;

        memcpy(&before, &node, sizeof node);
        uint64_t pub0 = log.n;
        gf_node_result r = gf_node_handle(&node, channel, msg, len, now);
        free(msg);
        now += 1000;

        REQUIRE((unsigned)r < GF_NODE_RESULT_COUNT);
        REQUIRE(node.counts.received == before.counts.received + 1);
        uint64_t sum = 0;
        for (int k = 0; k < GF_NODE_RESULT_COUNT; k++) {
            uint64_t want = before.counts.by_result[k] + (k == (int)r);
            REQUIRE(node.counts.by_result[k] == want);
            sum += node.counts.by_result[k];
        }
        REQUIRE(sum == node.counts.received);
        REQUIRE(node.counts.published ==
                before.counts.published + (log.n - pub0));
        REQUIRE(node.ntracks <= GF_NODE_MAX_TRACKS);
        REQUIRE(node.ntracks >= before.ntracks);
        for (unsigned t = 0; t < before.ntracks; t++) {
            REQUIRE(node.tracks[t].id == before.tracks[t].id);
            // A rejected message changes no belief, unless it came from a
            // newer simulator session: then its track was first reset to
            // the prior (counted in resyncs), whatever became of the message.
            if (r != GF_NODE_APPLIED &&
                !(r == GF_NODE_GATED &&
                  node.tracks[t].model ==
                      GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR) &&
                node.counts.resyncs == before.counts.resyncs) {
                REQUIRE(memcmp(&node.tracks[t].f, &before.tracks[t].f,
                               sizeof node.tracks[t].f) == 0);
            }
        }
        for (unsigned t = 0; t < node.ntracks; t++) {
            REQUIRE(belief_finite(&node.tracks[t]));
        }
    }
    return 0;
}

#else // FUZZ_NODE_MAKE_SEEDS: fuzz_node_seeds DIR writes the seed corpus

static size_t put(uint8_t *out, uint8_t kind, int8_t track, const void *msg,
                  int len)
{
    out[0] = kind;
    out[1] = (uint8_t)track;
    out[2] = (uint8_t)(len & 0xff);
    out[3] = (uint8_t)(len >> 8);
    memcpy(out + 4, msg, (size_t)len);
    return 4 + (size_t)len;
}

static size_t ctrl(uint8_t *out, int8_t track, int64_t seq, int8_t model,
                   int8_t n, double u0, double u1)
{
    gf_wire_ctrl c;
    memset(&c, 0, sizeof c);
    c.utime = 1000 * seq;
    c.seq = seq;
    c.track = track;
    c.model = model;
    c.n = n;
    c.u[0] = u0;
    c.u[1] = u1;
    uint8_t buf[256];
    int len = gf_wire_ctrl_encode(buf, sizeof buf, &c);
    REQUIRE(len > 0);
    return put(out, 1, track, buf, len);
}

static size_t meas(uint8_t *out, int8_t track, int64_t seq, int8_t model,
                   int8_t m, double z0, double q00, uint8_t kind)
{
    gf_wire_meas z;
    memset(&z, 0, sizeof z);
    z.utime = 1000 * seq;
    z.seq = seq;
    z.track = track;
    z.model = model;
    z.m = m;
    z.z[0] = z0;
    z.q[0][0] = q00;
    z.q[1][1] = q00;
    uint8_t buf[256];
    int len = gf_wire_meas_encode(buf, sizeof buf, &z);
    REQUIRE(len > 0);
    return put(out, kind, track, buf, len);
}

static size_t model(uint8_t *out, int8_t track, int8_t kind_of, int8_t measure,
                    double dt, double var, int8_t reset)
{
    gaussfilt_lcm_model_t m;
    memset(&m, 0, sizeof m);
    m.track = track;
    m.model = kind_of;
    m.measure = measure;
    m.dt = dt;
    m.accel_var = var;
    m.odometry[0] = m.odometry[3] = var;
    m.landmark[0] = 5.0;
    m.landmark[1] = 3.0;
    m.reset = reset;
    m.prior_cov[0][0] = m.prior_cov[1][1] = m.prior_cov[2][2] = 0.01;
    uint8_t buf[512];
    int len = gaussfilt_lcm_model_t_encode(buf, 0, sizeof buf, &m);
    REQUIRE(len > 0);
    return put(out, 6, track, buf, len); // kind 6: GF_MODEL_<track>
}

static void save(const char *dir, const char *name, const uint8_t *d, size_t n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    REQUIRE(f && fwrite(d, 1, n, f) == n && fclose(f) == 0);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 2);
    const int8_t car = GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR;
    const int8_t robot = GAUSSFILT_LCM_MEASUREMENT_T_MODEL_ROBOT;
    static uint8_t d[8192];
    size_t n = 0;
    // Exercise 2 on track 1: five predictions, then z = 5 with Q = 10.
    for (int s = 1; s <= 5; s++) {
        n += ctrl(d + n, 1, 2 * s - 1, car, 0, 0, 0);
    }
    n += meas(d + n, 1, 10, car, 1, 5.0, 10.0, 0);
    save(argv[1], "exercise2", d, n);
    // Exercise 4 on track 2: move 1 forward, observe x = -0.7.
    n = ctrl(d, 2, 1, robot, 2, 1.0, 0.0);
    n += meas(d + n, 2, 2, robot, 1, -0.7, 0.01, 0);
    save(argv[1], "exercise4", d, n);
    // A duplicate, an old seq, a control on a measurement channel
    // (type mismatch), a truncated message and a non-finite z.
    n = ctrl(d, 3, 1, car, 0, 0, 0);
    n += ctrl(d + n, 3, 1, car, 0, 0, 0);
    n += meas(d + n, 3, 3, car, 1, 1.0, 10.0, 0);
    n += meas(d + n, 3, 2, car, 1, 1.0, 10.0, 0);
    size_t c0 = n;
    n += ctrl(d + n, 3, 4, car, 0, 0, 0);
    d[c0] = 0; // kind 0: onto GF_MEAS_3
    size_t t0 = n;
    n += meas(d + n, 3, 5, car, 1, 1.0, 10.0, 0);
    d[t0 + 2] = (uint8_t)(d[t0 + 2] - 9); // 9 bytes short
    n -= 9;
    n += meas(d + n, 3, 6, car, 1, NAN, 10.0, 0);
    save(argv[1], "rejections", d, n);
    // Run-time models: a car at 100 Hz measuring position and velocity, a
    // robot seeing a landmark's range and bearing, then their inputs.
    n = model(d, 4, car, 3, 0.01, 4.0, 1);
    n += ctrl(d + n, 4, 1, car, 0, 0, 0);
    n += meas(d + n, 4, 2, car, 2, 0.1, 0.01, 0);
    n += model(d + n, 5, robot, 5, 0.0, 0.001, 0);
    n += ctrl(d + n, 5, 1, robot, 2, 1.0, 0.1);
    n += meas(d + n, 5, 2, robot, 2, 4.0, 0.01, 0);
    save(argv[1], "models", d, n);
    // The vehicle on track 100: its sensors at irregular times (a sensor's
    // kind: 8 + 16 * its index), a late one, a wild gnss fix; the rover's
    // compass on track 80 after a control.
    {
        const int8_t lin = GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR;
        n = meas(d, 100, 1, lin, 1, 10.0, 0.0025, 8);       // wheel
        n += meas(d + n, 100, 2, lin, 1, 0.01, 0.0001, 24); // gyro
        n += meas(d + n, 100, 3, lin, 2, 0.3, 0.0, 40);     // gnss, q 0
        n += meas(d + n, 100, 9, lin, 1, 10.1, 0.0025, 8);
        n += meas(d + n, 100, 4, lin, 1, 0.02, 0.0001, 24); // late
        n += meas(d + n, 100, 10, lin, 2, 1e6, 1.0, 40);    // gated
        n += ctrl(d + n, 80, 1, robot, 2, 1.0, 0.1);
        n += meas(d + n, 80, 1, robot, 1, 0.4, 0.0004, 56); // compass
        save(argv[1], "sensors", d, n);
    }
    return 0;
}

#endif
