// SPDX-License-Identifier: MIT
// gaussfilt sim: track models as data and the configuration file (see
// node_model.h). This builds the core's model structs from numbers and
// holds the range-bearing measurement callback; every filter step stays in
// the core.
#include "node_model.h"

#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "book.h"
#include "gf_channels.h"

// ---- presets ----------------------------------------------------------------

// The book's numbers come from examples/book.h.
static const gf_node_model book_car = {
    "book-car",
    GF_NODE_KIND_CAR,
    GF_NODE_MEASURE_AUTO,
    GF_BOOK_CAR_DT,
    GF_BOOK_CAR_ACCEL_VAR, // R = ((0.25, 0.5), (0.5, 1))
    {0, 0, 0, 0},
    {0, 0},
    0.0,
    {0, 0, 0}, // at rest at 0, known exactly (exercise 1)
    {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}},
    {{GF_BOOK_EX2_Q, 0, 0}, {0, 0, 0}, {0, 0, 0}},
    NULL,
    NULL,
    NULL,
    GF_NODE_LATE_WINDOW,
};

static const gf_node_model book_robot = {
    "book-robot",
    GF_NODE_KIND_ROBOT,
    GF_NODE_MEASURE_AUTO,
    0.0,
    0.0,
    {0, 0, 0, 0}, // R = 0 (exercise 4)
    {0, 0},
    0.0,
    {0, 0, 0}, // at the origin, heading unknown
    {{GF_BOOK_EX4_XY_VAR, 0, 0},
     {0, GF_BOOK_EX4_XY_VAR, 0},
     {0, 0, GF_BOOK_EX4_HEADING_VAR}},
    {{GF_BOOK_EX4_Q, 0, 0}, {0, 0, 0}, {0, 0, 0}},
    NULL,
    NULL,
    NULL,
    GF_NODE_LATE_WINDOW,
};

const gf_node_model *gf_node_model_book_car(void)
{
    return &book_car;
}
const gf_node_model *gf_node_model_book_robot(void)
{
    return &book_robot;
}

unsigned gf_node_measure_m(int8_t kind, int8_t measure)
{
    if (kind == GF_NODE_KIND_CAR) {
        if (measure == GF_NODE_MEASURE_X || measure == GF_NODE_MEASURE_V) {
            return 1;
        }
        return measure == GF_NODE_MEASURE_XV ? 2u : 0u;
    }
    if (kind == GF_NODE_KIND_ROBOT) {
        if (measure == GF_NODE_MEASURE_X || measure == GF_NODE_MEASURE_RANGE ||
            measure == GF_NODE_MEASURE_BEARING ||
            measure == GF_NODE_MEASURE_HEADING) {
            return 1;
        }
        if (measure == GF_NODE_MEASURE_XY ||
            measure == GF_NODE_MEASURE_RANGE_BEARING) {
            return 2;
        }
    }
    return 0;
}

int gf_node_model_measure(const gf_node_model *mdl, unsigned m)
{
    int measure = mdl->measure;
    if (measure == GF_NODE_MEASURE_AUTO) {
        measure = m == 1                          ? GF_NODE_MEASURE_X
                  : m != 2                        ? -1
                  : mdl->kind == GF_NODE_KIND_CAR ? GF_NODE_MEASURE_XV
                                                  : GF_NODE_MEASURE_XY;
    }
    if (measure < 0 || gf_node_measure_m(mdl->kind, (int8_t)measure) != m) {
        return -1;
    }
    return measure;
}

// Every principal minor of the leading n x n block >= -tol (scaled by the
// diagonal): positive semidefinite, for n <= 3; and symmetric.
static int psd(const double a[3][3], unsigned n)
{
    double s = 0.0, tol;
    unsigned i, j;
    for (i = 0; i < n; i++) {
        if (!(a[i][i] >= 0.0)) {
            return 0;
        }
        s = a[i][i] > s ? a[i][i] : s;
        for (j = 0; j < n; j++) {
            if (!isfinite(a[i][j]) ||
                fabs(a[i][j] - a[j][i]) > 1e-12 * (fabs(a[i][j]) + 1e-300)) {
                return 0;
            }
        }
    }
    tol = 1e-12 * (s * s + 1e-300);
    for (i = 0; i < n; i++) {
        for (j = i + 1; j < n; j++) {
            if (a[i][i] * a[j][j] - a[i][j] * a[j][i] < -tol) {
                return 0;
            }
        }
    }
    if (n == 3) {
        double d = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                   a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                   a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        if (d < -tol * s) {
            return 0;
        }
    }
    return 1;
}

// The prior as the track's filter starts from it: 1 if the filter's init
// (gf_kf2_init for the car, gf_ekf3_init for the robot) takes prior_mean
// and prior_cov in gf_real, so that a track made from a checked model
// always starts.
static int prior_starts(const gf_node_model *mdl)
{
    if (mdl->kind == GF_NODE_KIND_CAR) {
        gf_vec2 mu;
        gf_mat2 sigma;
        for (unsigned i = 0; i < 2; i++) {
            mu.v[i] = (gf_real)mdl->prior_mean[i];
            for (unsigned j = 0; j < 2; j++) {
                sigma.m[i][j] = (gf_real)mdl->prior_cov[i][j];
            }
        }
        gf_kf2 kf;
        return gf_kf2_init(&kf, &mu, &sigma) == GF_OK;
    }
    gf_vec3 mu;
    gf_mat3 sigma;
    for (unsigned i = 0; i < 3; i++) {
        mu.v[i] = (gf_real)mdl->prior_mean[i];
        for (unsigned j = 0; j < 3; j++) {
            sigma.m[i][j] = (gf_real)mdl->prior_cov[i][j];
        }
    }
    gf_ekf3 ekf;
    return gf_ekf3_init(&ekf, &mu, &sigma) == GF_OK;
}

// A linear model's numbers as gf_kf takes them: 0, or -1 with the key at
// fault in why.
static int linear_check(const gf_node_model *mdl, const char **why)
{
    const gf_node_linear *l = mdl->lin;
    gf_kf_work work;
    gf_kf kf;
    gf_kf_pmodel pm;
    gf_kf_pmeas pq;
    gf_kf_model km;
    gf_kf_meas mm;
    gf_real A[GF_NODE_NMAX * GF_NODE_NMAX], B[GF_NODE_NMAX * GF_NODE_NMAX],
        R[GF_NODE_NMAX * GF_NODE_NMAX], C[GF_NODE_NMAX * GF_NODE_NMAX],
        Q[GF_NODE_NMAX * GF_NODE_NMAX], mu[GF_NODE_NMAX],
        P[GF_NODE_NMAX * GF_NODE_NMAX];
    unsigned i, n, m;
    if (l == NULL || l->n < 1 || l->n > GF_NODE_NMAX) {
        *why = "n: a linear model has 1 to " GF_NODE_NMAX_STR " states (n = N "
               "or motion = cv|ca ...)";
        return -1;
    }
    n = l->n;
    m = l->m;
    if (m == 0 && mdl->sensors != NULL && mdl->sensors->count > 0) {
        // measured by its named sensors only (checked by the configuration)
    } else if (m < 1 || m > n) {
        *why = "C: a linear model measures 1 to n quantities (C = m*n "
               "numbers)";
        return -1;
    }
    if (l->nu > GF_NODE_NMAX) {
        *why = "B: at most " GF_NODE_NMAX_STR " controls";
        return -1;
    }
    for (i = 0; i < n * n; i++) {
        A[i] = (gf_real)l->A[i];
        R[i] = (gf_real)l->R[i];
        P[i] = (gf_real)l->prior_cov[i];
    }
    for (i = 0; i < n * l->nu; i++) {
        B[i] = (gf_real)l->B[i];
    }
    for (i = 0; i < m * n; i++) {
        C[i] = (gf_real)l->C[i];
    }
    for (i = 0; i < m * m; i++) {
        Q[i] = (gf_real)l->Q[i];
    }
    for (i = 0; i < n; i++) {
        mu[i] = (gf_real)l->prior_mean[i];
    }
    km.nu = l->nu;
    km.A = A;
    km.B = B;
    km.R = R;
    km.c = NULL;
    if (gf_kf_prepare_model(&pm, n, &km, &work) != GF_OK) {
        // which of A, B, R: non-finite numbers first, then R's shape
        *why = "R must be symmetric positive semidefinite (and A, B, R "
               "finite)";
        for (i = 0; i < n * n; i++) {
            if (!isfinite(l->A[i])) {
                *why = "A must be finite";
            }
        }
        for (i = 0; i < n * l->nu; i++) {
            if (!isfinite(l->B[i])) {
                *why = "B must be finite";
            }
        }
        return -1;
    }
    mm.m = m;
    mm.C = C;
    mm.Q = Q;
    mm.c = NULL;
    mm.gate = (gf_real)mdl->gate;
    if (m > 0 && gf_kf_prepare_meas(&pq, n, &mm, &work) != GF_OK) {
        *why = "Q must be symmetric positive semidefinite (and C finite)";
        for (i = 0; i < m * n; i++) {
            if (!isfinite(l->C[i])) {
                *why = "C must be finite";
            }
        }
        return -1;
    }
    for (i = 0; i < n; i++) {
        if (!isfinite(l->prior_mean[i])) {
            *why = "prior_mean must be finite";
            return -1;
        }
    }
    if (gf_kf_init(&kf, n, mu, P, &work) != GF_OK) {
        *why = "prior_cov must be symmetric positive semidefinite (as "
               "gf_kf_init takes it)";
        return -1;
    }
    return 0;
}

