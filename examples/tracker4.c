// SPDX-License-Identifier: MIT
// tracker4: a 2-D constant-velocity target, the state x = (x, vx, y, vy),
// its position (x, y) measured every DT seconds, tracked by gf_kf (kf.h).
//
// Each axis moves with the continuous white-noise acceleration model of
// Bar-Shalom, Li and Kirubarajan, Estimation with Applications to Tracking
// and Navigation (2001), section 6.3.3: over a step of dt, with q the
// power spectral density of the acceleration,
//   A_axis = [1 dt; 0 1],
//   R_axis = q [dt^3/3  dt^2/2; dt^2/2  dt]   (the book's Q; here the
//                                              process noise is R),
// and the two axes are independent. The position is measured with noise
// Q = SIGMA_Z^2 I.
//
// The truth is simulated from the same model by a seeded generator of the
// program's own (splitmix64 and Box-Muller, in double: both precisions
// see the same truth and measurements). The program prints a short table
// and the rms position error, the mean NEES (normalised estimation error
// squared, 4 degrees of freedom per step) and the mean NIS (2 per step),
// and checks them: every step accepted, the mean NEES and NIS inside
// their chi-square 95% intervals, the rms position error below the rms
// error of the raw measurements. "tracker4: checks passed" is printed and
// 0 returned only then.
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "sim_rng.h"
#include "gaussfilt/kf.h"

#define STEPS 200
#define DT 1.0       // s
#define QACC 0.5     // m^2 / s^3: the acceleration's spectral density
#define SIGMA_Z 10.0 // m: the position measurement's noise
#define SEED 0x7a3c4e1du

// ---- the simulation's generator (double, examples/sim_rng.h) ----------

static sim_rng rng = {SEED};

static double normal(void)
{
    return sim_normal(&rng);
}

// ---- the model -----------------------------------------------------------

#define R11 (QACC * DT * DT * DT / 3.0)
#define R12 (QACC * DT * DT / 2.0)
#define R22 (QACC * DT)

static const gf_real A[16] = {1, (gf_real)DT, 0, 0,           0, 1, 0, 0,
                              0, 0,           1, (gf_real)DT, 0, 0, 0, 1};
static const gf_real R[16] = {
    (gf_real)R11, (gf_real)R12, 0, 0, (gf_real)R12, (gf_real)R22, 0, 0, 0, 0,
    (gf_real)R11, (gf_real)R12, 0, 0, (gf_real)R12, (gf_real)R22};
static const gf_real C[8] = {1, 0, 0, 0, 0, 0, 1, 0};
static const gf_real Q[4] = {(gf_real)(SIGMA_Z * SIGMA_Z), 0, 0,
                             (gf_real)(SIGMA_Z *SIGMA_Z)};

// chi-square quantile of k degrees of freedom at the standard normal
// quantile zq, by Wilson and Hilferty's cube-root approximation (good to
// well under 1% for k >= 100).
static double chi2_quantile(double k, double zq)
{
    double h = 2.0 / (9.0 * k);
    double c = 1.0 - h + zq * sqrt(h);
    return k * c * c * c;
}

// e^T S^-1 e for a 4 x 4 symmetric positive definite S, by Cholesky in
// double; -1 when S is not positive definite.
static double mahalanobis4(const gf_real *s, const double e[4])
{
    double L[4][4] = {{0}}, y[4];
    for (int j = 0; j < 4; j++) {
        for (int i = j; i < 4; i++) {
            double v = (double)s[i * 4 + j];
            for (int k = 0; k < j; k++) {
                v -= L[i][k] * L[j][k];
            }
            if (i == j) {
                if (!(v > 0)) {
                    return -1.0;
                }
                L[j][j] = sqrt(v);
            } else {
                L[i][j] = v / L[j][j];
            }
        }
    }
    double d = 0;
    for (int i = 0; i < 4; i++) { // L y = e
        y[i] = e[i];
        for (int k = 0; k < i; k++) {
            y[i] -= L[i][k] * y[k];
        }
        y[i] /= L[i][i];
        d += y[i] * y[i];
    }
    return d;
}

static gf_kf kf;
static gf_kf_work work;
static gf_kf_pmodel pmodel;
static gf_kf_pmeas pmeas;

