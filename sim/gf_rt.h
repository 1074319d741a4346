// SPDX-License-Identifier: MIT
// gf_rt.h: real-time placement for the LCM programs (gf_node, gf_lcmbench),
// the way a latency-critical node is deployed: threads pinned to CPUs,
// SCHED_FIFO, memory locked (mlockall, as root or with an unlimited
// RLIMIT_MEMLOCK, and only with SCHED_FIFO), 1 ns timer slack. Header-only, Linux only
// (elsewhere every request is reported as not applied). Needs _GNU_SOURCE
// before the first system header (sched_setaffinity, CPU_SET).
//
// LCM's udpm provider reads its socket in a thread of its own, started by
// the first lcm_subscribe, which inherits the CPU set and the policy of the
// thread that subscribes. So:
//   gf_rt_setup()      before lcm_subscribe: policy for every thread, and
//                      the CPU for LCM's receive thread (rx_cpu, else cpu)
//   lcm_subscribe(), pthread_create() of any receiving thread
//   gf_rt_pin_main()   after: moves the calling thread to cpu
// Nothing fails hard: what cannot be applied (not root, no CAP_SYS_NICE, an
// RT-throttled cgroup, a CPU not in the set) is said on stderr, recorded,
// and the program runs on without it; gf_rt_describe() says what holds.
#ifndef GF_RT_H
#define GF_RT_H

#include <errno.h>
#include <stdio.h>
#include <string.h>

#ifdef __linux__
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>
#endif

typedef struct gf_rt {
    int cpu;    // CPU of the calling (handling / publishing) thread, -1: any
    int rx_cpu; // CPU of LCM's receive thread, -1: same as cpu
    int prio;   // SCHED_FIFO priority (1-99), 0: leave SCHED_OTHER
    int cpu_ok, rx_ok, fifo_ok, mlock_ok; // what took effect
} gf_rt;

#ifdef __linux__
// Pins the calling thread to cpu; 0 on success, else says why and -1.
static inline int gf_rt_pin(const char *who, const char *what, int cpu)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET((size_t)cpu, &set);
    if (sched_setaffinity(0, sizeof set, &set) == 0) {
        return 0;
    }
    fprintf(stderr, "%s: cannot pin the %s to CPU %d (%s): left unpinned\n",
            who, what, cpu, strerror(errno));
    return -1;
}
#endif

// Before lcm_subscribe. Returns the number of requests not met.
static inline int gf_rt_setup(gf_rt *rt, const char *who)
{
    int missed = 0;
    rt->cpu_ok = rt->rx_ok = rt->fifo_ok = rt->mlock_ok = 0;
    if (rt->cpu < 0) {
        rt->cpu = rt->rx_cpu; // --rx-cpu alone: every thread there
    }
#ifdef __linux__
    (void)prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    if (rt->rx_cpu >= 0) {
        rt->rx_ok = gf_rt_pin(who, "LCM receive thread", rt->rx_cpu) == 0;
        missed += !rt->rx_ok;
    } else if (rt->cpu >= 0) {
        rt->cpu_ok = rt->rx_ok = gf_rt_pin(who, "process", rt->cpu) == 0;
        missed += !rt->cpu_ok;
    }
    if (rt->prio > 0) {
        struct sched_param sp;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = rt->prio;
        rt->fifo_ok = sched_setscheduler(0, SCHED_FIFO, &sp) == 0;
        if (!rt->fifo_ok) {
            fprintf(stderr,
                    "%s: SCHED_FIFO priority %d not permitted (%s; "
                    "needs root or CAP_SYS_NICE): running "
                    "SCHED_OTHER\n",
                    who, rt->prio, strerror(errno));
            missed++;
        }
        // Locked memory only when nothing caps it: under a finite
        // RLIMIT_MEMLOCK, MCL_FUTURE would make later allocations fail.
        struct rlimit lim;
        if (rt->fifo_ok &&
            (geteuid() == 0 || (getrlimit(RLIMIT_MEMLOCK, &lim) == 0 &&
                                lim.rlim_cur == RLIM_INFINITY))) {
            rt->mlock_ok = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
            if (!rt->mlock_ok) {
                fprintf(stderr,
                        "%s: mlockall failed (%s): memory not "
                        "locked\n",
                        who, strerror(errno));
                missed++;
            }
        }
    }
#else
    if (rt->cpu >= 0 || rt->rx_cpu >= 0 || rt->prio > 0) {
        fprintf(stderr,
                "%s: CPU pinning and SCHED_FIFO need Linux: "
                "ignored\n",
                who);
        missed++;
    }
#endif
    return missed;
}

// After lcm_subscribe (and after creating any thread that should share LCM
// receive thread's CPU): moves the calling thread to rt->cpu when the
// receive thread was given a CPU of its own. Returns 0, or -1 if not met.
static inline int gf_rt_pin_main(gf_rt *rt, const char *who)
{
#ifdef __linux__
    if (rt->rx_cpu >= 0 && rt->cpu >= 0) {
        rt->cpu_ok = gf_rt_pin(who, "main thread", rt->cpu) == 0;
        return rt->cpu_ok ? 0 : -1;
    }
#else
    (void)who;
#endif
    (void)rt;
    return 0;
}

// What took effect, e.g. "cpu=1 rx_cpu=0 sched=fifo:50 mlock=yes".
static inline void gf_rt_describe(const gf_rt *rt, char *buf, size_t len)
{
    char cpu[16] = "any", rx[16] = "any", sched[24] = "other";
    if (rt->cpu_ok) {
        snprintf(cpu, sizeof cpu, "%d", rt->cpu);
    }
    if (rt->rx_ok) {
        snprintf(rx, sizeof rx, "%d", rt->rx_cpu >= 0 ? rt->rx_cpu : rt->cpu);
    }
    if (rt->fifo_ok) {
        snprintf(sched, sizeof sched, "fifo:%d", rt->prio);
    }
    snprintf(buf, len, "cpu=%s rx_cpu=%s sched=%s mlock=%s", cpu, rx, sched,
             rt->mlock_ok ? "yes" : "no");
}

#endif