int gf_node_model_check(const gf_node_model *mdl, const char **why)
{
    const char *w = NULL;
    unsigned i, n, m;
    if (mdl == NULL) {
        w = "no model";
        goto bad;
    }
    if (!(mdl->late_window >= 0.0) || !isfinite(mdl->late_window)) {
        w = "late_window must be finite and >= 0 (seconds)";
        goto bad;
    }
    if (mdl->kind == GF_NODE_KIND_LINEAR) {
        if (!(mdl->gate >= 0.0) || !isfinite(mdl->gate)) {
            w = "gate must be finite and >= 0";
        } else if (!(mdl->dt > 0.0) || !isfinite(mdl->dt)) {
            w = "dt must be a finite number > 0";
        } else if (linear_check(mdl, &w) == 0) {
            return 0;
        }
        goto bad;
    }
    n = mdl->kind == GF_NODE_KIND_CAR ? 2u : 3u;
    m = gf_node_measure_m(mdl->kind, mdl->measure);
    if (mdl->measure == GF_NODE_MEASURE_AUTO) {
        m = 1; // meas_cov: the first entry
    }
    if (mdl->kind != GF_NODE_KIND_CAR && mdl->kind != GF_NODE_KIND_ROBOT) {
        w = "type must be car, robot or linear";
    } else if (m == 0) {
        w = mdl->kind == GF_NODE_KIND_CAR
                ? "measure: a car measures position, velocity or position "
                  "velocity"
                : "measure: a robot measures x, x y, range bearing, range, "
                  "bearing or heading";
    } else if (mdl->kind == GF_NODE_KIND_CAR &&
               (!(mdl->dt > 0.0) || !isfinite(mdl->dt))) {
        w = "dt must be a finite number > 0";
    } else if (mdl->kind == GF_NODE_KIND_CAR &&
               (!(mdl->accel_var >= 0.0) || !isfinite(mdl->accel_var))) {
        w = "accel_var must be finite and >= 0";
    } else if (!(mdl->gate >= 0.0) || !isfinite(mdl->gate)) {
        w = "gate must be finite and >= 0";
    } else if (!isfinite(mdl->landmark[0]) || !isfinite(mdl->landmark[1])) {
        w = "landmark must be finite";
    } else if (!psd(mdl->prior_cov, n)) {
        w = "prior_cov must be symmetric positive semidefinite";
    } else if (!psd(mdl->meas_cov, m)) {
        w = "meas_cov must be symmetric positive semidefinite";
    }
    if (w == NULL && mdl->kind == GF_NODE_KIND_ROBOT) {
        for (i = 0; i < 4; i++) {
            if (!(mdl->odometry[i] >= 0.0) || !isfinite(mdl->odometry[i])) {
                w = "odometry: its four numbers must be finite and >= 0";
            }
        }
    }
    for (i = 0; w == NULL && i < n; i++) {
        if (!isfinite(mdl->prior_mean[i])) {
            w = "prior_mean must be finite";
        }
    }
    if (w == NULL && !prior_starts(mdl)) {
        w = "prior_cov: the filter's init refuses prior_mean and prior_cov "
            "in its precision";
    }
    if (w == NULL) {
        return 0;
    }
bad:
    if (why != NULL) {
        *why = w;
    }
    return -1;
}

void gf_node_linear_motion(const gf_node_linear *lin, double dt, double *A,
                           double *R)
{
    unsigned a, k = 0, n = lin->n, i, j;
    memset(A, 0, sizeof(double) * n * n);
    memset(R, 0, sizeof(double) * n * n);
    for (a = 0; a < lin->axes && k < n; a++) {
        unsigned d = lin->axis[a];
        // g = (dt^2/2, dt[, 1]): how the axis's white acceleration (cv) or
        // acceleration change (ca) enters over one step; a constant's
        // random walk adds q dt
        double g[3] = {0.5 * dt * dt, dt, 1.0}, q = lin->accel_var[a];
        if (d == GF_NODE_AXIS_C) {
            A[k * n + k] = 1.0;
            R[k * n + k] = q * dt;
            k++;
            continue;
        }
        for (i = 0; i < d; i++) {
            // A block: 1, dt, dt^2/2 above the diagonal
            A[(k + i) * n + k + i] = 1.0;
            if (i + 1 < d) {
                A[(k + i) * n + k + i + 1] = dt;
            }
            if (i + 2 < d) {
                A[(k + i) * n + k + i + 2] = 0.5 * dt * dt;
            }
            // R block = q g g^T
            for (j = 0; j < d; j++) {
                R[(k + i) * n + k + j] = q * g[i] * g[j];
            }
        }
        k += d;
    }
}

void gf_node_linear_build(gf_node_linear *lin, double dt)
{
    unsigned a, n = 0;
    for (a = 0; a < lin->axes; a++) {
        n += lin->axis[a];
    }
    if (lin->axes == 0 || n > GF_NODE_NMAX) {
        return;
    }
    lin->n = n;
    memset(lin->A, 0, sizeof lin->A);
    memset(lin->R, 0, sizeof lin->R);
    gf_node_linear_motion(lin, dt, lin->A, lin->R);
}

const gf_node_sensor *gf_node_model_sensor(const gf_node_model *mdl,
                                           const char *name)
{
    unsigned i;
    if (mdl == NULL || mdl->sensors == NULL || name == NULL) {
        return NULL;
    }
    for (i = 0; i < mdl->sensors->count; i++) {
        if (strcmp(mdl->sensors->s[i].name, name) == 0) {
            return &mdl->sensors->s[i];
        }
    }
    return NULL;
}

// ---- the core's structs -----------------------------------------------------

void gf_node_model_car(const gf_node_model *mdl, gf_kf2_model *out)
{
    double dt = mdl->dt, q = mdl->accel_var;
    memset(out, 0, sizeof(*out));
    // A = ((1, dt), (0, 1)), B = I
    out->A.m[0][0] = GF_R(1.0);
    out->A.m[0][1] = (gf_real)dt;
    out->A.m[1][1] = GF_R(1.0);
    out->B.m[0][0] = GF_R(1.0);
    out->B.m[1][1] = GF_R(1.0);
    // R = q G G^T, G = (dt^2/2, dt)^T
    out->R.m[0][0] = (gf_real)(q * dt * dt * dt * dt / 4.0);
    out->R.m[0][1] = (gf_real)(q * dt * dt * dt / 2.0);
    out->R.m[1][0] = out->R.m[0][1];
    out->R.m[1][1] = (gf_real)(q * dt * dt);
}

void gf_node_model_car_meas(const gf_node_model *mdl, int measure,
                            const double q[3][3], gf_kf2_meas *out)
{
    unsigned i, j, m = gf_node_measure_m(GF_NODE_KIND_CAR, (int8_t)measure);
    memset(out, 0, sizeof(*out));
    out->m = m;
    if (measure == GF_NODE_MEASURE_V) {
        out->C.m[0][1] = GF_R(1.0); // C = (0, 1)
    } else {
        out->C.m[0][0] = GF_R(1.0); // C = (1, 0) or I
        out->C.m[1][1] = m == 2 ? GF_R(1.0) : GF_R(0.0);
    }
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++) {
            out->Q.m[i][j] = (gf_real)q[i][j];
        }
    }
    out->gate = (gf_real)mdl->gate;
}

void gf_node_model_robot(const gf_node_model *mdl, gf_real theta,
                         const gf_real u[2], gf_ekf3_motion *out)
{
    double d = (double)u[0], phi = (double)u[1];
    double c = cos((double)theta), s = sin((double)theta);
    const double *a = mdl->odometry;
    double vd = a[0] * d * d + a[1] * phi * phi;
    double vp = a[2] * d * d + a[3] * phi * phi;
    memset(out, 0, sizeof(*out));
    out->g = gf_ekf3_motion_forward_turn;
    // R = V diag(vd, vp) V^T, V = ((c, 0), (s, 0), (0, 1))
    out->R.m[0][0] = (gf_real)(c * c * vd);
    out->R.m[0][1] = (gf_real)(c * s * vd);
    out->R.m[1][0] = out->R.m[0][1];
    out->R.m[1][1] = (gf_real)(s * s * vd);
    out->R.m[2][2] = (gf_real)vp;
}

