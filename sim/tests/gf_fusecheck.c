// SPDX-License-Identifier: MIT
// gf_fusecheck: a track fused from several sensors, checked from the logs
// of gf_sim (truths, inputs) and of the node (beliefs). Two checks:
//
//   gf_fusecheck --truth URL --beliefs URL --first ID --runs M [--label L]
//
// consistency: every corrected belief (STAGE_UPDATE, TRIGGER_INPUT) of
// tracks ID..ID+M-1 against the truth at its utime. Per sensor
// (belief_t.sensor) and over all updates, as gf_consist judges: the
// average over the runs of the k-th update must lie in the two-sided 95%
// bounds chi2inv(0.025 / 0.975, M dof) / M at all but the binomial 99.9%
// quantile of K * 0.05 updates, and the mean over all in 99.9% bounds (M
// n dof for the NEES, whose errors persist over time; M K m for the NIS,
// white; over all sensors the NIS per degree of freedom, sum NIS / sum m).
// The runs must be aligned: the k-th update of a sensor at one utime in
// every run, each with status 0.
//
//   gf_fusecheck --reference CONFIG MODEL --inputs URL --beliefs URL
//
// reference: a Kalman filter written here in covariance form (double,
// Joseph update; A(dt) and R(dt) of the model's cv, ca and c axes built
// here from its accel_var) steps through the measurements of the inputs
// log in their order, each track predicted over the dt between its
// inputs' utimes (the model's dt before the first), each measurement by
// its sensor's C and its q (the sensor's Q when q is all zero), angle
// residuals wrapped; every corrected belief of the node (matched by track,
// sensor and seq) must equal it to 1e-9 (relative to max(1, |value|)).
// Says how many updates it compared, the smallest and largest dt, and the
// longest time a sensor went without a measurement.
//
// Exit 0 when all holds, 1 when a check fails (each verdict printed), 2 on
// missing or malformed data.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "gf_channels.h"
#include "gf_wire.h"
#include "node_model.h"
#include "trust.h"

#define NMAX GF_WIRE_NMAX
#define MAX_RUNS 64
#define MAX_SENSORS 8
#define MAX_UPDATES 8192 // of one sensor in one run

typedef struct truth {
    int64_t utime;
    double x[NMAX];
} truth;

typedef struct per_sensor {
    char name[32];
    long count[MAX_RUNS]; // updates seen per run
    double *nees, *nis;   // [k]: sums over runs
    int64_t *utime;       // [k]: the k-th update's utime
    long *runs;           // [k]: runs that had it
    int m;
} per_sensor;

typedef struct data {
    long first, runs;
    truth *truth[MAX_RUNS];
    long ntruth[MAX_RUNS], cap[MAX_RUNS];
    per_sensor s[MAX_SENSORS];
    int nsensors, n, bad;
    // over all sensors: the run's k-th update
    long all_count[MAX_RUNS];
    double *all_nees;
    long *all_runs;
    double nis_sum;
    long m_sum, updates;
    // reference mode: the node's corrected beliefs
    gf_wire_belief *b;
    long nb, bcap;
} data;

static void *grow(void *p, long *cap, size_t size)
{
    long c = *cap ? 2 * *cap : 1024;
    void *q = realloc(p, (size_t)c * size);
    if (q == NULL) {
        fprintf(stderr, "gf_fusecheck: out of memory\n");
        exit(2);
    }
    *cap = c;
    return q;
}

// x^T S^-1 x for S n x n positive definite (Cholesky); NaN if it is not.
static double quad_form(const double *s, const double *x, int n)
{
    double l[NMAX][NMAX], y[NMAX], q = 0.0;
    int i, j, k;
    for (j = 0; j < n; j++) {
        double d = s[j * n + j];
        for (k = 0; k < j; k++) {
            d -= l[j][k] * l[j][k];
        }
        if (!(d > 0.0)) {
            return (double)NAN;
        }
        l[j][j] = sqrt(d);
        for (i = j + 1; i < n; i++) {
            double v = s[i * n + j];
            for (k = 0; k < j; k++) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / l[j][j];
        }
    }
    for (i = 0; i < n; i++) {
        double v = x[i];
        for (k = 0; k < i; k++) {
            v -= l[i][k] * y[k];
        }
        y[i] = v / l[i][i];
        q += y[i] * y[i];
    }
    return q;
}

