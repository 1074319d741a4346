// SPDX-License-Identifier: MIT
// gf_consist: statistical consistency of the node's beliefs, from the wire.
// Reads beliefs (GF_BELIEF_<id>) and the simulator's truths (GF_TRUTH_<id>)
// of M tracks, each one Monte-Carlo run of `gf_sim --config F --model NAME
// --runs M` (a control and a measurement every step), typically from a
// log (file:///x.lcmlog?speed=0), and judges the NEES of each corrected
// belief against its truth and the NIS of each update as tests/trust's
// consistency test does (trust.h's chi-square and binomial quantiles):
//
// - per step t, the average over the M runs must lie in the two-sided 95%
//   bounds chi2inv(0.025 / 0.975, M k) / M (k = n for NEES, m for NIS) at
//   all but the binomial 99.9% quantile of T * 0.05 steps;
// - the average over all runs and steps in 99.9% bounds: M T m degrees of
//   freedom for the NIS (white innovations), M n for the NEES (errors are
//   correlated over time; one step's bounds are conservative).
//
//   gf_consist --url URL [--url URL2] --first ID --runs M --steps T
//              [--skip K] [--label NAME]
//
// Each URL is read to its end (a log), beliefs and truths taken from any.
// --skip K leaves out the first K steps (0 by default). Exit 0 when both
// pass, 1 when one fails (each verdict is printed), 2 on missing data.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "gf_wire.h"
#include "trust.h"

#define MAX_RUNS 64
#define MAX_STEPS 200
#define NMAX GF_WIRE_NMAX

typedef struct step {
    int have_truth, have_belief;
    double truth[NMAX];
    gf_wire_belief b;
} step;

// x^T S^-1 x for S n x n positive definite (Cholesky); NaN if it is not.
static double quad_form(double s[NMAX][NMAX], const double *x, int n)
{
    double l[NMAX][NMAX], y[NMAX], q = 0.0;
    int i, j, k;
    for (j = 0; j < n; j++) {
        double d = s[j][j];
        for (k = 0; k < j; k++) {
            d -= l[j][k] * l[j][k];
        }
        if (!(d > 0.0)) {
            return (double)NAN;
        }
        l[j][j] = sqrt(d);
        for (i = j + 1; i < n; i++) {
            double v = s[i][j];
            for (k = 0; k < j; k++) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / l[j][j];
        }
    }
    // L y = x, q = |y|^2
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

typedef struct data {
    long first, runs, steps;
    step s[MAX_RUNS][MAX_STEPS + 1];
} data;

static step *find(data *d, int32_t track, long t)
{
    long r = (long)track - d->first;
    if (r < 0 || r >= d->runs || t < 1 || t > d->steps) {
        return NULL;
    }
    return &d->s[r][t];
}

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    gf_wire_belief b;
    step *s;
    (void)channel;
    if (gf_wire_belief_decode(rbuf->data, rbuf->data_size, &b) != 0) {
        return;
    }
    // step t: control seq 2t - 1, measurement seq 2t
    if (b.stage != GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE || b.input_seq % 2) {
        return;
    }
    s = find(user, b.track, (long)(b.input_seq / 2));
    if (s != NULL) {
        s->b = b;
        s->have_belief = 1;
    }
}

static void on_truth(const lcm_recv_buf_t *rbuf, const char *channel,
                     void *user)
{
    gf_wire_truth g;
    step *s;
    int i;
    (void)channel;
    if (gf_wire_truth_decode(rbuf->data, rbuf->data_size, &g) != 0) {
        return;
    }
    s = find(user, g.track, (long)((g.seq + 1) / 2));
    if (s != NULL) {
        for (i = 0; i < g.n; i++) {
            s->truth[i] = g.state[i];
        }
        s->have_truth = 1;
    }
}

