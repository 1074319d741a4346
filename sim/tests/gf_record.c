// SPDX-License-Identifier: MIT
// gf_record: records LCM traffic to a log file, for the udpm tests that
// count what went over the wire. lcm-logger cannot be used for that: its
// subscription keeps LCM's default queue of 30 messages, so whenever its
// main thread falls 30 messages behind the receive thread (a busy machine,
// a fast sender) LCM drops the rest without a word.
//
//   gf_record [--url URL] [--channels REGEX] [--count N] [--timeout-ms MS]
//             [--linger-ms MS] [--rcvbuf BYTES] FILE
//
// What it does so that nothing sent after its ready line is lost:
//   - the subscription's queue is unbounded (LCM's limit off): a message
//     the receive thread has read is always written;
//   - LCM's receive socket gets a buffer of --rcvbuf bytes (default 16 MiB;
//     the kernel doubles it): with CAP_NET_ADMIN (root) by SO_RCVBUFFORCE,
//     beyond net.core.rmem_max, so that a whole test's traffic fits in it
//     even if the recorder is not scheduled at all while it is sent;
//     otherwise SO_RCVBUF, which net.core.rmem_max caps (the ready line
//     says which);
//   - "gf_record: ready" is printed once subscribed: the socket is bound
//     and in the multicast group, so every later datagram is queued for it.
// What the kernel still drops (socket buffer full) is counted from the
// socket (SO_MEMINFO) and printed as kernel_drops= in the summary line.
//
// --count N: stops once N events are written and --linger-ms (default
// 200) more have passed without another, or after --timeout-ms (default
// 30000) from the ready line; exits 0 only if exactly N were recorded.
// Without --count it records until SIGINT/SIGTERM. Either way it exits 1
// if the kernel dropped a datagram. Event timestamps are LCM's receive
// times, as lcm-logger writes them.
#define _GNU_SOURCE // SO_RCVBUFFORCE, SO_MEMINFO
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <sys/socket.h>

#include <lcm/eventlog.h>
#include <lcm/lcm.h>

#include "gf_help.h"
#include "gf_sock.h"

static volatile sig_atomic_t g_stop; // set by the signal handler only

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

typedef struct recorder {
    lcm_eventlog_t *log;
    long events;
    int write_errno;      // errno of the first failed write, 0 if none
    struct timespec last; // when the last event was written
} recorder;

static void on_message(const lcm_recv_buf_t *rbuf, const char *channel,
                       void *user)
{
    recorder *r = (recorder *)user;
    lcm_eventlog_event_t e;
    char name[LCM_MAX_CHANNEL_NAME_LENGTH + 1]; // the event's is not const
    snprintf(name, sizeof name, "%s", channel);
    memset(&e, 0, sizeof e);
    e.timestamp = rbuf->recv_utime;
    e.channellen = (int32_t)strlen(name);
    e.datalen = (int32_t)rbuf->data_size;
    e.channel = name;
    e.data = rbuf->data;
    if (lcm_eventlog_write_event(r->log, &e) != 0) {
        if (r->write_errno == 0) {
            r->write_errno = errno != 0 ? errno : EIO;
        }
    } else {
        r->events++;
    }
    clock_gettime(CLOCK_MONOTONIC, &r->last);
}

static long ms_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (long)(t.tv_sec - t0->tv_sec) * 1000L +
           (t.tv_nsec - t0->tv_nsec) / 1000000L;
}

static const char help_text[] =
    "gf_record: records LCM traffic to a log file and counts it, losing\n"
    "nothing sent after its ready line (unbounded LCM queue, a socket buffer\n"
    "that holds a whole test's traffic); what the kernel drops is counted.\n\n"
    "usage: gf_record [--url URL] [--channels REGEX] [--count N]\n"
    "                 [--timeout-ms MS] [--linger-ms MS] [--rcvbuf BYTES] "
    "FILE\n\n"
    "  --url URL        where to listen (default LCM's)\n"
    "  --channels RE    channels to record (default .*)\n"
    "  --count N        stop once N events are recorded and --linger-ms\n"
    "                   (default 200) pass without another; exit 0 only if\n"
    "                   exactly N; give up after --timeout-ms (default 30000)\n"
    "  --rcvbuf BYTES   the receive socket's buffer (default 16777216;\n"
    "                   beyond net.core.rmem_max only with CAP_NET_ADMIN)\n\n"
    "Prints \"gf_record: ready ...\" once subscribed, and at the end\n"
    "\"gf_record: summary events=N kernel_drops=D\"; exits 1 if D > 0.\n\n"
    "example:\n"
    "  gf_record --url 'udpm://239.255.76.67:7667?ttl=0' --count 768 "
    "in.lcmlog\n";