// z_hat = (r, b) of the landmark at ctx (double[2]) and H, rows first..
// first + m - 1 of ((-dx/r, -dy/r, 0), (dy/q, -dx/q, -1)); GF_ERR_MODEL on
// the landmark.
static gf_status landmark_meas(const double *lm, const gf_vec3 *mu_bar,
                               unsigned first, unsigned m, gf_vec3 *z_hat,
                               gf_mat3 *H)
{
    gf_real dx = (gf_real)lm[0] - mu_bar->v[0];
    gf_real dy = (gf_real)lm[1] - mu_bar->v[1];
    gf_real q = dx * dx + dy * dy, r;
    gf_real z[2], h[2][3];
    unsigned i, j;
    if (!(q > GF_R(0.0))) {
        return GF_ERR_MODEL;
    }
    r = GF_SQRT(q);
    // z_hat = (r, atan2(dy, dx) - theta)
    z[0] = r;
    z[1] = gf_angle_wrap(gf_atan2(dy, dx) - mu_bar->v[2]);
    h[0][0] = -dx / r;
    h[0][1] = -dy / r;
    h[0][2] = GF_R(0.0);
    h[1][0] = dy / q;
    h[1][1] = -dx / q;
    h[1][2] = GF_R(-1.0);
    for (i = 0; i < m; i++) {
        z_hat->v[i] = z[first + i];
        for (j = 0; j < 3; j++) {
            H->m[i][j] = h[first + i][j];
        }
    }
    for (i = m; i < 3; i++) {
        z_hat->v[i] = GF_R(0.0);
    }
    return GF_OK;
}

gf_status gf_node_meas_range_bearing(void *ctx, const gf_vec3 *mu_bar,
                                     gf_vec3 *z_hat, gf_mat3 *H)
{
    const gf_node_model *mdl = (const gf_node_model *)ctx;
    return landmark_meas(mdl->landmark, mu_bar, 0, 2, z_hat, H);
}

// The sensors' callbacks: ctx is the landmark (double[2]).
static gf_status meas_rb(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                         gf_mat3 *H)
{
    return landmark_meas((const double *)ctx, mu_bar, 0, 2, z_hat, H);
}

static gf_status meas_range(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    return landmark_meas((const double *)ctx, mu_bar, 0, 1, z_hat, H);
}

static gf_status meas_bearing(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                              gf_mat3 *H)
{
    return landmark_meas((const double *)ctx, mu_bar, 1, 1, z_hat, H);
}

// z_hat = theta, H = (0, 0, 1).
static gf_status meas_heading(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                              gf_mat3 *H)
{
    (void)ctx;
    z_hat->v[0] = mu_bar->v[2];
    z_hat->v[1] = GF_R(0.0);
    z_hat->v[2] = GF_R(0.0);
    H->m[0][0] = GF_R(0.0);
    H->m[0][1] = GF_R(0.0);
    H->m[0][2] = GF_R(1.0);
    return GF_OK;
}

// A robot's measurement of this measure: callback, angle mask, m; the
// landmark's for the callbacks that need one.
static void robot_meas(int measure, const double *landmark,
                       const double q[3][3], double gate, gf_ekf3_meas *out)
{
    unsigned i, j, m = gf_node_measure_m(GF_NODE_KIND_ROBOT, (int8_t)measure);
    memset(out, 0, sizeof(*out));
    out->m = m;
    out->ctx = (void *)(uintptr_t)landmark; // read only
    switch (measure) {
    case GF_NODE_MEASURE_RANGE_BEARING:
        out->h = meas_rb;
        out->angle_mask = 2u; // the bearing
        break;
    case GF_NODE_MEASURE_RANGE:
        out->h = meas_range;
        break;
    case GF_NODE_MEASURE_BEARING:
        out->h = meas_bearing;
        out->angle_mask = 1u;
        break;
    case GF_NODE_MEASURE_HEADING:
        out->h = meas_heading;
        out->angle_mask = 1u;
        break;
    default:
        out->h = m == 1 ? gf_ekf3_meas_x : gf_ekf3_meas_xy;
        out->ctx = NULL;
    }
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++) {
            out->Q.m[i][j] = (gf_real)q[i][j];
        }
    }
    out->gate = (gf_real)gate;
}

void gf_node_model_robot_meas(const gf_node_model *mdl, int measure,
                              const double q[3][3], gf_ekf3_meas *out)
{
    robot_meas(measure, mdl->landmark, q, mdl->gate, out);
    if (measure == GF_NODE_MEASURE_RANGE_BEARING) {
        // the public callback, on the model (see node_model.h)
        out->h = gf_node_meas_range_bearing;
        out->ctx = (void *)(uintptr_t)mdl;
    }
}

void gf_node_sensor_robot_meas(const gf_node_sensor *sen, const double q[3][3],
                               gf_ekf3_meas *out)
{
    robot_meas(sen->measure, sen->landmark, q, sen->gate, out);
}

// ---- the configuration file ---------------------------------------------
//
// Why this format: a model is a dozen named numbers and a pattern, and
// nothing nests; an INI-like "[model NAME]" + "key = value" file says that
// in a form every reader knows, and its parser is a page of C99 with no
// library to install. (Debian's parsers for richer formats, e.g. libyaml
// or json-c, would add a dependency and a build check to the node for
// features the models do not use.)

static char *trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r')) {
        *--e = '\0';
    }
    return s;
}

// Reads up to max numbers from s; returns how many, or -1 on junk.
static int numbers(const char *s, double *out, int max)
{
    int k = 0;
    char *end;
    for (;;) {
        while (*s == ' ' || *s == '\t') {
            s++;
        }
        if (*s == '\0') {
            return k;
        }
        if (k == max) {
            return -1;
        }
        errno = 0;
        out[k] = strtod(s, &end);
        if (end == s || errno == ERANGE) {
            return -1;
        }
        k++;
        s = end;
    }
}

// n x n matrix from n numbers (diagonal) or n*n (row by row).
static int matrix(const char *s, double a[3][3], unsigned n)
{
    double v[9];
    unsigned i, j;
    int k = numbers(s, v, 9);
    if (k != (int)n && k != (int)(n * n)) {
        return -1;
    }
    memset(a, 0, sizeof(double[3][3]));
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            a[i][j] = (unsigned)k == n ? (i == j ? v[i] : 0.0) : v[i * n + j];
        }
    }
    return 0;
}

static int words_are(const char *s, const char *want)
{
    // compares word by word, any blanks between
    for (;;) {
        while (*s == ' ' || *s == '\t') {
            s++;
        }
        while (*want == ' ') {
            want++;
        }
        if (*s == '\0' || *want == '\0') {
            return *s == '\0' && *want == '\0';
        }
        while (*s != '\0' && *s != ' ' && *s != '\t' && *s == *want) {
            s++;
            want++;
        }
        if ((*s != '\0' && *s != ' ' && *s != '\t') ||
            (*want != '\0' && *want != ' ')) {
            return 0;
        }
    }
}

static int measure_parse(const char *v, int8_t kind, int8_t *out)
{
    // what each kind of model can measure, by the words that name it
    static const struct {
        int8_t kind; // -1: any kind; ROBOT: any kind but CAR
        const char *words;
        int8_t measure;
    } names[] = {
        {-1, "auto", GF_NODE_MEASURE_AUTO},
        {GF_NODE_KIND_CAR, "position", GF_NODE_MEASURE_X},
        {GF_NODE_KIND_CAR, "velocity", GF_NODE_MEASURE_V},
        {GF_NODE_KIND_CAR, "position velocity", GF_NODE_MEASURE_XV},
        {GF_NODE_KIND_ROBOT, "x", GF_NODE_MEASURE_X},
        {GF_NODE_KIND_ROBOT, "x y", GF_NODE_MEASURE_XY},
        {GF_NODE_KIND_ROBOT, "range bearing", GF_NODE_MEASURE_RANGE_BEARING},
        {GF_NODE_KIND_ROBOT, "range", GF_NODE_MEASURE_RANGE},
        {GF_NODE_KIND_ROBOT, "bearing", GF_NODE_MEASURE_BEARING},
        {GF_NODE_KIND_ROBOT, "heading", GF_NODE_MEASURE_HEADING},
    };
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
        const int car = kind == GF_NODE_KIND_CAR;
        if ((names[i].kind < 0 || (names[i].kind == GF_NODE_KIND_CAR) == car) &&
            words_are(v, names[i].words)) {
            *out = names[i].measure;
            return 0;
        }
    }
    return -1;
}

static int fail(char *err, size_t size, unsigned line, const char *fmt, ...)
{
    va_list ap;
    int n = snprintf(err, size, "line %u: ", line);
    va_start(ap, fmt);
    if (n >= 0 && (size_t)n < size) {
        vsnprintf(err + n, size - (size_t)n, fmt, ap);
    }
    va_end(ap);
    return -1;
}

const gf_node_model *gf_node_config_find(const gf_node_config *cfg,
                                         const char *name)
{
    unsigned i;
    if (strcmp(name, book_car.name) == 0) {
        return &book_car;
    }
    if (strcmp(name, book_robot.name) == 0) {
        return &book_robot;
    }
    for (i = 0; cfg != NULL && i < cfg->count; i++) {
        if (strcmp(cfg->model[i].name, name) == 0) {
            return &cfg->model[i];
        }
    }
    return NULL;
}

// The section being read: where it starts and the line of each key it
// set, so that an error found at its end names the key's line.
#define SECTION_KEYS 32
typedef struct section {
    unsigned start;
    unsigned nkeys;
    char key[SECTION_KEYS][16];
    unsigned line[SECTION_KEYS];
} section;