int main(void)
{
    // Truth and prior: the target starts near the origin at about 10 m/s;
    // the prior is N(mu0, S0) and the truth a draw from it.
    const double sd0[4] = {50.0, 5.0, 50.0, 5.0};
    const double mean0[4] = {0.0, 10.0, 0.0, -5.0};
    double x[4];
    gf_real mu0[4], S0[16] = {0};
    for (int i = 0; i < 4; i++) {
        mu0[i] = (gf_real)mean0[i];
        S0[i * 4 + i] = (gf_real)(sd0[i] * sd0[i]);
        x[i] = mean0[i] + sd0[i] * normal();
    }
    const gf_kf_model model = {0, A, NULL, R, NULL};
    const gf_kf_meas meas = {2, C, Q, NULL, 0};
    if (gf_kf_init(&kf, 4, mu0, S0, &work) != GF_OK ||
        gf_kf_prepare_model(&pmodel, 4, &model, &work) != GF_OK ||
        gf_kf_prepare_meas(&pmeas, 4, &meas, &work) != GF_OK) {
        puts("tracker4: set-up refused");
        return 1;
    }
    // The truth's process noise per axis: R_axis = L L^T.
    const double l11 = sqrt(R11), l21 = R12 / l11;
    const double l22 = sqrt(R22 - l21 * l21);

    printf("tracker4 (%s): 4 states, (x, y) measured, sigma_z %.0f m, "
           "q %.2f m^2/s^3, dt %.0f s\n",
           sizeof(gf_real) == 4 ? "float" : "double", SIGMA_Z, QACC, DT);
    printf("%5s %10s %10s %10s %10s %8s %7s %7s\n", "step", "x", "y", "x est",
           "y est", "err m", "NEES", "NIS");
    double sum_e2 = 0, sum_z2 = 0, sum_nees = 0, sum_nis = 0;
    int refused = 0;
    for (int k = 1; k <= STEPS; k++) {
        for (int axis = 0; axis < 2; axis++) {
            double w1 = normal(), w2 = normal();
            double *p = &x[2 * axis];
            p[0] += DT * p[1] + l11 * w1;
            p[1] += l21 * w1 + l22 * w2;
        }
        double zx = x[0] + SIGMA_Z * normal(), zy = x[2] + SIGMA_Z * normal();
        const gf_real z[2] = {(gf_real)zx, (gf_real)zy};
        gf_kf_innovation info;
        if (gf_kf_predict_prepared(&kf, &pmodel, NULL, &work) != GF_OK ||
            gf_kf_update_prepared(&kf, &pmeas, z, &info, &work) != GF_OK) {
            refused++;
            continue;
        }
        gf_real s[16];
        (void)gf_kf_cov(&kf, s);
        double e[4];
        for (int i = 0; i < 4; i++) {
            e[i] = x[i] - (double)kf.mu[i];
        }
        double nees = mahalanobis4(s, e);
        double e2 = e[0] * e[0] + e[2] * e[2];
        sum_e2 += e2;
        sum_z2 += (zx - x[0]) * (zx - x[0]) + (zy - x[2]) * (zy - x[2]);
        sum_nees += nees;
        sum_nis += (double)info.nis;
        if (k % 20 == 0) {
            printf("%5d %10.1f %10.1f %10.1f %10.1f %8.2f %7.2f %7.2f\n", k,
                   x[0], x[2], (double)kf.mu[0], (double)kf.mu[2], sqrt(e2),
                   nees, (double)info.nis);
        }
    }

    const double n = STEPS;
    const double rms = sqrt(sum_e2 / n), rms_z = sqrt(sum_z2 / n);
    const double nees = sum_nees / n, nis = sum_nis / n;
    const double z975 = 1.959963984540054;
    const double nees_lo = chi2_quantile(4 * n, -z975) / n;
    const double nees_hi = chi2_quantile(4 * n, z975) / n;
    const double nis_lo = chi2_quantile(2 * n, -z975) / n;
    const double nis_hi = chi2_quantile(2 * n, z975) / n;
    printf("tracker4: rms position error %.2f m (raw measurements %.2f m) "
           "over %d steps; mean NEES %.3f (95%%: %.3f..%.3f); mean NIS "
           "%.3f (95%%: %.3f..%.3f)\n",
           rms, rms_z, STEPS, nees, nees_lo, nees_hi, nis, nis_lo, nis_hi);
    int ok = refused == 0 && nees >= nees_lo && nees <= nees_hi &&
             nis >= nis_lo && nis <= nis_hi && rms < rms_z;
    if (!ok) {
        printf("tracker4: checks FAILED (%d steps refused)\n", refused);
        return 1;
    }
    puts("tracker4: checks passed");
    return 0;
}
