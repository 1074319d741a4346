// SPDX-License-Identifier: MIT
// The workloads of the filters of n states (workloads_n.h): models,
// simulated truth, and the measurement table the measured loops replay.
#include "workloads_n.h"

#include <math.h>
#include <string.h>

const char *const wl_n_names[WL_N_ROWS] = {"cv2", "cv3",  "cv4", "cv6",
                                           "cv8", "cv12", "gps"};

wl_n wl_nw;
gf_kf_work wl_n_work;
gf_real wl_n_z[WL_TAB][GF_KF_NMAX];

// The models' matrices (row-major, n x n or m x n).
static gf_real mA[GF_KF_NMAX * GF_KF_NMAX];
static gf_real mR[GF_KF_NMAX * GF_KF_NMAX];
static gf_real mC[GF_KF_NMAX * GF_KF_NMAX];
static gf_real mQ[GF_KF_NMAX * GF_KF_NMAX];

// The simulated truth's generator (workloads.c's wl_normal), with a state
// of its own.
static unsigned long long rng;

static double normal01(void)
{
    return wl_normal(&rng);
}

// A draw of the white-acceleration noise of one axis, R = q ((dt^3/3,
// dt^2/2), (dt^2/2, dt)), through R's Cholesky factor: (dp, dv).
static void wa_draw(double q, double dt, double *dp, double *dv)
{
    const double l11 = sqrt(q * dt * dt * dt / 3.0);
    const double l21 = q * dt * dt / 2.0 / l11;
    const double l22 = sqrt(q * dt - l21 * l21);
    const double a = normal01(), b = normal01();
    *dp = l11 * a;
    *dv = l21 * a + l22 * b;
}

// One constant-velocity axis in the models: states i, i + 1 of n.
static void cv_axis(unsigned n, unsigned i, double q, double dt)
{
    mA[i * n + i] = 1;
    mA[i * n + i + 1] = (gf_real)dt;
    mA[(i + 1) * n + i + 1] = 1;
    mR[i * n + i] = (gf_real)(q * dt * dt * dt / 3.0);
    mR[i * n + i + 1] = (gf_real)(q * dt * dt / 2.0);
    mR[(i + 1) * n + i] = (gf_real)(q * dt * dt / 2.0);
    mR[(i + 1) * n + i + 1] = (gf_real)(q * dt);
}

static void run_check(void)
{
    gf_kf kf = wl_nw.init;
    for (unsigned i = 0; i < WL_TAB; i++) {
        gf_status st =
            wl_nw.ekf ? gf_ekf_predict(&kf, &wl_nw.motion, NULL, &wl_n_work)
                      : gf_kf_predict(&kf, &wl_nw.model, NULL, &wl_n_work);
        if (st != GF_OK) {
            wl_die(wl_nw.name, (int)i, st);
        }
        st = wl_nw.ekf
                 ? gf_ekf_update(&kf, &wl_nw.emeas, wl_n_z[i], NULL, &wl_n_work)
                 : gf_kf_update(&kf, &wl_nw.meas, wl_n_z[i], NULL, &wl_n_work);
        if (st != GF_OK) {
            wl_die(wl_nw.name, (int)i, st);
        }
    }
}

static void setup_cv(unsigned n)
{
    const double dt = 0.1;
    const unsigned axes = n / 2, m = (n + 1) / 2;
    double x[GF_KF_NMAX];
    for (unsigned a = 0; a < axes; a++) {
        cv_axis(n, 2 * a, 0.5 + 0.1 * a, dt);
        mC[a * n + 2 * a] = 1;
        mQ[a * m + a] = (gf_real)(1.0 + 0.25 * a);
    }
    if (n % 2) { // cv3: the random-walk state, measured
        mA[(n - 1) * n + n - 1] = 1;
        mR[(n - 1) * n + n - 1] = (gf_real)(0.01 * dt);
        mC[(m - 1) * n + n - 1] = 1;
        mQ[(m - 1) * m + m - 1] = GF_R(0.25);
    }
    // Prior: positions N(0, 100), velocities N(0, 10) (the random-walk
    // state N(0, 1)); the truth starts from a draw of it.
    for (unsigned i = 0; i < n; i++) {
        const double var = (n % 2 && i == n - 1) ? 1.0 : (i % 2 ? 10.0 : 100.0);
        wl_nw.mu0[i] = 0;
        wl_nw.sigma0[i * n + i] = (gf_real)var;
        x[i] = sqrt(var) * normal01();
    }
    for (unsigned t = 0; t < WL_TAB; t++) {
        for (unsigned a = 0; a < axes; a++) {
            double dp, dv;
            wa_draw(0.5 + 0.1 * a, dt, &dp, &dv);
            x[2 * a] += dt * x[2 * a + 1] + dp;
            x[2 * a + 1] += dv;
            wl_n_z[t][a] =
                (gf_real)(x[2 * a] + sqrt(1.0 + 0.25 * a) * normal01());
        }
        if (n % 2) {
            x[n - 1] += sqrt(0.01 * dt) * normal01();
            wl_n_z[t][m - 1] = (gf_real)(x[n - 1] + 0.5 * normal01());
        }
    }
    wl_nw.model.nu = 0;
    wl_nw.model.A = mA;
    wl_nw.model.B = NULL;
    wl_nw.model.R = mR;
    wl_nw.model.c = NULL;
    wl_nw.meas.m = m;
    wl_nw.meas.C = mC;
    wl_nw.meas.Q = mQ;
    wl_nw.meas.c = NULL;
    wl_nw.meas.gate = 0;
    wl_nw.m = m;
}