static void key_seen(section *sec, const char *key, unsigned line)
{
    unsigned i;
    for (i = 0; i < sec->nkeys; i++) {
        if (strcmp(sec->key[i], key) == 0) {
            break;
        }
    }
    if (i == SECTION_KEYS) {
        return;
    }
    if (i == sec->nkeys) {
        snprintf(sec->key[i], sizeof sec->key[i], "%s", key);
        sec->nkeys++;
    }
    sec->line[i] = line;
}

// The line of a key this section set, 0 if none.
static unsigned key_line(const section *sec, const char *key, size_t len)
{
    unsigned i;
    for (i = 0; i < sec->nkeys; i++) {
        if (strlen(sec->key[i]) == len && strncmp(sec->key[i], key, len) == 0) {
            return sec->line[i];
        }
    }
    return 0;
}

// The line to blame for a model check's reason, which starts with the key
// at fault: that key's line, else (a key the model took from its base or
// preset) the base key's, else the section's header.
static unsigned blame(const section *sec, const char *why)
{
    size_t len = strcspn(why, " :");
    unsigned line = key_line(sec, why, len);
    if (line == 0 && len == 8 && strncmp(why, "meas_cov", 8) == 0) {
        line = key_line(sec, "Q", 1);
    }
    if (line == 0 && len == 1 && why[0] == 'Q') {
        line = key_line(sec, "meas_cov", 8);
    }
    if (line == 0 && len == 1 && (why[0] == 'A' || why[0] == 'R')) {
        line = key_line(sec, "motion", 6);
    }
    if (line == 0) {
        line = key_line(sec, "base", 4);
    }
    if (line == 0) {
        line = key_line(sec, "type", 4);
    }
    return line != 0 ? line : sec->start;
}

// A sensor of a model that checked out: 0, or -1 with the key at fault in
// why.
static int sensor_check(const gf_node_model *mdl, const gf_node_sensor *sen,
                        const char **why)
{
    unsigned i, j, m = sen->m;
    if (!(sen->gate >= 0.0) || !isfinite(sen->gate)) {
        *why = "gate must be finite and >= 0";
        return -1;
    }
    if (!(sen->rate >= 0.0) || !isfinite(sen->rate)) {
        *why = "rate must be finite and >= 0 (samples per second)";
        return -1;
    }
    if (!isfinite(sen->landmark[0]) || !isfinite(sen->landmark[1])) {
        *why = "landmark must be finite";
        return -1;
    }
    if (m == 0) {
        *why = mdl->kind == GF_NODE_KIND_LINEAR
                   ? "C: a sensor of a linear model gives C (m rows of n)"
                   : "measure: a robot's sensor gives its measure";
        return -1;
    }
    if ((sen->angle_mask >> m) != 0u) {
        *why = "angles: a row beyond the sensor's m";
        return -1;
    }
    if (mdl->kind == GF_NODE_KIND_LINEAR) {
        static gf_kf_work work;
        gf_kf_pmeas pq;
        gf_kf_meas mm;
        gf_real C[GF_NODE_NMAX * GF_NODE_NMAX], Q[GF_NODE_NMAX * GF_NODE_NMAX];
        for (i = 0; i < m * mdl->lin->n; i++) {
            C[i] = (gf_real)sen->C[i];
        }
        for (i = 0; i < m * m; i++) {
            Q[i] = (gf_real)sen->Q[i];
        }
        mm.m = m;
        mm.C = C;
        mm.Q = Q;
        mm.c = NULL;
        mm.gate = (gf_real)sen->gate;
        if (gf_kf_prepare_meas(&pq, mdl->lin->n, &mm, &work) != GF_OK) {
            *why = "Q must be symmetric positive semidefinite (and C finite)";
            return -1;
        }
        return 0;
    }
    {
        double q[3][3];
        memset(q, 0, sizeof q);
        for (i = 0; i < m; i++) {
            for (j = 0; j < m; j++) {
                q[i][j] = sen->Q[i * m + j];
            }
        }
        if (!psd((const double(*)[3])q, m)) {
            *why = "Q must be symmetric positive semidefinite";
            return -1;
        }
    }
    return 0;
}

// ---- generated models (type = generated) --------------------------------

static int sensor_name_ok(const char *name);

// The folder of the configuration file being read ("" for text: the
// working directory): a relative library path is taken from there.
static char config_dir[256];

// Loads the library of a generated model (library = PATH at line): its
// descriptor checked against this node (export version, precision, sizes,
// names), then n, the inputs and the sensors taken from it. The model's
// A is I and R 0 for the linear checks, which then check the prior and
// the sensors' noise; the track runs g and R(dt) (node_core.c).
static int generated_load(gf_node_config *cfg, gf_node_model *mdl,
                          gf_node_linear *lin, const char *path, unsigned line,
                          char *err, size_t size)
{
    size_t i = (size_t)(mdl - cfg->model);
    gf_node_generated *gen = &cfg->generated[i];
    gf_node_sensors *set = &cfg->sensors[i];
    const gf_codegen_export *ex;
    const gf_codegen_model *d;
    char full[512];
    const char *e;
    unsigned k, j;
    if (lin->gen != NULL) {
        return fail(err, size, line, "model %s: library given twice",
                    mdl->name);
    }
    if (strlen(path) >= sizeof gen->path) {
        return fail(err, size, line, "library: a path of at most %u characters",
                    (unsigned)sizeof gen->path - 1);
    }
    if (path[0] != '/') { // never dlopen's search of the system's folders
        snprintf(full, sizeof full, "%s/%s",
                 config_dir[0] != '\0' ? config_dir : ".", path);
    } else {
        snprintf(full, sizeof full, "%s", path);
    }
    memset(gen, 0, sizeof(*gen));
    strcpy(gen->path, path);
    (void)dlerror();
    gen->handle = dlopen(full, RTLD_NOW | RTLD_LOCAL);
    if (gen->handle == NULL) {
        e = dlerror();
        return fail(err, size, line, "model %s: library does not load: %s",
                    mdl->name, e != NULL ? e : full);
    }
    ex = (const gf_codegen_export *)dlsym(gen->handle, "gf_codegen_exported");
    if (ex == NULL) {
        return fail(err, size, line,
                    "model %s: library %s has no gf_codegen_exported (build "
                    "gaussfilt.codegen's C with -DGF_CODEGEN_EXPORT)",
                    mdl->name, full);
    }
    if (ex->version != GF_CODEGEN_EXPORT_VERSION || ex->model == NULL ||
        ex->model->version != 1u) {
        return fail(err, size, line,
                    "model %s: library %s: descriptor version %u (export %u), "
                    "this node reads 1 (export %u): generate it again",
                    mdl->name, full,
                    ex->model != NULL ? ex->model->version : 0u, ex->version,
                    GF_CODEGEN_EXPORT_VERSION);
    }
    if (ex->real_size != (unsigned)sizeof(gf_real)) {
        return fail(err, size, line,
                    "model %s: library %s is built with gf_real of %u bytes, "
                    "this node with %u (%s -DGF_SINGLE_PRECISION)",
                    mdl->name, full, ex->real_size, (unsigned)sizeof(gf_real),
                    sizeof(gf_real) == 4 ? "build it with"
                                         : "build it without");
    }
    d = ex->model;
    if (d->n < 1 || d->n > GF_NODE_NMAX || d->nu + 1u > GF_NODE_NMAX) {
        return fail(err, size, line,
                    "model %s: library %s: n = %u and %u inputs, this node "
                    "takes n = 1..%d and at most %d inputs",
                    mdl->name, full, d->n, d->nu, GF_NODE_NMAX,
                    GF_NODE_NMAX - 1);
    }
    if (d->nparams > GF_NODE_PARAMS) {
        return fail(err, size, line,
                    "model %s: library %s: %u parameters, this node takes at "
                    "most %d",
                    mdl->name, full, d->nparams, GF_NODE_PARAMS);
    }
    if (d->nsensors < 1 || d->nsensors > GF_NODE_SENSORS) {
        return fail(err, size, line,
                    "model %s: library %s: %u sensors, this node takes 1 to %d",
                    mdl->name, full, d->nsensors, GF_NODE_SENSORS);
    }
    if (d->g == NULL || d->R == NULL || d->states == NULL || d->units == NULL) {
        return fail(err, size, line, "model %s: library %s: no motion",
                    mdl->name, full);
    }
    for (k = 0; k < d->n; k++) {
        if (d->states[k] == NULL || d->units[k] == NULL) {
            return fail(err, size, line,
                        "model %s: library %s: state %u has no name", mdl->name,
                        full, k);
        }
    }
    set->count = d->nsensors;
    for (k = 0; k < d->nsensors; k++) {
        const gf_codegen_sensor *ds = &d->sensors[k];
        gf_node_sensor *sen = &set->s[k];
        if (ds->name == NULL || !sensor_name_ok(ds->name)) {
            return fail(err, size, line,
                        "model %s: library %s: sensor %u's name %s is not a "
                        "letter, then letters or digits, at most %d characters "
                        "(a channel GF_MEAS_<id>_<sensor>)",
                        mdl->name, full, k, ds->name != NULL ? ds->name : "",
                        GF_NODE_SENSOR_NAME - 1);
        }
        if (ds->m < 1 || ds->m > d->n || ds->h == NULL || ds->Q == NULL ||
            (ds->angle_mask >> ds->m) != 0u) {
            return fail(err, size, line,
                        "model %s: library %s: sensor %s has m = %u, n = %u "
                        "(m must be 1..n, with h and Q)",
                        mdl->name, full, ds->name, ds->m, d->n);
        }
        memset(sen, 0, sizeof(*sen));
        strcpy(sen->name, ds->name);
        sen->m = ds->m;
        sen->angle_mask = ds->angle_mask;
    }
    mdl->sensors = set;
    lin->n = d->n;
    lin->nu = d->nu;
    lin->m = 0;
    memset(lin->A, 0, sizeof lin->A);
    memset(lin->R, 0, sizeof lin->R);
    for (j = 0; j < d->n; j++) {
        lin->A[j * d->n + j] = 1.0;
    }
    gen->desc = d;
    lin->gen = gen;
    return 0;
}

