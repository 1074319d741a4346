// SPDX-License-Identifier: MIT
// gf_sim: the simulators of the exercises, publishing over LCM.
//
//   gf_sim --model car|robot [--track N] [--steps N] [--seed S] [--rate HZ]
//          [--meas-every K] [--meas-var V] [--turn PHI] [--session S]
//          [--url URL]
//   gf_sim --exercise 1|2|4 [--track N] [--session S] [--url URL]
//   gf_sim --config FILE --model NAME [--runs M] [--track N] [--steps N]
//          [--seed S] [--rate HZ] [--turn PHI] [--jitter J]
//          [--drop SENSOR:FROM:TO] [--delay SENSOR:SECONDS] [--session S]
//          [--url URL]
//   any of them with --wait FILE (repeatable): first waits until each FILE
//   has a ready line (": ready", as gf_node and examples/beliefs.py print
//   one once they listen), up to --wait-s seconds (default 60)
//
// car (exercises 1-2): each step a random acceleration a ~ N(0, 1) moves the
//   true state (x += v + a/2, v += a); every K-th step the position is
//   measured with variance V (default 10).
// robot (exercise 4): from (0, 0) with a heading drawn uniformly, each step
//   "move 1 forward, then turn PHI" (default 0.1 rad) by odometry, then x is
//   observed with variance V (default 0.01).
// --config: the model NAME of a node configuration (sim/node_model.h; the
//   presets book-car and book-robot too): the truth starts from a draw of
//   the model's prior and moves as the model says (the car with a white
//   acceleration of variance accel_var over dt; the robot "move 1, turn
//   PHI" with the odometry's noise on d and phi), and each step is
//   measured as the model's measure says, with noise drawn from meas_cov
//   and sent as q. A linear model (any n): x_t = A x_{t-1} + B u_t + eps,
//   eps ~ N(0, R), z = C x + delta, delta ~ N(0, Q), with u_i = sin(0.1 t
//   + i) when it has controls (B). --runs M: M independent runs at once on
//   tracks N .. N + M - 1, run k seeded S + k (the Monte-Carlo runs of a
//   consistency test): every step goes out for each run in turn, so
//   --rate HZ is HZ steps per second of each run, M * HZ in all. utime is
//   t * dt for the car and a linear model, t seconds for the robot.
// A linear model in time (motion = ...) with named sensors and no
//   controls: each sensor sends at its rate (every dt for rate 0) on
//   GF_MEAS_<track>_<name> with its own seq, the truth moved to each
//   sample's utime with A(dt), R(dt) (the model's dt before the first
//   sample) and sent before it; --jitter J moves sample k of a sensor of
//   period T to (k + J (u - 1/2)) T, u uniform; --drop NAME:FROM:TO
//   silences a sensor from FROM to TO seconds; --delay NAME:SECONDS sends
//   a sensor's measurements that much later (in the samples' time: after
//   the other sensors' samples up to then), as a sensor with a latency
//   would. --steps N: N steps of dt.
// --exercise replays the book exactly:
//   1: the car, 10 prediction steps, no measurement (Table 1.1, Fig. 1.2);
//   2: the car, 5 prediction steps, z = 5 (Q = 10) at t = 5 (Table 2.1);
//      --steps N, --z Z and --meas-var V change exercise 2's numbers
//      (examples/book.h, where every exercise number is);
//   4: the robot moves once (u = (1, 0)), then observes x = -0.7 (Q = 0.01)
//      (Table 4.2).
//
// Per step: GF_CTRL_<track> (a prediction step), GF_TRUTH_<track> (random
// modes), and GF_MEAS_<track> when there is a measurement; seq counts the
// track's controls and measurements together from 1. utime is simulated
// time, t * dt with dt = 1 s (or 1/HZ s with --rate), so a seed always gives
// the same bytes. --rate 0 (default) sends as fast as possible; otherwise
// one step every 1/HZ s of wall-clock time.
//
// session: every control and measurement carries the run's session number,
// by default the wall-clock time of the start in microseconds, so a
// restarted simulator (seq from 1 again) has a larger one and the node
// re-initialises its track (sim/node_core.h). --session S fixes it, for
// runs that must give the same bytes. SIGINT/SIGTERM stop the run early;
// the summary line still says what was sent.
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/lcm.h>

#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_groundtruth_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "book.h"
#include "gf_channels.h"
#include "gf_help.h"
#include "gf_route.h"
#include "node_model.h"

#define MODEL_CAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
#define MODEL_ROBOT GAUSSFILT_LCM_MEASUREMENT_T_MODEL_ROBOT
#define MODEL_LINEAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR
#define NMAX GF_NODE_NMAX

// ---- deterministic random numbers: xoshiro256** seeded by splitmix64 ------