int main(int argc, char **argv)
{
    const char *url = NULL, *channels = ".*", *path = NULL;
    long count = -1, timeout_ms = 30000, linger_ms = 200, drops;
    int rcvbuf_want = 16 << 20, rcvbuf = -1, forced = 0, fd, i, bad = 0;
    int rc = 0;
    socklen_t len;
    struct sigaction sa;
    struct timespec t_ready;
    lcm_t *lcm;
    lcm_subscription_t *sub;
    recorder r;

    gf_help(argc, argv, help_text);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (i + 1 < argc && strcmp(a, "--url") == 0) {
            url = argv[++i];
        } else if (i + 1 < argc && strcmp(a, "--channels") == 0) {
            channels = argv[++i];
        } else if (i + 1 < argc && strcmp(a, "--count") == 0) {
            count = atol(argv[++i]);
        } else if (i + 1 < argc && strcmp(a, "--timeout-ms") == 0) {
            timeout_ms = atol(argv[++i]);
        } else if (i + 1 < argc && strcmp(a, "--linger-ms") == 0) {
            linger_ms = atol(argv[++i]);
        } else if (i + 1 < argc && strcmp(a, "--rcvbuf") == 0) {
            rcvbuf_want = atoi(argv[++i]);
        } else if (a[0] != '-' && path == NULL) {
            path = a;
        } else {
            bad = 1;
        }
    }
    if (bad || path == NULL || rcvbuf_want < 1 || timeout_ms < 1 ||
        linger_ms < 0) {
        fprintf(stderr, "usage: gf_record [--url URL] [--channels REGEX] "
                        "[--count N] [--timeout-ms MS] [--linger-ms MS] "
                        "[--rcvbuf BYTES] FILE\n");
        return 2;
    }

    memset(&r, 0, sizeof r);
    r.log = lcm_eventlog_create(path, "w");
    if (r.log == NULL) {
        fprintf(stderr, "gf_record: cannot write %s\n", path);
        return 1;
    }
    lcm = lcm_create(url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_record: cannot open LCM at %s\n",
                url ? url : "(default URL)");
        lcm_eventlog_destroy(r.log);
        return 1;
    }
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    // lcm_subscribe makes the receive socket, binds it and joins the group.
    sub = lcm_subscribe(lcm, channels, on_message, &r);
    if (sub == NULL || lcm_subscription_set_queue_capacity(sub, 0) != 0) {
        fprintf(stderr, "gf_record: cannot subscribe to %s\n", channels);
        lcm_destroy(lcm);
        lcm_eventlog_destroy(r.log);
        return 1;
    }
    fd = gf_sock_udpm();
    if (fd >= 0) {
        forced = setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf_want,
                            sizeof rcvbuf_want) == 0;
        if (!forced) {
            setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf_want,
                       sizeof rcvbuf_want);
        }
        len = sizeof rcvbuf;
        if (getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, &len) != 0) {
            rcvbuf = -1;
        }
    }
    printf("gf_record: ready channels=%s rcvbuf=%d (%s) file=%s\n", channels,
           rcvbuf,
           fd < 0   ? "no udpm socket found: not set, drops not counted"
           : forced ? "SO_RCVBUFFORCE"
                    : "SO_RCVBUF, capped by net.core.rmem_max",
           path);
    fflush(stdout);

    clock_gettime(CLOCK_MONOTONIC, &t_ready);
    while (!g_stop && r.write_errno == 0) {
        if (count >= 0 && r.events >= count && ms_since(&r.last) >= linger_ms) {
            break;
        }
        if (count >= 0 && ms_since(&t_ready) >= timeout_ms) {
            break;
        }
        if (lcm_handle_timeout(lcm, 50) < 0) {
            break;
        }
    }
    drops = gf_sock_drops(fd);
    lcm_destroy(lcm);
    lcm_eventlog_destroy(r.log);

    printf("gf_record: summary events=%ld kernel_drops=%ld\n", r.events, drops);
    if (r.write_errno != 0) {
        fprintf(stderr, "gf_record: cannot write %s: %s\n", path,
                strerror(r.write_errno));
        rc = 1;
    }
    if (drops > 0) {
        fprintf(stderr,
                "gf_record: the kernel dropped %ld datagrams (socket buffer "
                "of %d bytes full)\n",
                drops, rcvbuf);
        rc = 1;
    }
    if (count >= 0 && r.events != count) {
        fprintf(stderr, "gf_record: %ld events where %ld were expected%s\n",
                r.events, count, r.events < count ? " (timed out)" : "");
        rc = 1;
    }
    return rc;
}
