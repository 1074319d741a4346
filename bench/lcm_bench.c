// SPDX-License-Identifier: MIT
// gaussfilt LCM pipeline benchmark: publishes measurements for
// T car tracks at a given rate to a running gf_node and times the beliefs
// that come back, all over real udpm sockets.
//
//   gf_lcmbench --url URL [--belief-url URL2] --rate R --seconds S
//               [--tracks T] [--first ID] [--tick NS] [--cpu N]
//               [--rx-cpu M] [--rt P] [--dump FILE]
//
// Beliefs are listened for on URL2 (default URL): scripts/bench-lcm runs the
// node with --out-url on another port, so that neither the node nor this
// program has the other direction's packets on its socket.
// R is measurements per second in total (0: as fast as possible), spread
// round-robin over tracks ID .. ID+T-1 (each message: m = 1, z, Q = 10, the
// car of exercise 2; every one is answered by a belief). Publish times are
// taken just before lcm_publish, receive times in the receiving thread just
// after LCM hands the belief over (one process, one CLOCK_MONOTONIC), and
// matched by (track, input_seq). Prints one line: sent, beliefs matched,
// lost, achieved rate, and latency p50/p99/max in microseconds. Also, to
// show where the time goes: lcm_rx_p50/p99, the same up to LCM's receive
// timestamp of the belief (rbuf->recv_utime: in LCM 1.5 the time LCM's
// receive thread read the packet, once its receive buffers are recycled),
// i.e. without this program's own hand-off to its handler; and
// publish_p50/p99, how long lcm_publish took (over loopback the receiver's
// kernel path runs inside it).
//
// Pacing: message k is due at t0 + k / R. The publisher sends what is due,
// then sleeps (clock_nanosleep to an absolute deadline, 1 ns timer slack)
// to the next deadline rounded up to a multiple of --tick NS (default 0:
// every message's own deadline; a coarser tick sends bursts of R * tick
// messages). It never spins: the node needs the CPU.
// --cpu N pins the publishing thread to CPU N, --rx-cpu M the receiving
// threads (LCM's and ours; default: N too); --rt P makes every thread
// SCHED_FIFO at priority P (sim/gf_rt.h; says so and goes on without when
// not permitted). --dump FILE writes one line per belief: publish time
// since the start, latency and lcm_rx latency, in microseconds.

#define _GNU_SOURCE // sched_setaffinity, CPU_SET (gf_rt.h)
#include <errno.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gf_rt.h"

#define MAX_TRACKS 1024

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

typedef struct run {
    int tracks, first;
    long per_track; // capacity of each track's time arrays
    int64_t *t_pub; // [track][seq - 1]
    int64_t *t_rx;
    int64_t *t_lcm;    // LCM's receive timestamps, on CLOCK_MONOTONIC
    int64_t real_mono; // CLOCK_REALTIME - CLOCK_MONOTONIC, ns
    volatile int stop;
    unsigned long beliefs, unmatched;
} run;

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    (void)channel;
    run *r = user;
    int64_t t = now_ns();
    gaussfilt_lcm_belief_t b;
    if (gaussfilt_lcm_belief_t_decode(rbuf->data, 0, (int)rbuf->data_size, &b) <
        0) {
        return;
    }
    r->beliefs++;
    int k = b.track - r->first;
    int64_t input_seq = b.input_seq;
    gaussfilt_lcm_belief_t_decode_cleanup(&b); // mean, cov: not needed
    if (k < 0 || k >= r->tracks || input_seq < 1 || input_seq > r->per_track) {
        r->unmatched++; // initial beliefs (input_seq -1) and strangers
        return;
    }
    r->t_rx[(long)k * r->per_track + (input_seq - 1)] = t;
    r->t_lcm[(long)k * r->per_track + (input_seq - 1)] =
        rbuf->recv_utime * 1000 - r->real_mono;
}

typedef struct rx_arg {
    lcm_t *lcm;
    run *r;
} rx_arg;

static void *rx_thread(void *p)
{
    rx_arg *a = p;
    while (!a->r->stop) {
        lcm_handle_timeout(a->lcm, 50);
    }
    return NULL;
}

