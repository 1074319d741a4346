// SPDX-License-Identifier: MIT
// gf_wake: what one thread waking another costs on this machine, the floor
// under every LCM hop (scripts/bench-lcm prints it before its runs).
//
//   gf_wake [ROUNDS]
//
// Two threads play ping-pong over a pair of pipes, as LCM's udpm receive
// thread hands a message to the handling thread: one byte written, the
// other thread blocked in read() wakes and answers. Both placed by
// sim/gf_rt.h as gf_node and gf_lcmbench place theirs: pinned, SCHED_FIFO
// when permitted (priorities 50 and 40), memory locked. Printed:
// the median and p99 round trip, twice per placement, with the two threads
// on different CPUs (0 and 1) and on the same CPU (0): back to back, and
// with 200 us of sleep between rounds, so that the CPUs go idle as they do
// between messages at a moderate rate. One-way wake-up = half a round trip.
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "gf_rt.h"

typedef struct pong {
    int in, out, cpu, rounds;
} pong;

static void *ponger(void *arg)
{
    const pong *p = arg;
    char c;
    gf_rt rt = {p->cpu, -1, 50, 0, 0, 0, 0}; // the calling thread only
    (void)gf_rt_setup(&rt, "gf_wake");
    for (int i = 0; i < p->rounds; i++) {
        if (read(p->in, &c, 1) != 1 || write(p->out, &c, 1) != 1) {
            return NULL;
        }
    }
    return NULL;
}

static int cmp(const void *a, const void *b)
{
    long x = *(const long *)a, y = *(const long *)b;
    return (x > y) - (x < y);
}

static int measure(int cpu, int idle_us, int rounds, long *rt, char *placed,
                   size_t len)
{
    int a2b[2], b2a[2];
    if (pipe(a2b) != 0 || pipe(b2a) != 0) {
        return -1;
    }
    pong p = {a2b[0], b2a[1], cpu, rounds};
    pthread_t th;
    if (pthread_create(&th, NULL, ponger, &p) != 0) {
        return -1;
    }
    gf_rt me = {0, -1, 40, 0, 0, 0, 0};
    (void)gf_rt_setup(&me, "gf_wake");
    gf_rt_describe(&me, placed, len);
    char c = 'x';
    struct timespec gap = {0, (long)idle_us * 1000};
    for (int i = 0; i < rounds; i++) {
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        if (write(a2b[1], &c, 1) != 1 || read(b2a[0], &c, 1) != 1) {
            return -1;
        }
        clock_gettime(CLOCK_MONOTONIC, &t1);
        rt[i] = (t1.tv_sec - t0.tv_sec) * 1000000000L + t1.tv_nsec - t0.tv_nsec;
        if (idle_us > 0) {
            nanosleep(&gap, NULL);
        }
    }
    pthread_join(th, NULL);
    close(a2b[0]), close(a2b[1]), close(b2a[0]), close(b2a[1]);
    qsort(rt, (size_t)rounds, sizeof *rt, cmp);
    return 0;
}

int main(int argc, char **argv)
{
    int rounds = argc > 1 ? atoi(argv[1]) : 20000;
    long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
    if (rounds < 100 || argc > 2) {
        fprintf(stderr, "usage: gf_wake [ROUNDS >= 100]\n");
        return 2;
    }
    long *rt = malloc(sizeof *rt * (size_t)rounds);
    if (!rt) {
        return 1;
    }
    char placed[64] = "";
    for (int cpu = ncpu > 1 ? 1 : 0; cpu >= 0; cpu--) {
        for (int idle = 0; idle <= 200; idle += 200) {
            if (measure(cpu, idle, rounds, rt, placed, sizeof placed) != 0) {
                perror("gf_wake");
                return 1;
            }
            printf("gf_wake: cpu0<->cpu%d%s: round trip p50 %.1f us, p99 "
                   "%.1f us (%d rounds; caller %s)\n",
                   cpu, idle ? ", 200 us idle between" : ", back to back",
                   (double)rt[rounds / 2] / 1e3,
                   (double)rt[rounds / 100 * 99] / 1e3, rounds, placed);
        }
    }
    free(rt);
    return 0;
}