static const truth *truth_at(const data *d, long r, int64_t utime)
{
    long lo = 0, hi = d->ntruth[r] - 1;
    while (lo <= hi) { // the truths of a run come in time order
        long mid = (lo + hi) / 2;
        if (d->truth[r][mid].utime == utime) {
            return &d->truth[r][mid];
        }
        if (d->truth[r][mid].utime < utime) {
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return NULL;
}

static void on_truth(const lcm_recv_buf_t *rbuf, const char *channel,
                     void *user)
{
    data *d = user;
    gf_wire_truth g;
    long r;
    (void)channel;
    if (gf_wire_truth_decode(rbuf->data, rbuf->data_size, &g) != 0) {
        return;
    }
    r = (long)g.track - d->first;
    if (r < 0 || r >= d->runs) {
        return;
    }
    if (d->ntruth[r] == d->cap[r]) {
        d->truth[r] = grow(d->truth[r], &d->cap[r], sizeof(truth));
    }
    d->truth[r][d->ntruth[r]].utime = g.utime;
    memcpy(d->truth[r][d->ntruth[r]].x, g.state, sizeof g.state);
    d->ntruth[r]++;
}

static per_sensor *sensor_of(data *d, const char *name)
{
    int i;
    for (i = 0; i < d->nsensors; i++) {
        if (strcmp(d->s[i].name, name) == 0) {
            return &d->s[i];
        }
    }
    if (d->nsensors == MAX_SENSORS) {
        return NULL;
    }
    per_sensor *s = &d->s[d->nsensors++];
    snprintf(s->name, sizeof s->name, "%s", name);
    s->nees = calloc(MAX_UPDATES, sizeof(double));
    s->nis = calloc(MAX_UPDATES, sizeof(double));
    s->utime = calloc(MAX_UPDATES, sizeof(int64_t));
    s->runs = calloc(MAX_UPDATES, sizeof(long));
    return s;
}

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    data *d = user;
    gf_wire_belief b;
    const truth *g;
    per_sensor *s;
    double e[NMAX], nees;
    long r, k;
    int i;
    (void)channel;
    if (gf_wire_belief_decode(rbuf->data, rbuf->data_size, &b) != 0 ||
        b.stage != GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE ||
        b.trigger != GAUSSFILT_LCM_BELIEF_T_TRIGGER_INPUT) {
        return;
    }
    if (d->runs == 0) { // reference mode: keep it
        if (d->nb == d->bcap) {
            d->b = grow(d->b, &d->bcap, sizeof(gf_wire_belief));
        }
        d->b[d->nb++] = b;
        return;
    }
    r = (long)b.track - d->first;
    if (r < 0 || r >= d->runs) {
        return;
    }
    g = truth_at(d, r, b.utime);
    s = sensor_of(d, b.sensor);
    if (b.status != 0 || g == NULL || s == NULL) {
        fprintf(stderr,
                "gf_fusecheck: track %ld sensor \"%s\" utime %lld: %s\n",
                (long)b.track, b.sensor, (long long)b.utime,
                b.status != 0 ? "status not 0"
                : g == NULL   ? "no truth at its utime"
                              : "too many sensors");
        d->bad++;
        return;
    }
    for (i = 0; i < b.n; i++) {
        e[i] = g->x[i] - b.mean[i];
    }
    {
        double cov[NMAX * NMAX];
        int j;
        for (i = 0; i < b.n; i++) {
            for (j = 0; j < b.n; j++) {
                cov[i * b.n + j] = b.cov[i][j];
            }
        }
        nees = quad_form(cov, e, b.n);
    }
    d->n = b.n;
    s->m = b.m;
    k = s->count[r]++;
    if (k >= MAX_UPDATES) {
        d->bad++;
        return;
    }
    if (s->runs[k] > 0 && s->utime[k] != b.utime) {
        fprintf(stderr,
                "gf_fusecheck: sensor %s's update %ld at utime %lld in one "
                "run, %lld in another: the runs are not aligned\n",
                s->name, k, (long long)b.utime, (long long)s->utime[k]);
        d->bad++;
    }
    s->utime[k] = b.utime;
    s->nees[k] += nees;
    s->nis[k] += b.nis;
    s->runs[k]++;
    k = d->all_count[r]++;
    if (k < MAX_UPDATES * MAX_SENSORS) {
        d->all_nees[k] += nees;
        d->all_runs[k]++;
    }
    d->nis_sum += b.nis;
    d->m_sum += b.m;
    d->updates++;
}

// Judges per-update sums over runs (K updates): prints the verdict.
static int judge(const char *label, const char *what, const double *sum, long K,
                 long runs, int dof, int white)
{
    double k = (double)runs * dof, total = 0.0, mean, all_lo, all_hi;
    double lo = trust_chi2_inv(0.025, k) / (double)runs;
    double hi = trust_chi2_inv(0.975, k) / (double)runs;
    long t, outside = 0;
    int allowed = trust_binom_quantile((int)K, 0.05, 0.999), ok;
    for (t = 0; t < K; t++) {
        double avg = sum[t] / (double)runs;
        total += sum[t];
        if (avg < lo || avg > hi) {
            outside++;
        }
    }
    mean = total / (double)(runs * K);
    if (white) {
        double kk = (double)(runs * K) * dof;
        all_lo = trust_chi2_inv(0.0005, kk) / (double)(runs * K);
        all_hi = trust_chi2_inv(0.9995, kk) / (double)(runs * K);
    } else {
        all_lo = trust_chi2_inv(0.0005, k) / (double)runs;
        all_hi = trust_chi2_inv(0.9995, k) / (double)runs;
    }
    ok = outside <= allowed && mean >= all_lo && mean <= all_hi;
    printf("gf_fusecheck: %s %s dof=%d runs=%ld updates=%ld mean=%.3f "
           "(99.9%% bounds %.3f..%.3f) updates_outside_95%%=%ld (allowed %d, "
           "bounds %.3f..%.3f) %s\n",
           label, what, dof, runs, K, mean, all_lo, all_hi, outside, allowed,
           lo, hi, ok ? "PASS" : "FAIL");
    return ok;
}

// Every run has the same updates of a sensor: K of them.
static long complete(const data *d, const long *count, const char *what)
{
    long r, K = count[0];
    for (r = 1; r < d->runs; r++) {
        if (count[r] != K) {
            fprintf(stderr,
                    "gf_fusecheck: %s: %ld updates in run 0, %ld in "
                    "run %ld\n",
                    what, K, count[r], r);
            return -1;
        }
    }
    return K;
}

static void read_log(const char *url, data *d, int truths, int beliefs)
{
    lcm_t *lcm = lcm_create(url);
    if (lcm == NULL) {
        fprintf(stderr, "gf_fusecheck: cannot open %s\n", url);
        exit(2);
    }
    if (truths) {
        lcm_subscribe(lcm, GF_CHANNEL_TRUTH "-?[0-9]+", on_truth, d);
    }
    if (beliefs) {
        lcm_subscribe(lcm, GF_CHANNEL_BELIEF "-?[0-9]+", on_belief, d);
    }
    while (lcm_handle(lcm) == 0)
        ;
    lcm_destroy(lcm);
}

static int consistency(data *d, const char *label)
{
    int i, ok = 1;
    long K;
    char what[64];
    if (d->updates == 0 || d->bad) {
        fprintf(stderr, "gf_fusecheck: %s\n",
                d->bad ? "bad beliefs (above)" : "no corrected beliefs");
        return 2;
    }
    for (i = 0; i < d->nsensors; i++) {
        per_sensor *s = &d->s[i];
        snprintf(what, sizeof what, "%s %s", label, s->name);
        K = complete(d, s->count, what);
        if (K < 1) {
            return 2;
        }
        ok &= judge(what, "NEES", s->nees, K, d->runs, d->n, 0);
        ok &= judge(what, "NIS", s->nis, K, d->runs, s->m, 1);
    }
    snprintf(what, sizeof what, "%s all", label);
    K = complete(d, d->all_count, what);
    if (K < 1) {
        return 2;
    }
    ok &= judge(what, "NEES", d->all_nees, K, d->runs, d->n, 0);
    {
        double lo = trust_chi2_inv(0.0005, (double)d->m_sum) / (double)d->m_sum;
        double hi = trust_chi2_inv(0.9995, (double)d->m_sum) / (double)d->m_sum;
        double mean = d->nis_sum / (double)d->m_sum;
        int in = mean >= lo && mean <= hi;
        printf("gf_fusecheck: %s NIS per dof over %ld updates (%ld dof): "
               "%.3f (99.9%% bounds %.3f..%.3f) %s\n",
               what, d->updates, d->m_sum, mean, lo, hi, in ? "PASS" : "FAIL");
        ok &= in;
    }
    return ok ? 0 : 1;
}

// ---- reference mode ---------------------------------------------------------

typedef struct ref_track {
    int32_t id;
    int started;
    int64_t time;
    double x[NMAX], P[NMAX * NMAX];
} ref_track;

typedef struct ref {
    const gf_node_model *mdl;
    ref_track t[MAX_RUNS];
    int ntracks;
    data *d;
    long compared, failed;
    double dt_min, dt_max, worst;
    int64_t last[MAX_RUNS][MAX_SENSORS], gap_max;
} ref;

// A(dt), R(dt) of the model's axes, written out (n x n).
static void motion(const gf_node_linear *l, double dt, double *A, double *R)
{
    unsigned a, k = 0, n = l->n, i, j;
    memset(A, 0, sizeof(double) * n * n);
    memset(R, 0, sizeof(double) * n * n);
    for (a = 0; a < l->axes; a++) {
        double q = l->accel_var[a];
        if (l->axis[a] == GF_NODE_AXIS_C) { // x += w, var(w) = q dt
            A[k * n + k] = 1.0;
            R[k * n + k] = q * dt;
            k += 1;
        } else if (l->axis[a] == GF_NODE_AXIS_CV) {
            // ((1, dt), (0, 1)); q ((dt^4/4, dt^3/2), (dt^3/2, dt^2))
            A[k * n + k] = A[(k + 1) * n + k + 1] = 1.0;
            A[k * n + k + 1] = dt;
            R[k * n + k] = q * pow(dt, 4) / 4.0;
            R[k * n + k + 1] = R[(k + 1) * n + k] = q * pow(dt, 3) / 2.0;
            R[(k + 1) * n + k + 1] = q * dt * dt;
            k += 2;
        } else { // ca: g = (dt^2/2, dt, 1), R = q g g^T
            double g[3] = {dt * dt / 2.0, dt, 1.0};
            for (i = 0; i < 3; i++) {
                A[(k + i) * n + k + i] = 1.0;
                for (j = 0; j < 3; j++) {
                    R[(k + i) * n + k + j] = q * g[i] * g[j];
                }
            }
            A[k * n + k + 1] = A[(k + 1) * n + k + 2] = dt;
            A[k * n + k + 2] = dt * dt / 2.0;
            k += 3;
        }
    }
}

// x = A x, P = A P A^T + R.
static void ref_predict(const gf_node_linear *l, ref_track *t, double dt)
{
    double A[NMAX * NMAX], R[NMAX * NMAX], x[NMAX], AP[NMAX * NMAX];
    unsigned i, j, k, n = l->n;
    motion(l, dt, A, R);
    for (i = 0; i < n; i++) {
        x[i] = 0.0;
        for (k = 0; k < n; k++) {
            x[i] += A[i * n + k] * t->x[k];
        }
    }
    memcpy(t->x, x, sizeof(double) * n);
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            AP[i * n + j] = 0.0;
            for (k = 0; k < n; k++) {
                AP[i * n + j] += A[i * n + k] * t->P[k * n + j];
            }
        }
    }
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            double v = R[i * n + j];
            for (k = 0; k < n; k++) {
                v += AP[i * n + k] * A[j * n + k];
            }
            t->P[i * n + j] = v;
        }
    }
}

