// SPDX-License-Identifier: MIT
// gps8: positioning from pseudoranges with gf_ekf (ekf.h), 8 states:
// position and velocity in an Earth-centred frame (m, m/s), the receiver's
// clock bias b and drift d (both times the speed of light: m, m/s).
//
//   motion: each axis constant velocity with white acceleration
//           (Bar-Shalom 6.3.3: R_axis = QACC [dt^3/3 dt^2/2; dt^2/2 dt]),
//           the clock b' = b + d dt, d' = d, with R_clock = [QB dt +
//           QD dt^3/3, QD dt^2/2; QD dt^2/2, QD dt];
//   measurement: 4 satellites per fix, rho_k = |s_k - p| + b + noise,
//           noise SIGMA_RHO (6 m) each; H_k = (-(s_k - p)^T / |s_k - p|,
//           0 0 0, 1, 0), the unit line of sight and the clock.
//
// At Earth scale: the receiver starts on the surface (radius 6.371e6 m)
// moving at about 20 m/s, the satellites are on circular orbits of radius
// 2.66e7 m (speed sqrt(GM / r), about 3.9 km/s), all above the receiver's
// horizon. Truth, satellites and pseudoranges are simulated in double by
// the program's own seeded generator, so a float and a double build see
// the same numbers until they are handed to the filter (rounded to
// gf_real there); the callbacks compute in gf_real, as firmware would.
//
//   gps8                 runs, prints a table and its errors against the
//                        truth; checks every step accepted and the rms
//                        position error below 3 SIGMA_RHO
//   gps8 --write FILE    also writes the estimated position and clock
//                        bias of every step to FILE (%.17g)
//   gps8 --compare FILE  also reads FILE (written by the other
//                        precision's build) and prints this build's
//                        position against it at every 30th step, its rms
//                        and worst; checks the worst below SIGMA_RHO
//
// The ctest runs the double build with --write and the float build with
// --compare: the float filter within the sensor noise of the double one
// at every step. "gps8 (PRECISION): checks passed" is printed and 0
// returned only when every check passed.
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sim_rng.h"
#include "gaussfilt/ekf.h"

#define STEPS 300
#define DT 1.0            // s
#define SIGMA_RHO 6.0     // m: pseudorange noise
#define QACC 0.1          // m^2/s^3: the receiver's acceleration
#define QB 0.1            // m^2/s: clock bias (white frequency noise)
#define QD 0.01           // m^2/s^3: clock drift (random-walk frequency)
#define R_EARTH 6.371e6   // m
#define R_ORBIT 2.66e7    // m
#define GM 3.986004418e14 // m^3/s^2
#define NSAT 4
#define SEED 0x6e5a7f01u

// ---- the simulation's generator (double, examples/sim_rng.h) ----------

static sim_rng rng = {SEED};

static double normal(void)
{
    return sim_normal(&rng);
}

// ---- satellites ------------------------------------------------------------

// Satellite k at time t: R_ORBIT (cos(w t) u_k + sin(w t) v_k), u_k and v_k
// orthonormal, w = sqrt(GM / R_ORBIT^3).
typedef struct sat {
    double u[3], v[3];
} sat;

static void unit(double a[3])
{
    double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int i = 0; i < 3; i++) {
        a[i] /= n;
    }
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static void sat_pos(const sat *s, double t, double p[3])
{
    double w = sqrt(GM / (R_ORBIT * R_ORBIT * R_ORBIT));
    double c = cos(w * t), sn = sin(w * t);
    for (int i = 0; i < 3; i++) {
        p[i] = R_ORBIT * (c * s->u[i] + sn * s->v[i]);
    }
}

// ---- the filter's models (gf_real, as firmware computes them) ------------

// The satellites of the current fix, as the receiver knows them.
typedef struct fix {
    gf_real s[NSAT][3];
} fix;

// mu_bar = F mu: position += velocity dt, bias += drift dt; G = F.
static gf_status motion(void *ctx, unsigned n, const gf_real *mu,
                        const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    (void)ctx;
    (void)u;
    const gf_real dt = (gf_real)DT;
    for (unsigned i = 0; i < 3; i++) {
        mu_bar[i] = mu[i] + dt * mu[i + 3];
        G[i * n + i + 3] = dt;
    }
    mu_bar[6] = mu[6] + dt * mu[7];
    G[6 * n + 7] = dt;
    return GF_OK;
}

// rho_k = |s_k - p| + b, H_k = (-(s_k - p) / |s_k - p|, 0, 0, 0, 1, 0).
static gf_status pseudoranges(void *ctx, unsigned n, unsigned m,
                              const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    const fix *f = ctx;
    for (unsigned k = 0; k < m; k++) {
        gf_real d[3], r2 = 0;
        for (unsigned i = 0; i < 3; i++) {
            d[i] = f->s[k][i] - mu_bar[i];
            r2 += d[i] * d[i];
        }
        gf_real r = GF_SQRT(r2);
        if (!(r > 0)) {
            return GF_ERR_MODEL;
        }
        z_hat[k] = r + mu_bar[6];
        for (unsigned i = 0; i < 3; i++) {
            H[k * n + i] = -d[i] / r;
        }
        H[k * n + 6] = 1;
    }
    return GF_OK;
}

