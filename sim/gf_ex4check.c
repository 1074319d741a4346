// SPDX-License-Identifier: MIT
// gf_ex4check: exercise 4 three ways, checked from the wire. Listens to
// three robot tracks run by three nodes (gf_node --filter ekf|ukf|pf), each
// fed `gf_sim --exercise 4`, and checks what each filter must show
// (sim/ex4_modes.h): the EKF's corrected mean at (0.15, 0, 0); the UKF's
// predicted mean inside the unit circle, not at (1, 0); the PF's particle
// cloud after z = -0.7 with two modes near (-0.7, +-0.714). Each belief
// must also say which filter made it. Exit 0 only if all hold.
//
//   gf_ex4check --ekf N --ukf N --pf N [--url URL] [--timeout-ms MS]
//
// Prints "gf_ex4check: ready" once subscribed.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "ex4_modes.h"
#include "gaussfilt_lcm_particles_t.h"
#include "gf_channels.h"
#include "gf_help.h"
#include "gf_route.h"
#include "gf_wire.h"

#define CLOUD_MAX 4096
#ifdef GF_SINGLE_PRECISION
#define TOL 2e-5
#else
#define TOL 1e-12
#endif

enum { EKF, UKF, PF, NFILTERS };

typedef struct state {
    int32_t track[NFILTERS];
    gf_wire_belief b[NFILTERS][3]; // by belief seq 0..2
    int have[NFILTERS][3];
    float x[CLOUD_MAX], y[CLOUD_MAX], w[CLOUD_MAX];
    int count, have_cloud, bad;
    gaussfilt_lcm_particles_t cloud; // its header (arrays copied above)
} state;

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    state *s = (state *)user;
    gf_wire_belief b;
    int f;
    (void)channel;
    if (gf_wire_belief_decode(rbuf->data, rbuf->data_size, &b) != 0) {
        s->bad++;
        return;
    }
    for (f = 0; f < NFILTERS; f++) {
        if (b.track == s->track[f] && b.seq >= 0 && b.seq < 3) {
            s->b[f][b.seq] = b;
            s->have[f][b.seq] = 1;
        }
    }
}

static void on_particles(const lcm_recv_buf_t *rbuf, const char *channel,
                         void *user)
{
    state *s = (state *)user;
    gaussfilt_lcm_particles_t p;
    (void)channel;
    if (gaussfilt_lcm_particles_t_decode(rbuf->data, 0, (int)rbuf->data_size,
                                         &p) != (int)rbuf->data_size) {
        s->bad++;
        return;
    }
    if (p.track == s->track[PF] && p.seq == 2 && p.count > 0 &&
        p.count <= CLOUD_MAX) {
        memcpy(s->x, p.x, sizeof(float) * (size_t)p.count);
        memcpy(s->y, p.y, sizeof(float) * (size_t)p.count);
        memcpy(s->w, p.w, sizeof(float) * (size_t)p.count);
        s->count = p.count;
        s->cloud = p;
        s->cloud.x = s->cloud.y = s->cloud.theta = s->cloud.w = NULL;
        s->have_cloud = 1;
    }
    gaussfilt_lcm_particles_t_decode_cleanup(&p);
}

