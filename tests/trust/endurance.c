// SPDX-License-Identifier: MIT
// Float endurance: runs KF2 and EKF3 for many steps in float and in double
// side by side on the same inputs (controls and measurements from a
// simulated truth, fixed seed) and checks, at every step:
//
//  - both filters' calls succeed;
//  - the float covariance is finite, exactly symmetric and positive
//    definite (Cholesky in double of the float values);
//  - the float estimate stays within ENDURANCE_MU_BOUND standard deviations
//    (sqrt of the double filter's variance) of the double estimate, and
//    each float covariance entry within ENDURANCE_SIGMA_BOUND of the double
//    one, relative to sqrt(sigma_ii sigma_jj).
//
// It also reports both filters' mean NEES against the truth: a float
// filter that stays close to the double one and consistent after 10^7
// steps has not drifted.
//
//   endurance [STEPS] [--progress]      (STEPS default 10000000)
//
// Exit status 0 when every check held, 1 otherwise.
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "endurance.h"
#include "trust.h"

// The stated bounds (README, "How we test"). Float has 24 bits (relative
// resolution 6e-8); a steady-state filter forgets old rounding errors
// geometrically, so the float estimate should stay within a few hundred
// ulps of the state's scale. 10^7 steps showed at most 4.9e-5 standard
// deviations (EKF3, positions near 20 where a float ulp is 2e-6) and
// 1.9e-6 on the covariance; the bounds leave a margin of 20 and 50.
#define ENDURANCE_MU_BOUND 1e-3    // standard deviations of the estimate
#define ENDURANCE_SIGMA_BOUND 1e-4 // relative to sqrt(sigma_ii sigma_jj)

typedef struct stats {
    const char *name;
    int n; // state size
    long steps, updates;
    double max_dmu[3]; // max |mu_f - mu_d| / sqrt(sigma_d ii)
    double max_dsigma; // max |s_f - s_d| / sqrt(s_d ii s_d jj)
    long max_dmu_step;
    double nees_d, nees_f; // sums
    long failures;
} stats;

static int is_pd(double s[3][3], int n)
{
    const double zero[3] = {0, 0, 0};
    return isfinite(trust_quad_form(s, zero, n));
}

// Checks one step's pair of beliefs; prints and counts a failure.
static void check(stats *st, long t, const endurance_belief *d,
                  const endurance_belief *f, const double *truth, int heading)
{
    const int n = st->n;
    const char *why = NULL;
    if (d->predict_status != 0 || f->predict_status != 0 ||
        (d->update_status != 0 && d->update_status != 1) ||
        (f->update_status != 0 && f->update_status != 1) ||
        d->update_status != f->update_status) {
        why = "a call failed";
    }
    for (int i = 0; i < n && !why; i++) {
        if (!isfinite(f->mu[i]) || !isfinite(d->mu[i])) {
            why = "non-finite mean";
        }
        for (int j = 0; j < n; j++) {
            if (!isfinite(f->sigma[i][j]) || !isfinite(d->sigma[i][j])) {
                why = "non-finite covariance";
            } else if (f->sigma[i][j] != f->sigma[j][i]) {
                why = "float covariance not symmetric";
            }
        }
    }
    double sf[3][3], sd[3][3];
    memcpy(sf, f->sigma, sizeof sf);
    memcpy(sd, d->sigma, sizeof sd);
    if (!why && (!is_pd(sf, n) || !is_pd(sd, n))) {
        why = "covariance not positive definite";
    }
    if (!why) {
        for (int i = 0; i < n; i++) {
            double e = f->mu[i] - d->mu[i];
            if (heading && i == 2) {
                e = trust_wrap(e);
            }
            double r = fabs(e) / sqrt(d->sigma[i][i]);
            if (r > st->max_dmu[i]) {
                st->max_dmu[i] = r;
                st->max_dmu_step = t;
            }
            if (r > ENDURANCE_MU_BOUND) {
                why = "float mean too far from double";
            }
            for (int j = 0; j < n; j++) {
                double rs = fabs(f->sigma[i][j] - d->sigma[i][j]) /
                            sqrt(d->sigma[i][i] * d->sigma[j][j]);
                st->max_dsigma = rs > st->max_dsigma ? rs : st->max_dsigma;
                if (rs > ENDURANCE_SIGMA_BOUND) {
                    why = "float covariance too far from double";
                }
            }
        }
        double ed[3] = {0, 0, 0}, ef[3] = {0, 0, 0};
        for (int i = 0; i < n; i++) {
            ed[i] = truth[i] - d->mu[i];
            ef[i] = truth[i] - f->mu[i];
            if (heading && i == 2) {
                ed[i] = trust_wrap(ed[i]);
                ef[i] = trust_wrap(ef[i]);
            }
        }
        st->nees_d += trust_quad_form(sd, ed, n);
        st->nees_f += trust_quad_form(sf, ef, n);
    }
    if (why) {
        if (st->failures < 5) {
            fprintf(stderr, "%s step %ld: %s\n", st->name, t, why);
            for (int i = 0; i < n; i++) {
                fprintf(stderr, "  mu[%d] float %.9g double %.17g\n", i,
                        f->mu[i], d->mu[i]);
            }
        }
        st->failures++;
    }
}

static void progress(const stats *st, long t, long steps, int on)
{
    if (on && steps >= 10 && t % (steps / 10) == 0) {
        fprintf(stderr,
                "  %s: %3ld%% (%ld steps), max |dmu|/sd %.3g, "
                "max dsigma %.3g, failures %ld\n",
                st->name, 100 * t / steps, t,
                fmax(fmax(st->max_dmu[0], st->max_dmu[1]), st->max_dmu[2]),
                st->max_dsigma, st->failures);
    }
}

