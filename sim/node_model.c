// SPDX-License-Identifier: MIT
// gaussfilt sim: track models as data and the configuration file (see
// node_model.h). This builds the core's model structs from numbers and
// holds the range-bearing measurement callback; every filter step stays in
// the core.
#include "node_model.h"

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
        if (measure == GF_NODE_MEASURE_X || measure == GF_NODE_MEASURE_V)
            return 1;
        return measure == GF_NODE_MEASURE_XV ? 2u : 0u;
    }
    if (kind == GF_NODE_KIND_ROBOT) {
        if (measure == GF_NODE_MEASURE_X)
            return 1;
        if (measure == GF_NODE_MEASURE_XY ||
            measure == GF_NODE_MEASURE_RANGE_BEARING)
            return 2;
    }
    return 0;
}

int gf_node_model_measure(const gf_node_model *mdl, unsigned m)
{
    int measure = mdl->measure;
    if (measure == GF_NODE_MEASURE_AUTO)
        measure = m == 1                          ? GF_NODE_MEASURE_X
                  : m != 2                        ? -1
                  : mdl->kind == GF_NODE_KIND_CAR ? GF_NODE_MEASURE_XV
                                                  : GF_NODE_MEASURE_XY;
    if (measure < 0 || gf_node_measure_m(mdl->kind, (int8_t)measure) != m)
        return -1;
    return measure;
}