static int64_t real_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    const char *url = NULL, *burl = NULL, *dump = NULL;
    double rate = 0, seconds = 1;
    int tracks = 1, first = 1000, i;
    long tick_min = 0;
    gf_rt rt = {-1, -1, 0, 0, 0, 0, 0};
    char placement[96];
    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0) {
            url = argv[i + 1];
        } else if (strcmp(argv[i], "--belief-url") == 0) {
            burl = argv[i + 1];
        } else if (strcmp(argv[i], "--rate") == 0) {
            rate = atof(argv[i + 1]);
        } else if (strcmp(argv[i], "--seconds") == 0) {
            seconds = atof(argv[i + 1]);
        } else if (strcmp(argv[i], "--tracks") == 0) {
            tracks = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--first") == 0) {
            first = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--tick") == 0) {
            tick_min = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--cpu") == 0) {
            rt.cpu = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--rx-cpu") == 0) {
            rt.rx_cpu = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--rt") == 0) {
            rt.prio = atoi(argv[i + 1]);
        } else if (strcmp(argv[i], "--dump") == 0) {
            dump = argv[i + 1];
        } else {
            break;
        }
    }
    if (i != argc || !url || rate < 0 || seconds <= 0 || tracks < 1 ||
        tracks > MAX_TRACKS || tick_min < 0) {
        fprintf(stderr,
                "usage: gf_lcmbench --url URL [--belief-url URL2] "
                "--rate R --seconds S [--tracks T] [--first ID] "
                "[--tick NS] [--cpu N] [--rx-cpu M] [--rt P] "
                "[--dump FILE]\n"
                "  R >= 0 (0: flat out), S > 0, 1 <= T <= %d\n",
                MAX_TRACKS);
        return 2;
    }

    // Before LCM starts its receive thread, which inherits CPU and policy.
    gf_rt_setup(&rt, "gf_lcmbench");
    run r;
    memset(&r, 0, sizeof r);
    r.real_mono = real_ns() - now_ns();
    r.tracks = tracks;
    r.first = first;
    // Room for the whole run at up to 2 million messages per second.
    long total_cap = (long)((rate > 0 ? rate : 2e6) * seconds) + 16;
    r.per_track = total_cap / tracks + 2;
    r.t_pub = calloc((size_t)(r.per_track * tracks), sizeof(int64_t));
    r.t_rx = calloc((size_t)(r.per_track * tracks), sizeof(int64_t));
    r.t_lcm = calloc((size_t)(r.per_track * tracks), sizeof(int64_t));
    int64_t *pub_cost = calloc((size_t)(r.per_track * tracks), sizeof(int64_t));
    lcm_t *pub = lcm_create(url), *sub = lcm_create(burl ? burl : url);
    if (!r.t_pub || !r.t_rx || !r.t_lcm || !pub_cost || !pub || !sub) {
        fprintf(stderr, "gf_lcmbench: cannot set up (LCM URL %s)\n", url);
        return 1;
    }
    lcm_subscription_t *s = lcm_subscribe(sub, "GF_BELIEF_.*", on_belief, &r);
    lcm_subscription_set_queue_capacity(s, 1 << 20);
    rx_arg ra = {sub, &r};
    pthread_t th;
    if (pthread_create(&th, NULL, rx_thread, &ra) != 0) {
        return 1;
    }
    gf_rt_pin_main(&rt, "gf_lcmbench"); // after: the receivers keep rx_cpu
    gf_rt_describe(&rt, placement, sizeof placement);

    uint8_t buf[512];
    char ch[MAX_TRACKS][32];
    for (i = 0; i < tracks; i++) {
        snprintf(ch[i], sizeof ch[i], "GF_MEAS_%d", first + i);
    }
    gaussfilt_lcm_measurement_t m;
    double z0 = 0.0, q00 = 10.0, *q0 = &q00; // m = 1: z[1], q[1][1]
    memset(&m, 0, sizeof m);
    m.model = GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR;
    m.m = 1;
    m.z = &z0;
    m.q = &q0;

    // Pacing without spinning (see the top): each tick sends what is due,
    // then an absolute sleep to the next tick.
    const int64_t t0 = now_ns();
    const int64_t t_end = t0 + (int64_t)(seconds * 1e9);
    const double period = rate > 0 ? 1e9 / rate : 0;
    const int64_t tick =
        period > (double)tick_min ? (int64_t)period : (int64_t)tick_min;
    int64_t next_tick = t0;
    long sent = 0, seq = 0, pub_fail = 0;
    for (;;) {
        int64_t t = now_ns();
        if (t >= t_end || seq >= r.per_track - 1) {
            break;
        }
        if (period > 0) {
            long due = (long)((double)(t - t0) / period) + 1;
            if (sent >= due) {
                next_tick += tick;
                if (next_tick > t) {
                    struct timespec d;
                    d.tv_sec = (time_t)(next_tick / 1000000000);
                    d.tv_nsec = (long)(next_tick % 1000000000);
                    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &d,
                                           NULL) == EINTR)
                        ;
                } else {
                    next_tick = t;
                }
                continue;
            }
        }
        int k = (int)(sent % tracks);
        if (k == 0) {
            seq++;
        }
        m.track = first + k;
        m.seq = seq;
        m.utime = seq * 10000; // 100 Hz in simulated time
        z0 = (double)seq;
        int len = gaussfilt_lcm_measurement_t_encode(buf, 0, sizeof buf, &m);
        int64_t tp = now_ns();
        r.t_pub[(long)k * r.per_track + (seq - 1)] = tp;
        if (lcm_publish(pub, ch[k], buf, (unsigned)len) != 0) {
            pub_fail++;
        }
        pub_cost[sent] = now_ns() - tp; // sent < per_track * tracks
        sent++;
    }
    const int64_t t_stop = now_ns();
    struct timespec settle = {0, 500000000}; // stragglers
    nanosleep(&settle, NULL);
    r.stop = 1;
    pthread_join(th, NULL);

    long matched = 0;
    int64_t *lat = malloc((size_t)(sent + 1) * sizeof(int64_t));
    int64_t *llat = malloc((size_t)(sent + 1) * sizeof(int64_t));
    FILE *df = dump ? fopen(dump, "w") : NULL;
    if (!lat || !llat || (dump && !df)) {
        return 1;
    }
    for (int k = 0; k < tracks; k++) {
        for (long q = 0; q < r.per_track; q++) {
            long idx = (long)k * r.per_track + q;
            if (!r.t_pub[idx] || !r.t_rx[idx]) {
                continue;
            }
            llat[matched] = r.t_lcm[idx] - r.t_pub[idx];
            lat[matched] = r.t_rx[idx] - r.t_pub[idx];
            if (df) {
                fprintf(
                    df, "%.1f %.1f %.1f\n", (double)(r.t_pub[idx] - t0) / 1e3,
                    (double)lat[matched] / 1e3, (double)llat[matched] / 1e3);
            }
            matched++;
        }
    }
    if (df) {
        fclose(df);
    }
    qsort(lat, (size_t)matched, sizeof(int64_t), cmp_i64);
    qsort(llat, (size_t)matched, sizeof(int64_t), cmp_i64);
    qsort(pub_cost, (size_t)sent, sizeof(int64_t), cmp_i64);
    double secs = (double)(t_stop - t0) / 1e9;
    printf("gf_lcmbench: rate_target=%.0f sent=%ld publish_failed=%ld "
           "seconds=%.3f rate=%.0f beliefs=%lu matched=%ld lost=%ld",
           rate, sent, pub_fail, secs, (double)sent / secs, r.beliefs, matched,
           sent - matched);
    if (matched > 0) {
        printf(" p50_us=%.1f p99_us=%.1f max_us=%.1f",
               (double)lat[matched / 2] / 1e3,
               (double)lat[(long)((double)matched * 0.99)] / 1e3,
               (double)lat[matched - 1] / 1e3);
    }
    if (matched > 0) {
        printf(" lcm_rx_p50_us=%.1f lcm_rx_p99_us=%.1f",
               (double)llat[matched / 2] / 1e3,
               (double)llat[(long)((double)matched * 0.99)] / 1e3);
    }
    if (sent > 0) {
        printf(" publish_p50_us=%.1f publish_p99_us=%.1f",
               (double)pub_cost[sent / 2] / 1e3,
               (double)pub_cost[(long)((double)sent * 0.99)] / 1e3);
    }
    printf(" tick_ns=%lld %s\n", (long long)tick, placement);
    free(lat);
    free(llat);
    free(pub_cost);
    lcm_destroy(pub);
    lcm_destroy(sub);
    return 0;
}