// The car, kept near the origin by a controller that sees the truth
// (a = -0.05 x - 0.3 v, closed-loop poles of modulus 0.85); a random
// acceleration of variance 1 on top; 90% of the steps have a measurement.
static void run_kf2(stats *st, long steps, int prog)
{
    trust_rng rng;
    trust_rng_seed(&rng, UINT64_C(0x656e647572616e63));
    if (endurance_kf2_start_d() != 0 || endurance_kf2_start_f() != 0) {
        fprintf(stderr, "KF2 init failed\n");
        st->failures++;
        return;
    }
    double x = 10.0 * trust_normal(&rng), v = 10.0 * trust_normal(&rng);
    for (long t = 1; t <= steps; t++) {
        double u = -0.05 * x - 0.3 * v, a = u + trust_normal(&rng);
        x += v + 0.5 * a;
        v += a;
        double z = x + sqrt(ENDURANCE_KF2_Q) * trust_normal(&rng);
        const double *zp = trust_uniform(&rng) < 0.9 ? &z : NULL;
        endurance_belief bd, bf;
        endurance_kf2_step_d(u, zp, &bd);
        endurance_kf2_step_f(u, zp, &bf);
        const double truth[3] = {x, v, 0};
        check(st, t, &bd, &bf, truth, 0);
        st->updates += zp != NULL;
        st->steps = t;
        progress(st, t, steps, prog);
    }
}

// The robot drives a circle of radius 20 around the origin (d = 1), its
// turn phi steering it back onto the circle from the true pose (so the
// heading passes through +-pi every 126 steps); process noise as the
// filter's R; 90% of the steps have an (x, y) measurement.
static void run_ekf3(stats *st, long steps, int prog)
{
    trust_rng rng;
    trust_rng_seed(&rng, UINT64_C(0x656e647572656b66));
    if (endurance_ekf3_start_d() != 0 || endurance_ekf3_start_f() != 0) {
        fprintf(stderr, "EKF3 init failed\n");
        st->failures++;
        return;
    }
    const double pi = 3.14159265358979323846;
    double x = 20.0 + trust_normal(&rng), y = trust_normal(&rng),
           th = trust_wrap(pi / 2 + sqrt(0.1) * trust_normal(&rng));
    for (long t = 1; t <= steps; t++) {
        double r = hypot(x, y);
        double want = atan2(y, x) + pi / 2 + 0.5 * (r - 20.0) / 20.0;
        double phi = fmax(-0.3, fmin(0.3, trust_wrap(want - th)));
        const double u[2] = {1.0, phi};
        double c = cos(th), s = sin(th);
        x += c + sqrt(ENDURANCE_EKF3_R_XY) * trust_normal(&rng);
        y += s + sqrt(ENDURANCE_EKF3_R_XY) * trust_normal(&rng);
        th = trust_wrap(th + phi +
                        sqrt(ENDURANCE_EKF3_R_TH) * trust_normal(&rng));
        double z[2] = {x + sqrt(ENDURANCE_EKF3_Q) * trust_normal(&rng),
                       y + sqrt(ENDURANCE_EKF3_Q) * trust_normal(&rng)};
        const double *zp = trust_uniform(&rng) < 0.9 ? z : NULL;
        endurance_belief bd, bf;
        endurance_ekf3_step_d(u, zp, &bd);
        endurance_ekf3_step_f(u, zp, &bf);
        const double truth[3] = {x, y, th};
        check(st, t, &bd, &bf, truth, 1);
        st->updates += zp != NULL;
        st->steps = t;
        progress(st, t, steps, prog);
    }
}

static void report(const stats *st, double seconds)
{
    printf("%s: %ld steps (%ld updates) in %.1f s, failures %ld\n", st->name,
           st->steps, st->updates, seconds, st->failures);
    printf("  max |mu_f - mu_d| / sd:");
    for (int i = 0; i < st->n; i++) {
        printf(" %.3g", st->max_dmu[i]);
    }
    printf(" (bound %g; worst at step %ld)\n", ENDURANCE_MU_BOUND,
           st->max_dmu_step);
    printf("  max |sigma_f - sigma_d| / sqrt(s_ii s_jj): %.3g (bound %g)\n",
           st->max_dsigma, ENDURANCE_SIGMA_BOUND);
    printf("  mean NEES vs truth: double %.4f, float %.4f (n = %d)\n",
           st->nees_d / (double)st->steps, st->nees_f / (double)st->steps,
           st->n);
}

int main(int argc, char **argv)
{
    long steps = 10000000;
    int prog = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--progress") == 0) {
            prog = 1;
        } else {
            char *end;
            steps = strtol(argv[i], &end, 10);
            if (*end || steps < 1) {
                fprintf(stderr, "usage: %s [STEPS] [--progress]\n", argv[0]);
                return 2;
            }
        }
    }
    stats kf = {.name = "KF2", .n = 2}, ekf = {.name = "EKF3", .n = 3};
    clock_t c0 = clock();
    run_kf2(&kf, steps, prog);
    clock_t c1 = clock();
    run_ekf3(&ekf, steps, prog);
    clock_t c2 = clock();
    report(&kf, (double)(c1 - c0) / CLOCKS_PER_SEC);
    report(&ekf, (double)(c2 - c1) / CLOCKS_PER_SEC);
    int ok = kf.failures == 0 && ekf.failures == 0;
    printf("endurance: %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}