static gf_kf ekf;
static gf_kf_work work;
static gf_ekf_pmotion pmotion;
static gf_ekf_pmeas pmeas;

int main(int argc, char **argv)
{
    const char *prec = sizeof(gf_real) == 4 ? "float" : "double";
    FILE *out = NULL, *other = NULL;
    if (argc == 3 && strcmp(argv[1], "--write") == 0) {
        out = fopen(argv[2], "w");
    } else if (argc == 3 && strcmp(argv[1], "--compare") == 0) {
        other = fopen(argv[2], "r");
    } else if (argc != 1) {
        fprintf(stderr, "usage: gps8 [--write FILE | --compare FILE]\n");
        return 2;
    }
    if (argc == 3 && !out && !other) {
        fprintf(stderr, "gps8: cannot open %s\n", argv[2]);
        return 2;
    }

    // The receiver: on the surface at latitude 45, longitude 7 degrees,
    // moving east at 20 m/s; clock bias 30 km, drift 2 m/s.
    const double lat = 0.7853981633974483, lon = 0.12217304763960307;
    const double up[3] = {cos(lat) * cos(lon), cos(lat) * sin(lon), sin(lat)};
    const double east[3] = {-sin(lon), cos(lon), 0.0};
    double north[3];
    cross(up, east, north);
    double x[8];
    for (int i = 0; i < 3; i++) {
        x[i] = R_EARTH * up[i];
        x[i + 3] = 20.0 * east[i];
    }
    x[6] = 3.0e4;
    x[7] = 2.0;

    // Satellites: one near the zenith, three 40 degrees (seen from the
    // Earth's centre) away from it at azimuths 0, 120 and 240 degrees;
    // each orbit's plane holds its position and a random direction.
    sat sats[NSAT];
    for (int k = 0; k < NSAT; k++) {
        double el = k == 0 ? 0.1 : 0.6981317007977318; // from the zenith
        double az = 2.0943951023931953 * (k - 1) + 0.3;
        for (int i = 0; i < 3; i++) {
            sats[k].u[i] = cos(el) * up[i] +
                           sin(el) * (cos(az) * north[i] + sin(az) * east[i]);
        }
        unit(sats[k].u);
        double r[3] = {normal(), normal(), normal()}, t[3];
        cross(sats[k].u, r, t);
        cross(t, sats[k].u, sats[k].v);
        unit(sats[k].v);
    }

    // The prior: 100 m on each position, 5 m/s on each velocity, 1e5 m
    // on the clock bias and 10 m/s on its drift, centred on a draw from it.
    const double sd0[8] = {100, 100, 100, 5, 5, 5, 1e5, 10};
    gf_real mu0[8], S0[64] = {0};
    for (int i = 0; i < 8; i++) {
        mu0[i] = (gf_real)(x[i] + sd0[i] * normal());
        S0[i * 8 + i] = (gf_real)(sd0[i] * sd0[i]);
    }
    // Process noise R (the book's name): the receiver's three axes and
    // the clock, each a 2 x 2 block of the white-noise model.
    gf_real R[64] = {0};
    const double dt = DT;
    for (int i = 0; i < 3; i++) {
        R[i * 8 + i] = (gf_real)(QACC * dt * dt * dt / 3.0);
        R[i * 8 + i + 3] = R[(i + 3) * 8 + i] = (gf_real)(QACC * dt * dt / 2.0);
        R[(i + 3) * 8 + i + 3] = (gf_real)(QACC * dt);
    }
    R[6 * 8 + 6] = (gf_real)(QB * dt + QD * dt * dt * dt / 3.0);
    R[6 * 8 + 7] = R[7 * 8 + 6] = (gf_real)(QD * dt * dt / 2.0);
    R[7 * 8 + 7] = (gf_real)(QD * dt);
    // The truth's noise, R = L L^T per block.
    const double a11 = sqrt(QACC * dt * dt * dt / 3.0);
    const double a21 = QACC * dt * dt / 2.0 / a11;
    const double a22 = sqrt(QACC * dt - a21 * a21);
    const double c11 = sqrt(QB * dt + QD * dt * dt * dt / 3.0);
    const double c21 = QD * dt * dt / 2.0 / c11;
    const double c22 = sqrt(QD * dt - c21 * c21);
    gf_real Q[NSAT * NSAT] = {0};
    for (int k = 0; k < NSAT; k++) {
        Q[k * NSAT + k] = (gf_real)(SIGMA_RHO * SIGMA_RHO);
    }

    static fix f;
    const gf_ekf_motion mo = {motion, NULL, R};
    const gf_ekf_meas me = {NSAT, pseudoranges, &f, Q, 0, 0};
    if (gf_ekf_init(&ekf, 8, mu0, S0, 0, &work) != GF_OK ||
        gf_ekf_prepare_motion(&pmotion, 8, &mo, &work) != GF_OK ||
        gf_ekf_prepare_meas(&pmeas, 8, &me, &work) != GF_OK) {
        printf("gps8 (%s): set-up refused\n", prec);
        return 1;
    }

    printf("gps8 (%s): 8 states, %d pseudoranges per fix, sigma %.0f m, "
           "%d fixes of %.0f s\n",
           prec, NSAT, SIGMA_RHO, STEPS, DT);
    printf("%5s %9s %9s %9s %8s", "step", "pos err", "clk err", "vel err",
           "NIS");
    if (other) {
        printf(" %12s", "vs other m");
    }
    printf("\n");
    double sum_e2 = 0, sum_d2 = 0, worst_d = 0;
    int refused = 0, worst_k = 0, compared = 0;
    for (int k = 1; k <= STEPS; k++) {
        const double t = k * dt;
        double w[8];
        for (int i = 0; i < 8; i++) {
            w[i] = normal();
        }
        for (int i = 0; i < 3; i++) {
            x[i] += dt * x[i + 3] + a11 * w[i];
            x[i + 3] += a21 * w[i] + a22 * w[i + 3];
        }
        x[6] += dt * x[7] + c11 * w[6];
        x[7] += c21 * w[6] + c22 * w[7];
        gf_real z[NSAT];
        for (int s = 0; s < NSAT; s++) {
            double p[3], r2 = 0;
            sat_pos(&sats[s], t, p);
            for (int i = 0; i < 3; i++) {
                f.s[s][i] = (gf_real)p[i];
                r2 += (p[i] - x[i]) * (p[i] - x[i]);
            }
            z[s] = (gf_real)(sqrt(r2) + x[6] + SIGMA_RHO * normal());
        }
        gf_kf_innovation info;
        if (gf_ekf_predict_prepared(&ekf, &pmotion, NULL, &work) != GF_OK ||
            gf_ekf_update_prepared(&ekf, &pmeas, z, &info, &work) != GF_OK) {
            refused++;
            continue;
        }
        double e2 = 0, v2 = 0;
        for (int i = 0; i < 3; i++) {
            double e = (double)ekf.mu[i] - x[i];
            double v = (double)ekf.mu[i + 3] - x[i + 3];
            e2 += e * e;
            v2 += v * v;
        }
        sum_e2 += e2;
        if (out) {
            fprintf(out, "%d %.17g %.17g %.17g %.17g\n", k, (double)ekf.mu[0],
                    (double)ekf.mu[1], (double)ekf.mu[2], (double)ekf.mu[6]);
        }
        double dpos = -1;
        if (other) {
            int ko = 0;
            double q[4];
            if (fscanf(other, "%d %lf %lf %lf %lf", &ko, &q[0], &q[1], &q[2],
                       &q[3]) != 5 ||
                ko != k) {
                printf("gps8 (%s): %s has no step %d\n", prec, argv[2], k);
                return 1;
            }
            double d2 = 0;
            for (int i = 0; i < 3; i++) {
                double d = (double)ekf.mu[i] - q[i];
                d2 += d * d;
            }
            dpos = sqrt(d2);
            sum_d2 += d2;
            compared++;
            if (dpos > worst_d) {
                worst_d = dpos;
                worst_k = k;
            }
        }
        if (k % 30 == 0 || k == 1) {
            printf("%5d %9.2f %9.2f %9.3f %8.2f", k, sqrt(e2),
                   (double)ekf.mu[6] - x[6], sqrt(v2), (double)info.nis);
            if (other) {
                printf(" %12.3f", dpos);
            }
            printf("\n");
        }
    }
    if (out) {
        fclose(out);
    }
    if (other) {
        fclose(other);
    }

    const double rms = sqrt(sum_e2 / (STEPS - refused));
    printf("gps8 (%s): rms position error %.2f m against the truth over %d "
           "fixes, %d refused\n",
           prec, rms, STEPS, refused);
    int ok = refused == 0 && rms < 3.0 * SIGMA_RHO;
    if (other) {
        const double rms_d = compared ? sqrt(sum_d2 / compared) : 0.0;
        printf("gps8 (%s) against the other build: position difference rms "
               "%.3f m, worst %.3f m (fix %d), sensor noise %.0f m: %s\n",
               prec, rms_d, worst_d, worst_k, SIGMA_RHO,
               worst_d < SIGMA_RHO ? "within it at every fix" : "NOT within");
        ok = ok && compared == STEPS && worst_d < SIGMA_RHO;
    }
    if (!ok) {
        printf("gps8 (%s): checks FAILED\n", prec);
        return 1;
    }
    printf("gps8 (%s): checks passed\n", prec);
    return 0;
}