// params = P ... of a generated model: one number per parameter.
static int generated_params(gf_node_model *mdl, gf_node_linear *lin,
                            gf_node_config *cfg, char *val, unsigned line,
                            char *err, size_t size)
{
    gf_node_generated *gen = &cfg->generated[mdl - cfg->model];
    const gf_codegen_model *d = lin->gen != NULL ? lin->gen->desc : NULL;
    double v[GF_NODE_PARAMS + 1];
    char names[256];
    int got;
    unsigned k;
    if (d == NULL) {
        return fail(err, size, line, "model %s: library before params",
                    mdl->name);
    }
    got = numbers(val, v, GF_NODE_PARAMS + 1);
    if (got != (int)d->nparams) {
        names[0] = '\0';
        for (k = 0; k < d->nparams && d->params != NULL; k++) {
            size_t len = strlen(names);
            snprintf(names + len, sizeof names - len, "%s%s", k > 0 ? " " : "",
                     d->params[k] != NULL ? d->params[k] : "?");
        }
        return fail(err, size, line,
                    "model %s: params takes %u number%s, its library's "
                    "parameters (%s) in order",
                    mdl->name, d->nparams, d->nparams == 1 ? "" : "s",
                    d->nparams > 0 ? names : "none");
    }
    for (k = 0; k < d->nparams; k++) {
        if (!isfinite(v[k])) {
            return fail(err, size, line, "model %s: params must be finite",
                        mdl->name);
        }
        gen->params[k] = (gf_real)v[k];
    }
    gen->has_params = 1;
    return 0;
}

// The end of a generated model's section: its library read, its params
// given (here or by its base), and each sensor's Q the library's unless
// the configuration gave one (a Q of zeros: none, as a message's q).
static int generated_finish(const gf_node_model *mdl, const gf_node_linear *lin,
                            gf_node_sensors *set, const section *sec, char *err,
                            size_t size)
{
    const gf_codegen_model *d = lin->gen != NULL ? lin->gen->desc : NULL;
    gf_real Q[GF_NODE_NMAX * GF_NODE_NMAX];
    unsigned k, j;
    if (d == NULL) {
        return fail(err, size, sec->start,
                    "model %s: a generated model needs library = PATH",
                    mdl->name);
    }
    if (d->nparams > 0 && !lin->gen->has_params) {
        return fail(err, size, sec->start,
                    "model %s: params = ... (%u numbers: its library's "
                    "parameters)",
                    mdl->name, d->nparams);
    }
    for (k = 0; k < set->count; k++) {
        gf_node_sensor *sen = &set->s[k];
        int given = 0;
        for (j = 0; j < sen->m * sen->m; j++) {
            given |= fabs(sen->Q[j]) > 0.0;
        }
        if (given) {
            continue;
        }
        d->sensors[k].Q(lin->gen->params, Q);
        for (j = 0; j < sen->m * sen->m; j++) {
            sen->Q[j] = (double)Q[j];
        }
    }
    return 0;
}

// Ends the section being read: builds a linear model's dt-built A and R,
// checks the model and compiles its pattern.
static int finish(gf_node_config *cfg, const section *sec, const section *ssec,
                  char *err, size_t size)
{
    unsigned i = cfg->count - 1;
    gf_node_model *mdl = &cfg->model[i];
    const char *why = NULL;
    char re[160];
    if (mdl->kind == GF_NODE_KIND_LINEAR && cfg->linear[i].generated) {
        if (generated_finish(mdl, &cfg->linear[i], &cfg->sensors[i], sec, err,
                             size) != 0) {
            return -1;
        }
    } else if (mdl->kind == GF_NODE_KIND_LINEAR) {
        gf_node_linear *lin = &cfg->linear[i];
        if (key_line(sec, "A", 1) && key_line(sec, "motion", 6)) {
            return fail(err, size, key_line(sec, "A", 1),
                        "model %s: A or motion, not both", mdl->name);
        }
        if (key_line(sec, "R", 1) && key_line(sec, "accel_var", 9)) {
            return fail(err, size, key_line(sec, "R", 1),
                        "model %s: R or accel_var, not both", mdl->name);
        }
        gf_node_linear_build(lin, mdl->dt);
    }
    if (gf_node_model_check(mdl, &why) != 0) {
        return fail(err, size, blame(sec, why), "model %s: %s", mdl->name, why);
    }
    for (unsigned k = 0; mdl->sensors != NULL && k < mdl->sensors->count; k++) {
        const gf_node_sensor *sen = &mdl->sensors->s[k];
        if (sensor_check(mdl, sen, &why) != 0) {
            return fail(err, size, blame(&ssec[k], why),
                        "model %s: sensor %s: %s", mdl->name, sen->name, why);
        }
    }
    if (cfg->channels[i][0] != '\0') {
        snprintf(re, sizeof re, "^(%s)$", cfg->channels[i]);
        if (regcomp(&cfg->regex[i], re, REG_EXTENDED | REG_NOSUB) != 0) {
            return fail(err, size, key_line(sec, "channels", 8),
                        "model %s: bad channels regex %s", mdl->name,
                        cfg->channels[i]);
        }
        cfg->has_regex[i] = 1;
        mdl->channels = cfg->channels[i];
    } else {
        mdl->channels = NULL;
    }
    return 0;
}

// Reads numbers as numbers() does, a ';' allowed between them (the end of
// a matrix's row, for the reader: not checked).
static int numbers_rows(char *s, double *out, int max)
{
    char *p;
    for (p = s; *p != '\0'; p++) {
        if (*p == ';') {
            *p = ' ';
        }
    }
    return numbers(s, out, max);
}

// A square k x k matrix (row-major, rows of k) from k numbers (its
// diagonal) or k*k.
static int square(char *s, double *a, unsigned k)
{
    double v[GF_NODE_NMAX * GF_NODE_NMAX];
    unsigned i, j;
    int got = numbers_rows(s, v, GF_NODE_NMAX * GF_NODE_NMAX);
    if (k == 0 || (got != (int)k && got != (int)(k * k))) {
        return -1;
    }
    for (i = 0; i < k; i++) {
        for (j = 0; j < k; j++) {
            a[i * k + j] =
                (unsigned)got == k ? (i == j ? v[i] : 0.0) : v[i * k + j];
        }
    }
    return 0;
}

// Rows of n numbers: returns how many rows (1..max_rows), or -1.
static int rows_of(char *s, double *a, unsigned n, unsigned max_rows)
{
    int got = numbers_rows(s, a, GF_NODE_NMAX * GF_NODE_NMAX);
    if (n == 0 || got <= 0 || got % (int)n != 0 ||
        (unsigned)got / n > max_rows) {
        return -1;
    }
    return got / (int)n;
}

// The linear model's keys (see node_model.h). Returns 0, 1 if key is not
// one of them, or -1 with the error.
// states = NAME ... and units = UNIT ...: one word per state, read by the
// tools that draw a track (scripts/plot, examples/beliefs.py); the node
// only checks that there are n of them.
static int state_words(const gf_node_model *mdl, const gf_node_linear *lin,
                       const char *key, const char *val, unsigned line,
                       char *err, size_t size)
{
    unsigned n = mdl->kind == GF_NODE_KIND_CAR     ? 2u
                 : mdl->kind == GF_NODE_KIND_ROBOT ? 3u
                                                   : lin->n;
    unsigned words = 0;
    const char *p = val;
    if (n == 0) {
        return fail(err, size, line, "model %s: n or motion before %s",
                    mdl->name, key);
    }
    while (*p != '\0') {
        if (*p == ' ' || *p == '\t') {
            p++;
            continue;
        }
        words++;
        while (*p != '\0' && *p != ' ' && *p != '\t') {
            p++;
        }
    }
    if (words != n) {
        return fail(err, size, line,
                    "model %s: %s takes %u words, one per state", mdl->name,
                    key, n);
    }
    return 0;
}