// Inverts the m x m positive definite S (Gauss-Jordan, no pivoting
// needed); 0 or -1.
static int invert(double *S, unsigned m)
{
    double a[NMAX][2 * NMAX];
    unsigned i, j, k;
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++) {
            a[i][j] = S[i * m + j];
            a[i][m + j] = i == j ? 1.0 : 0.0;
        }
    }
    for (k = 0; k < m; k++) {
        double p = a[k][k];
        if (!(p > 0.0)) {
            return -1;
        }
        for (j = 0; j < 2 * m; j++) {
            a[k][j] /= p;
        }
        for (i = 0; i < m; i++) {
            if (i != k) {
                double f = a[i][k];
                for (j = 0; j < 2 * m; j++) {
                    a[i][j] -= f * a[k][j];
                }
            }
        }
    }
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++) {
            S[i * m + j] = a[i][m + j];
        }
    }
    return 0;
}

// The Joseph form: K = P C^T S^-1, x += K y, P = (I - K C) P (I - K C)^T
// + K Q K^T.
static int ref_update(const gf_node_linear *l, const gf_node_sensor *sen,
                      ref_track *t, const double *z, const double *Q)
{
    unsigned i, j, k, n = l->n, m = sen->m;
    double y[NMAX], S[NMAX * NMAX], PCt[NMAX * NMAX], K[NMAX * NMAX],
        IKC[NMAX * NMAX], T[NMAX * NMAX], P[NMAX * NMAX];
    const double *C = sen->C;
    for (i = 0; i < m; i++) {
        y[i] = z[i];
        for (k = 0; k < n; k++) {
            y[i] -= C[i * n + k] * t->x[k];
        }
        if (sen->angle_mask & (1u << i)) {
            y[i] = remainder(y[i], 2.0 * 3.14159265358979323846);
        }
    }
    for (i = 0; i < n; i++) { // P C^T, n x m
        for (j = 0; j < m; j++) {
            PCt[i * m + j] = 0.0;
            for (k = 0; k < n; k++) {
                PCt[i * m + j] += t->P[i * n + k] * C[j * n + k];
            }
        }
    }
    for (i = 0; i < m; i++) { // S = C P C^T + Q
        for (j = 0; j < m; j++) {
            S[i * m + j] = Q[i * m + j];
            for (k = 0; k < n; k++) {
                S[i * m + j] += C[i * n + k] * PCt[k * m + j];
            }
        }
    }
    if (invert(S, m) != 0) {
        return -1;
    }
    for (i = 0; i < n; i++) { // K = P C^T S^-1
        for (j = 0; j < m; j++) {
            K[i * m + j] = 0.0;
            for (k = 0; k < m; k++) {
                K[i * m + j] += PCt[i * m + k] * S[k * m + j];
            }
        }
    }
    for (i = 0; i < n; i++) {
        for (k = 0; k < m; k++) {
            t->x[i] += K[i * m + k] * y[k];
        }
        for (j = 0; j < n; j++) { // I - K C
            IKC[i * n + j] = i == j ? 1.0 : 0.0;
            for (k = 0; k < m; k++) {
                IKC[i * n + j] -= K[i * m + k] * C[k * n + j];
            }
        }
    }
    for (i = 0; i < n; i++) { // T = (I - K C) P
        for (j = 0; j < n; j++) {
            T[i * n + j] = 0.0;
            for (k = 0; k < n; k++) {
                T[i * n + j] += IKC[i * n + k] * t->P[k * n + j];
            }
        }
    }
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            double v = 0.0;
            unsigned a, b;
            for (k = 0; k < n; k++) {
                v += T[i * n + k] * IKC[j * n + k];
            }
            for (a = 0; a < m; a++) { // + K Q K^T
                for (b = 0; b < m; b++) {
                    v += K[i * m + a] * Q[a * m + b] * K[j * m + b];
                }
            }
            P[i * n + j] = v;
        }
    }
    memcpy(t->P, P, sizeof(double) * n * n);
    return 0;
}