// Every principal minor of the leading n x n block >= -tol (scaled by the
// diagonal): positive semidefinite, for n <= 3; and symmetric.
static int psd(const double a[3][3], unsigned n)
{
    double s = 0.0, tol;
    unsigned i, j;
    for (i = 0; i < n; i++) {
        if (!(a[i][i] >= 0.0))
            return 0;
        s = a[i][i] > s ? a[i][i] : s;
        for (j = 0; j < n; j++)
            if (!isfinite(a[i][j]) ||
                fabs(a[i][j] - a[j][i]) > 1e-12 * (fabs(a[i][j]) + 1e-300))
                return 0;
    }
    tol = 1e-12 * (s * s + 1e-300);
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++)
            if (a[i][i] * a[j][j] - a[i][j] * a[j][i] < -tol)
                return 0;
    if (n == 3) {
        double d = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                   a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                   a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        if (d < -tol * s)
            return 0;
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

int gf_node_model_check(const gf_node_model *mdl, const char **why)
{
    const char *w = NULL;
    unsigned i, n, m;
    if (mdl == NULL) {
        w = "no model";
        goto bad;
    }
    n = mdl->kind == GF_NODE_KIND_CAR ? 2u : 3u;
    m = gf_node_measure_m(mdl->kind, mdl->measure);
    if (mdl->measure == GF_NODE_MEASURE_AUTO)
        m = 1; // meas_cov: the first entry
    if (mdl->kind != GF_NODE_KIND_CAR && mdl->kind != GF_NODE_KIND_ROBOT)
        w = "type must be car or robot";
    else if (m == 0)
        w = mdl->kind == GF_NODE_KIND_CAR
                ? "a car measures position, velocity or position velocity"
                : "a robot measures x, x y or range bearing";
    else if (mdl->kind == GF_NODE_KIND_CAR &&
             (!(mdl->dt > 0.0) || !isfinite(mdl->dt)))
        w = "dt must be a finite number > 0";
    else if (mdl->kind == GF_NODE_KIND_CAR &&
             (!(mdl->accel_var >= 0.0) || !isfinite(mdl->accel_var)))
        w = "accel_var must be finite and >= 0";
    else if (!(mdl->gate >= 0.0) || !isfinite(mdl->gate))
        w = "gate must be finite and >= 0";
    else if (!isfinite(mdl->landmark[0]) || !isfinite(mdl->landmark[1]))
        w = "landmark must be finite";
    else if (!psd(mdl->prior_cov, n))
        w = "prior_cov must be symmetric positive semidefinite";
    else if (!psd(mdl->meas_cov, m))
        w = "meas_cov must be symmetric positive semidefinite";
    if (w == NULL && mdl->kind == GF_NODE_KIND_ROBOT)
        for (i = 0; i < 4; i++)
            if (!(mdl->odometry[i] >= 0.0) || !isfinite(mdl->odometry[i]))
                w = "odometry's four numbers must be finite and >= 0";
    for (i = 0; w == NULL && i < n; i++)
        if (!isfinite(mdl->prior_mean[i]))
            w = "prior_mean must be finite";
    if (w == NULL && !prior_starts(mdl))
        w = "the filter's init refuses prior_mean and prior_cov in its "
            "precision";
    if (w == NULL)
        return 0;
bad:
    if (why != NULL)
        *why = w;
    return -1;
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
    for (i = 0; i < m; i++)
        for (j = 0; j < m; j++)
            out->Q.m[i][j] = (gf_real)q[i][j];
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

gf_status gf_node_meas_range_bearing(void *ctx, const gf_vec3 *mu_bar,
                                     gf_vec3 *z_hat, gf_mat3 *H)
{
    const gf_node_model *mdl = (const gf_node_model *)ctx;
    gf_real dx = (gf_real)mdl->landmark[0] - mu_bar->v[0];
    gf_real dy = (gf_real)mdl->landmark[1] - mu_bar->v[1];
    gf_real q = dx * dx + dy * dy, r;
    if (!(q > GF_R(0.0)))
        return GF_ERR_MODEL;
    r = GF_SQRT(q);
    // z_hat = (r, atan2(dy, dx) - theta)
    z_hat->v[0] = r;
    z_hat->v[1] = gf_angle_wrap(GF_ATAN2(dy, dx) - mu_bar->v[2]);
    z_hat->v[2] = GF_R(0.0);
    // H = ((-dx/r, -dy/r, 0), (dy/q, -dx/q, -1))
    H->m[0][0] = -dx / r;
    H->m[0][1] = -dy / r;
    H->m[0][2] = GF_R(0.0);
    H->m[1][0] = dy / q;
    H->m[1][1] = -dx / q;
    H->m[1][2] = GF_R(-1.0);
    return GF_OK;
}

void gf_node_model_robot_meas(const gf_node_model *mdl, int measure,
                              const double q[3][3], gf_ekf3_meas *out)
{
    unsigned i, j, m = gf_node_measure_m(GF_NODE_KIND_ROBOT, (int8_t)measure);
    memset(out, 0, sizeof(*out));
    out->m = m;
    if (measure == GF_NODE_MEASURE_RANGE_BEARING) {
        out->h = gf_node_meas_range_bearing;
        out->ctx = (void *)(uintptr_t)mdl; // read only, see the callback
        out->angle_mask = 2u;              // the bearing
    } else {
        out->h = m == 1 ? gf_ekf3_meas_x : gf_ekf3_meas_xy;
    }
    for (i = 0; i < m; i++)
        for (j = 0; j < m; j++)
            out->Q.m[i][j] = (gf_real)q[i][j];
    out->gate = (gf_real)mdl->gate;
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
    while (*s == ' ' || *s == '\t')
        s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
        *--e = '\0';
    return s;
}

// Reads up to max numbers from s; returns how many, or -1 on junk.
static int numbers(const char *s, double *out, int max)
{
    int k = 0;
    char *end;
    for (;;) {
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s == '\0')
            return k;
        if (k == max)
            return -1;
        errno = 0;
        out[k] = strtod(s, &end);
        if (end == s || errno == ERANGE)
            return -1;
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
    if (k != (int)n && k != (int)(n * n))
        return -1;
    memset(a, 0, sizeof(double[3][3]));
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++)
            a[i][j] = (unsigned)k == n ? (i == j ? v[i] : 0.0) : v[i * n + j];
    return 0;
}

static int words_are(const char *s, const char *want)
{
    // compares word by word, any blanks between
    for (;;) {
        while (*s == ' ' || *s == '\t')
            s++;
        while (*want == ' ')
            want++;
        if (*s == '\0' || *want == '\0')
            return *s == '\0' && *want == '\0';
        while (*s != '\0' && *s != ' ' && *s != '\t' && *s == *want) {
            s++;
            want++;
        }
        if ((*s != '\0' && *s != ' ' && *s != '\t') ||
            (*want != '\0' && *want != ' '))
            return 0;
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
    if (n >= 0 && (size_t)n < size)
        vsnprintf(err + n, size - (size_t)n, fmt, ap);
    va_end(ap);
    return -1;
}

const gf_node_model *gf_node_config_find(const gf_node_config *cfg,
                                         const char *name)
{
    unsigned i;
    if (strcmp(name, book_car.name) == 0)
        return &book_car;
    if (strcmp(name, book_robot.name) == 0)
        return &book_robot;
    for (i = 0; cfg != NULL && i < cfg->count; i++)
        if (strcmp(cfg->model[i].name, name) == 0)
            return &cfg->model[i];
    return NULL;
}

// Ends the section being read: checks its model and compiles its pattern.
static int finish(gf_node_config *cfg, unsigned line, char *err, size_t size)
{
    unsigned i = cfg->count - 1;
    const char *why = NULL;
    char re[160];
    if (gf_node_model_check(&cfg->model[i], &why) != 0)
        return fail(err, size, line, "model %s: %s", cfg->model[i].name, why);
    if (cfg->channels[i][0] != '\0') {
        snprintf(re, sizeof re, "^(%s)$", cfg->channels[i]);
        if (regcomp(&cfg->regex[i], re, REG_EXTENDED | REG_NOSUB) != 0)
            return fail(err, size, line, "model %s: bad channels regex %s",
                        cfg->model[i].name, cfg->channels[i]);
        cfg->has_regex[i] = 1;
    }
    return 0;
}

int gf_node_config_parse(gf_node_config *cfg, const char *text, char *err,
                         size_t err_size)
{
    char buf[512];
    unsigned line = 0, start = 0;
    gf_node_model *mdl = NULL;
    memset(cfg, 0, sizeof(*cfg));
    if (err_size > 0)
        err[0] = '\0';
    while (*text != '\0') {
        size_t len = strcspn(text, "\n");
        char *s, *eq, *key, *val;
        line++;
        if (len >= sizeof buf)
            return fail(err, err_size, line, "longer than %u characters",
                        (unsigned)sizeof buf - 1);
        memcpy(buf, text, len);
        buf[len] = '\0';
        text += len + (text[len] == '\n');
        s = strchr(buf, '#');
        if (s != NULL)
            *s = '\0';
        s = trim(buf);
        if (*s == '\0')
            continue;
        if (*s == '[') {
            char name[64];
            char *close = strchr(s, ']');
            if (close == NULL || trim(close + 1)[0] != '\0')
                return fail(err, err_size, line, "expected [model NAME]");
            *close = '\0';
            if (sscanf(s + 1, " model %63s", name) != 1 ||
                strlen(name) >= GF_NODE_MODEL_NAME)
                return fail(err, err_size, line,
                            "expected [model NAME] (a name of at most %d "
                            "characters)",
                            GF_NODE_MODEL_NAME - 1);
            if (mdl != NULL && finish(cfg, start, err, err_size) != 0)
                return -1;
            if (gf_node_config_find(cfg, name) != NULL)
                return fail(err, err_size, line, "model %s defined twice",
                            name);
            if (cfg->count == GF_NODE_CONFIG_MODELS)
                return fail(err, err_size, line, "more than %d models",
                            GF_NODE_CONFIG_MODELS);
            mdl = &cfg->model[cfg->count++];
            memset(mdl, 0, sizeof(*mdl));
            strcpy(mdl->name, name);
            start = line;
            continue;
        }
        eq = strchr(s, '=');
        if (eq == NULL)
            return fail(err, err_size, line, "expected key = value");
        if (mdl == NULL)
            return fail(err, err_size, line,
                        "a key before the first [model NAME]");
        *eq = '\0';
        key = trim(s);
        val = trim(eq + 1);
        if (strcmp(key, "base") == 0) {
            const gf_node_model *b = gf_node_config_find(cfg, val);
            char name[GF_NODE_MODEL_NAME];
            if (b == NULL || b == mdl)
                return fail(err, err_size, line, "no model %s before this",
                            val);
            memcpy(name, mdl->name, sizeof name);
            *mdl = *b;
            memcpy(mdl->name, name, sizeof name);
        } else if (strcmp(key, "type") == 0) {
            int8_t kind = strcmp(val, "car") == 0     ? GF_NODE_KIND_CAR
                          : strcmp(val, "robot") == 0 ? GF_NODE_KIND_ROBOT
                                                      : 0;
            if (kind == 0)
                return fail(err, err_size, line, "type is car or robot");
            if (mdl->kind != kind) {
                // a type of its own starts from that type's preset
                char name[GF_NODE_MODEL_NAME];
                memcpy(name, mdl->name, sizeof name);
                *mdl = kind == GF_NODE_KIND_CAR ? book_car : book_robot;
                memcpy(mdl->name, name, sizeof name);
            }
        } else if (mdl->kind == 0) {
            return fail(err, err_size, line, "type or base first");
        } else if (strcmp(key, "channels") == 0) {
            size_t i = (size_t)(mdl - cfg->model);
            if (strlen(val) >= sizeof cfg->channels[0])
                return fail(err, err_size, line, "channels regex too long");
            strcpy(cfg->channels[i], val);
        } else if (strcmp(key, "measure") == 0) {
            if (measure_parse(val, mdl->kind, &mdl->measure) != 0)
                return fail(err, err_size, line,
                            mdl->kind == GF_NODE_KIND_CAR
                                ? "a car measures position, velocity or "
                                  "position velocity"
                                : "a robot measures x, x y or range bearing");
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
                if (strcmp(key, one[k].key) != 0)
                    continue;
                if (!(mdl->kind == GF_NODE_KIND_CAR ? one[k].car
                                                    : one[k].robot))
                    return fail(err, err_size, line, "a %s has no %s",
                                mdl->kind == GF_NODE_KIND_CAR ? "car" : "robot",
                                key);
                want = one[k].v == mdl->prior_mean ? (int)n : one[k].n;
                if (numbers(val, one[k].v, want) != want)
                    return fail(err, err_size, line, "%s takes %d number%s",
                                key, want, want == 1 ? "" : "s");
                done = 1;
            }
            if (!done && strcmp(key, "prior_cov") == 0) {
                if (matrix(val, mdl->prior_cov, n) != 0)
                    return fail(err, err_size, line,
                                "prior_cov takes %u or %u numbers", n, n * n);
                done = 1;
            }
            if (!done && strcmp(key, "meas_cov") == 0) {
                unsigned m = gf_node_measure_m(mdl->kind, mdl->measure);
                if (m == 0 || matrix(val, mdl->meas_cov, m) != 0)
                    return fail(err, err_size, line,
                                "meas_cov takes %u or %u numbers (after "
                                "measure)",
                                m, m * m);
                done = 1;
            }
            if (!done)
                return fail(err, err_size, line, "unknown key %s", key);
        }
    }
    if (mdl != NULL && finish(cfg, start, err, err_size) != 0)
        return -1;
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
    rc = gf_node_config_parse(cfg, text, err, err_size);
    if (rc != 0) {
        char where[256];
        snprintf(where, sizeof where, "%s", err);
        snprintf(err, err_size, "%s: %s", path, where);
    }
    return rc;
}

void gf_node_config_free(gf_node_config *cfg)
{
    unsigned i;
    for (i = 0; i < cfg->count; i++)
        if (cfg->has_regex[i])
            regfree(&cfg->regex[i]);
    memset(cfg, 0, sizeof(*cfg));
}

const gf_node_model *gf_node_config_lookup(const gf_node_config *cfg,
                                           int32_t id, int8_t kind)
{
    char meas[GF_CHANNEL_MAX], ctrl[GF_CHANNEL_MAX];
    unsigned i;
    snprintf(meas, sizeof meas, "%s%ld", GF_CHANNEL_MEAS, (long)id);
    snprintf(ctrl, sizeof ctrl, "%s%ld", GF_CHANNEL_CTRL, (long)id);
    for (i = 0; cfg != NULL && i < cfg->count; i++)
        if (cfg->has_regex[i] && cfg->model[i].kind == kind &&
            (regexec(&cfg->regex[i], meas, 0, NULL, 0) == 0 ||
             regexec(&cfg->regex[i], ctrl, 0, NULL, 0) == 0))
            return &cfg->model[i];
    return kind == GF_NODE_KIND_CAR ? &book_car : &book_robot;
}