static int linear_key(gf_node_model *mdl, gf_node_linear *lin, const char *key,
                      char *val, unsigned line, char *err, size_t size)
{
    unsigned n = lin->n;
    if (strcmp(key, "n") == 0 || strcmp(key, "motion") == 0) {
        unsigned axes = 0, states = 0;
        unsigned char axis[GF_NODE_NMAX];
        if (key[0] == 'n') {
            char *end;
            long v;
            errno = 0;
            v = strtol(val, &end, 10);
            if (end == val || *trim(end) != '\0' || v < 1 || v > GF_NODE_NMAX) {
                return fail(err, size, line, "n takes a number 1..%d",
                            GF_NODE_NMAX);
            }
            states = (unsigned)v;
        } else {
            char *w = strtok(val, " \t");
            for (; w != NULL; w = strtok(NULL, " \t")) {
                unsigned d = strcmp(w, "cv") == 0   ? GF_NODE_AXIS_CV
                             : strcmp(w, "ca") == 0 ? GF_NODE_AXIS_CA
                             : strcmp(w, "c") == 0  ? GF_NODE_AXIS_C
                                                    : 0;
                if (d == 0) {
                    return fail(err, size, line,
                                "motion takes axes: cv (position, velocity), "
                                "ca (position, velocity, acceleration) or c "
                                "(a constant)");
                }
                if (states + d > GF_NODE_NMAX) {
                    return fail(err, size, line, "motion: more than %d states",
                                GF_NODE_NMAX);
                }
                axis[axes++] = (unsigned char)d;
                states += d;
            }
            if (axes == 0) {
                return fail(err, size, line, "motion takes axes: cv or ca");
            }
        }
        // a new size: everything sized by n starts again
        memset(lin, 0, sizeof(*lin));
        lin->n = states;
        for (unsigned i = 0; i < states; i++) {
            lin->A[i * states + i] = 1.0;
        }
        lin->axes = axes;
        memcpy(lin->axis, axis, axes);
        return 0;
    }
    if (strcmp(key, "accel_var") == 0) {
        int got;
        if (lin->axes == 0) {
            return fail(err, size, line, "accel_var needs motion first");
        }
        got = numbers(val, lin->accel_var, GF_NODE_NMAX);
        if (got == 1) {
            for (unsigned a = 1; a < lin->axes; a++) {
                lin->accel_var[a] = lin->accel_var[0];
            }
        } else if (got != (int)lin->axes) {
            return fail(err, size, line,
                        "accel_var takes 1 number or one per axis (%u)",
                        lin->axes);
        }
        for (unsigned a = 0; a < lin->axes; a++) {
            if (!(lin->accel_var[a] >= 0.0) || !isfinite(lin->accel_var[a])) {
                return fail(err, size, line,
                            "accel_var must be finite and >= 0");
            }
        }
        return 0;
    }
    if (strcmp(key, "dt") == 0) {
        if (numbers(val, &mdl->dt, 1) != 1) {
            return fail(err, size, line, "dt takes 1 number");
        }
        return 0;
    }
    if (strcmp(key, "gate") == 0) {
        if (numbers(val, &mdl->gate, 1) != 1) {
            return fail(err, size, line, "gate takes 1 number");
        }
        return 0;
    }
    if (strcmp(key, "A") != 0 && strcmp(key, "B") != 0 &&
        strcmp(key, "R") != 0 && strcmp(key, "C") != 0 &&
        strcmp(key, "Q") != 0 && strcmp(key, "meas_cov") != 0 &&
        strcmp(key, "prior_mean") != 0 && strcmp(key, "prior_cov") != 0) {
        return 1;
    }
    if (n == 0) {
        return fail(err, size, line, "n (or motion) first");
    }
    if (strcmp(key, "A") == 0) {
        if (numbers_rows(val, lin->A, GF_NODE_NMAX * GF_NODE_NMAX) !=
            (int)(n * n)) {
            return fail(err, size, line, "A takes %u numbers (n = %u)", n * n,
                        n);
        }
        lin->axes = 0; // as given, not built from dt
    } else if (strcmp(key, "B") == 0) {
        double b[GF_NODE_NMAX * GF_NODE_NMAX];
        int nu = rows_of(val, b, n, GF_NODE_NMAX);
        unsigned i, j;
        if (nu < 0) {
            return fail(err, size, line,
                        "B takes n*nu numbers (n = %u rows of nu controls)", n);
        }
        // read as n rows of nu (the numbers were counted in rows of n)
        lin->nu = (unsigned)nu;
        for (i = 0; i < n; i++) {
            for (j = 0; j < lin->nu; j++) {
                lin->B[i * lin->nu + j] = b[i * lin->nu + j];
            }
        }
    } else if (strcmp(key, "R") == 0) {
        if (square(val, lin->R, n) != 0) {
            return fail(err, size, line, "R takes %u or %u numbers", n, n * n);
        }
    } else if (strcmp(key, "C") == 0) {
        int m = rows_of(val, lin->C, n, n);
        if (m < 0) {
            return fail(err, size, line,
                        "C takes m*n numbers, one row of n = %u per measured "
                        "quantity (m <= n)",
                        n);
        }
        if ((unsigned)m != lin->m) {
            memset(lin->Q, 0, sizeof lin->Q);
        }
        lin->m = (unsigned)m;
    } else if (strcmp(key, "prior_mean") == 0) {
        if (numbers(val, lin->prior_mean, GF_NODE_NMAX) != (int)n) {
            return fail(err, size, line, "prior_mean takes %u numbers", n);
        }
    } else if (strcmp(key, "prior_cov") == 0) {
        if (square(val, lin->prior_cov, n) != 0) {
            return fail(err, size, line, "prior_cov takes %u or %u numbers", n,
                        n * n);
        }
    } else { // Q, meas_cov
        if (lin->m == 0) {
            return fail(err, size, line, "%s after C (its rows give m)", key);
        }
        if (square(val, lin->Q, lin->m) != 0) {
            return fail(err, size, line, "%s takes %u or %u numbers (m = %u)",
                        key, lin->m, lin->m * lin->m, lin->m);
        }
    }
    return 0;
}

// A sensor section's keys (see node_model.h): 0, or -1 with the error.
static int sensor_key(const gf_node_model *mdl, gf_node_sensor *sen,
                      const char *key, char *val, unsigned line, char *err,
                      size_t size)
{
    const int linear = mdl->kind == GF_NODE_KIND_LINEAR;
    unsigned n = linear ? mdl->lin->n : 3u;
    if (linear && mdl->lin->generated &&
        (strcmp(key, "C") == 0 || strcmp(key, "measure") == 0 ||
         strcmp(key, "landmark") == 0)) {
        return fail(err, size, line,
                    "a sensor of a generated model has no %s (its library "
                    "gives h); it takes Q, gate, angles and rate",
                    key);
    }
    if (strcmp(key, "C") == 0 && linear) {
        int m = rows_of(val, sen->C, n, n);
        if (m < 0) {
            return fail(err, size, line,
                        "C takes m*n numbers, one row of n = %u per measured "
                        "quantity (m <= n)",
                        n);
        }
        if ((unsigned)m != sen->m) {
            memset(sen->Q, 0, sizeof sen->Q);
        }
        sen->m = (unsigned)m;
    } else if (strcmp(key, "measure") == 0 && !linear) {
        int8_t measure = 0;
        if (measure_parse(val, GF_NODE_KIND_ROBOT, &measure) != 0 ||
            measure == GF_NODE_MEASURE_AUTO) {
            return fail(err, size, line,
                        "a robot's sensor measures x, x y, range bearing, "
                        "range, bearing or heading");
        }
        sen->measure = measure;
        sen->m = gf_node_measure_m(GF_NODE_KIND_ROBOT, measure);
        memset(sen->Q, 0, sizeof sen->Q);
        sen->angle_mask = measure == GF_NODE_MEASURE_RANGE_BEARING ? 2u
                          : measure == GF_NODE_MEASURE_BEARING ||
                                  measure == GF_NODE_MEASURE_HEADING
                              ? 1u
                              : 0u;
    } else if (strcmp(key, "Q") == 0 || strcmp(key, "meas_cov") == 0) {
        if (sen->m == 0) {
            return fail(err, size, line, "%s after %s (it gives m)", key,
                        linear ? "C" : "measure");
        }
        if (square(val, sen->Q, sen->m) != 0) {
            return fail(err, size, line, "%s takes %u or %u numbers (m = %u)",
                        key, sen->m, sen->m * sen->m, sen->m);
        }
    } else if (linear &&
               (strcmp(key, "measure") == 0 || strcmp(key, "landmark") == 0)) {
        // the built-in nonlinear measures know where a robot's x, y and
        // theta are; a linear model's states have no such names
        return fail(err, size, line,
                    "a sensor of a linear model has no %s: it measures C x "
                    "(range, bearing and heading are a robot model's "
                    "sensors)",
                    key);
    } else if (strcmp(key, "landmark") == 0 && !linear) {
        if (numbers(val, sen->landmark, 2) != 2) {
            return fail(err, size, line, "landmark takes 2 numbers");
        }
    } else if (strcmp(key, "gate") == 0 || strcmp(key, "rate") == 0) {
        if (numbers(val, key[0] == 'g' ? &sen->gate : &sen->rate, 1) != 1) {
            return fail(err, size, line, "%s takes 1 number", key);
        }
    } else if (strcmp(key, "angles") == 0) {
        double v[GF_NODE_NMAX];
        int k = numbers(val, v, GF_NODE_NMAX);
        sen->angle_mask = 0;
        for (int i = 0; i < k; i++) {
            if (!(v[i] >= 0.0 && v[i] < (double)GF_NODE_NMAX) ||
                v[i] - floor(v[i]) > 0.0) {
                k = -1;
                break;
            }
            sen->angle_mask |= 1u << (unsigned)v[i];
        }
        if (k < 0) {
            return fail(err, size, line,
                        "angles takes the rows (from 0) whose residual is an "
                        "angle");
        }
    } else {
        return fail(err, size, line, "a sensor of a %s model has no %s",
                    linear ? "linear" : "robot", key);
    }
    return 0;
}