static const gf_wire_belief *belief_for(const data *d, int32_t track,
                                        const char *sensor, int64_t seq)
{
    long i;
    for (i = 0; i < d->nb; i++) { // few: a handful of runs
        if (d->b[i].track == track && d->b[i].input_seq == seq &&
            strcmp(d->b[i].sensor, sensor) == 0) {
            return &d->b[i];
        }
    }
    return NULL;
}

static double rel(double got, double want)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    return fabs(got - want) / scale;
}

static void on_input(const lcm_recv_buf_t *rbuf, const char *channel,
                     void *user)
{
    ref *f = user;
    const gf_node_linear *l = f->mdl->lin;
    gaussfilt_lcm_measurement_t z;
    const char *us = strchr(channel + strlen(GF_CHANNEL_MEAS), '_');
    const gf_node_sensor *sen;
    const gf_wire_belief *b;
    ref_track *t = NULL;
    double Q[NMAX * NMAX], worst = 0.0;
    unsigned i, j, n = l->n;
    int zero = 1, k;
    if (us == NULL || (sen = gf_node_model_sensor(f->mdl, us + 1)) == NULL ||
        gaussfilt_lcm_measurement_t_decode(rbuf->data, 0, (int)rbuf->data_size,
                                           &z) != (int)rbuf->data_size) {
        return;
    }
    for (k = 0; k < f->ntracks; k++) {
        if (f->t[k].id == z.track) {
            t = &f->t[k];
        }
    }
    if (t == NULL && f->ntracks < MAX_RUNS) {
        t = &f->t[f->ntracks++];
        t->id = z.track;
        memcpy(t->x, l->prior_mean, sizeof(double) * n);
        memcpy(t->P, l->prior_cov, sizeof(double) * n * n);
    }
    if (t != NULL && (unsigned)z.m == sen->m) {
        double dt = t->started ? (double)(z.utime - t->time) / 1e6 : f->mdl->dt;
        int si = (int)(sen - f->mdl->sensors->s);
        int64_t *last = &f->last[t - f->t][si];
        if (*last != 0 && z.utime - *last > f->gap_max) {
            f->gap_max = z.utime - *last;
        }
        *last = z.utime;
        if (dt > 0.0) {
            ref_predict(l, t, dt);
            f->dt_min = dt < f->dt_min ? dt : f->dt_min;
            f->dt_max = dt > f->dt_max ? dt : f->dt_max;
        }
        t->started = 1;
        t->time = z.utime;
        for (i = 0; i < sen->m * sen->m; i++) {
            Q[i] = z.q[i / sen->m][i % sen->m];
            zero &= !(Q[i] < 0.0 || Q[i] > 0.0);
        }
        if (zero) {
            memcpy(Q, sen->Q, sizeof(double) * sen->m * sen->m);
        }
        if (ref_update(l, sen, t, z.z, Q) != 0) {
            f->failed++;
        }
        b = belief_for(f->d, z.track, sen->name, z.seq);
        if (b == NULL || b->status != 0 || b->n != (int)n) {
            fprintf(stderr, "gf_fusecheck: track %ld %s seq %lld: %s\n",
                    (long)z.track, sen->name, (long long)z.seq,
                    b == NULL ? "no corrected belief" : "status or n wrong");
            f->failed++;
        } else {
            for (i = 0; i < n; i++) {
                double e = rel(b->mean[i], t->x[i]);
                worst = e > worst ? e : worst;
                for (j = 0; j < n; j++) {
                    e = rel(b->cov[i][j], t->P[i * n + j]);
                    worst = e > worst ? e : worst;
                }
            }
            f->compared++;
            if (!(worst <= 1e-9)) {
                if (f->failed < 5) {
                    fprintf(stderr,
                            "gf_fusecheck: track %ld %s seq %lld utime %lld: "
                            "the belief differs from the reference by %.3g\n",
                            (long)z.track, sen->name, (long long)z.seq,
                            (long long)z.utime, worst);
                }
                f->failed++;
            }
            f->worst = worst > f->worst ? worst : f->worst;
        }
    }
    gaussfilt_lcm_measurement_t_decode_cleanup(&z);
}

