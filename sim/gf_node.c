// SPDX-License-Identifier: MIT
// gf_node: the filter node. Subscribes to the controls, measurements and
// models of its tracks over LCM; LCM's dispatch copies each message into
// the node's input queue (gf_inq.h), and a handling thread hands it to
// gf_node_handle() (node_core.c), which publishes the beliefs.
// SIGINT/SIGTERM (or the end of a file:// log) end it, once the queue is
// drained, with a one-line summary on stdout.
//
//   gf_node [--config FILE] [--strict] [--name NAME] [--url URL]
//           [--out-url URL] [--channels REGEX] [--queue N]
//           [--filter ekf|ukf|pf] [--seed S] [--cpu N] [--rx-cpu M]
//           [--rt PRIO] [--rate HZ] [--timing] [--help]
//
//   --config    the tracks' models (sim/node_model.h, docs/node.md):
//               channel patterns to car, robot and linear models; car and
//               robot tracks no model names run the book's presets
//               (book-car, book-robot), a linear one is refused. Each new
//               track's line says which model it got and why
//   --strict    refuse every track no configured model names (no_model)
//   --name      the node's id in every belief (belief_t.node; default
//               host:pid:start). A belief of one of its tracks from
//               another id is counted (peer_beliefs) and warned about
//               once per track: two nodes filter it. Another process
//               with the same id (its status says another host, pid or
//               start) is counted (name_clashes) and warned about once
//
// Its status (node_status_t on GF_NODE_STATUS: its counters, and per
// track the results of its inputs, its updates and NIS) goes out at
// start, once a second and as it stops; a replay's at its end only.
//   --url       where to listen (default: $LCM_DEFAULT_URL, else LCM's
//               default udpm URL); file:///log.lcmlog?speed=0 replays a log
//   --out-url   publish beliefs on another LCM instead (needed with a
//               file:// input, which cannot publish), e.g.
//               file:///out.lcmlog?mode=w
//   --channels  regex of the channels to take (default
//               GF_(MEAS|CTRL|MODEL)_-?[0-9]+(_[A-Za-z0-9]+)?: sensors
//               too); e.g.
//               'GF_(MEAS|CTRL|MODEL)_[0-4]' so that several nodes split
//               the tracks
//   --queue     messages the node's input queue holds (default 65536, in
//               GF_INQ_BYTES_PER_MSG bytes each: sim/gf_inq.h). LCM's
//               dispatch only copies each message into it; the handling
//               thread filters and publishes. A message that finds it
//               full is dropped and counted (dropped= in the summary,
//               apart from gaps); a file:// replay waits instead. The
//               kernel's socket buffer: GF_NODE_RCVBUF bytes asked, or
//               the URL's udpm://...?recv_buf_size=BYTES (the ready line
//               says what the kernel gave; kernel_drops= in the summary
//               what it dropped for want of room)
//   --filter    the robot tracks' filter (the car is always KF2): ekf
//               (EKF3, default), ukf (UKF3) or pf (PF3, GF_NODE_PF_PARTICLES
//               particles per track, at most GF_NODE_PF_TRACKS tracks; each
//               PF step also publishes a particles_t cloud on
//               GF_PARTICLES_<track>)
//   --seed      PF tracks' generator seed, plus the track id (default 1)
//   --cpu N     pin the node's handling thread (the one that filters and
//               publishes) to CPU N; with --rx-cpu M, LCM's receive thread
//               (which reads the socket) and the thread that copies each
//               message into the node's queue go to CPU M, else also to N.
//               Latency is lowest with the receive thread on the CPU where
//               the packets arrive (the sender's over loopback, the NIC
//               interrupt's otherwise): its wake-up then needs no IPI
//   --rt P      SCHED_FIFO priority P (1-99) and mlockall for every thread,
//               as a latency-critical node is deployed; needs root or
//               CAP_SYS_NICE, else it says so and runs SCHED_OTHER (the
//               ready line says what took effect)
//   --rate HZ   also publish, HZ times a second, every track's belief
//               predicted to now (belief_t.trigger TRIGGER_RATE; see
//               gf_node_tick in node_core.h); live inputs only
//   --timing    time each message in the node, from LCM's receive
//               timestamp to the return of its belief's publish, and print
//               p50/p99/max at exit (see scripts/bench-lcm)
#define _GNU_SOURCE // sched_setaffinity, CPU_SET (gf_rt.h)
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <pthread.h>