typedef struct rng {
    uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

static void rng_seed(rng *r, uint64_t seed)
{
    unsigned i;
    for (i = 0; i < 4; i++) {
        r->s[i] = splitmix64(&seed);
    }
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t rng_next(rng *r)
{
    uint64_t *s = r->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

// Uniform in (0, 1).
static double rng_uniform(rng *r)
{
    return ((double)(rng_next(r) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

// Standard normal (Box-Muller; one of the pair is dropped, for simplicity).
static double rng_normal(rng *r)
{
    double u1 = rng_uniform(r), u2 = rng_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * 3.14159265358979323846 * u2);
}

// ---- publishing -------------------------------------------------------------

typedef struct sim {
    lcm_t *lcm;
    int32_t track;
    int8_t model;
    int64_t seq; // last seq used on the track
    int64_t session;
    int64_t step_us; // utime per step
    char ch_ctrl[GF_CHANNEL_MAX], ch_meas[GF_CHANNEL_MAX],
        ch_truth[GF_CHANNEL_MAX];
    unsigned long sent_ctrl, sent_meas, sent_truth;
    int failed;
    uint8_t buf[64 + 8 * (NMAX + NMAX * NMAX)];
} sim;

static void publish_bytes(sim *s, const char *channel, int len)
{
    if (len < 0 || lcm_publish(s->lcm, channel, s->buf, (unsigned)len) != 0) {
        s->failed = 1;
    }
}

static void send_ctrl_v(sim *s, long t, int n, const double *u)
{
    gaussfilt_lcm_control_t c;
    double uu[NMAX];
    int i;
    memset(&c, 0, sizeof(c));
    for (i = 0; i < n; i++) {
        uu[i] = u[i];
    }
    c.utime = t * s->step_us;
    c.seq = ++s->seq;
    c.session = s->session;
    c.track = s->track;
    c.model = s->model;
    c.n = (int8_t)n;
    c.u = uu;
    publish_bytes(
        s, s->ch_ctrl,
        gaussfilt_lcm_control_t_encode(s->buf, 0, (int)sizeof(s->buf), &c));
    s->sent_ctrl++;
}

static void send_ctrl(sim *s, long t, int n, double u0, double u1)
{
    const double u[2] = {u0, u1};
    send_ctrl_v(s, t, n, u);
}

// A measurement of m quantities z with noise q (m x m, rows of m).
static void send_meas_m(sim *s, long t, int m, const double *z, const double *q)
{
    gaussfilt_lcm_measurement_t msg;
    double zz[NMAX], qq[NMAX * NMAX], *rows[NMAX];
    int i;
    memset(&msg, 0, sizeof(msg));
    for (i = 0; i < m; i++) {
        zz[i] = z[i];
        memcpy(&qq[i * m], &q[i * m], sizeof(double) * (size_t)m);
        rows[i] = &qq[i * m];
    }
    msg.utime = t * s->step_us;
    msg.seq = ++s->seq;
    msg.session = s->session;
    msg.track = s->track;
    msg.model = s->model;
    msg.m = (int8_t)m;
    msg.z = zz;
    msg.q = rows;
    publish_bytes(s, s->ch_meas,
                  gaussfilt_lcm_measurement_t_encode(
                      s->buf, 0, (int)sizeof(s->buf), &msg));
    s->sent_meas++;
}

// A measurement on a sensor's channel with its own seq, at utime u.
// Its bytes into buf (at most size): the encoded length, or < 0.
static int encode_meas_on(sim *s, int64_t *seq, int64_t u, int m,
                          const double *z, const double *q, uint8_t *buf,
                          int size)
{
    gaussfilt_lcm_measurement_t msg;
    double zz[NMAX], qq[NMAX * NMAX], *rows[NMAX];
    int i;
    memset(&msg, 0, sizeof(msg));
    for (i = 0; i < m; i++) {
        zz[i] = z[i];
        memcpy(&qq[i * m], &q[i * m], sizeof(double) * (size_t)m);
        rows[i] = &qq[i * m];
    }
    msg.utime = u;
    msg.seq = ++*seq;
    msg.session = s->session;
    msg.track = s->track;
    msg.model = s->model;
    msg.m = (int8_t)m;
    msg.z = zz;
    msg.q = rows;
    return gaussfilt_lcm_measurement_t_encode(buf, 0, size, &msg);
}

static void send_meas_on(sim *s, const char *channel, int64_t *seq, int64_t u,
                         int m, const double *z, const double *q)
{
    publish_bytes(
        s, channel,
        encode_meas_on(s, seq, u, m, z, q, s->buf, (int)sizeof(s->buf)));
    s->sent_meas++;
}

static void send_meas(sim *s, long t, double z, double q)
{
    send_meas_m(s, t, 1, &z, &q);
}

static void send_truth_at(sim *s, int64_t u, int n, const double *x);

static void send_truth(sim *s, long t, int n, const double *x)
{
    send_truth_at(s, t * s->step_us, n, x);
}

// The true state at utime u, with the seq of the track's last input.
static void send_truth_at(sim *s, int64_t u, int n, const double *x)
{
    gaussfilt_lcm_groundtruth_t g;
    double state[NMAX];
    int i;
    memset(&g, 0, sizeof(g));
    for (i = 0; i < n; i++) {
        state[i] = x[i];
    }
    g.utime = u;
    g.seq = s->seq; // the seq of the step's control
    g.track = s->track;
    g.model = s->model;
    g.n = (int8_t)n;
    g.state = state;
    publish_bytes(
        s, s->ch_truth,
        gaussfilt_lcm_groundtruth_t_encode(s->buf, 0, (int)sizeof(s->buf), &g));
    s->sent_truth++;
}

// Sleeps until the absolute monotonic time *next, then advances it by
// period_ns. Does nothing with period_ns == 0 (as fast as possible).
static void pace(struct timespec *next, long period_ns)
{
    if (period_ns <= 0) {
        return;
    }
    next->tv_nsec += period_ns;
    while (next->tv_nsec >= 1000000000L) {
        next->tv_nsec -= 1000000000L;
        next->tv_sec++;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, next, NULL) != 0)
        ;
}

// x = mean + L w, L L^T = cov (n x n PSD, rows of n; a zero pivot adds
// nothing). mean may be NULL (zero).
static void draw_n(rng *r, unsigned n, const double *mean, const double *cov,
                   double *x)
{
    double l[NMAX][NMAX], w[NMAX];
    unsigned i, j, k;
    memset(l, 0, sizeof l);
    for (j = 0; j < n; j++) {
        double d = cov[j * n + j];
        for (k = 0; k < j; k++) {
            d -= l[j][k] * l[j][k];
        }
        l[j][j] = d > 0.0 ? sqrt(d) : 0.0;
        for (i = j + 1; i < n; i++) {
            double v = cov[i * n + j];
            for (k = 0; k < j; k++) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = l[j][j] > 0.0 ? v / l[j][j] : 0.0;
        }
    }
    for (i = 0; i < n; i++) {
        w[i] = rng_normal(r);
    }
    for (i = 0; i < n; i++) {
        x[i] = mean != NULL ? mean[i] : 0.0;
        for (k = 0; k <= i; k++) {
            x[i] += l[i][k] * w[k];
        }
    }
}

// draw_n of the leading n x n block of a 3 x 3 matrix.
static void draw(rng *r, unsigned n, const double *mean, const double cov[3][3],
                 double *x)
{
    double c[9];
    unsigned i, j;
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            c[i * n + j] = cov[i][j];
        }
    }
    draw_n(r, n, mean, c, x);
}

// Waits until the file has a ready line (": ready"), up to seconds;
// 0 when it has.
static int wait_ready(const char *path, double seconds)
{
    struct timespec nap = {0, 50000000L};
    long tries = (long)(seconds * 20.0) + 1, k;
    char line[1024];
    for (k = 0; k < tries; k++) {
        FILE *f = fopen(path, "r");
        if (f != NULL) {
            while (fgets(line, sizeof line, f) != NULL) {
                if (strstr(line, ": ready") != NULL) {
                    fclose(f);
                    return 0;
                }
            }
            fclose(f);
        }
        nanosleep(&nap, NULL);
    }
    return -1;
}

#define MAX_RUNS 64

// One run of a configured model (see the top): the state, its generator.
typedef struct run {
    sim s;
    rng r;
    double x[NMAX];
} run;

// One step of a linear model's truth and its measurement (see the top).
static void linear_step(run *q, const gf_node_linear *l, long t, int measure)
{
    double x[NMAX], u[NMAX], w[NMAX], z[NMAX];
    unsigned i, j;
    for (j = 0; j < l->nu; j++) {
        u[j] = sin(0.1 * (double)t + (double)j);
    }
    draw_n(&q->r, l->n, NULL, l->R, w);
    // x_t = A x_{t-1} + B u_t + eps
    for (i = 0; i < l->n; i++) {
        x[i] = w[i];
        for (j = 0; j < l->n; j++) {
            x[i] += l->A[i * l->n + j] * q->x[j];
        }
        for (j = 0; j < l->nu; j++) {
            x[i] += l->B[i * l->nu + j] * u[j];
        }
    }
    memcpy(q->x, x, sizeof(double) * l->n);
    send_ctrl_v(&q->s, t, (int)l->nu, u);
    send_truth(&q->s, t, (int)l->n, q->x);
    if (!measure) {
        return;
    }
    // z = C x + delta
    draw_n(&q->r, l->m, NULL, l->Q, z);
    for (i = 0; i < l->m; i++) {
        for (j = 0; j < l->n; j++) {
            z[i] += l->C[i * l->n + j] * q->x[j];
        }
    }
    send_meas_m(&q->s, t, (int)l->m, z, l->Q);
}

// ---- a linear model's named sensors (see the top) ---------------------------

// One run's sensors: each one's channel, seq and next sample.
#define SENSOR_HELD 64

typedef struct sensor_run {
    char ch[GF_NODE_SENSORS][GF_CHANNEL_MAX];
    int64_t seq[GF_NODE_SENSORS];
    long k[GF_NODE_SENSORS];       // samples drawn so far
    int64_t next[GF_NODE_SENSORS]; // utime of the next sample
    int64_t last;                  // utime of the last sample (truth's time)
    int started;
    // the delayed sensor's measurements, sent once the samples have
    // reached their utime + delay (in order)
    struct {
        int64_t release;
        int len;
        uint8_t buf[64 + 8 * (NMAX + NMAX * NMAX)];
    } held[SENSOR_HELD];
    unsigned nheld, first_held;
} sensor_run;

// Sensors' samples: sample k of a sensor of rate r (every step of dt when
// r = 0) at (k + jitter (u - 1/2)) / r seconds, u uniform in (0, 1); none
// while the sensor is dropped.
typedef struct sensor_opts {
    double jitter;     // a fraction of the sensor's period, < 1
    int drop;          // the sensor index dropped, -1 for none
    int64_t drop_from; // utime
    int64_t drop_to;   // utime
    int delay;         // the sensor index delayed, -1 for none
    int64_t delay_us;  // its measurements go out this much later
} sensor_opts;

// Sends the delayed sensor's held measurements due by utime u (all of
// them for INT64_MAX).
static void release_held(run *q, sensor_run *sr, const sensor_opts *o,
                         int64_t u)
{
    while (sr->nheld > 0 && sr->held[sr->first_held].release <= u) {
        unsigned i = sr->first_held;
        if (sr->held[i].len < 0 ||
            lcm_publish(q->s.lcm, sr->ch[o->delay], sr->held[i].buf,
                        (unsigned)sr->held[i].len) != 0) {
            q->s.failed = 1;
        }
        sr->first_held = (sr->first_held + 1) % SENSOR_HELD;
        sr->nheld--;
    }
}

static double sensor_period(const gf_node_sensor *sen, double dt)
{
    return sen->rate > 0.0 ? 1.0 / sen->rate : dt;
}

// The utime of sensor i's next sample after the k-th.
static int64_t sensor_next(sensor_run *sr, rng *r, const gf_node_sensor *sen,
                           unsigned i, double dt, const sensor_opts *o)
{
    double t = ((double)++sr->k[i] +
                (o->jitter > 0.0 ? o->jitter * (rng_uniform(r) - 0.5) : 0.0)) *
               sensor_period(sen, dt);
    return (int64_t)llround(t * 1e6);
}

// Samples every sensor due at or before utime `until` in time order: the
// truth moves to each sample's time (A(dt), R(dt) from the motion over the
// dt since the last sample; the model's dt before the first, where the
// prior holds), then is sent, then the measurement.
static void sensors_until(run *q, sensor_run *sr, const gf_node_model *mdl,
                          int64_t until, const sensor_opts *o)
{
    const gf_node_linear *l = mdl->lin;
    const gf_node_sensors *set = mdl->sensors;
    for (;;) {
        static double A[NMAX * NMAX], R[NMAX * NMAX];
        double x[NMAX], w[NMAX], z[NMAX];
        unsigned i, j, k, best = 0;
        int64_t u = INT64_MAX;
        double dt;
        for (k = 0; k < set->count; k++) {
            if (sr->next[k] < u) {
                u = sr->next[k];
                best = k;
            }
        }
        if (u > until) {
            return;
        }
        release_held(q, sr, o, u); // those due before this sample
        k = best;
        sr->next[k] = sensor_next(sr, &q->r, &set->s[k], k, mdl->dt, o);
        if (k == (unsigned)o->drop && u >= o->drop_from && u < o->drop_to) {
            continue;
        }
        dt = sr->started ? (double)(u - sr->last) / 1e6 : mdl->dt;
        sr->started = 1;
        sr->last = u;
        // x = A(dt) x + eps, eps ~ N(0, R(dt))
        gf_node_linear_motion(l, dt, A, R);
        draw_n(&q->r, l->n, NULL, R, w);
        for (i = 0; i < l->n; i++) {
            x[i] = w[i];
            for (j = 0; j < l->n; j++) {
                x[i] += A[i * l->n + j] * q->x[j];
            }
        }
        memcpy(q->x, x, sizeof(double) * l->n);
        q->s.seq++; // the truths count the samples
        send_truth_at(&q->s, u, (int)l->n, q->x);
        // z = C x + delta, delta ~ N(0, Q); an angle's residual wrapped
        {
            const gf_node_sensor *sen = &set->s[k];
            draw_n(&q->r, sen->m, NULL, sen->Q, z);
            for (i = 0; i < sen->m; i++) {
                for (j = 0; j < l->n; j++) {
                    z[i] += sen->C[i * l->n + j] * q->x[j];
                }
                if (sen->angle_mask & (1u << i)) {
                    z[i] = remainder(z[i], 2.0 * 3.14159265358979323846);
                }
            }
            if ((int)k == o->delay && sr->nheld < SENSOR_HELD) {
                unsigned h = (sr->first_held + sr->nheld++) % SENSOR_HELD;
                sr->held[h].release = u + o->delay_us;
                sr->held[h].len = encode_meas_on(
                    &q->s, &sr->seq[k], u, (int)sen->m, z, sen->Q,
                    sr->held[h].buf, (int)sizeof sr->held[i].buf);
                q->s.sent_meas++;
            } else {
                send_meas_on(&q->s, sr->ch[k], &sr->seq[k], u, (int)sen->m, z,
                             sen->Q);
            }
        }
    }
}

// The measurement of truth x under model mdl, noise included.
static int measure(const gf_node_model *mdl, rng *r, const double *x, double *z)
{
    static const double zero[3] = {0, 0, 0};
    double noise[3] = {0, 0, 0};
    int measure = mdl->measure;
    unsigned m;
    if (measure == GF_NODE_MEASURE_AUTO) {
        measure = GF_NODE_MEASURE_X;
    }
    m = gf_node_measure_m(mdl->kind, (int8_t)measure);
    draw(r, m, zero, mdl->meas_cov, noise);
    z[1] = 0.0;
    switch (measure) {
    case GF_NODE_MEASURE_X:
        z[0] = x[0];
        break;
    case GF_NODE_MEASURE_V:
        z[0] = x[1];
        break;
    case GF_NODE_MEASURE_XV:
    case GF_NODE_MEASURE_XY:
        z[0] = x[0];
        z[1] = x[1];
        break;
    default: {
        double dx = mdl->landmark[0] - x[0], dy = mdl->landmark[1] - x[1];
        z[0] = sqrt(dx * dx + dy * dy);
        z[1] = atan2(dy, dx) - x[2];
    }
    }
    z[0] += noise[0];
    if (m == 2) {
        z[1] += noise[1];
    }
    if (measure == GF_NODE_MEASURE_RANGE_BEARING) {
        z[1] = remainder(z[1], 2.0 * 3.14159265358979323846);
    }
    return (int)m;
}

static volatile sig_atomic_t g_stop; // set by the signal handler only

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static void usage(void)
{
    fprintf(stderr,
            "usage: gf_sim --model car|robot [--track N] [--steps N] "
            "[--seed S] [--rate HZ]\n"
            "              [--meas-every K] [--meas-var V] [--turn PHI] "
            "[--session S] [--url URL]\n"
            "       gf_sim --exercise 1|2|4 [--track N] [--session S] "
            "[--url URL]\n"
            "       gf_sim --config FILE --model NAME [--runs M] ... "
            "(gf_sim --help)\n"
            "       (any with --wait FILE ... [--wait-s S])\n");
}

static const char help_text[] =
    "gf_sim: streams a simulated car, robot or linear model over LCM: each\n"
    "step a control (GF_CTRL_<track>), the true state (GF_TRUTH_<track>) and\n"
    "a measurement (GF_MEAS_<track>), for a gf_node to filter. Nothing\n"
    "waits for a receiver: what goes out before a node listens is lost (the\n"
    "node counts it, lost_before_first); --wait makes sure it listens.\n\n"
    "usage: gf_sim --exercise 1|2|4 [--track N] [--session S] [--url URL]\n"
    "       gf_sim --model car|robot [--track N] [--steps N] [--seed S]\n"
    "              [--rate HZ] [--meas-every K] [--meas-var V] [--turn PHI]\n"
    "       gf_sim --config FILE --model NAME [--runs M] [--track N]\n"
    "              [--steps N] [--seed S] [--rate HZ] [--turn PHI]\n"
    "              [--jitter J] [--drop SENSOR:FROM:TO] [--delay S:SECONDS]\n\n"
    "  --exercise E    Probabilistic Robotics ch. 3, exercise 1, 2 or 4 "
    "exactly;\n"
    "                  exercise 2 with --steps N, --z Z, --meas-var V changed\n"
    "  --model car|robot  the exercises' car or robot with random motion\n"
    "  --config FILE --model NAME  a model of a gf_node configuration (car,\n"
    "                  robot or linear; or book-car, book-robot): truth from\n"
    "                  its prior, moved and measured with its noise\n"
    "  --runs M        M independent runs on tracks N..N+M-1 (seed S+k),\n"
    "                  sent together: each step goes out for every run, at\n"
    "                  --rate HZ each (M * HZ steps per second in all)\n"
    "  --track N       track id (default 1); --steps N; --seed S (default 1)\n"
    "  --rate HZ       steps per second of wall-clock time (default: flat "
    "out)\n"
    "  --meas-every K, --meas-var V, --turn PHI  (car/robot without --config)\n"
    "  --jitter J      a model's sensors: each sample moved by up to J/2 of\n"
    "                  its sensor's period (0 <= J < 1)\n"
    "  --drop S:A:B    a model's sensor S sends nothing from A to B seconds\n"
    "  --delay S:D     a model's sensor S sends each measurement D seconds\n"
    "                  later (after the others' of that time: late at the\n"
    "                  node)\n"
    "  --session S     the run's session (default: the start time in us)\n"
    "  --url URL       LCM URL (default LCM's); file:///x.lcmlog?mode=w "
    "writes\n"
    "  --wait FILE     first wait until FILE has a ready line (\": ready\",\n"
    "                  as gf_node's and beliefs.py's output say once they\n"
    "                  listen); repeatable; up to --wait-s S seconds (60)\n\n"
    "example:\n"
    "  gf_node --config examples/node.conf > node.out &\n"
    "  gf_sim --wait node.out --config examples/node.conf --model car100 "
    "--track 100 --rate 100\n";

int main(int argc, char **argv)
{
    const char *url = NULL, *config_path = NULL, *model_name = NULL;
    gf_book book = GF_BOOK_DEFAULTS;
    static gf_node_config config;
    static run runs[MAX_RUNS];
    static sensor_run sruns[MAX_RUNS];
    sensor_opts so = {0.0, -1, 0, 0, -1, 0};
    const char *drop = NULL, *delay = NULL;
    int sensors = 0;
    const gf_node_model *mdl = NULL;
    long nruns = 1;
    char err[512];
    int exercise = 0, i;
    long steps = -1, meas_every = 1, t;
    double rate = 0.0, meas_var = -1.0, turn = 0.1;
    uint64_t seed = 1;
    long period_ns = 0;
    struct timespec next;
    struct sigaction sa;
    int have_session = 0;
    const char *wait_for[16];
    int nwait = 0;
    double wait_s = 60.0;
    static sim s; // holds the encode buffer; off the stack
    rng r;

    memset(&s, 0, sizeof(s));
    s.track = 1;
    s.model = 0;
    gf_help(argc, argv, help_text);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (v == NULL) {
            usage();
            return 2;
        }
        i++;
        if (strcmp(a, "--url") == 0) {
            url = v;
        } else if (strcmp(a, "--z") == 0 || strcmp(a, "--heading-var") == 0) {
            // exercise 2's z; exercise 4's heading variance is the node's
            // prior, not the stream's: taken so one command line fits all
            int k = i - 1;
            if (gf_book_option(&book, argc, argv, &k) != 1) {
                return 2;
            }
        } else if (strcmp(a, "--model") == 0 && strcmp(v, "car") == 0) {
            s.model = MODEL_CAR;
        } else if (strcmp(a, "--model") == 0 && strcmp(v, "robot") == 0) {
            s.model = MODEL_ROBOT;
        } else if (strcmp(a, "--model") == 0) {
            model_name = v;
        } else if (strcmp(a, "--config") == 0) {
            config_path = v;
        } else if (strcmp(a, "--runs") == 0) {
            nruns = atol(v);
        } else if (strcmp(a, "--exercise") == 0) {
            exercise = atoi(v);
        } else if (strcmp(a, "--track") == 0) {
            s.track = (int32_t)atol(v);
        } else if (strcmp(a, "--steps") == 0) {
            steps = atol(v);
        } else if (strcmp(a, "--seed") == 0) {
            seed = strtoull(v, NULL, 0);
        } else if (strcmp(a, "--rate") == 0) {
            rate = atof(v);
        } else if (strcmp(a, "--meas-every") == 0) {
            meas_every = atol(v);
        } else if (strcmp(a, "--meas-var") == 0) {
            meas_var = atof(v);
        } else if (strcmp(a, "--turn") == 0) {
            turn = atof(v);
        } else if (strcmp(a, "--jitter") == 0) {
            so.jitter = atof(v);
        } else if (strcmp(a, "--drop") == 0) {
            drop = v;
        } else if (strcmp(a, "--delay") == 0) {
            delay = v;
        } else if (strcmp(a, "--wait") == 0 && nwait < 16) {
            wait_for[nwait++] = v;
        } else if (strcmp(a, "--wait-s") == 0) {
            wait_s = atof(v);
        } else if (strcmp(a, "--session") == 0) {
            s.session = strtoll(v, NULL, 0);
            have_session = 1;
        } else {
            usage();
            return 2;
        }
    }
    if (model_name != NULL) {
        if (config_path != NULL &&
            gf_node_config_load(&config, config_path, err, sizeof err) != 0) {
            fprintf(stderr, "gf_sim: %s\n", err);
            return 2;
        }
        mdl = gf_node_config_find(&config, model_name);
        if (mdl == NULL) {
            fprintf(stderr, "gf_sim: no model %s%s%s\n", model_name,
                    config_path ? " in " : "", config_path ? config_path : "");
            return 2;
        }
        if (nruns < 1 || nruns > MAX_RUNS) {
            fprintf(stderr, "gf_sim: --runs 1..%d\n", MAX_RUNS);
            return 2;
        }
        if (mdl->lin != NULL && mdl->lin->generated) {
            fprintf(stderr,
                    "gf_sim: model %s is generated (type = generated): "
                    "gf_sim does not simulate it (docs/codegen.md, \"In "
                    "the node\")\n",
                    model_name);
            return 2;
        }
        s.model = mdl->kind;
        sensors = mdl->kind == MODEL_LINEAR && mdl->sensors != NULL &&
                  mdl->sensors->count > 0;
        if (sensors && (mdl->lin->nu > 0 || mdl->lin->axes == 0)) {
            fprintf(stderr,
                    "gf_sim: model %s: only a model in time (motion "
                    "= ...) without controls (B) is simulated with "
                    "its sensors\n",
                    model_name);
            return 2;
        }
        if (!(so.jitter >= 0.0 && so.jitter < 1.0)) {
            fprintf(stderr, "gf_sim: --jitter takes 0 <= J < 1\n");
            return 2;
        }
        if (drop != NULL) {
            char name[GF_NODE_SENSOR_NAME];
            double from, to;
            const gf_node_sensor *d = NULL;
            if (sscanf(drop, "%15[A-Za-z0-9]:%lf:%lf", name, &from, &to) == 3) {
                d = gf_node_model_sensor(mdl, name);
            }
            if (d == NULL || !(from < to)) {
                fprintf(stderr,
                        "gf_sim: --drop SENSOR:FROM:TO (seconds), "
                        "SENSOR one of model %s's\n",
                        model_name);
                return 2;
            }
            so.drop = (int)(d - mdl->sensors->s);
            so.drop_from = (int64_t)llround(from * 1e6);
            so.drop_to = (int64_t)llround(to * 1e6);
        }
        if (delay != NULL) {
            char name[GF_NODE_SENSOR_NAME];
            double by;
            const gf_node_sensor *d = NULL;
            if (sscanf(delay, "%15[A-Za-z0-9]:%lf", name, &by) == 2) {
                d = gf_node_model_sensor(mdl, name);
            }
            if (d == NULL || !(by > 0.0 && by < 3600.0)) {
                fprintf(stderr,
                        "gf_sim: --delay SENSOR:SECONDS (0 < SECONDS "
                        "< 3600), SENSOR one of model %s's\n",
                        model_name);
                return 2;
            }
            so.delay = (int)(d - mdl->sensors->s);
            so.delay_us = (int64_t)llround(by * 1e6);
        }
    }
    if (exercise == 1 || exercise == 2) {
        s.model = MODEL_CAR;
    } else if (exercise == 4) {
        s.model = MODEL_ROBOT;
    } else if (exercise != 0 || s.model == 0 || meas_every < 1 || rate < 0.0) {
        usage();
        return 2;
    }
    if (steps < 0) {
        steps = exercise == 1   ? GF_BOOK_EX1_STEPS
                : exercise == 2 ? book.ex2_steps
                : exercise == 4 ? 1
                                : 100;
    }
    if (exercise == 2) { // --steps and --meas-var are exercise 2's
        book.ex2_steps = (int)steps;
        if (meas_var > 0.0) {
            book.ex2_q = meas_var;
        }
    }
    if (meas_var < 0.0) {
        meas_var = s.model == MODEL_CAR ? 10.0 : 0.01;
    }
    s.step_us = 1000000;
    if (mdl != NULL && mdl->kind != MODEL_ROBOT) {
        s.step_us = (int64_t)(mdl->dt * 1e6 + 0.5);
    }
    if (rate > 0.0 && mdl != NULL) {
        period_ns = (long)(1e9 / rate);
    } else if (rate > 0.0) {
        period_ns = (long)(1e9 / rate);
        s.step_us = (int64_t)(1e6 / rate);
    }
    snprintf(s.ch_ctrl, sizeof(s.ch_ctrl), "%s%ld", GF_CHANNEL_CTRL,
             (long)s.track);
    snprintf(s.ch_meas, sizeof(s.ch_meas), "%s%ld", GF_CHANNEL_MEAS,
             (long)s.track);
    snprintf(s.ch_truth, sizeof(s.ch_truth), "%s%ld", GF_CHANNEL_TRUTH,
             (long)s.track);

    if (!have_session) {
        struct timespec now;
        clock_gettime(CLOCK_REALTIME, &now);
        s.session = (int64_t)now.tv_sec * 1000000 + now.tv_nsec / 1000;
    }
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    for (i = 0; i < nwait; i++) {
        if (wait_ready(wait_for[i], wait_s) != 0) {
            fprintf(stderr,
                    "gf_sim: %s has no ready line after %g s: is the program "
                    "writing it running? (nothing sent)\n",
                    wait_for[i], wait_s);
            return 1;
        }
    }
    s.lcm = gf_lcm_open("gf_sim", url);
    if (s.lcm == NULL) {
        fprintf(stderr, "gf_sim: cannot open LCM at %s\n",
                url ? url : "(default URL)");
        return 1;
    }
    rng_seed(&r, seed);
    clock_gettime(CLOCK_MONOTONIC, &next);

    if (mdl != NULL) {
        long k;
        unsigned n = mdl->kind == MODEL_CAR     ? 2u
                     : mdl->kind == MODEL_ROBOT ? 3u
                                                : mdl->lin->n;
        for (k = 0; k < nruns; k++) {
            run *q = &runs[k];
            q->s = s;
            q->s.track = s.track + (int32_t)k;
            snprintf(q->s.ch_ctrl, sizeof(q->s.ch_ctrl), "%s%ld",
                     GF_CHANNEL_CTRL, (long)q->s.track);
            snprintf(q->s.ch_meas, sizeof(q->s.ch_meas), "%s%ld",
                     GF_CHANNEL_MEAS, (long)q->s.track);
            snprintf(q->s.ch_truth, sizeof(q->s.ch_truth), "%s%ld",
                     GF_CHANNEL_TRUTH, (long)q->s.track);
            rng_seed(&q->r, seed + (uint64_t)k);
            if (mdl->kind == MODEL_LINEAR) {
                draw_n(&q->r, n, mdl->lin->prior_mean, mdl->lin->prior_cov,
                       q->x);
            } else {
                draw(&q->r, n, mdl->prior_mean, mdl->prior_cov, q->x);
            }
            if (sensors) {
                sensor_run *sr = &sruns[k];
                unsigned j;
                memset(sr, 0, sizeof(*sr));
                for (j = 0; j < mdl->sensors->count; j++) {
                    snprintf(sr->ch[j], sizeof sr->ch[j], "%s%ld_%s",
                             GF_CHANNEL_MEAS, (long)q->s.track,
                             mdl->sensors->s[j].name);
                    sr->next[j] = sensor_next(sr, &q->r, &mdl->sensors->s[j], j,
                                              mdl->dt, &so);
                }
            }
        }
        for (t = 1; t <= steps && !g_stop; t++) {
            for (k = 0; k < nruns; k++) {
                run *q = &runs[k];
                double z[3];
                int m;
                if (sensors) {
                    // every sample up to this step's end
                    sensors_until(q, &sruns[k], mdl,
                                  (int64_t)llround((double)t * mdl->dt * 1e6),
                                  &so);
                    continue;
                }
                if (mdl->kind == MODEL_LINEAR) {
                    linear_step(q, mdl->lin, t, t % meas_every == 0);
                    continue;
                }
                if (mdl->kind == MODEL_CAR) {
                    double a = sqrt(mdl->accel_var) * rng_normal(&q->r);
                    double dt = mdl->dt;
                    q->x[0] += q->x[1] * dt + 0.5 * a * dt * dt;
                    q->x[1] += a * dt;
                    send_ctrl(&q->s, t, 0, 0.0, 0.0);
                } else {
                    const double *al = mdl->odometry;
                    double d = 1.0, phi = turn;
                    double dd = d + sqrt(al[0] * d * d + al[1] * phi * phi) *
                                        rng_normal(&q->r);
                    double dp = phi + sqrt(al[2] * d * d + al[3] * phi * phi) *
                                          rng_normal(&q->r);
                    q->x[0] += dd * cos(q->x[2]);
                    q->x[1] += dd * sin(q->x[2]);
                    q->x[2] =
                        remainder(q->x[2] + dp, 2.0 * 3.14159265358979323846);
                    send_ctrl(&q->s, t, 2, d, phi);
                }
                send_truth(&q->s, t, (int)n, q->x);
                if (t % meas_every == 0) {
                    m = measure(mdl, &q->r, q->x, z);
                    double qm[9];
                    for (int a = 0; a < m; a++) {
                        for (int b = 0; b < m; b++) {
                            qm[a * m + b] = mdl->meas_cov[a][b];
                        }
                    }
                    send_meas_m(&q->s, t, m, z, qm);
                }
            }
            pace(&next, period_ns);
        }
        for (k = 0; sensors && k < nruns; k++) {
            release_held(&runs[k], &sruns[k], &so, INT64_MAX); // the rest
        }
        s.sent_ctrl = s.sent_meas = s.sent_truth = 0;
        for (k = 0; k < nruns; k++) {
            s.sent_ctrl += runs[k].s.sent_ctrl;
            s.sent_meas += runs[k].s.sent_meas;
            s.sent_truth += runs[k].s.sent_truth;
            s.failed |= runs[k].s.failed;
        }
    } else if (exercise == 1 || exercise == 2) {
        for (t = 1; t <= steps && !g_stop; t++) {
            send_ctrl(&s, t, 0, 0.0, 0.0);
            if (exercise == 2 && t == book.ex2_steps) {
                send_meas(&s, t, book.ex2_z, book.ex2_q);
            }
            pace(&next, period_ns);
        }
    } else if (exercise == 4) {
        send_ctrl(&s, 1, 2, GF_BOOK_EX4_D, GF_BOOK_EX4_PHI);
        send_meas(&s, 1, GF_BOOK_EX4_Z, GF_BOOK_EX4_Q);
    } else if (s.model == MODEL_CAR) {
        double x[2] = {0.0, 0.0};
        for (t = 1; t <= steps && !g_stop; t++) {
            double a = rng_normal(&r);
            x[0] += x[1] + 0.5 * a; // x_t = A x_{t-1} + G a, G = (0.5, 1)^T
            x[1] += a;
            send_ctrl(&s, t, 0, 0.0, 0.0);
            send_truth(&s, t, 2, x);
            if (t % meas_every == 0) {
                send_meas(&s, t, x[0] + sqrt(meas_var) * rng_normal(&r),
                          meas_var);
            }
            pace(&next, period_ns);
        }
    } else {
        double x[3];
        x[0] = 0.0;
        x[1] = 0.0;
        x[2] = (2.0 * rng_uniform(&r) - 1.0) * 3.14159265358979323846;
        for (t = 1; t <= steps && !g_stop; t++) {
            x[0] += cos(x[2]); // move 1 forward, then turn
            x[1] += sin(x[2]);
            x[2] = remainder(x[2] + turn, 2.0 * 3.14159265358979323846);
            send_ctrl(&s, t, 2, 1.0, turn);
            send_truth(&s, t, 3, x);
            if (t % meas_every == 0) {
                send_meas(&s, t, x[0] + sqrt(meas_var) * rng_normal(&r),
                          meas_var);
            }
            pace(&next, period_ns);
        }
    }

    printf("gf_sim: track=%ld runs=%ld session=%lld sent controls=%lu "
           "measurements=%lu truths=%lu%s%s\n",
           (long)s.track, nruns, (long long)s.session, s.sent_ctrl, s.sent_meas,
           s.sent_truth, g_stop ? " (stopped by a signal)" : "",
           s.failed ? " (some publishes FAILED)" : "");
    lcm_destroy(s.lcm);
    gf_node_config_free(&config);
    return s.failed ? 1 : 0;
}