static int reference(data *d, const char *conf, const char *model,
                     const char *inputs)
{
    static gf_node_config cfg;
    static ref f;
    char err[256];
    lcm_t *lcm;
    if (gf_node_config_load(&cfg, conf, err, sizeof err) != 0) {
        fprintf(stderr, "gf_fusecheck: %s\n", err);
        return 2;
    }
    f.mdl = gf_node_config_find(&cfg, model);
    if (f.mdl == NULL || f.mdl->lin == NULL || f.mdl->sensors == NULL ||
        f.mdl->lin->axes == 0) {
        fprintf(stderr,
                "gf_fusecheck: %s is no linear model in time with "
                "sensors\n",
                model);
        return 2;
    }
    f.d = d;
    f.dt_min = 1e300;
    lcm = lcm_create(inputs);
    if (lcm == NULL) {
        fprintf(stderr, "gf_fusecheck: cannot open %s\n", inputs);
        return 2;
    }
    lcm_subscribe(lcm, GF_CHANNEL_MEAS "-?[0-9]+_[A-Za-z0-9]+", on_input, &f);
    while (lcm_handle(lcm) == 0)
        ;
    lcm_destroy(lcm);
    printf("gf_fusecheck: reference %s: %ld corrected beliefs of %d tracks "
           "equal the reference to %.3g (1e-9 allowed); dt %.6f..%.6f s; "
           "the longest a sensor went without a measurement: %.3f s; %s\n",
           model, f.compared, f.ntracks, f.worst, f.dt_min, f.dt_max,
           (double)f.gap_max / 1e6,
           f.failed == 0 && f.compared > 0 ? "PASS" : "FAIL");
    gf_node_config_free(&cfg);
    return f.failed == 0 && f.compared > 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    static data d;
    const char *truth_url = NULL, *beliefs_url = NULL, *inputs = NULL,
               *conf = NULL, *model = NULL, *label = "track";
    int i;
    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--truth") == 0) {
            truth_url = argv[i + 1];
        } else if (strcmp(argv[i], "--beliefs") == 0) {
            beliefs_url = argv[i + 1];
        } else if (strcmp(argv[i], "--inputs") == 0) {
            inputs = argv[i + 1];
        } else if (strcmp(argv[i], "--first") == 0) {
            d.first = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--runs") == 0) {
            d.runs = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--label") == 0) {
            label = argv[i + 1];
        } else if (strcmp(argv[i], "--reference") == 0 && i + 2 < argc) {
            conf = argv[i + 1];
            model = argv[i + 2];
            i++;
        } else {
            break;
        }
    }
    if (i != argc || beliefs_url == NULL ||
        (conf == NULL &&
         (truth_url == NULL || d.runs < 2 || d.runs > MAX_RUNS)) ||
        (conf != NULL && inputs == NULL)) {
        fprintf(stderr,
                "usage: gf_fusecheck --truth URL --beliefs URL --first ID "
                "--runs M [--label L]\n"
                "       gf_fusecheck --reference CONFIG MODEL --inputs URL "
                "--beliefs URL\n");
        return 2;
    }
    if (conf != NULL) {
        d.runs = 0;
        read_log(beliefs_url, &d, 0, 1);
        return reference(&d, conf, model, inputs);
    }
    d.all_nees = calloc(MAX_UPDATES * MAX_SENSORS, sizeof(double));
    d.all_runs = calloc(MAX_UPDATES * MAX_SENSORS, sizeof(long));
    read_log(truth_url, &d, 1, 0);
    read_log(beliefs_url, &d, 0, 1);
    return consistency(&d, label);
}
