// SPDX-License-Identifier: MIT
// gf_inject: publishes broken messages on one track's node channels, to
// show the node counts them, drops them and keeps answering.
//
//   gf_inject --track N [--rounds K] [--seed S] [--url URL]
//
// Each round sends, in this order: a truncated measurement (GF_MEAS_N), a
// control with a wrong fingerprint (GF_CTRL_N), random bytes (GF_MEAS_N),
// and a belief where a control belongs (GF_CTRL_N): 3 malformed and 1 type
// mismatch. Prints "gf_inject: malformed=M type_mismatch=T".
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "gf_msgs.h"

int main(int argc, char **argv)
{
    const char *url = NULL;
    long track = 1, rounds = 10, k;
    uint32_t x = 1;
    int i, j, failed = 0;
    char meas_ch[GF_CHANNEL_MAX], ctrl_ch[GF_CHANNEL_MAX];
    uint8_t junk[256];
    lcm_t *lcm;

    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0) {
            url = argv[i + 1];
        } else if (strcmp(argv[i], "--track") == 0) {
            track = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--rounds") == 0) {
            rounds = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--seed") == 0) {
            x = (uint32_t)strtoul(argv[i + 1], NULL, 0);
        } else {
            break;
        }
    }
    if (i != argc || rounds < 1) {
        fprintf(stderr, "usage: gf_inject --track N [--rounds K] [--seed S] "
                        "[--url URL]\n");
        return 2;
    }
    lcm = lcm_create(url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_inject: cannot open LCM\n");
        return 1;
    }
    snprintf(meas_ch, sizeof(meas_ch), "%s%ld", GF_CHANNEL_MEAS, track);
    snprintf(ctrl_ch, sizeof(ctrl_ch), "%s%ld", GF_CHANNEL_CTRL, track);
    for (k = 0; k < rounds; k++) {
        gf_msg m = gf_msg_meas((int32_t)track, GF_CAR, k + 1, k, 1.0, 10.0);
        gaussfilt_lcm_belief_t b;
        unsigned len;
        x = x * 1664525u + 1013904223u;
        len = 1u + (x >> 8) % (unsigned)(m.len - 1); // 1 .. len-1 bytes
        failed |= lcm_publish(lcm, meas_ch, m.data, len);

        m = gf_msg_ctrl((int32_t)track, GF_CAR, k + 1, k, 0, 0, 0);
        m.data[(x >> 4) % 8] ^= 0x01; // one bit of the fingerprint
        failed |= lcm_publish(lcm, ctrl_ch, m.data, (unsigned)m.len);

        x = x * 1664525u + 1013904223u;
        len = 1u + (x >> 8) % (unsigned)sizeof(junk);
        for (j = 0; j < (int)len; j++) {
            x = x * 1664525u + 1013904223u;
            junk[j] = (uint8_t)(x >> 24);
        }
        failed |= lcm_publish(lcm, meas_ch, junk, len);

        memset(&b, 0, sizeof(b));
        b.node = (char *)"";
        b.sensor = (char *)"";
        b.track = (int32_t)track;
        m.len =
            gaussfilt_lcm_belief_t_encode(m.data, 0, (int)sizeof(m.data), &b);
        failed |= lcm_publish(lcm, ctrl_ch, m.data, (unsigned)m.len);
    }
    lcm_destroy(lcm);
    printf("gf_inject: malformed=%ld type_mismatch=%ld%s\n", 3 * rounds, rounds,
           failed ? " (some publishes FAILED)" : "");
    return failed ? 1 : 0;
}