// ---- gps -----------------------------------------------------------------

#define GPS_DT 1.0
#define GPS_Q 0.1         // white acceleration, m^2/s^3
#define GPS_QB 0.1        // clock bias white noise, m^2/s
#define GPS_QD 0.01       // clock drift white noise, m^2/s^3
#define GPS_SIGMA 5.0     // pseudorange noise, m
#define GPS_RE 6371000.0  // receiver radius, m
#define GPS_RS 26560000.0 // satellites' orbit radius, m

static gf_real sats[4][3];

gf_status wl_gps_motion(void *ctx, unsigned n, const gf_real *mu,
                        const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    (void)ctx;
    (void)u;
    const gf_real dt = (gf_real)GPS_DT;
    // mu_bar arrives as mu, G as the identity: only the couplings.
    for (unsigned k = 0; k < 3; k++) {
        mu_bar[k] = mu[k] + dt * mu[3 + k];
        G[k * n + 3 + k] = dt;
    }
    mu_bar[6] = mu[6] + dt * mu[7];
    G[6 * n + 7] = dt;
    return GF_OK;
}

gf_status wl_gps_meas(void *ctx, unsigned n, unsigned m, const gf_real *mu_bar,
                      gf_real *z_hat, gf_real *H)
{
    (void)ctx;
    // z_hat and H arrive as zeros.
    for (unsigned i = 0; i < m; i++) {
        const gf_real dx = sats[i][0] - mu_bar[0];
        const gf_real dy = sats[i][1] - mu_bar[1];
        const gf_real dz = sats[i][2] - mu_bar[2];
        const gf_real r = GF_SQRT(dx * dx + dy * dy + dz * dz);
        const gf_real ir = GF_R(1.0) / r;
        z_hat[i] = r + mu_bar[6];
        H[i * n + 0] = -dx * ir;
        H[i * n + 1] = -dy * ir;
        H[i * n + 2] = -dz * ir;
        H[i * n + 6] = 1;
    }
    return GF_OK;
}