// A sensor's name: [A-Za-z][A-Za-z0-9]*, shorter than GF_NODE_SENSOR_NAME.
static int sensor_name_ok(const char *name)
{
    size_t i, len = strlen(name);
    if (len == 0 || len >= GF_NODE_SENSOR_NAME ||
        !((name[0] >= 'a' && name[0] <= 'z') ||
          (name[0] >= 'A' && name[0] <= 'Z'))) {
        return 0;
    }
    for (i = 1; i < len; i++) {
        char c = name[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
              (c >= '0' && c <= '9'))) {
            return 0;
        }
    }
    return 1;
}

static int parse(gf_node_config *cfg, const char *text, char *err,
                 size_t err_size);

int gf_node_config_parse(gf_node_config *cfg, const char *text, char *err,
                         size_t err_size)
{
    int rc = parse(cfg, text, err, err_size);
    if (rc != 0) {
        gf_node_config_free(cfg); // the libraries it opened
    }
    return rc;
}

static int parse(gf_node_config *cfg, const char *text, char *err,
                 size_t err_size)
{
    char buf[4096];
    unsigned line = 0;
    section sec, ssec[GF_NODE_SENSORS];
    gf_node_model *mdl = NULL;
    gf_node_linear *lin = NULL;
    gf_node_sensor *sen = NULL; // the sensor section being read, if any
    // per model: the line of its [model NAME], and whether a later model
    // takes it as its base
    unsigned start[GF_NODE_CONFIG_MODELS], im;
    int based[GF_NODE_CONFIG_MODELS];
    memset(based, 0, sizeof based);
    memset(cfg, 0, sizeof(*cfg));
    memset(&sec, 0, sizeof(sec));
    memset(ssec, 0, sizeof(ssec));
    if (err_size > 0) {
        err[0] = '\0';
    }
    while (*text != '\0') {
        size_t len = strcspn(text, "\n");
        char *s, *eq, *key, *val;
        line++;
        if (len >= sizeof buf) {
            return fail(err, err_size, line, "longer than %u characters",
                        (unsigned)sizeof buf - 1);
        }
        memcpy(buf, text, len);
        buf[len] = '\0';
        text += len + (text[len] == '\n');
        s = strchr(buf, '#');
        if (s != NULL) {
            *s = '\0';
        }
        s = trim(buf);
        if (*s == '\0') {
            continue;
        }
        if (*s == '[') {
            char name[64];
            char *close = strchr(s, ']');
            if (close == NULL || trim(close + 1)[0] != '\0') {
                return fail(err, err_size, line, "expected [model NAME]");
            }
            *close = '\0';
            if (sscanf(s + 1, " sensor %63s", name) == 1) {
                size_t i = mdl != NULL ? (size_t)(mdl - cfg->model) : 0u;
                gf_node_sensors *set = &cfg->sensors[i];
                if (mdl == NULL || (mdl->kind != GF_NODE_KIND_LINEAR &&
                                    mdl->kind != GF_NODE_KIND_ROBOT)) {
                    return fail(err, err_size, line,
                                "[sensor %s] belongs to a linear or robot "
                                "model: after its [model NAME] and keys",
                                name);
                }
                if (lin->generated) {
                    // one of its library's sensors, configured
                    const gf_node_sensor *got = gf_node_model_sensor(mdl, name);
                    if (got == NULL) {
                        char names[160] = "";
                        for (unsigned k = 0;
                             mdl->sensors != NULL && k < mdl->sensors->count;
                             k++) {
                            size_t used = strlen(names);
                            snprintf(names + used, sizeof names - used, "%s%s",
                                     k > 0 ? " " : "", mdl->sensors->s[k].name);
                        }
                        return fail(err, err_size, line,
                                    "model %s: its library has no sensor %s "
                                    "(it has: %s)",
                                    mdl->name, name,
                                    names[0] != '\0' ? names
                                                     : "none: library first");
                    }
                    sen = &set->s[got - set->s];
                    if (ssec[got - set->s].start != 0) {
                        return fail(err, err_size, line,
                                    "model %s: sensor %s configured twice",
                                    mdl->name, name);
                    }
                    ssec[got - set->s].start = line;
                    continue;
                }
                if (!sensor_name_ok(name)) {
                    return fail(err, err_size, line,
                                "a sensor's name is a letter, then letters "
                                "or digits, at most %d characters",
                                GF_NODE_SENSOR_NAME - 1);
                }
                if (gf_node_model_sensor(mdl, name) != NULL) {
                    return fail(err, err_size, line,
                                "model %s: sensor %s defined twice", mdl->name,
                                name);
                }
                if (set->count == GF_NODE_SENSORS) {
                    return fail(err, err_size, line,
                                "model %s: more than %d sensors", mdl->name,
                                GF_NODE_SENSORS);
                }
                mdl->sensors = set;
                memset(&ssec[set->count], 0, sizeof ssec[0]);
                ssec[set->count].start = line;
                sen = &set->s[set->count++];
                memset(sen, 0, sizeof(*sen));
                strcpy(sen->name, name);
                continue;
            }
            if (sscanf(s + 1, " model %63s", name) != 1 ||
                strlen(name) >= GF_NODE_MODEL_NAME) {
                return fail(err, err_size, line,
                            "expected [model NAME] (a name of at most %d "
                            "characters) or [sensor NAME]",
                            GF_NODE_MODEL_NAME - 1);
            }
            if (mdl != NULL && finish(cfg, &sec, ssec, err, err_size) != 0) {
                return -1;
            }
            sen = NULL;
            if (gf_node_config_find(cfg, name) != NULL) {
                return fail(err, err_size, line, "model %s defined twice",
                            name);
            }
            if (cfg->count == GF_NODE_CONFIG_MODELS) {
                return fail(err, err_size, line, "more than %d models",
                            GF_NODE_CONFIG_MODELS);
            }
            lin = &cfg->linear[cfg->count];
            mdl = &cfg->model[cfg->count++];
            memset(mdl, 0, sizeof(*mdl));
            memset(lin, 0, sizeof(*lin));
            strcpy(mdl->name, name);
            mdl->late_window = GF_NODE_LATE_WINDOW;
            memset(&sec, 0, sizeof(sec));
            memset(ssec, 0, sizeof(ssec));
            sec.start = line;
            start[cfg->count - 1] = line;
            continue;
        }
        eq = strchr(s, '=');
        if (eq == NULL) {
            return fail(err, err_size, line, "expected key = value");
        }
        if (mdl == NULL) {
            return fail(err, err_size, line,
                        "a key before the first [model NAME]");
        }
        *eq = '\0';
        key = trim(s);
        val = trim(eq + 1);
        if (sen != NULL) {
            key_seen(&ssec[sen - mdl->sensors->s], key, line);
            if (sensor_key(mdl, sen, key, val, line, err, err_size) != 0) {
                return -1;
            }
            continue;
        }
        key_seen(&sec, key, line);
        if (strcmp(key, "base") == 0) {
            const gf_node_model *b = gf_node_config_find(cfg, val);
            char name[GF_NODE_MODEL_NAME];
            if (b == NULL || b == mdl) {
                return fail(err, err_size, line, "no model %s before this",
                            val);
            }
            if (b >= cfg->model && b < mdl) {
                based[b - cfg->model] = 1;
            }
            memcpy(name, mdl->name, sizeof name);
            *mdl = *b;
            memcpy(mdl->name, name, sizeof name);
            if (b->lin != NULL) {
                *lin = *b->lin;
                mdl->lin = lin;
            }
            if (b->sensors != NULL) { // its sensors too, as its own
                size_t i = (size_t)(mdl - cfg->model);
                cfg->sensors[i] = *b->sensors;
                mdl->sensors = &cfg->sensors[i];
            }
            if (b->lin != NULL && b->lin->gen != NULL) {
                // its library's descriptor and params, the library kept
                // open (and closed) by the base
                size_t i = (size_t)(mdl - cfg->model);
                cfg->generated[i] = *b->lin->gen;
                cfg->generated[i].handle = NULL;
                lin->gen = &cfg->generated[i];
            }
        } else if (strcmp(key, "type") == 0) {
            int generated = strcmp(val, "generated") == 0;
            int8_t kind = strcmp(val, "car") == 0      ? GF_NODE_KIND_CAR
                          : strcmp(val, "robot") == 0  ? GF_NODE_KIND_ROBOT
                          : strcmp(val, "linear") == 0 ? GF_NODE_KIND_LINEAR
                          : generated                  ? GF_NODE_KIND_LINEAR
                                                       : 0;
            if (kind == 0) {
                return fail(err, err_size, line,
                            "type is car, robot, linear or generated");
            }
            if (mdl->kind == kind && lin->generated != generated) {
                return fail(err, err_size, line,
                            "model %s: type %s after the type of its base",
                            mdl->name, val);
            }
            if (mdl->kind != kind) {
                // a type of its own starts from that type's preset (a
                // linear model from nothing: n or motion next)
                char name[GF_NODE_MODEL_NAME];
                memcpy(name, mdl->name, sizeof name);
                if (kind == GF_NODE_KIND_LINEAR) {
                    memset(mdl, 0, sizeof(*mdl));
                    memset(lin, 0, sizeof(*lin));
                    mdl->kind = kind;
                    mdl->dt = 1.0;
                    mdl->lin = lin;
                    lin->generated = generated;
                    mdl->late_window = GF_NODE_LATE_WINDOW;
                } else {
                    *mdl = kind == GF_NODE_KIND_CAR ? book_car : book_robot;
                }
                memcpy(mdl->name, name, sizeof name);
            }
        } else if (mdl->kind == 0) {
            return fail(err, err_size, line, "type or base first");
        } else if (strcmp(key, "channels") == 0) {
            size_t i = (size_t)(mdl - cfg->model);
            if (strlen(val) >= sizeof cfg->channels[0]) {
                return fail(err, err_size, line, "channels regex too long");
            }
            strcpy(cfg->channels[i], val);
        } else if (mdl->kind == GF_NODE_KIND_LINEAR && lin->generated &&
                   strcmp(key, "library") == 0) {
            if (generated_load(cfg, mdl, lin, val, line, err, err_size) != 0) {
                return -1;
            }
        } else if (mdl->kind == GF_NODE_KIND_LINEAR && lin->generated &&
                   strcmp(key, "params") == 0) {
            if (generated_params(mdl, lin, cfg, val, line, err, err_size) !=
                0) {
                return -1;
            }
        } else if (mdl->kind == GF_NODE_KIND_LINEAR && lin->generated &&
                   strcmp(key, "prior_mean") != 0 &&
                   strcmp(key, "prior_cov") != 0 && strcmp(key, "gate") != 0 &&
                   strcmp(key, "late_window") != 0 && strcmp(key, "dt") != 0) {
            return fail(err, err_size, line,
                        "a generated model has no %s (its library gives the "
                        "states, the motion and the sensors)",
                        key);
        } else if (mdl->kind == GF_NODE_KIND_LINEAR && lin->generated &&
                   lin->gen == NULL) {
            return fail(err, err_size, line, "model %s: library before %s",
                        mdl->name, key);
        } else if (strcmp(key, "states") == 0 || strcmp(key, "units") == 0) {
            if (state_words(mdl, lin, key, val, line, err, err_size) != 0) {
                return -1;
            }
        } else if (strcmp(key, "late_window") == 0) {
            if (numbers(val, &mdl->late_window, 1) != 1) {
                return fail(err, err_size, line, "late_window takes 1 number");
            }
        } else if (mdl->kind == GF_NODE_KIND_LINEAR) {
            int r = linear_key(mdl, lin, key, val, line, err, err_size);
            if (r < 0) {
                return -1;
            }
            if (r > 0) {
                return fail(err, err_size, line, "a linear model has no %s",
                            key);
            }
        } else if (strcmp(key, "measure") == 0) {
            if (measure_parse(val, mdl->kind, &mdl->measure) != 0) {
                return fail(err, err_size, line,
                            mdl->kind == GF_NODE_KIND_CAR
                                ? "a car measures position, velocity or "
                                  "position velocity"
                                : "a robot measures x, x y, range bearing, "
                                  "range, bearing or heading");
            }
        } else {
            struct {
                const char *key;
                double *v;
                int n, car, robot;
            } one[] = {
                {"dt", &mdl->dt, 1, 1, 0},
                {"accel_var", &mdl->accel_var, 1, 1, 0},
                {"gate", &mdl->gate, 1, 1, 1},
                {"odometry", mdl->odometry, 4, 0, 1},
                {"landmark", mdl->landmark, 2, 0, 1},
                {"prior_mean", mdl->prior_mean, 3, 1, 1},
            };
            unsigned k, n = mdl->kind == GF_NODE_KIND_CAR ? 2u : 3u;
            int done = 0;
            for (k = 0; k < sizeof one / sizeof one[0]; k++) {
                int want;
                if (strcmp(key, one[k].key) != 0) {
                    continue;
                }
                if (!(mdl->kind == GF_NODE_KIND_CAR ? one[k].car
                                                    : one[k].robot)) {
                    return fail(err, err_size, line, "a %s has no %s",
                                mdl->kind == GF_NODE_KIND_CAR ? "car" : "robot",
                                key);
                }
                want = one[k].v == mdl->prior_mean ? (int)n : one[k].n;
                if (numbers(val, one[k].v, want) != want) {
                    return fail(err, err_size, line, "%s takes %d number%s",
                                key, want, want == 1 ? "" : "s");
                }
                done = 1;
            }
            if (!done && strcmp(key, "prior_cov") == 0) {
                if (matrix(val, mdl->prior_cov, n) != 0) {
                    return fail(err, err_size, line,
                                "prior_cov takes %u or %u numbers", n, n * n);
                }
                done = 1;
            }
            if (!done && strcmp(key, "meas_cov") == 0) {
                unsigned m = gf_node_measure_m(mdl->kind, mdl->measure);
                if (m == 0 || matrix(val, mdl->meas_cov, m) != 0) {
                    return fail(err, err_size, line,
                                "meas_cov takes %u or %u numbers (after "
                                "measure)",
                                m, m * m);
                }
                done = 1;
            }
            if (!done) {
                return fail(err, err_size, line, "unknown key %s", key);
            }
        }
    }
    if (mdl != NULL && finish(cfg, &sec, ssec, err, err_size) != 0) {
        return -1;
    }
    // A linear model no channels pattern names could run no track (there is
    // no linear preset), unless it is a base of others.
    for (im = 0; im < cfg->count; im++) {
        if (cfg->model[im].kind == GF_NODE_KIND_LINEAR &&
            cfg->model[im].channels == NULL && !based[im]) {
            return fail(err, err_size, start[im],
                        "model %s: a linear model needs channels (the tracks "
                        "that run it: no preset stands in for a linear "
                        "track), or another model taking it as its base",
                        cfg->model[im].name);
        }
    }
    return 0;
}