static int complete(const state *s)
{
    return s->have[EKF][2] && s->have[UKF][1] && s->have[PF][2] &&
           s->have_cloud;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static int check(const state *s)
{
    static const int8_t want[NFILTERS] = {GAUSSFILT_LCM_BELIEF_T_FILTER_EKF3,
                                          GAUSSFILT_LCM_BELIEF_T_FILTER_UKF3,
                                          GAUSSFILT_LCM_BELIEF_T_FILTER_PF3};
    static const char *names[NFILTERS] = {"EKF3", "UKF3", "PF3"};
    const gf_wire_belief *pf = &s->b[PF][2];
    int f, j, fails = 0;
    for (f = 0; f < NFILTERS; f++) {
        for (j = 0; j < 3; j++) {
            if (s->have[f][j] &&
                (s->b[f][j].filter != want[f] || s->b[f][j].status != 0)) {
                printf("  track %ld belief %d: filter %d status %d, want "
                       "%s and 0\n",
                       (long)s->track[f], j, s->b[f][j].filter,
                       s->b[f][j].status, names[f]);
                fails++;
            }
        }
    }
    printf("exercise 4 three ways, from the wire (tracks %ld, %ld, %ld):\n",
           (long)s->track[EKF], (long)s->track[UKF], (long)s->track[PF]);
    fails += gf_ex4_check_ekf_post(s->b[EKF][2].mean, TOL);
    fails += gf_ex4_check_ukf_pred(s->b[UKF][1].mean[0], s->b[UKF][1].mean[1]);
    printf("  UKF corrected mean (%.4f, %.4f): one Gaussian, on neither "
           "point\n",
           s->b[UKF][2].mean[0], s->b[UKF][2].mean[1]);
    printf("  PF belief (summary) mean (%.4f, %.4f), cloud of %d of %d "
           "particles, neff %.0f before resampling (resampled %d)\n",
           pf->mean[0], pf->mean[1], s->count, s->cloud.n_filter, s->cloud.neff,
           s->cloud.resampled);
    fails += gf_ex4_check_modes(s->x, s->y, s->w, s->count);
    return fails;
}

static const char help_text[] =
    "gf_ex4check: exercise 4 three ways from the wire: the beliefs of an EKF,\n"
    "a UKF and a PF node (gf_node --filter) each fed gf_sim --exercise 4; "
    "exit\n"
    "0 if the EKF is at (0.15, 0), the UKF's prediction inside the unit "
    "circle\n"
    "and the PF's cloud shows the two modes.\n\n"
    "usage: gf_ex4check --ekf N --ukf N --pf N [--url URL] [--timeout-ms "
    "MS]\n\n"
    "example:\n"
    "  gf_ex4check --ekf 41 --ukf 42 --pf 43 --url "
    "'udpm://239.255.76.67:7667?ttl=0'\n";

int main(int argc, char **argv)
{
    static state s;
    const char *url = NULL;
    char ch[GF_CHANNEL_MAX];
    double timeout = 10000, t0;
    int i, f, fails;
    lcm_t *lcm;
    for (f = 0; f < NFILTERS; f++) {
        s.track[f] = -1;
    }
    gf_help(argc, argv, help_text);
    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--ekf") == 0) {
            s.track[EKF] = (int32_t)atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--ukf") == 0) {
            s.track[UKF] = (int32_t)atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--pf") == 0) {
            s.track[PF] = (int32_t)atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--url") == 0) {
            url = argv[i + 1];
        } else if (strcmp(argv[i], "--timeout-ms") == 0) {
            timeout = atof(argv[i + 1]);
        } else {
            break;
        }
    }
    if (i != argc || s.track[EKF] < 0 || s.track[UKF] < 0 || s.track[PF] < 0) {
        fprintf(stderr, "usage: gf_ex4check --ekf N --ukf N --pf N [--url "
                        "URL] [--timeout-ms MS]\n");
        return 2;
    }
    lcm = gf_lcm_open("gf_ex4check", url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_ex4check: cannot open LCM\n");
        return 1;
    }
    for (f = 0; f < NFILTERS; f++) {
        snprintf(ch, sizeof(ch), "%s%ld", GF_CHANNEL_BELIEF, (long)s.track[f]);
        lcm_subscribe(lcm, ch, on_belief, &s);
    }
    snprintf(ch, sizeof(ch), "%s%ld", GF_CHANNEL_PARTICLES, (long)s.track[PF]);
    lcm_subscribe(lcm, ch, on_particles, &s);
    printf("gf_ex4check: ready\n");
    fflush(stdout);
    t0 = now_ms();
    while (!complete(&s) && now_ms() - t0 < timeout) {
        if (lcm_handle_timeout(lcm, 100) < 0) {
            break;
        }
    }
    lcm_destroy(lcm);
    if (!complete(&s)) {
        fprintf(stderr,
                "gf_ex4check: timed out: EKF %d/%d/%d UKF %d/%d/%d "
                "PF %d/%d/%d cloud %d (undecodable %d)\n",
                s.have[EKF][0], s.have[EKF][1], s.have[EKF][2], s.have[UKF][0],
                s.have[UKF][1], s.have[UKF][2], s.have[PF][0], s.have[PF][1],
                s.have[PF][2], s.have_cloud, s.bad);
        return 1;
    }
    fails = check(&s);
    printf("gf_ex4check: %s (%d failed checks)\n", fails ? "FAILED" : "passed",
           fails);
    return fails ? 1 : 0;
}