static void setup_gps(void)
{
    const unsigned n = 8, m = 4;
    const double lat = 0.7853981633974483, lon = 0.17453292519943295;
    const double up[3] = {cos(lat) * cos(lon), cos(lat) * sin(lon), sin(lat)};
    const double east[3] = {-sin(lon), cos(lon), 0};
    const double north[3] = {-sin(lat) * cos(lon), -sin(lat) * sin(lon),
                             cos(lat)};
    // Directions from the Earth's centre, tilted from the receiver's
    // vertical (central angles 6 to 48 degrees: all well above the
    // horizon, spread in azimuth).
    static const double tilt[4][2] = {
        {0.1, 0.05}, {0.9, 0.2}, {-0.5, 0.75}, {-0.4, -0.8}};
    double s[4][3];
    for (unsigned i = 0; i < m; i++) {
        double d[3], len = 0;
        for (unsigned k = 0; k < 3; k++) {
            d[k] = up[k] + tilt[i][0] * east[k] + tilt[i][1] * north[k];
            len += d[k] * d[k];
        }
        for (unsigned k = 0; k < 3; k++) {
            s[i][k] = GPS_RS * d[k] / sqrt(len);
            sats[i][k] = (gf_real)s[i][k];
        }
    }
    for (unsigned k = 0; k < 3; k++) {
        mR[k * n + k] = (gf_real)(GPS_Q * GPS_DT * GPS_DT * GPS_DT / 3.0);
        mR[k * n + 3 + k] = (gf_real)(GPS_Q * GPS_DT * GPS_DT / 2.0);
        mR[(3 + k) * n + k] = mR[k * n + 3 + k];
        mR[(3 + k) * n + 3 + k] = (gf_real)(GPS_Q * GPS_DT);
    }
    mR[6 * n + 6] =
        (gf_real)(GPS_QB * GPS_DT + GPS_QD * GPS_DT * GPS_DT * GPS_DT / 3.0);
    mR[6 * n + 7] = (gf_real)(GPS_QD * GPS_DT * GPS_DT / 2.0);
    mR[7 * n + 6] = mR[6 * n + 7];
    mR[7 * n + 7] = (gf_real)(GPS_QD * GPS_DT);
    for (unsigned i = 0; i < m; i++) {
        mQ[i * m + i] = (gf_real)(GPS_SIGMA * GPS_SIGMA);
    }

    // Truth: on the surface, 15 m/s east; clock 300 m off, drifting
    // 0.5 m/s. The prior: 50 m, 5 m/s, 1000 m and 1 m/s off at most.
    double x[8];
    for (unsigned k = 0; k < 3; k++) {
        x[k] = GPS_RE * up[k];
        x[3 + k] = 15.0 * east[k];
    }
    x[6] = 300;
    x[7] = 0.5;
    static const double sd0[8] = {50, 50, 50, 5, 5, 5, 1000, 1};
    for (unsigned i = 0; i < n; i++) {
        wl_nw.mu0[i] = (gf_real)(x[i] + sd0[i] * normal01());
        wl_nw.sigma0[i * n + i] = (gf_real)(sd0[i] * sd0[i]);
    }
    for (unsigned t = 0; t < WL_TAB; t++) {
        for (unsigned k = 0; k < 3; k++) {
            double dp, dv;
            wa_draw(GPS_Q, GPS_DT, &dp, &dv);
            x[k] += GPS_DT * x[3 + k] + dp;
            x[3 + k] += dv;
        }
        x[6] += GPS_DT * x[7] + sqrt(GPS_QB * GPS_DT) * normal01();
        x[7] += sqrt(GPS_QD * GPS_DT) * normal01();
        for (unsigned i = 0; i < m; i++) {
            const double dx = s[i][0] - x[0], dy = s[i][1] - x[1],
                         dz = s[i][2] - x[2];
            wl_n_z[t][i] = (gf_real)(sqrt(dx * dx + dy * dy + dz * dz) + x[6] +
                                     GPS_SIGMA * normal01());
        }
    }
    wl_nw.motion.g = wl_gps_motion;
    wl_nw.motion.ctx = NULL;
    wl_nw.motion.R = mR;
    wl_nw.emeas.m = m;
    wl_nw.emeas.h = wl_gps_meas;
    wl_nw.emeas.ctx = NULL;
    wl_nw.emeas.Q = mQ;
    wl_nw.emeas.angle_mask = 0;
    wl_nw.emeas.gate = 0;
    wl_nw.m = m;
}

int wl_setup_n(const char *name)
{
    unsigned row = 0;
    while (row < WL_N_ROWS && strcmp(name, wl_n_names[row]) != 0) {
        row++;
    }
    if (row == WL_N_ROWS) {
        return -1;
    }
    memset(&wl_nw, 0, sizeof wl_nw);
    memset(mA, 0, sizeof mA);
    memset(mR, 0, sizeof mR);
    memset(mC, 0, sizeof mC);
    memset(mQ, 0, sizeof mQ);
    memset(wl_n_z, 0, sizeof wl_n_z);
    rng = 0x9E3779B97F4A7C15ull + row;
    wl_nw.name = wl_n_names[row];
    wl_nw.ekf = row == WL_N_ROWS - 1;
    static const unsigned sizes[WL_N_ROWS] = {2, 3, 4, 6, 8, 12, 8};
    wl_nw.n = sizes[row];
    if (wl_nw.ekf) {
        setup_gps();
    } else {
        setup_cv(wl_nw.n);
    }
    gf_status st = wl_nw.ekf ? gf_ekf_init(&wl_nw.init, wl_nw.n, wl_nw.mu0,
                                           wl_nw.sigma0, 0, &wl_n_work)
                             : gf_kf_init(&wl_nw.init, wl_nw.n, wl_nw.mu0,
                                          wl_nw.sigma0, &wl_n_work);
    if (st != GF_OK) {
        wl_die(wl_nw.name, -1, st);
    }
    run_check();
    return 0;
}
