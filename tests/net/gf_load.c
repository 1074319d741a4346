// SPDX-License-Identifier: MIT
// gf_load: load for the node. Many car tracks from one process: every
// step of every track is a control and a position measurement (variance
// 10) on GF_CTRL_<n> / GF_MEAS_<n>, tracks F..F+N-1 (--first F, default
// 0), paced in 1 ms ticks.
//
//   gf_load --url URL [--tracks N] [--first F] [--rate STEPS_PER_S_PER_TRACK]
//           [--seconds S] [--seed S]
//
// Ends with "gf_load: sent=M steps=K" (M messages published).
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gf_channels.h"

#define MAX_TRACKS 4096

static uint64_t g_rng = 88172645463325252u; // xorshift64

static double noise(void) // roughly N(0, 1): sum of 12 uniforms - 6
{
    double s = 0.0;
    int i;
    for (i = 0; i < 12; i++) {
        g_rng ^= g_rng << 13;
        g_rng ^= g_rng >> 7;
        g_rng ^= g_rng << 17;
        s += (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
    }
    return s - 6.0;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    const char *url = NULL;
    long tracks = 32, k = 0, first = 0;
    double rate = 200.0, seconds = 3.0, t0, x[MAX_TRACKS][2];
    int64_t step = 0;
    unsigned long long sent = 0, failed = 0;
    static uint8_t buf[512];
    char ch[GF_CHANNEL_MAX];
    lcm_t *lcm;
    int i;

    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0) {
            url = argv[i + 1];
        } else if (strcmp(argv[i], "--tracks") == 0) {
            tracks = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--first") == 0) {
            first = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--rate") == 0) {
            rate = atof(argv[i + 1]);
        } else if (strcmp(argv[i], "--seconds") == 0) {
            seconds = atof(argv[i + 1]);
        } else if (strcmp(argv[i], "--seed") == 0) {
            g_rng ^= strtoull(argv[i + 1], NULL, 0) * 0x9e3779b97f4a7c15u;
        } else {
            break;
        }
    }
    if (i < argc || tracks < 1 || tracks > MAX_TRACKS || rate <= 0.0) {
        fprintf(stderr,
                "usage: gf_load --url URL [--tracks N<=%d] "
                "[--first F] [--rate HZ] [--seconds S] [--seed S]\n",
                MAX_TRACKS);
        return 2;
    }
    lcm = lcm_create(url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_load: cannot open LCM at %s\n", url ? url : "");
        return 1;
    }
    memset(x, 0, sizeof(x));
    t0 = now_s();
    for (;;) {
        // Steps due by now (1 ms ticks), every track each step.
        double el = now_s() - t0;
        int64_t due = (int64_t)(el * rate);
        if (el >= seconds) {
            break;
        }
        for (; step < due; step++) {
            for (k = 0; k < tracks; k++) {
                gaussfilt_lcm_control_t c;
                gaussfilt_lcm_measurement_t z;
                double z0, q00 = 10.0, *q0 = &q00; // m = 1
                int len;
                double a = noise();
                x[k][0] += x[k][1] + 0.5 * a;
                x[k][1] += a;
                memset(&c, 0, sizeof(c));
                c.utime = (step + 1) * 1000;
                c.seq = 2 * step + 1;
                c.session = 1;
                c.track = (int32_t)(first + k);
                c.model = GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR;
                snprintf(ch, sizeof(ch), "%s%ld", GF_CHANNEL_CTRL, first + k);
                len = gaussfilt_lcm_control_t_encode(buf, 0, sizeof(buf), &c);
                failed += lcm_publish(lcm, ch, buf, (unsigned)len) != 0;
                memset(&z, 0, sizeof(z));
                z.utime = c.utime;
                z.seq = c.seq + 1;
                z.session = 1;
                z.track = c.track;
                z.model = c.model;
                z.m = 1;
                z0 = x[k][0] + sqrt(10.0) * noise();
                z.z = &z0;
                z.q = &q0;
                snprintf(ch, sizeof(ch), "%s%ld", GF_CHANNEL_MEAS, first + k);
                len =
                    gaussfilt_lcm_measurement_t_encode(buf, 0, sizeof(buf), &z);
                failed += lcm_publish(lcm, ch, buf, (unsigned)len) != 0;
                sent += 2;
            }
        }
        {
            struct timespec ms = {0, 1000000L};
            nanosleep(&ms, NULL);
        }
    }
    printf("gf_load: sent=%llu steps=%lld tracks=%ld failed=%llu\n", sent,
           (long long)step, tracks, failed);
    lcm_destroy(lcm);
    return failed != 0;
}