// Judges per-step sums (t = first..last) over runs; prints the verdict.
static int judge(const char *label, const char *what, const double *sum,
                 long first, long last, long runs, int dof, int white)
{
    double k = (double)runs * dof, total = 0.0, mean, all_lo, all_hi;
    double lo = trust_chi2_inv(0.025, k) / (double)runs;
    double hi = trust_chi2_inv(0.975, k) / (double)runs;
    long t, steps = last - first + 1, outside = 0;
    int allowed = trust_binom_quantile((int)steps, 0.05, 0.999), ok;
    for (t = first; t <= last; t++) {
        double avg = sum[t] / (double)runs;
        total += sum[t];
        if (avg < lo || avg > hi) {
            outside++;
        }
    }
    mean = total / (double)(runs * steps);
    if (white) {
        double kk = (double)(runs * steps) * dof;
        all_lo = trust_chi2_inv(0.0005, kk) / (double)(runs * steps);
        all_hi = trust_chi2_inv(0.9995, kk) / (double)(runs * steps);
    } else {
        all_lo = trust_chi2_inv(0.0005, k) / (double)runs;
        all_hi = trust_chi2_inv(0.9995, k) / (double)runs;
    }
    ok = outside <= allowed && mean >= all_lo && mean <= all_hi;
    printf("gf_consist: %s %s dof=%d runs=%ld steps=%ld mean=%.3f "
           "(99.9%% bounds %.3f..%.3f) steps_outside_95%%=%ld (allowed %d, "
           "bounds %.3f..%.3f) %s\n",
           label, what, dof, runs, steps, mean, all_lo, all_hi, outside,
           allowed, lo, hi, ok ? "PASS" : "FAIL");
    return ok;
}

int main(int argc, char **argv)
{
    static data d;
    static double nees[MAX_STEPS + 1], nis[MAX_STEPS + 1];
    const char *url[2] = {NULL, NULL}, *label = "track";
    int nurl = 0;
    long skip = 0, r, t;
    int i, n = 0, m = 0, ok;
    lcm_t *lcm;

    d.runs = d.steps = 0;
    d.first = 0;
    for (i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0 && nurl < 2) {
            url[nurl++] = argv[i + 1];
        } else if (strcmp(argv[i], "--first") == 0) {
            d.first = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--runs") == 0) {
            d.runs = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--steps") == 0) {
            d.steps = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--skip") == 0) {
            skip = atol(argv[i + 1]);
        } else if (strcmp(argv[i], "--label") == 0) {
            label = argv[i + 1];
        } else {
            break;
        }
    }
    if (i != argc || nurl == 0 || d.runs < 2 || d.runs > MAX_RUNS ||
        d.steps < 1 || d.steps > MAX_STEPS || skip < 0 || skip >= d.steps) {
        fprintf(stderr, "usage: gf_consist --url URL [--url URL2] --first ID "
                        "--runs M --steps T [--skip K] [--label NAME]\n");
        return 2;
    }
    for (i = 0; i < nurl; i++) {
        lcm = lcm_create(url[i]);
        if (lcm == NULL) {
            fprintf(stderr, "gf_consist: cannot open %s\n", url[i]);
            return 2;
        }
        lcm_subscribe(lcm, "GF_BELIEF_-?[0-9]+", on_belief, &d);
        lcm_subscribe(lcm, "GF_TRUTH_-?[0-9]+", on_truth, &d);
        while (lcm_handle(lcm) == 0)
            ;
        lcm_destroy(lcm);
    }

    for (r = 0; r < d.runs; r++) {
        for (t = skip + 1; t <= d.steps; t++) {
            step *s = &d.s[r][t];
            double e[NMAX];
            int k;
            if (!s->have_truth || !s->have_belief || s->b.status != 0) {
                fprintf(stderr, "gf_consist: track %ld step %ld: %s\n",
                        d.first + r, t,
                        !s->have_truth    ? "no truth"
                        : !s->have_belief ? "no corrected belief"
                                          : "belief with a failed status");
                return 2;
            }
            n = s->b.n;
            m = s->b.m;
            for (k = 0; k < n; k++) {
                e[k] = s->truth[k] - s->b.mean[k];
            }
            if (s->b.model == 2) { // the robot's heading
                e[2] = trust_wrap(e[2]);
            }
            nees[t] += quad_form(s->b.cov, e, n);
            nis[t] += s->b.nis;
        }
    }
    ok = judge(label, "NEES", nees, skip + 1, d.steps, d.runs, n, 0);
    ok &= judge(label, "NIS", nis, skip + 1, d.steps, d.runs, m, 1);
    return ok ? 0 : 1;
}