int gf_node_config_load(gf_node_config *cfg, const char *path, char *err,
                        size_t err_size)
{
    static char text[65536];
    size_t n;
    FILE *f = fopen(path, "r");
    int rc;
    if (f == NULL) {
        snprintf(err, err_size, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    n = fread(text, 1, sizeof text - 1, f);
    if (n == sizeof text - 1 && fgetc(f) != EOF) {
        fclose(f);
        snprintf(err, err_size, "%s: longer than %u bytes", path,
                 (unsigned)sizeof text - 1);
        return -1;
    }
    fclose(f);
    text[n] = '\0';
    {
        const char *slash = strrchr(path, '/');
        size_t len = slash != NULL ? (size_t)(slash - path) : 0u;
        if (slash == path) {
            len = 1; // the root
        }
        if (slash != NULL && len < sizeof config_dir) {
            memcpy(config_dir, path, len);
            config_dir[len] = '\0';
        } else {
            config_dir[0] = '\0';
        }
    }
    rc = gf_node_config_parse(cfg, text, err, err_size);
    config_dir[0] = '\0';
    if (rc != 0) {
        char where[512];
        snprintf(where, sizeof where, "%s", err);
        snprintf(err, err_size, "%s: %s", path, where);
    }
    return rc;
}

void gf_node_config_free(gf_node_config *cfg)
{
    unsigned i;
    for (i = 0; i < cfg->count; i++) {
        if (cfg->has_regex[i]) {
            regfree(&cfg->regex[i]);
        }
    }
    for (i = 0; i < cfg->count; i++) {
        if (cfg->generated[i].handle != NULL) {
            (void)dlclose(cfg->generated[i].handle);
        }
    }
    memset(cfg, 0, sizeof(*cfg));
}

const gf_node_model *gf_node_config_named(const gf_node_config *cfg, int32_t id,
                                          int8_t kind)
{
    char meas[GF_CHANNEL_MAX], ctrl[GF_CHANNEL_MAX];
    unsigned i;
    snprintf(meas, sizeof meas, "%s%ld", GF_CHANNEL_MEAS, (long)id);
    snprintf(ctrl, sizeof ctrl, "%s%ld", GF_CHANNEL_CTRL, (long)id);
    for (i = 0; cfg != NULL && i < cfg->count; i++) {
        if (cfg->has_regex[i] && cfg->model[i].kind == kind &&
            (regexec(&cfg->regex[i], meas, 0, NULL, 0) == 0 ||
             regexec(&cfg->regex[i], ctrl, 0, NULL, 0) == 0)) {
            return &cfg->model[i];
        }
    }
    return NULL;
}

const gf_node_model *gf_node_config_lookup(const gf_node_config *cfg,
                                           int32_t id, int8_t kind)
{
    const gf_node_model *m = gf_node_config_named(cfg, id, kind);
    if (m != NULL) {
        return m;
    }
    if (kind == GF_NODE_KIND_CAR) {
        return &book_car;
    }
    return kind == GF_NODE_KIND_ROBOT ? &book_robot : NULL;
}