#include <lcm/lcm.h>

#include "gf_inq.h"
#include "gf_route.h"
#include "gf_rt.h"
#include "gf_sock.h"
#include "node_core.h"

#if GF_INQ_MAX_DATA < GF_NODE_MAX_LEN
#error "the input queue must keep every message the node reads"
#endif

// The receive buffer the node asks of the kernel for its udpm socket
// unless the URL says (recv_buf_size=BYTES): 4 MiB holds about 25 000 of
// its inputs, a tenth of a second of the heaviest burst net_burst sends.
// The kernel caps it at net.core.rmem_max.
#define GF_NODE_RCVBUF 4194304L

// The node's status goes out once a second.
#define GF_NODE_STATUS_PERIOD_US 1000000

static volatile sig_atomic_t g_stop; // set by the signal handler only

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

// The node's lines about its tracks (node_core.h's log callback).
static void log_line(void *ctx, const char *line)
{
    (void)ctx;
    printf("gf_node: %s\n", line);
    fflush(stdout);
}

static int publish_lcm(void *ctx, const char *channel, const void *data,
                       size_t len)
{
    return lcm_publish((lcm_t *)ctx, channel, data, (unsigned)len) == 0 ? 0
                                                                        : -1;
}

// --timing: microseconds from LCM's receive timestamp (rbuf->recv_utime,
// CLOCK_REALTIME) to the end of the handling (belief published), one
// bucket per microsecond. LCM 1.5 takes that timestamp from the kernel
// (SO_TIMESTAMP) only on the first use of each of its receive buffers;
// on recycled ones (it does not clear the field) it is the time its
// receive thread read the packet, so this is the node's own hand-off,
// filter and publish, without the wake-up of LCM's receive thread.
#define TIMING_BUCKETS 10000
typedef struct node_ctx {
    gf_node *node;
    gf_inq q;
    gf_rt *rt;
    pthread_mutex_t mu;      // with started: the handling thread is placed
    pthread_mutex_t node_mu; // the node: handling, and others' beliefs
    pthread_cond_t cv;
    int started;
    int timing;
    unsigned long count;
    int64_t max_us;
    uint32_t hist[TIMING_BUCKETS + 1]; // last: TIMING_BUCKETS us or more
} node_ctx;

// LCM's dispatch: the message into the node's input queue, nothing else.
static void on_message(const lcm_recv_buf_t *rbuf, const char *channel,
                       void *user)
{
    node_ctx *c = user;
    (void)gf_inq_push(&c->q, channel, rbuf->data, rbuf->data_size,
                      rbuf->recv_utime);
}

// LCM's dispatch of a node's status (its own come back over udpm): one of
// another process with this node's id is counted and warned about
// (gf_node_peer_status), under the node's lock.
static void on_status(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    node_ctx *c = user;
    (void)channel;
    pthread_mutex_lock(&c->node_mu);
    (void)gf_node_peer_status(c->node, rbuf->data, rbuf->data_size);
    pthread_mutex_unlock(&c->node_mu);
}

// LCM's dispatch of a belief (the node's own come back over udpm): one of
// another node is checked against the node's tracks right here
// (gf_node_peer_belief), under the lock the handling thread holds while it
// handles a message; it never enters the input queue, so the queue's
// counts stay the inputs'. The id is fixed before LCM starts: reading it
// races with nothing.
static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    node_ctx *c = user;
    char id[GF_NODE_ID_MAX];
    int32_t track;
    (void)channel;
    if (gf_node_belief_origin(rbuf->data, rbuf->data_size, &track, id,
                              sizeof id) != 0 ||
        strcmp(id, c->node->id) == 0) {
        return;
    }
    pthread_mutex_lock(&c->node_mu);
    (void)gf_node_peer_belief(c->node, rbuf->data, rbuf->data_size);
    pthread_mutex_unlock(&c->node_mu);
}

// The handling thread: every queued message through gf_node_handle (which
// publishes), in order, until the queue is closed and empty.
static void *handling(void *arg)
{
    node_ctx *c = arg;
    const gf_inq_entry *e;
    gf_rt_pin_main(c->rt, "gf_node");
    pthread_mutex_lock(&c->mu);
    c->started = 1;
    pthread_cond_signal(&c->cv);
    pthread_mutex_unlock(&c->mu);
    while ((e = gf_inq_peek(&c->q)) != NULL) {
        pthread_mutex_lock(&c->node_mu);
        gf_node_handle(c->node, gf_inq_channel(e), gf_inq_data(e), e->len,
                       e->recv_utime);
        pthread_mutex_unlock(&c->node_mu);
        if (c->timing) {
            struct timespec ts;
            clock_gettime(CLOCK_REALTIME, &ts);
            int64_t us = (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000 -
                         e->recv_utime;
            if (us < 0) {
                us = 0;
            }
            c->hist[us < TIMING_BUCKETS ? us : TIMING_BUCKETS]++;
            if (us > c->max_us) {
                c->max_us = us;
            }
            c->count++;
        }
        gf_inq_release(&c->q, e);
    }
    return NULL;
}

// CLOCK_REALTIME in microseconds: the clock of LCM's recv_utime.
static int64_t wall_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

// Publishes the node's status (gf_node_status): stopping = 1 for its last.
static void publish_status(node_ctx *c, int sock, int replay, int stopping)
{
    static uint8_t buf[GF_NODE_STATUS_BYTES];
    gf_node_status_info info;
    info.utime = wall_us();
    info.rx_now = replay ? -1 : info.utime;
    info.kernel_drops = gf_sock_drops(sock);
    pthread_mutex_lock(&c->q.mu);
    info.queue_depth = (int32_t)c->q.count;
    info.queue_peak = (int32_t)c->q.peak;
    pthread_mutex_unlock(&c->q.mu);
    info.stopping = stopping;
    pthread_mutex_lock(&c->node_mu);
    (void)gf_node_status(c->node, &info, buf, sizeof buf);
    pthread_mutex_unlock(&c->node_mu);
}

// The microsecond below which a fraction q of the timed messages fall.
static long timing_quantile(const node_ctx *c, double q)
{
    unsigned long want = (unsigned long)((double)c->count * q), seen = 0;
    long b;
    for (b = 0; b < TIMING_BUCKETS; b++) {
        seen += c->hist[b];
        if (seen > want) {
            return b;
        }
    }
    return TIMING_BUCKETS;
}

static const char usage_text[] =
    "usage: gf_node [--config FILE] [--strict] [--name NAME] [--url URL]\n"
    "               [--out-url URL] [--channels REGEX] [--queue N]\n"
    "               [--filter ekf|ukf|pf] [--seed S] [--cpu N] [--rx-cpu M]\n"
    "               [--rt PRIO] [--rate HZ] [--timing]\n";

static void usage(void)
{
    fputs(usage_text, stderr);
    fputs("gf_node --help says more\n", stderr);
}

static void help(void)
{
    fputs("gf_node: the gaussfilt filter node. Takes each track's controls\n"
          "(GF_CTRL_<id>) and measurements (GF_MEAS_<id>) over LCM, runs the\n"
          "track's filter (KF2 for a car, EKF3/UKF3/PF3 for a robot, gf_kf\n"
          "for a linear model of any size) and publishes its belief on\n"
          "GF_BELIEF_<id> after every input, a refused one too (its status\n"
          "says why). GF_MODEL_<id> (model_t) sets a car's or robot's model\n"
          "or resets any track at run time. Publishes its status\n"
          "(node_status_t: counters, per track results and NIS) on\n"
          "GF_NODE_STATUS once a second. Prints a ready line once it\n"
          "listens, a line for each new track (its model and why), the first\n"
          "refusal of each kind on each track, and at exit (SIGINT, SIGTERM,\n"
          "end of a log) one summary line of counters.\n"
          "udpm needs a multicast route: ip route add 224.0.0.0/4 dev lo (or\n"
          "your interface), else it says \"no route\" and stops.\n\n",
          stdout);
    fputs(usage_text, stdout);
    fputs(
        "\n"
        "  --config FILE   models for channel patterns (docs/node.md); other\n"
        "                  car/robot tracks run the book's presets book-car,\n"
        "                  book-robot; other linear tracks are refused\n"
        "  --strict        refuse every track no configured model names\n"
        "  --name NAME     the node's id in its beliefs (default "
        "host:pid:start)\n"
        "  --url URL       where to listen (default $LCM_DEFAULT_URL or LCM's\n"
        "                  udpm default); file:///x.lcmlog?speed=0 replays a "
        "log\n"
        "  --out-url URL   publish beliefs there instead (needed with "
        "file://)\n"
        "  --channels RE   channels to take (default " GF_CHANNEL_NODE_DEFAULT
        ")\n"
        "  --queue N       the node's input queue, in messages (default\n"
        "                  65536); one that finds it full is dropped, counted\n"
        "  --filter F      robot filter: ekf (default), ukf or pf\n"
        "  --seed S        PF tracks' generator seed, plus the track id (1)\n"
        "  --cpu N, --rx-cpu M, --rt PRIO   thread placement, SCHED_FIFO\n"
        "  --rate HZ       also publish each track's belief predicted to now,\n"
        "                  HZ times a second (trigger TRIGGER_RATE)\n"
        "  --timing        per-message time in the node, p50/p99/max at exit\n"
        "  --help          this text\n\n"
        "example:\n"
        "  gf_node --config car100.conf --url "
        "'udpm://239.255.76.67:7667?ttl=0'\n",
        stdout);
}

// The node's model lookup: the model the configuration names, or NULL
// (node_core then takes the preset, or refuses the track).
static const gf_node_model *lookup_model(const void *ctx, int32_t id,
                                         int8_t kind)
{
    return gf_node_config_named((const gf_node_config *)ctx, id, kind);
}

int main(int argc, char **argv)
{
    const char *url = NULL, *out_url = NULL, *config_path = NULL;
    const char *name = NULL;
    int strict = 0;
    char id[GF_NODE_ID_MAX];
    static gf_node_config config;
    char err[512];
    const char *channels = GF_CHANNEL_NODE_DEFAULT;
    static gf_node node;         // ~15 kB: keep it off the stack
    static gf_node_pf_pool pool; // ~516 kB, used with --filter pf only
    static node_ctx ctx;         // ~40 kB: the --timing histogram
    gf_rt rt = {-1, -1, 0, 0, 0, 0, 0};
    char placement[96];
    gf_node_filter filter = GF_NODE_FILTER_EKF;
    const char *filter_name = "ekf";
    unsigned long seed = 1;
    char summary[1024];
    lcm_t *in, *out;
    struct sigaction sa;
    int i, rc = 0, queue = 65536, have_handler = 0, replay;
    double rate = 0.0;
    int64_t period_us = 0, next_tick = 0;
    pthread_t handler;
    long rcvbuf_asked = GF_NODE_RCVBUF, rcvbuf = -1;
    int sock = -1;
    lcm_subscription_t *sub, *peers, *statuses = NULL;
    int64_t next_status = 0;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            help();
            return 0;
        } else if (strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
            config_path = argv[++i];
        } else if (strcmp(argv[i], "--strict") == 0) {
            strict = 1;
        } else if (strcmp(argv[i], "--name") == 0 && i + 1 < argc &&
                   argv[i + 1][0] != '\0') {
            name = argv[++i];
        } else if (strcmp(argv[i], "--url") == 0 && i + 1 < argc) {
            url = argv[++i];
        } else if (strcmp(argv[i], "--out-url") == 0 && i + 1 < argc) {
            out_url = argv[++i];
        } else if (strcmp(argv[i], "--channels") == 0 && i + 1 < argc) {
            channels = argv[++i];
        } else if (strcmp(argv[i], "--queue") == 0 && i + 1 < argc) {
            queue = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--filter") == 0 && i + 1 < argc &&
                   gf_node_filter_parse(argv[i + 1], &filter) == 0) {
            filter_name = argv[++i];
        } else if (strcmp(argv[i], "--seed") == 0 && i + 1 < argc) {
            seed = strtoul(argv[++i], NULL, 0);
        } else if (strcmp(argv[i], "--cpu") == 0 && i + 1 < argc) {
            rt.cpu = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--rx-cpu") == 0 && i + 1 < argc) {
            rt.rx_cpu = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--rt") == 0 && i + 1 < argc) {
            rt.prio = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--timing") == 0) {
            ctx.timing = 1;
        } else if (strcmp(argv[i], "--rate") == 0 && i + 1 < argc) {
            char *end;
            rate = strtod(argv[++i], &end);
            if (*end != '\0' || !(rate > 0.0 && rate <= 1000.0)) {
                fprintf(stderr, "gf_node: --rate takes 0 < HZ <= 1000\n");
                return 2;
            }
        } else {
            usage();
            return 2;
        }
    }

    if (config_path != NULL &&
        gf_node_config_load(&config, config_path, err, sizeof err) != 0) {
        fprintf(stderr, "gf_node: %s\n", err);
        return 2;
    }

    // the kernel's socket buffer as the URL asks (LCM sets it), else ours
    {
        const char *u = url != NULL ? url : getenv("LCM_DEFAULT_URL");
        const char *r = u != NULL ? strstr(u, "recv_buf_size=") : NULL;
        if (r != NULL) {
            rcvbuf_asked = strtol(r + 14, NULL, 10);
        }
    }

    // LCM's receive thread, started by lcm_subscribe, inherits CPU and policy.
    gf_rt_setup(&rt, "gf_node");
    in = gf_lcm_open("gf_node", url);
    if (in == NULL) {
        fprintf(stderr, "gf_node: cannot open LCM at %s\n",
                url ? url : "(default URL)");
        return 1;
    }
    out = in;
    if (out_url != NULL) {
        out = gf_lcm_open("gf_node", out_url);
        if (out == NULL) {
            fprintf(stderr, "gf_node: cannot open LCM at %s\n", out_url);
            lcm_destroy(in);
            return 1;
        }
    }

    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    gf_node_init(&node, publish_lcm, out);
    gf_node_set_filter(&node, filter, &pool, (uint32_t)seed);
    gf_node_set_models(&node, lookup_model, &config);
    gf_node_set_strict(&node, strict);
    gf_node_set_log(&node, log_line, NULL);
    if (name != NULL) {
        snprintf(id, sizeof id, "%s", name);
    } else {
        char host[40] = "host";
        (void)gethostname(host, sizeof host);
        host[sizeof host - 1] = '\0';
        snprintf(id, sizeof id, "%s:%ld:%lld", host, (long)getpid(),
                 (long long)time(NULL));
    }
    gf_node_set_id(&node, id);
    {
        char host[GF_NODE_HOST_MAX] = "host";
        (void)gethostname(host, sizeof host);
        host[sizeof host - 1] = '\0';
        gf_node_set_process(&node, host, (int32_t)getpid(), wall_us());
    }
    ctx.node = &node;
    ctx.rt = &rt;
    pthread_mutex_init(&ctx.mu, NULL);
    pthread_mutex_init(&ctx.node_mu, NULL);
    pthread_cond_init(&ctx.cv, NULL);
    {
        const char *u = url != NULL ? url : getenv("LCM_DEFAULT_URL");
        replay = u != NULL && strncmp(u, "file://", 7) == 0;
    }
    if (replay && rate > 0.0) {
        fprintf(stderr, "gf_node: --rate needs a live input (a replay's "
                        "beliefs must not depend on the wall clock)\n");
        return 2;
    }
    if (queue < 1 || gf_inq_init(&ctx.q, (unsigned)queue, replay) != 0) {
        fprintf(stderr, "gf_node: no input queue of %d messages\n", queue);
        return 1;
    }
    sub = lcm_subscribe(in, channels, on_message, &ctx);
    // other nodes' beliefs of this node's tracks (gf_node_peer_belief)
    peers = replay ? NULL
                   : lcm_subscribe(in, GF_CHANNEL_BELIEF "-?[0-9]+", on_belief,
                                   &ctx);
    // other processes with this node's id (gf_node_peer_status)
    if (!replay) {
        statuses = lcm_subscribe(in, GF_CHANNEL_STATUS, on_status, &ctx);
    }
    // LCM's own limit off: every message goes to on_message (the queue
    // above is the node's bound, and it counts what it drops)
    if (sub == NULL || lcm_subscription_set_queue_capacity(sub, 0) != 0 ||
        (!replay &&
         (peers == NULL || lcm_subscription_set_queue_capacity(peers, 0) != 0 ||
          statuses == NULL)) ||
        pthread_create(&handler, NULL, handling, &ctx) != 0) {
        fprintf(stderr, "gf_node: cannot subscribe to %s\n", channels);
        rc = 1;
        g_stop = 1;
    } else {
        have_handler = 1;
        // (lcm_subscribe made LCM's receive socket)
        sock = gf_sock_udpm();
        if (sock >= 0 && rcvbuf_asked == GF_NODE_RCVBUF) {
            int v = (int)GF_NODE_RCVBUF;
            (void)setsockopt(sock, SOL_SOCKET, SO_RCVBUF, &v, sizeof v);
        }
        // (SO_RCVBUF reads twice what the kernel granted: its bookkeeping)
        rcvbuf = gf_sock_rcvbuf(sock) >= 0 ? gf_sock_rcvbuf(sock) / 2 : -1;
        pthread_mutex_lock(&ctx.mu);
        while (!ctx.started) {
            pthread_cond_wait(&ctx.cv, &ctx.mu);
        }
        pthread_mutex_unlock(&ctx.mu);
        gf_rt_describe(&rt, placement, sizeof placement);
        if (rcvbuf >= 0 && rcvbuf < rcvbuf_asked) {
            printf("gf_node: warning: the kernel granted the socket a "
                   "receive buffer of %ld bytes of the %ld asked: "
                   "net.core.rmem_max caps it; as root: sysctl -w "
                   "net.core.rmem_max=%ld\n",
                   rcvbuf, rcvbuf_asked, rcvbuf_asked);
        }
        printf("gf_node: ready channels=%s queue=%d queue_bytes=%zu ", channels,
               queue, ctx.q.cap);
        if (rcvbuf >= 0) {
            printf("rcvbuf=%ld rcvbuf_asked=%ld ", rcvbuf, rcvbuf_asked);
        } else {
            printf("rcvbuf=none ");
        }
        printf("max_tracks=%d track_bytes=%zu node_bytes=%zu "
               "filter=%s models=%u%s%s%s id=%s %s",
               GF_NODE_MAX_TRACKS, sizeof(gf_node_track), sizeof(gf_node),
               filter_name, config.count, config_path ? " config=" : "",
               config_path ? config_path : "", strict ? " strict" : "", id,
               placement);
        if (rate > 0.0) {
            printf(" rate=%g", rate);
        }
        if (filter == GF_NODE_FILTER_PF) {
            printf(" pf_tracks=%d pf_particles=%d pool_bytes=%zu",
                   GF_NODE_PF_TRACKS, GF_NODE_PF_PARTICLES, sizeof(pool));
        }
        printf("\n");
        fflush(stdout);
    }

    if (rate > 0.0) {
        period_us = (int64_t)(1e6 / rate + 0.5);
        next_tick = wall_us() + period_us;
    }
    if (have_handler && !replay) { // the first status: seq 0, at start
        publish_status(&ctx, sock, replay, 0);
        next_status = wall_us() + GF_NODE_STATUS_PERIOD_US;
    }
    while (!g_stop) {
        int ms = 100;
        if (period_us > 0) {
            int64_t left = next_tick - wall_us();
            ms = left <= 0 ? 0 : left >= 100000 ? 100 : (int)(left / 1000) + 1;
        }
        if (!replay && wall_us() >= next_status) {
            publish_status(&ctx, sock, replay, 0);
            next_status += GF_NODE_STATUS_PERIOD_US;
            if (next_status <= wall_us()) { // fell behind: from now on
                next_status = wall_us() + GF_NODE_STATUS_PERIOD_US;
            }
        }
        // < 0: the end of a file:// log, a dead socket, or a signal.
        if (lcm_handle_timeout(in, ms) < 0) {
            break;
        }
        if (period_us > 0 && wall_us() >= next_tick) {
            int64_t now = wall_us();
            // in the receive times' clock (LCM's recv_utime: the wall's)
            pthread_mutex_lock(&ctx.node_mu);
            (void)gf_node_tick(&node, now);
            pthread_mutex_unlock(&ctx.node_mu);
            next_tick += period_us;
            if (next_tick <= now) { // fell behind: from now on
                next_tick = now + period_us;
            }
        }
    }

    gf_inq_close(&ctx.q);
    if (have_handler) {
        pthread_join(handler, NULL);
    }
    gf_node_add_dropped(&node, ctx.q.dropped);
    if (have_handler) {
        publish_status(&ctx, sock, replay, 1); // its last
    }
    gf_node_summary(&node, summary, sizeof(summary));
    printf("gf_node: summary %s queue_peak=%u", summary, ctx.q.peak);
    if (gf_sock_drops(sock) >= 0) {
        printf(" kernel_drops=%ld", gf_sock_drops(sock));
    }
    printf("\n");
    if (ctx.timing && ctx.count > 0) {
        printf("gf_node: timing messages=%lu in_node_p50_us=%ld "
               "in_node_p99_us=%ld in_node_max_us=%lld\n",
               ctx.count, timing_quantile(&ctx, 0.5),
               timing_quantile(&ctx, 0.99), (long long)ctx.max_us);
    }
    fflush(stdout);
    if (out != in) {
        lcm_destroy(out);
    }
    lcm_destroy(in);
    gf_node_config_free(&config);
    gf_inq_free(&ctx.q);
    return rc;
}
