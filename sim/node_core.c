// SPDX-License-Identifier: MIT
// gaussfilt sim: the filter node's message handling (see node_core.h).
// Only message checking and bookkeeping live here; every filter step is a
// call into the core (gf_kf2_*, gf_ekf3_*, gf_ukf3_*, gf_pf3_*).
#include "node_core.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_groundtruth_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gaussfilt_lcm_model_t.h"
#include "gaussfilt_lcm_node_status_t.h"
#include "gaussfilt_lcm_particles_t.h"

#define MODEL_CAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
#define MODEL_ROBOT GAUSSFILT_LCM_MEASUREMENT_T_MODEL_ROBOT
#define FILTER_KF2 GAUSSFILT_LCM_BELIEF_T_FILTER_KF2
#define FILTER_EKF3 GAUSSFILT_LCM_BELIEF_T_FILTER_EKF3
#define FILTER_UKF3 GAUSSFILT_LCM_BELIEF_T_FILTER_UKF3
#define FILTER_PF3 GAUSSFILT_LCM_BELIEF_T_FILTER_PF3
#define FILTER_KF GAUSSFILT_LCM_BELIEF_T_FILTER_KF
#define MODEL_LINEAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR

const char *gf_node_result_str(gf_node_result r)
{
    switch (r) {
    case GF_NODE_APPLIED:
        return "applied";
    case GF_NODE_DUPLICATE:
        return "duplicate";
    case GF_NODE_OUT_OF_ORDER:
        return "out_of_order";
    case GF_NODE_MALFORMED:
        return "malformed";
    case GF_NODE_TYPE_MISMATCH:
        return "type_mismatch";
    case GF_NODE_BAD_FIELD:
        return "bad_field";
    case GF_NODE_UNKNOWN_CHANNEL:
        return "unknown_channel";
    case GF_NODE_TRACK_LIMIT:
        return "track_limit";
    case GF_NODE_NONFINITE:
        return "nonfinite";
    case GF_NODE_FILTER_ERROR:
        return "filter_error";
    case GF_NODE_STALE_SESSION:
        return "stale_session";
    case GF_NODE_NO_SUMMARY:
        return "no_summary";
    case GF_NODE_GATED:
        return "gated";
    case GF_NODE_NO_MODEL:
        return "no_model";
    case GF_NODE_LATE:
        return "late";
    case GF_NODE_TOO_OLD:
        return "too_old";
    case GF_NODE_RESULT_COUNT:
        break;
    }
    return "unknown";
}

int gf_node_init(gf_node *node, gf_node_publish_fn publish, void *ctx)
{
    if (node == NULL) {
        return -1;
    }
    memset(node, 0, sizeof(*node));
    node->publish = publish;
    node->ctx = ctx;
    return 0;
}

int gf_node_set_filter(gf_node *node, gf_node_filter filter,
                       gf_node_pf_pool *pool, uint32_t seed)
{
    if (node == NULL ||
        (filter != GF_NODE_FILTER_EKF && filter != GF_NODE_FILTER_UKF &&
         filter != GF_NODE_FILTER_PF)) {
        return -1;
    }
    if (filter == GF_NODE_FILTER_PF && pool == NULL) {
        return -1;
    }
    node->robot_filter = filter;
    node->pf_pool = pool;
    node->pf_seed = seed;
    if (pool != NULL) {
        pool->used = 0;
    }
    return 0;
}

int gf_node_set_models(gf_node *node, gf_node_model_fn fn, const void *ctx)
{
    if (node == NULL) {
        return -1;
    }
    node->models = fn;
    node->models_ctx = ctx;
    return 0;
}

void gf_node_add_dropped(gf_node *node, uint64_t n)
{
    if (node != NULL) {
        node->counts.dropped += n;
    }
}

int gf_node_set_id(gf_node *node, const char *id)
{
    if (node == NULL || id == NULL) {
        return -1;
    }
    snprintf(node->id, sizeof node->id, "%s", id);
    return 0;
}

int gf_node_set_process(gf_node *node, const char *host, int32_t pid,
                        int64_t start_utime)
{
    if (node == NULL || host == NULL) {
        return -1;
    }
    snprintf(node->host, sizeof node->host, "%s", host);
    node->pid = pid;
    node->start_utime = start_utime;
    return 0;
}

int gf_node_set_strict(gf_node *node, int strict)
{
    if (node == NULL) {
        return -1;
    }
    node->strict = strict != 0;
    return 0;
}

int gf_node_set_log(gf_node *node, gf_node_log_fn fn, void *ctx)
{
    if (node == NULL) {
        return -1;
    }
    node->log = fn;
    node->log_ctx = ctx;
    return 0;
}

// One line through the log callback.
static void say(const gf_node *node, const char *fmt, ...)
{
    char line[256];
    va_list ap;
    if (node->log == NULL) {
        return;
    }
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    node->log(node->log_ctx, line);
}

// What the node says once per track id (gf_node.said).
enum {
    SAY_TRACK,       // an input's track field not its channel's
    SAY_SIZE_M,      // a measurement's m its track cannot take
    SAY_SIZE_N,      // a control's n
    SAY_SENSOR,      // a sensor its model lacks (bad_field)
    SAY_KIND,        // another model kind than the track's (bad_field)
    SAY_NO_MODEL,    // refused for want of a model
    SAY_TRACK_LIMIT, // no room for the track
    SAY_MALFORMED,   // bytes that do not decode
    SAY_TYPE,        // another of our types on its channel
    SAY_DUPLICATE,
    SAY_OUT_OF_ORDER,
    SAY_STALE,
    SAY_LATE,
    SAY_TOO_OLD,
    SAY_STEP,        // a step the core refused (nonfinite, filter_error)
    SAY_GATED_FIRST, // its first updates all gated
    SAY_GATED_RUN    // later updates gated in a row
};

// The entry of id in the node's said table, made if new (NULL: full).
static int said_index(gf_node *node, int32_t id, int make)
{
    unsigned i;
    for (i = 0; i < node->nsaid; i++) {
        if (node->said[i].id == id) {
            return (int)i;
        }
    }
    if (!make || node->nsaid >= GF_NODE_SAID_IDS) {
        return -1;
    }
    memset(&node->said[node->nsaid], 0, sizeof node->said[0]);
    node->said[node->nsaid].id = id;
    return (int)node->nsaid++;
}

// 1 the first time topic is to be said about track id (it is then marked
// said), else 0: said before, or no room left to remember it.
static int say_first(gf_node *node, int32_t id, unsigned topic)
{
    int i = said_index(node, id, 1);
    if (i < 0 || (node->said[i].topics & (1u << topic)) != 0u) {
        return 0;
    }
    node->said[i].topics |= 1u << topic;
    return 1;
}

int gf_node_filter_parse(const char *name, gf_node_filter *out)
{
    if (name == NULL || out == NULL) {
        return -1;
    }
    if (strcmp(name, "ekf") == 0) {
        *out = GF_NODE_FILTER_EKF;
    } else if (strcmp(name, "ukf") == 0) {
        *out = GF_NODE_FILTER_UKF;
    } else if (strcmp(name, "pf") == 0) {
        *out = GF_NODE_FILTER_PF;
    } else {
        return -1;
    }
    return 0;
}

const gf_node_track *gf_node_find(const gf_node *node, int32_t id)
{
    unsigned i;
    if (node == NULL) {
        return NULL;
    }
    for (i = 0; i < node->ntracks; i++) {
        if (node->tracks[i].id == id) {
            return &node->tracks[i];
        }
    }
    return NULL;
}

// ---- channel and fingerprint ----------------------------------------------

enum { KIND_NONE, KIND_MEAS, KIND_CTRL, KIND_MODEL };

// Parses "<prefix><decimal int32>" exactly, in the id's one spelling (no
// leading zero, no "-0"); returns 1 and the track id. With sensor != NULL
// a "_<name>" may follow the id: *sensor points at the name (else NULL).
static int parse_track_sensor(const char *channel, const char *prefix,
                              int32_t *id, const char **sensor)
{
    size_t n = strlen(prefix);
    const char *p;
    int neg = 0;
    int64_t v = 0;
    if (strncmp(channel, prefix, n) != 0) {
        return 0;
    }
    p = channel + n;
    if (*p == '-') {
        neg = 1;
        p++;
    }
    if (sensor != NULL) {
        *sensor = NULL;
    }
    if (*p == '\0' || *p == '_' ||
        (p[0] == '0' && ((p[1] != '\0' && p[1] != '_') || neg))) {
        return 0;
    }
    for (; *p != '\0'; p++) {
        if (*p == '_' && sensor != NULL && p[1] != '\0') {
            *sensor = p + 1; // the sensor's name, checked against its model
            break;
        }
        if (*p < '0' || *p > '9') {
            return 0;
        }
        v = v * 10 + (*p - '0');
        if (v > (int64_t)INT32_MAX + 1) {
            return 0;
        }
    }
    v = neg ? -v : v;
    if (v > INT32_MAX) {
        return 0;
    }
    *id = (int32_t)v;
    return 1;
}

static int parse_track(const char *channel, const char *prefix, int32_t *id)
{
    return parse_track_sensor(channel, prefix, id, NULL);
}

static int channel_kind(const char *channel, int32_t *id, const char **sensor)
{
    if (channel == NULL) {
        return KIND_NONE;
    }
    if (parse_track_sensor(channel, GF_CHANNEL_MEAS, id, sensor)) {
        return KIND_MEAS;
    }
    if (parse_track(channel, GF_CHANNEL_CTRL, id)) {
        return KIND_CTRL;
    }
    if (parse_track(channel, GF_CHANNEL_MODEL, id)) {
        return KIND_MODEL;
    }
    return KIND_NONE;
}

// The 8-byte big-endian fingerprint an LCM message starts with.
static int64_t fingerprint(const uint8_t *b)
{
    uint64_t v = 0;
    unsigned i;
    for (i = 0; i < 8; i++) {
        v = (v << 8) | b[i];
    }
    return (int64_t)v;
}

// Checks the fingerprint against the expected type: GF_NODE_APPLIED when it
// matches, TYPE_MISMATCH when it is another of our types, else MALFORMED.
static gf_node_result check_fingerprint(const void *data, size_t len,
                                        int64_t want)
{
    int64_t got;
    if (data == NULL || len < 8 || len > GF_NODE_MAX_LEN) {
        return GF_NODE_MALFORMED;
    }
    got = fingerprint((const uint8_t *)data);
    if (got == want) {
        return GF_NODE_APPLIED;
    }
    if (got == __gaussfilt_lcm_measurement_t_get_hash() ||
        got == __gaussfilt_lcm_control_t_get_hash() ||
        got == __gaussfilt_lcm_belief_t_get_hash() ||
        got == __gaussfilt_lcm_groundtruth_t_get_hash() ||
        got == __gaussfilt_lcm_model_t_get_hash() ||
        got == __gaussfilt_lcm_particles_t_get_hash()) {
        return GF_NODE_TYPE_MISMATCH;
    }
    return GF_NODE_MALFORMED;
}

// ---- the inputs, decoded in place ------------------------------------------
//
// control_t and measurement_t carry variable-length arrays, which LCM's C
// decoder allocates (and leaks on a truncated message). The node reads
// them itself into fixed arrays instead: nothing allocated, every length
// checked against the bytes there are. A size beyond GF_NODE_NMAX in an
// otherwise whole message is bad_field; bytes that do not add up are
// malformed.

typedef struct wire {
    const uint8_t *p;
    size_t len, pos;
    int short_read;
} wire;

static uint64_t wire_bits(wire *w, unsigned bytes)
{
    uint64_t v = 0;
    unsigned i;
    if (w->pos + bytes > w->len) {
        w->short_read = 1;
        return 0;
    }
    for (i = 0; i < bytes; i++) {
        v = (v << 8) | w->p[w->pos + i];
    }
    w->pos += bytes;
    return v;
}

static int64_t wire_i64(wire *w)
{
    return (int64_t)wire_bits(w, 8);
}

static int32_t wire_i32(wire *w)
{
    return (int32_t)(uint32_t)wire_bits(w, 4);
}

static int8_t wire_i8(wire *w)
{
    return (int8_t)(uint8_t)wire_bits(w, 1);
}

static double wire_f64(wire *w)
{
    uint64_t v = wire_bits(w, 8);
    double d;
    memcpy(&d, &v, sizeof d);
    return d;
}

typedef struct node_ctrl {
    int64_t utime, seq, session;
    int32_t track;
    int8_t model, n;
    double u[GF_NODE_NMAX];
} node_ctrl;

typedef struct node_meas {
    int64_t utime, seq, session;
    int32_t track;
    int8_t model, m;
    double z[GF_NODE_NMAX];
    double q[GF_NODE_NMAX][GF_NODE_NMAX];
} node_meas;

// A size k followed by `per(k)` doubles to the end: APPLIED when it fits
// our arrays, BAD_FIELD when the message is whole but k too large,
// MALFORMED otherwise.
static gf_node_result wire_size(const wire *w, int8_t k, size_t doubles)
{
    if (w->short_read || k < 0) {
        return GF_NODE_MALFORMED;
    }
    if (w->pos + 8 * doubles != w->len) {
        return GF_NODE_MALFORMED;
    }
    return k > GF_NODE_NMAX ? GF_NODE_BAD_FIELD : GF_NODE_APPLIED;
}

static gf_node_result decode_ctrl(const void *data, size_t len, node_ctrl *c)
{
    wire w = {(const uint8_t *)data, len, 8, 0};
    gf_node_result r;
    int i;
    c->utime = wire_i64(&w);
    c->seq = wire_i64(&w);
    c->session = wire_i64(&w);
    c->track = wire_i32(&w);
    c->model = wire_i8(&w);
    c->n = wire_i8(&w);
    r = wire_size(&w, c->n, c->n > 0 ? (size_t)c->n : 0u);
    if (r != GF_NODE_APPLIED) {
        return r;
    }
    for (i = 0; i < c->n; i++) {
        c->u[i] = wire_f64(&w);
    }
    return GF_NODE_APPLIED;
}

static gf_node_result decode_meas(const void *data, size_t len, node_meas *z)
{
    wire w = {(const uint8_t *)data, len, 8, 0};
    gf_node_result r;
    size_t m;
    int i, j;
    z->utime = wire_i64(&w);
    z->seq = wire_i64(&w);
    z->session = wire_i64(&w);
    z->track = wire_i32(&w);
    z->model = wire_i8(&w);
    z->m = wire_i8(&w);
    m = z->m > 0 ? (size_t)z->m : 0u;
    r = wire_size(&w, z->m, m + m * m);
    if (r != GF_NODE_APPLIED) {
        return r;
    }
    for (i = 0; i < z->m; i++) {
        z->z[i] = wire_f64(&w);
    }
    for (i = 0; i < z->m; i++) {
        for (j = 0; j < z->m; j++) {
            z->q[i][j] = wire_f64(&w);
        }
    }
    return GF_NODE_APPLIED;
}

int gf_node_belief_origin(const void *data, size_t len, int32_t *track,
                          char *id, size_t size)
{
    // belief_t: fingerprint, utime, seq, input_seq, track, model, stage,
    // status, filter, then the node string (int32 length with its NUL)
    wire w = {(const uint8_t *)data, len, 0, 0};
    int32_t n;
    size_t k;
    if (data == NULL || id == NULL || size == 0 ||
        wire_i64(&w) != __gaussfilt_lcm_belief_t_get_hash()) {
        return -1;
    }
    w.pos = 32;
    *track = wire_i32(&w);
    w.pos += 4;
    n = wire_i32(&w);
    if (w.short_read || n < 1 || (size_t)n > w.len - w.pos ||
        w.p[w.pos + (size_t)n - 1] != '\0') {
        return -1;
    }
    k = (size_t)n - 1 < size - 1 ? (size_t)n - 1 : size - 1;
    memcpy(id, w.p + w.pos, k);
    id[k] = '\0';
    return 0;
}

// The warning, once per track, that node `id` publishes beliefs of t too.
static void peer_warn(gf_node *node, gf_node_track *t, const char *id)
{
    if (!t->peer_warned) {
        t->peer_warned = 1;
        say(node,
            "warning: node \"%s\" also publishes beliefs of track %ld "
            "(this node is \"%s\"): two nodes filter the same track; give "
            "each its own tracks (--channels)",
            id, (long)t->id, node->id);
    }
}

// How many entries of the ring peer_early hold a belief.
static unsigned peer_early_held(const gf_node *node)
{
    return node->npeer_early < GF_NODE_PEER_EARLY ? node->npeer_early
                                                  : GF_NODE_PEER_EARLY;
}

// Another node's belief of a track this node has not made (yet): kept in
// the ring of peer_early, one entry per track and node.
static void peer_remember(gf_node *node, int32_t track, const char *id)
{
    unsigned i, n = peer_early_held(node);
    for (i = 0; i < n; i++) {
        if (node->peer_early[i].track == track &&
            strcmp(node->peer_early[i].id, id) == 0) {
            node->peer_early[i].count++;
            return;
        }
    }
    i = node->npeer_early++ % GF_NODE_PEER_EARLY;
    node->peer_early[i].track = track;
    node->peer_early[i].count = 1;
    memcpy(node->peer_early[i].id, id, strlen(id) + 1);
}

// A new track: the beliefs of it other nodes published before it was
// made count now, and are warned about.
static void peer_early_track(gf_node *node, gf_node_track *t)
{
    unsigned i, n = peer_early_held(node);
    for (i = 0; i < n; i++) {
        if (node->peer_early[i].track == t->id &&
            node->peer_early[i].count > 0) {
            node->counts.peer_beliefs += node->peer_early[i].count;
            node->peer_early[i].count = 0;
            peer_warn(node, t, node->peer_early[i].id);
        }
    }
}

int gf_node_peer_belief(gf_node *node, const void *data, size_t len)
{
    char id[GF_NODE_ID_MAX];
    int32_t track;
    gf_node_track *t;
    if (node == NULL ||
        gf_node_belief_origin(data, len, &track, id, sizeof id) != 0 ||
        strcmp(id, node->id) == 0) {
        return 0;
    }
    t = (gf_node_track *)(uintptr_t)gf_node_find(node, track);
    if (t == NULL) {
        peer_remember(node, track, id);
        return 0;
    }
    node->counts.peer_beliefs++;
    peer_warn(node, t, id);
    return 1;
}

// ---- tracks ----------------------------------------------------------------

// The robot's prior in any filter: N(mu0, sigma0) (see track_prior).
static const gf_ukf3_params ukf_params = {GF_R(1.0), GF_R(2.0), GF_R(0.0)};

// The robot's moments as the belief carries them: the filter's own (the
// EKF's Sigma read from its factors), or the particles' last weighted
// summary.
static void robot_moments(const gf_node_track *t, gf_vec3 *mu, gf_mat3 *sigma)
{
    if (t->filter == FILTER_UKF3) {
        *mu = t->f.ukf3.mu;
        *sigma = t->f.ukf3.sigma;
    } else if (t->filter == FILTER_PF3) {
        *mu = t->f.pf3.mu;
        *sigma = t->f.pf3.sigma;
    } else {
        *mu = t->f.ekf3.mu;
        (void)gf_ekf3_cov(&t->f.ekf3, sigma); // fails only on NULL
    }
}

// Points a PF track's filter at its particles (the node may have moved).
static gf_pf3 *track_pf(gf_node *node, gf_node_track *t)
{
    t->f.pf3.pf.p = node->pf_pool->p[t->f.pf3.slot];
    return &t->f.pf3.pf;
}

static int finite3(const gf_vec3 *mu, const gf_mat3 *sigma)
{
    unsigned i, j;
    for (i = 0; i < 3; i++) {
        if (!isfinite((double)mu->v[i])) {
            return 0;
        }
        for (j = 0; j < 3; j++) {
            if (!isfinite((double)sigma->m[i][j])) {
                return 0;
            }
        }
    }
    return 1;
}

// The PF track's summary after a step that moved its particles: its
// weighted moments and effective sample size. When they cannot be
// computed (overflow, no mean direction, no weight) the track holds NaN
// and no_summary, and says GF_NODE_NO_SUMMARY; else GF_NODE_APPLIED.
static gf_node_result pf_summary(gf_node_track *t)
{
    gf_vec3 mu;
    gf_mat3 sigma;
    gf_real neff = GF_R(0.0);
    gf_status s = gf_pf3_estimate(&t->f.pf3.pf, &mu, &sigma);
    if (s == GF_OK && finite3(&mu, &sigma) &&
        gf_pf3_neff(&t->f.pf3.pf, &neff) == GF_OK && isfinite((double)neff)) {
        t->f.pf3.mu = mu;
        t->f.pf3.sigma = sigma;
        t->f.pf3.neff = neff;
        t->f.pf3.no_summary = 0;
        return GF_NODE_APPLIED;
    }
    {
        unsigned i, j;
        gf_real nan = (gf_real)NAN;
        for (i = 0; i < 3; i++) {
            t->f.pf3.mu.v[i] = nan;
            for (j = 0; j < 3; j++) {
                t->f.pf3.sigma.m[i][j] = nan;
            }
        }
    }
    t->f.pf3.neff = GF_R(0.0);
    t->f.pf3.no_summary = 1;
    return GF_NODE_NO_SUMMARY;
}

// The model's prior, which every new track starts from, and a resynced
// track again. A new track (filter 0) takes the node's robot filter; a
// resynced one keeps its own filter, and a PF track its pool slot. KF2's
// and EKF3's init take every prior of a model gf_node_model_check passed
// (it asks them), and a track's model is always one it passed.
static void track_prior(gf_node *node, gf_node_track *t)
{
    gf_vec3 mu0;
    gf_mat3 sigma0;
    unsigned i, j;
    int8_t filter = t->filter;
    if (filter == 0) {
        filter = node->robot_filter == GF_NODE_FILTER_UKF  ? FILTER_UKF3
                 : node->robot_filter == GF_NODE_FILTER_PF ? FILTER_PF3
                                                           : FILTER_EKF3;
    }
    if (t->model == MODEL_LINEAR) {
        const gf_node_linear *l = t->mdl.lin;
        gf_real *mu = node->vec[2], *sigma = node->lin[0];
        for (i = 0; i < l->n; i++) {
            mu[i] = (gf_real)l->prior_mean[i];
        }
        for (i = 0; i < l->n * l->n; i++) {
            sigma[i] = (gf_real)l->prior_cov[i];
        }
        memset(&t->f.kf, 0, sizeof(t->f.kf));
        if (l->gen != NULL) { // its angles kept in (-pi, pi]
            (void)gf_ekf_init(&t->f.kf, l->n, mu, sigma, l->gen->desc->angles,
                              &node->work);
        } else {
            (void)gf_kf_init(&t->f.kf, l->n, mu, sigma, &node->work);
        }
        t->filter = FILTER_KF;
        return;
    }
    if (t->model == MODEL_CAR) {
        gf_vec2 mu2;
        gf_mat2 sigma2;
        for (i = 0; i < 2; i++) {
            mu2.v[i] = (gf_real)t->mdl.prior_mean[i];
            for (j = 0; j < 2; j++) {
                sigma2.m[i][j] = (gf_real)t->mdl.prior_cov[i][j];
            }
        }
        memset(&t->f.kf2, 0, sizeof(t->f.kf2));
        (void)gf_kf2_init(&t->f.kf2, &mu2, &sigma2);
        t->filter = FILTER_KF2;
        return;
    }
    for (i = 0; i < 3; i++) {
        mu0.v[i] = (gf_real)t->mdl.prior_mean[i];
        for (j = 0; j < 3; j++) {
            sigma0.m[i][j] = (gf_real)t->mdl.prior_cov[i][j];
        }
    }
    if (filter == FILTER_UKF3) {
        t->filter = FILTER_UKF3;
        (void)gf_ukf3_init(&t->f.ukf3, &mu0, &sigma0, &ukf_params);
    } else if (filter == FILTER_PF3) {
        if (t->filter != FILTER_PF3) {
            t->f.pf3.slot = node->pf_pool->used++;
        }
        t->filter = FILTER_PF3;
        (void)gf_pf3_init(&t->f.pf3.pf, node->pf_pool->p[t->f.pf3.slot],
                          GF_NODE_PF_PARTICLES, node->pf_seed + (uint32_t)t->id,
                          &mu0, &sigma0);
        (void)pf_summary(t);
    } else {
        t->filter = FILTER_EKF3;
        (void)gf_ekf3_init(&t->f.ekf3, &mu0, &sigma0); // wraps the heading
    }
}

// belief_t.sensor of a belief no named sensor made.
static char no_sensor[1];

// The belief as belief_t carries it; its numbers live in the node's
// scratch until the next belief.
static void belief_fill(gf_node *node, const gf_node_track *t,
                        gaussfilt_lcm_belief_t *b)
{
    unsigned i, j, n;
    gf_vec3 mu3;
    gf_mat3 s3;
    gf_mat2 s2;
    gf_real *sl = node->lin[0];
    memset(b, 0, sizeof(*b));
    if (t->model == MODEL_LINEAR) {
        n = t->f.kf.n;
        (void)gf_kf_cov(&t->f.kf, sl); // fails only on NULL
        for (i = 0; i < n; i++) {
            node->mean[i] = (double)t->f.kf.mu[i];
            for (j = 0; j < n; j++) {
                node->cov[i * n + j] = (double)sl[i * n + j];
            }
        }
    } else if (t->model == MODEL_ROBOT) {
        n = 3;
        robot_moments(t, &mu3, &s3);
        for (i = 0; i < n; i++) {
            node->mean[i] = (double)mu3.v[i];
            for (j = 0; j < n; j++) {
                node->cov[i * n + j] = (double)s3.m[i][j];
            }
        }
    } else {
        n = 2;
        (void)gf_kf2_cov(&t->f.kf2, &s2); // fails only on NULL
        for (i = 0; i < n; i++) {
            node->mean[i] = (double)t->f.kf2.mu.v[i];
            for (j = 0; j < n; j++) {
                node->cov[i * n + j] = (double)s2.m[i][j];
            }
        }
    }
    for (i = 0; i < n; i++) {
        node->cov_rows[i] = &node->cov[i * n];
    }
    b->track = t->id;
    b->model = t->model;
    b->filter = t->filter;
    b->node = node->id;
    b->n = (int8_t)n;
    b->mean = node->mean;
    b->cov = node->cov_rows;
    b->m = 0;
    b->innovation = node->innovation;
    b->trigger = GAUSSFILT_LCM_BELIEF_T_TRIGGER_INPUT;
    b->sensor = no_sensor;
    if (t->filter == FILTER_PF3 && t->f.pf3.no_summary) {
        b->status = GF_NODE_STATUS_NO_SUMMARY;
    }
}

static void publish_belief(gf_node *node, gf_node_track *t,
                           gaussfilt_lcm_belief_t *b)
{
    char channel[GF_CHANNEL_MAX];
    int len;
    b->seq = t->belief_seq;
    len =
        gaussfilt_lcm_belief_t_encode(node->buf, 0, (int)sizeof(node->buf), b);
    if (len < 0) {
        node->counts.publish_failed++;
        return;
    }
    snprintf(channel, sizeof(channel), "%s%ld", GF_CHANNEL_BELIEF, (long)t->id);
    node->counts.published++;
    if (node->publish != NULL &&
        node->publish(node->ctx, channel, node->buf, (size_t)len) != 0) {
        node->counts.publish_failed++;
    }
}

// A particle's number as particles_t carries it: beyond float's range it
// is +-FLT_MAX, never inf.
static float to_float(gf_real v)
{
    if ((double)v > (double)FLT_MAX) {
        return FLT_MAX;
    }
    if ((double)v < -(double)FLT_MAX) {
        return -FLT_MAX;
    }
    return (float)v;
}

// A PF track's cloud, after its belief b: every stride-th particle.
static void publish_particles(gf_node *node, gf_node_track *t,
                              const gaussfilt_lcm_belief_t *b)
{
    gf_node_pf_pool *pool = node->pf_pool;
    const gf_pf3 *pf = track_pf(node, t);
    gaussfilt_lcm_particles_t m;
    char channel[GF_CHANNEL_MAX];
    unsigned k, i = 0;
    unsigned stride = (pf->n + GF_NODE_PF_CLOUD - 1u) / GF_NODE_PF_CLOUD;
    int len;
    for (k = 0; k < pf->n && i < GF_NODE_PF_CLOUD; k += stride, i++) {
        pool->x[i] = to_float(pf->p[k].x.v[0]);
        pool->y[i] = to_float(pf->p[k].x.v[1]);
        pool->theta[i] = to_float(pf->p[k].x.v[2]);
        pool->w[i] = to_float(pf->p[k].w);
    }
    memset(&m, 0, sizeof(m));
    m.utime = b->utime;
    m.seq = b->seq;
    m.input_seq = b->input_seq;
    m.track = t->id;
    m.stage = b->stage;
    m.resampled = (int8_t)t->f.pf3.resampled;
    m.n_filter = (int32_t)pf->n;
    m.stride = (int32_t)stride;
    m.neff = (double)t->f.pf3.neff;
    m.count = (int32_t)i;
    m.x = pool->x;
    m.y = pool->y;
    m.theta = pool->theta;
    m.w = pool->w;
    len = gaussfilt_lcm_particles_t_encode(pool->buf, 0, (int)sizeof(pool->buf),
                                           &m);
    if (len < 0) {
        node->counts.publish_failed++;
        return;
    }
    snprintf(channel, sizeof(channel), "%s%ld", GF_CHANNEL_PARTICLES,
             (long)t->id);
    node->counts.published++;
    if (node->publish != NULL &&
        node->publish(node->ctx, channel, pool->buf, (size_t)len) != 0) {
        node->counts.publish_failed++;
    }
}

// Publishes a track's belief, and a PF track's cloud after it.
static void publish_step(gf_node *node, gf_node_track *t,
                         gaussfilt_lcm_belief_t *b)
{
    publish_belief(node, t, b);
    if (t->filter == FILTER_PF3) {
        publish_particles(node, t, b);
    }
}

static const char *kind_name(int8_t kind)
{
    return kind == MODEL_CAR ? "car" : kind == MODEL_ROBOT ? "robot" : "linear";
}

// The model a new track of this id and kind gets; *named says whether the
// node's lookup named it (not a preset). NULL: the track is refused
// (no_model): a linear track nothing names, or any such track when strict.
static const gf_node_model *model_for(const gf_node *node, int32_t id,
                                      int8_t kind, int *named)
{
    const gf_node_model *m = NULL;
    const gf_node_model *car = gf_node_model_book_car(),
                        *robot = gf_node_model_book_robot();
    if (node->models != NULL) {
        m = node->models(node->models_ctx, id, kind);
    }
    if (m != NULL && (m->kind != kind || gf_node_model_check(m, NULL) != 0)) {
        m = NULL;
    }
    *named = m != NULL && m != car && m != robot;
    if (!*named && (node->strict || kind == MODEL_LINEAR)) {
        return NULL;
    }
    if (m == NULL) {
        m = kind == MODEL_CAR ? car : robot;
    }
    return m;
}

// A track refused for want of a model: said once per id, counted by the
// caller as no_model.
static gf_node_result refuse(gf_node *node, int32_t id, int8_t kind)
{
    if (!say_first(node, id, SAY_NO_MODEL)) {
        return GF_NODE_NO_MODEL;
    }
    if (kind == MODEL_LINEAR && !node->strict) {
        say(node,
            "track %ld (linear) refused: no configured linear model's "
            "channels name %s%ld or %s%ld (a linear track has no preset)",
            (long)id, GF_CHANNEL_MEAS, (long)id, GF_CHANNEL_CTRL, (long)id);
    } else {
        say(node,
            "track %ld (%s) refused (strict): no configured model's channels "
            "name %s%ld or %s%ld",
            (long)id, kind_name(kind), GF_CHANNEL_MEAS, (long)id,
            GF_CHANNEL_CTRL, (long)id);
    }
    return GF_NODE_NO_MODEL;
}

// The track with this id (of this kind), created from mdl (NULL: the
// lookup's) if it is new.
static gf_node_track *track_get_with(gf_node *node, int32_t id, int8_t model,
                                     int64_t utime, const gf_node_model *mdl,
                                     gf_node_result *why)
{
    gf_node_track *t;
    gaussfilt_lcm_belief_t b;
    const gf_node_model *use = mdl;
    unsigned i;
    int named = 0;
    for (i = 0; i < node->ntracks; i++) {
        t = &node->tracks[i];
        if (t->id == id) {
            if (t->model != model) {
                *why = GF_NODE_BAD_FIELD;
                return NULL;
            }
            return t;
        }
    }
    if (use == NULL) {
        use = model_for(node, id, model, &named);
        if (use == NULL) {
            *why = refuse(node, id, model);
            return NULL;
        }
    }
    if (node->ntracks >= GF_NODE_MAX_TRACKS ||
        (model == MODEL_ROBOT && node->robot_filter == GF_NODE_FILTER_PF &&
         (node->pf_pool == NULL || node->pf_pool->used >= GF_NODE_PF_TRACKS))) {
        if (say_first(node, id, SAY_TRACK_LIMIT)) {
            say(node,
                "track %ld (%s): no room for it: the node holds %u tracks "
                "(at most GF_NODE_MAX_TRACKS = %d, GF_NODE_PF_TRACKS = %d "
                "with --filter pf) (track_limit)",
                (long)id, kind_name(model), node->ntracks, GF_NODE_MAX_TRACKS,
                GF_NODE_PF_TRACKS);
        }
        *why = GF_NODE_TRACK_LIMIT;
        return NULL;
    }
    t = &node->tracks[node->ntracks++];
    memset(t, 0, sizeof(*t));
    t->id = id;
    t->model = model;
    t->mdl = *use;
    t->counting = (1u << GF_NODE_STREAMS) - 1u;
    track_prior(node, t);
    node->counts.tracks_created++;
    if (mdl != NULL) {
        say(node, "track %ld (%s): model %s from a model_t", (long)id,
            kind_name(model), use->name);
    } else if (named && use->channels != NULL && use->lin != NULL &&
               use->lin->gen != NULL) {
        // the states named as its library's descriptor names them
        const gf_codegen_model *d = use->lin->gen->desc;
        char states[256] = "";
        unsigned k;
        for (k = 0; k < d->n; k++) {
            size_t used = strlen(states);
            snprintf(states + used, sizeof states - used, "%s%s (%s)",
                     k > 0 ? ", " : "", d->states[k],
                     d->units[k][0] != '\0' ? d->units[k] : "-");
        }
        say(node,
            "track %ld (generated, gf_ekf: %s from %s): model %s, its "
            "channels %s name it",
            (long)id, states, use->lin->gen->path, use->name, use->channels);
    } else if (named && use->channels != NULL) {
        say(node, "track %ld (%s%s): model %s, its channels %s name it",
            (long)id, kind_name(model), model == MODEL_LINEAR ? ", gf_kf" : "",
            use->name, use->channels);
    } else if (named) {
        say(node, "track %ld (%s): model %s, named by the node's lookup",
            (long)id, kind_name(model), use->name);
    } else {
        say(node,
            "track %ld (%s): the preset %s: no configured model's channels "
            "name %s%ld or %s%ld (strict refuses such a track)",
            (long)id, kind_name(model), use->name, GF_CHANNEL_MEAS, (long)id,
            GF_CHANNEL_CTRL, (long)id);
    }
    peer_early_track(node, t);
    belief_fill(node, t, &b);
    b.utime = utime;
    b.input_seq = -1;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
    publish_step(node, t, &b);
    return t;
}

static gf_node_track *track_get(gf_node *node, int32_t id, int8_t model,
                                int64_t utime, gf_node_result *why)
{
    return track_get_with(node, id, model, utime, NULL, why);
}

// A track in time: its motion built from dt (dt-built axes, or a generated
// model's g and R(dt); see node_core.h).
static int timed(const gf_node_track *t)
{
    return t->model == MODEL_LINEAR &&
           (t->mdl.lin->axes > 0 || t->mdl.lin->gen != NULL);
}

// An input of a stream received, taken or refused, with a seq newer than
// the stream's last: the seq numbers skipped since that last are gaps; a
// session's first input of the stream with seq > 1 says that the ones
// before it never arrived (lost_before_first; those refused before the
// track was made did arrive).
static void stream_seen(gf_node *node, gf_node_track *t, unsigned stream,
                        int64_t seq)
{
    const char *sensor =
        stream > 0 ? t->mdl.sensors->s[stream - 1u].name : NULL;
    unsigned bit = 1u << stream;
    // seq > the stream's last here; unsigned arithmetic cannot overflow.
    if (t->has_seq & bit) {
        node->counts.gaps += (uint64_t)seq - (uint64_t)t->seq[stream] - 1u;
    } else if ((t->counting & bit) && seq > 1) {
        uint64_t lost = (uint64_t)seq - 1u;
        int i = said_index(node, t->id, 0);
        if (i >= 0) {
            uint64_t k = node->said[i].refused[stream];
            lost -= k < lost ? k : lost;
            node->said[i].refused[stream] = 0;
        }
        if (lost > 0) {
            // a session's seq starts at 1: the inputs before this one
            // were sent and never arrived (before the node was ready,
            // typically)
            node->counts.lost_before_first += lost;
            say(node,
                "track %ld: its first input%s%s has seq %lld: %llu earlier "
                "input%s never reached this node (sent before it was "
                "ready?)",
                (long)t->id, sensor != NULL ? " of sensor " : "",
                sensor != NULL ? sensor : "", (long long)seq,
                (unsigned long long)lost, lost == 1 ? "" : "s");
        }
    }
    t->counting &= ~bit;
    t->has_seq |= bit;
    t->seq[stream] = seq;
}

// Sequence rules, per stream: seq strictly increasing (equal = duplicate,
// lower = out of order). Time: an input older than the track's time is
// out of order (a track in time: late within its late_window, else
// too_old). After GF_NODE_RESYNC_AFTER such rejections in a row the next
// input is the new reference (node_core.h).
static gf_node_result check_order(gf_node *node, gf_node_track *t,
                                  unsigned stream, int64_t seq, int64_t utime)
{
    gf_node_result r = GF_NODE_APPLIED;
    unsigned bit = 1u << stream;
    if ((t->has_seq & bit) && seq == t->seq[stream]) {
        return GF_NODE_DUPLICATE;
    }
    if ((t->has_seq & bit) && seq < t->seq[stream]) {
        r = GF_NODE_OUT_OF_ORDER;
    } else if (t->has_time && utime < t->time) {
        r = GF_NODE_OUT_OF_ORDER;
        if (timed(t)) {
            // (a difference beyond int64's range is too old)
            r = (double)t->time - (double)utime <= t->mdl.late_window * 1e6
                    ? GF_NODE_LATE
                    : GF_NODE_TOO_OLD;
        }
    }
    if (r == GF_NODE_APPLIED) {
        return r;
    }
    if ((r == GF_NODE_LATE || r == GF_NODE_TOO_OLD) &&
        (!(t->has_seq & bit) || seq > t->seq[stream])) {
        // received, in its stream's order: no gap for it later
        stream_seen(node, t, stream, seq);
    }
    if (t->rejected >= GF_NODE_RESYNC_AFTER) {
        node->counts.seq_resyncs++;
        t->has_seq &= ~bit; // no gap counted for the jump
        if (utime < t->time) {
            t->time = utime; // and no prediction over it
        }
        t->rejected = 0;
        return GF_NODE_APPLIED;
    }
    t->rejected++;
    return r;
}

// Session rule (see node_core.h): a larger session re-initialises the
// track from the prior, a smaller one is stale; then the sequence rules.
static gf_node_result admit(gf_node *node, gf_node_track *t, unsigned stream,
                            int64_t session, int64_t seq, int64_t utime)
{
    gaussfilt_lcm_belief_t b;
    if (t->has_input && session != t->session) {
        if (session < t->session) {
            return GF_NODE_STALE_SESSION;
        }
        t->has_input = 0;
        t->has_time = 0;
        t->has_seq = 0;
        t->counting = (1u << GF_NODE_STREAMS) - 1u;
        track_prior(node, t);
        node->counts.resyncs++;
        t->belief_seq++;
        belief_fill(node, t, &b);
        b.utime = utime;
        b.input_seq = -1;
        b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
        publish_step(node, t, &b);
    }
    return check_order(node, t, stream, seq, utime);
}

// Takes an admitted input: gaps, the first input's losses, the track's
// time. Returns the seconds a track in time predicts over before it: the
// time since its last input, or, for its first, the model's dt (the
// prior holds dt before the first input).
static double consume(gf_node *node, gf_node_track *t, unsigned stream,
                      int64_t session, int64_t seq, int64_t utime, int64_t now)
{
    double dt = t->mdl.dt;
    stream_seen(node, t, stream, seq);
    if (t->has_time) {
        // utime >= time here (check_order)
        dt = (double)((uint64_t)utime - (uint64_t)t->time) / 1e6;
    }
    t->has_input = 1;
    t->rejected = 0;
    t->session = session;
    t->input_seq = seq;
    t->time = utime;
    t->has_time = 1;
    t->last_rx = now;
    return dt;
}

static gf_node_result from_status(int s)
{
    if (s == GF_OK) {
        return GF_NODE_APPLIED;
    }
    if (s == GF_NODE_STATUS_NO_SUMMARY) {
        return GF_NODE_NO_SUMMARY;
    }
    if (s == GF_ERR_GATED) {
        return GF_NODE_GATED;
    }
    return s == GF_ERR_NONFINITE ? GF_NODE_NONFINITE : GF_NODE_FILTER_ERROR;
}

// ---- the two inputs ---------------------------------------------------------

// A PF track's correction: importance weights, then low-variance
// resampling once fewer than GF_NODE_PF_RESAMPLE_FRACTION of the particles
// are effective. The summary is taken after resampling; the neff the
// cloud reports is the one that decided it.
static int pf_correct(gf_node *node, gf_node_track *t, const gf_ekf3_meas *mm,
                      const gf_vec3 *z)
{
    gf_pf3 *pf = track_pf(node, t);
    gf_real neff = GF_R(0.0);
    gf_status s = gf_pf3_update(pf, mm, z);
    t->f.pf3.resampled = 0;
    if (s != GF_OK) {
        return s;
    }
    if (gf_pf3_neff(pf, &neff) == GF_OK &&
        neff < (gf_real)(GF_NODE_PF_RESAMPLE_FRACTION * pf->n)) {
        s = gf_pf3_resample(pf);
        if (s != GF_OK) {
            return s;
        }
        t->f.pf3.resampled = 1;
    }
    if (pf_summary(t) != GF_NODE_APPLIED) {
        return GF_NODE_STATUS_NO_SUMMARY;
    }
    t->f.pf3.neff = neff;
    return GF_OK;
}

// A linear track's motion in gf_real, into the node's scratch: A, B, R,
// built for a step of dt seconds when the track is in time, else as given.
static void linear_motion(gf_node *node, const gf_node_track *t, double dt)
{
    const gf_node_linear *l = t->mdl.lin;
    const double *A = l->A, *R = l->R;
    unsigned i, n = l->n;
    if (timed(t)) {
        gf_node_linear_motion(l, dt, node->dA, node->dR);
        A = node->dA;
        R = node->dR;
    }
    for (i = 0; i < n * n; i++) {
        node->lin[0][i] = (gf_real)A[i];
        node->lin[2][i] = (gf_real)R[i];
    }
    for (i = 0; i < n * l->nu; i++) {
        node->lin[1][i] = (gf_real)l->B[i];
    }
}

// mu_bar = A mu + B u, Sigma_bar = A Sigma A^T + R, for dt seconds (u:
// nu entries in node->vec[0], or none when nu = 0).
static int linear_predict(gf_node *node, gf_node_track *t, gf_kf *kf, double dt,
                          unsigned nu)
{
    gf_kf_model km;
    const gf_node_generated *gen = t->mdl.lin->gen;
    if (gen != NULL) {
        // a generated model: g and R(dt) from its library; g's u is the
        // inputs (zeros without a control), then dt
        gf_ekf_motion em;
        unsigned i, nin = gen->desc->nu;
        for (i = nu; i < nin; i++) {
            node->vec[0][i] = GF_R(0.0);
        }
        node->vec[0][nin] = (gf_real)dt;
        gen->desc->R(gen->params, (gf_real)dt, node->lin[2]);
        em.g = gen->desc->g;
        em.ctx = (void *)(uintptr_t)gen->params;
        em.R = node->lin[2];
        return gf_ekf_predict(kf, &em, node->vec[0], &node->work);
    }
    linear_motion(node, t, dt);
    km.nu = t->mdl.lin->nu;
    km.A = node->lin[0];
    km.B = node->lin[1];
    km.R = node->lin[2];
    km.c = NULL;
    return gf_kf_predict(kf, &km, nu > 0 ? node->vec[0] : NULL, &node->work);
}

// A linear measurement with an angle mask (z_hat = C mu_bar, H = C): ctx
// is C in gf_real, m rows of n.
static gf_status linear_h(void *ctx, unsigned n, unsigned m,
                          const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    const gf_real *C = (const gf_real *)ctx;
    unsigned i, j;
    for (i = 0; i < m; i++) {
        gf_real v = GF_R(0.0);
        for (j = 0; j < n; j++) {
            v += C[i * n + j] * mu_bar[j];
            H[i * n + j] = C[i * n + j];
        }
        z_hat[i] = v;
    }
    return GF_OK;
}

static int good_kind(int8_t model)
{
    return model == MODEL_CAR || model == MODEL_ROBOT || model == MODEL_LINEAR;
}

// The noise of a measurement: its q, or, for a named sensor's message
// whose q is all zero, the sensor's Q (m x m, into q).
static void meas_noise(const gf_node_sensor *sen, const node_meas *z,
                       unsigned m, double q[GF_NODE_NMAX][GF_NODE_NMAX])
{
    unsigned i, j;
    int zero = 1;
    for (i = 0; i < m; i++) {
        for (j = 0; j < m; j++) {
            q[i][j] = z->q[i][j];
            zero &=
                !(z->q[i][j] < 0.0 || z->q[i][j] > 0.0) && !isnan(z->q[i][j]);
        }
    }
    if (sen != NULL && zero) {
        for (i = 0; i < m; i++) {
            for (j = 0; j < m; j++) {
                q[i][j] = sen->Q[i * m + j];
            }
        }
    }
}

// An input as its refusal sees it: a control's or a measurement's header.
typedef struct node_in {
    const char *what; // "control", "measurement"
    int8_t stage;     // of its status belief: the step it asked for
    int64_t utime, seq, session;
    const char *sensor; // the configured sensor it came from, or NULL
} node_in;

// The status belief of an input the node refused: the track's belief as
// it is, with the input's utime, seq and stage.
static void publish_refused(gf_node *node, gf_node_track *t, const node_in *in,
                            int status)
{
    gaussfilt_lcm_belief_t b;
    t->belief_seq++;
    belief_fill(node, t, &b);
    b.utime = in->utime;
    b.input_seq = in->seq;
    b.stage = in->stage;
    b.status = (int8_t)status;
    if (in->sensor != NULL) {
        b.sensor = (char *)(uintptr_t)in->sensor;
    }
    publish_step(node, t, &b);
}

// The track the node holds with this id, or NULL.
static gf_node_track *track_of(gf_node *node, int32_t id)
{
    return (gf_node_track *)(uintptr_t)gf_node_find(node, id);
}

// An input of track id refused for one of its fields (bad_field), which
// fmt says (once per track id and topic, as "track ID: ... (bad_field)").
// A track the node holds publishes a status belief for it, and counts its
// seq as received in its stream (-1: none), so that no gap is counted for
// it; before the track is made it is remembered as received for the
// track's first input (stream_seen).
static gf_node_result refuse_field(gf_node *node, int32_t id, unsigned topic,
                                   const node_in *in, int stream,
                                   const char *fmt, ...)
{
    gf_node_track *t = track_of(node, id);
    if (say_first(node, id, topic)) {
        char why[200];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(why, sizeof why, fmt, ap);
        va_end(ap);
        say(node, "track %ld: %s (bad_field)", (long)id, why);
    }
    if (t == NULL) {
        int i = stream >= 0 ? said_index(node, id, 1) : -1;
        if (i >= 0) {
            node->said[i].refused[stream]++;
        }
        return GF_NODE_BAD_FIELD;
    }
    if (stream >= 0 && (!t->has_input || in->session == t->session) &&
        (!(t->has_seq & (1u << stream)) || in->seq > t->seq[stream])) {
        stream_seen(node, t, (unsigned)stream, in->seq);
    }
    publish_refused(node, t, in, GF_NODE_STATUS_BAD_FIELD);
    return GF_NODE_BAD_FIELD;
}

// An input admit() refused (duplicate, out_of_order, stale_session, late,
// too_old): its status belief, and a line once per track and reason.
static gf_node_result refuse_order(gf_node *node, gf_node_track *t,
                                   gf_node_result r, const node_in *in,
                                   unsigned stream)
{
    const char *of = in->sensor != NULL ? " of sensor " : "";
    const char *sen = in->sensor != NULL ? in->sensor : "";
    double age = ((double)t->time - (double)in->utime) / 1e6;
    int status = GF_NODE_STATUS_OUT_OF_ORDER;
    unsigned topic = SAY_OUT_OF_ORDER;
    switch (r) {
    case GF_NODE_DUPLICATE:
        status = GF_NODE_STATUS_DUPLICATE;
        topic = SAY_DUPLICATE;
        break;
    case GF_NODE_STALE_SESSION:
        status = GF_NODE_STATUS_STALE_SESSION;
        topic = SAY_STALE;
        break;
    case GF_NODE_LATE:
        status = GF_NODE_STATUS_LATE;
        topic = SAY_LATE;
        break;
    case GF_NODE_TOO_OLD:
        status = GF_NODE_STATUS_TOO_OLD;
        topic = SAY_TOO_OLD;
        break;
    default:
        break;
    }
    if (say_first(node, t->id, topic)) {
        switch (r) {
        case GF_NODE_DUPLICATE:
            say(node,
                "track %ld: a %s%s%s with seq %lld came again (duplicate)",
                (long)t->id, in->what, of, sen, (long long)in->seq);
            break;
        case GF_NODE_STALE_SESSION:
            say(node,
                "track %ld: a %s%s%s of session %lld after session %lld's "
                "(stale_session)",
                (long)t->id, in->what, of, sen, (long long)in->session,
                (long long)t->session);
            break;
        case GF_NODE_LATE:
        case GF_NODE_TOO_OLD:
            say(node,
                "track %ld: a %s%s%s %.6g s older than the track's time, "
                "its model %s's late_window %g s (%s)",
                (long)t->id, in->what, of, sen, age, t->mdl.name,
                t->mdl.late_window, r == GF_NODE_LATE ? "late" : "too_old");
            break;
        default:
            say(node,
                "track %ld: a %s%s%s with seq %lld, utime %lld: its stream "
                "is at seq %lld, the track at utime %lld (out_of_order)",
                (long)t->id, in->what, of, sen, (long long)in->seq,
                (long long)in->utime, (long long)t->seq[stream],
                (long long)t->time);
            break;
        }
    }
    publish_refused(node, t, in, status);
    return r;
}

// A step the core refused (its belief published with that status), or a
// PF step without a summary: said once per track.
static void step_failed(gf_node *node, const gf_node_track *t,
                        const node_in *in, int s)
{
    if (s == GF_OK || s == GF_ERR_GATED || !say_first(node, t->id, SAY_STEP)) {
        return;
    }
    say(node,
        "track %ld: a %s%s%s with seq %lld: its step failed with status %d "
        "(%s), published with it (%s)",
        (long)t->id, in->what, in->sensor != NULL ? " of sensor " : "",
        in->sensor != NULL ? in->sensor : "", (long long)in->seq, s,
        s == GF_NODE_STATUS_NO_SUMMARY ? "STATUS_NO_SUMMARY"
                                       : gf_status_str((gf_status)s),
        gf_node_result_str(from_status(s)));
}

// An update that ran (applied or gated, belief b): its NIS into the
// track's sums; a track whose first GF_NODE_GATED_WARN updates were all
// gated, or later as many in a row, said once each.
static void update_seen(gf_node *node, gf_node_track *t,
                        const gaussfilt_lcm_belief_t *b, int s, double gate)
{
    if (s != GF_OK && s != GF_ERR_GATED) {
        return;
    }
    t->updates++;
    if (b->m > 0) {
        t->nis_last = b->nis;
        t->m_last = (unsigned)b->m;
        t->nis_sum += b->nis;
        t->nis_dof += (unsigned)b->m;
        t->nis_n++;
    }
    t->gated_run = s == GF_ERR_GATED ? t->gated_run + 1u : 0u;
    if (t->gated_run != GF_NODE_GATED_WARN) {
        return;
    }
    if (t->updates == t->gated_run) {
        if (say_first(node, t->id, SAY_GATED_FIRST)) {
            say(node,
                "track %ld: its first %u updates were all gated (the last "
                "NIS %.4g > gate %g of model %s): prior too tight or wrong?",
                (long)t->id, t->gated_run, b->nis, gate, t->mdl.name);
        }
    } else if (say_first(node, t->id, SAY_GATED_RUN)) {
        say(node,
            "track %ld: %u updates in a row gated (the last NIS %.4g > gate "
            "%g of model %s): has the track been lost? (a model_t with reset "
            "= 1 restarts it)",
            (long)t->id, t->gated_run, b->nis, gate, t->mdl.name);
    }
}

// The model of another kind the node's lookup names for track id, which
// a new track of this kind would otherwise run without (NULL: none).
static const gf_node_model *model_elsewhere(const gf_node *node, int32_t id,
                                            int8_t kind)
{
    static const int8_t kinds[3] = {MODEL_CAR, MODEL_ROBOT, MODEL_LINEAR};
    const gf_node_model *m;
    unsigned k;
    if (node->models == NULL) {
        return NULL;
    }
    for (k = 0; k < 3; k++) {
        if (kinds[k] != kind &&
            (m = node->models(node->models_ctx, id, kinds[k])) != NULL &&
            m->kind == kinds[k] && m != gf_node_model_book_car() &&
            m != gf_node_model_book_robot()) {
            return m;
        }
    }
    return NULL;
}

// The input stream of a message on GF_MEAS_<id>[_<sensor>] or
// GF_CTRL_<id> under model mdl: 0, 1 + the sensor's index, or -1 (a
// sensor mdl lacks).
static int stream_of(const gf_node_model *mdl, const char *sensor)
{
    const gf_node_sensor *sen;
    if (sensor == NULL) {
        return 0;
    }
    sen = mdl != NULL ? gf_node_model_sensor(mdl, sensor) : NULL;
    return sen != NULL ? 1 + (int)(sen - mdl->sensors->s) : -1;
}

// The model kind checks every input makes before its sizes: the kind
// names a model, is the track's, or (a track not made yet) no model of
// another kind names the track. Returns GF_NODE_APPLIED, or the refusal.
static gf_node_result check_kind(gf_node *node, int32_t id, int8_t kind,
                                 const node_in *in)
{
    const gf_node_track *t = gf_node_find(node, id);
    const gf_node_model *other;
    if (!good_kind(kind)) {
        return refuse_field(node, id, SAY_KIND, in,
                            stream_of(t != NULL ? &t->mdl : NULL, in->sensor),
                            "a %s says model %d (MODEL_CAR 1, MODEL_ROBOT 2 "
                            "or MODEL_LINEAR 3)",
                            in->what, (int)kind);
    }
    if (t != NULL && t->model != kind) {
        return refuse_field(node, id, SAY_KIND, in,
                            stream_of(&t->mdl, in->sensor),
                            "a %s says model %d (%s), the track is %s (model "
                            "%s)",
                            in->what, (int)kind, kind_name(kind),
                            kind_name(t->model), t->mdl.name);
    }
    if (t == NULL && (other = model_elsewhere(node, id, kind)) != NULL) {
        return refuse_field(
            node, id, SAY_KIND, in, stream_of(other, in->sensor),
            "a %s says model %d (%s), but the configured model %s (%s) "
            "names the track: its messages say model %d",
            in->what, (int)kind, kind_name(kind), other->name,
            kind_name(other->kind), (int)other->kind);
    }
    return GF_NODE_APPLIED;
}

static gf_node_result handle_ctrl(gf_node *node, int32_t id, const node_ctrl *c,
                                  int64_t now)
{
    gf_node_result r = GF_NODE_APPLIED;
    gf_node_track *t;
    const gf_node_model *mdl;
    gaussfilt_lcm_belief_t b;
    node_in in;
    double dt;
    int64_t time0;
    int s, has_time0, named;
    in.what = "control";
    in.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
    in.utime = c->utime;
    in.seq = c->seq;
    in.session = c->session;
    in.sensor = NULL;
    if (c->track != id) {
        return refuse_field(node, id, SAY_TRACK, &in, -1,
                            "a control on %s%ld says track %ld",
                            GF_CHANNEL_CTRL, (long)id, (long)c->track);
    }
    r = check_kind(node, id, c->model, &in);
    if (r != GF_NODE_APPLIED) {
        return r;
    }
    t = track_of(node, id);
    mdl = t != NULL ? &t->mdl : model_for(node, id, c->model, &named);
    if (c->n > GF_NODE_NMAX) {
        return refuse_field(node, id, SAY_SIZE_N, &in, 0,
                            "a control has n = %d, more than any model "
                            "takes (%d)",
                            (int)c->n, GF_NODE_NMAX);
    }
    if (c->model == MODEL_LINEAR) {
        // no control, or the model's nu
        if (mdl != NULL && c->n != 0 && (unsigned)c->n != mdl->lin->nu) {
            if (mdl->lin->nu == 0) {
                return refuse_field(node, id, SAY_SIZE_N, &in, 0,
                                    "a control has n = %d, its model %s "
                                    "takes n = 0 (it has no B)",
                                    (int)c->n, mdl->name);
            }
            return refuse_field(node, id, SAY_SIZE_N, &in, 0,
                                "a control has n = %d, its model %s takes n "
                                "= 0 or %u (%s)",
                                (int)c->n, mdl->name, mdl->lin->nu,
                                mdl->lin->gen != NULL ? "its inputs"
                                                      : "B's columns");
        }
    } else if (c->model == MODEL_CAR ? (c->n != 0 && c->n != 2) : c->n != 2) {
        return refuse_field(node, id, SAY_SIZE_N, &in, 0,
                            c->model == MODEL_CAR
                                ? "a control has n = %d, a car takes n = 0 "
                                  "or 2 (B u, B = I)"
                                : "a control has n = %d, a robot takes n = 2 "
                                  "(u = (d, phi))",
                            (int)c->n);
    }
    t = track_get(node, id, c->model, c->utime, &r);
    if (t == NULL) {
        return r;
    }
    r = admit(node, t, 0, c->session, c->seq, c->utime);
    if (r != GF_NODE_APPLIED) {
        return refuse_order(node, t, r, &in, 0);
    }
    time0 = t->time;
    has_time0 = t->has_time;
    dt = consume(node, t, 0, c->session, c->seq, c->utime, now);
    if (t->model == MODEL_LINEAR) {
        unsigned i;
        for (i = 0; i < (unsigned)c->n; i++) {
            node->vec[0][i] = (gf_real)c->u[i];
        }
        // one step of the model's A, or, in time, over the dt since the
        // last input (a failed one leaves the track where it was: its
        // belief and its time)
        s = linear_predict(node, t, &t->f.kf, dt, (unsigned)c->n);
        if (s != GF_OK && timed(t)) {
            t->time = time0;
            t->has_time = has_time0;
        }
    } else if (t->model == MODEL_CAR) {
        gf_kf2_model km;
        gf_vec2 u;
        gf_node_model_car(&t->mdl, &km);
        u.v[0] = (gf_real)c->u[0];
        u.v[1] = (gf_real)c->u[1];
        s = gf_kf2_predict(&t->f.kf2, &km, c->n == 2 ? &u : NULL);
    } else {
        gf_ekf3_motion mot;
        gf_real u[2];
        gf_vec3 mu;
        gf_mat3 sigma;
        robot_moments(t, &mu, &sigma);
        u[0] = (gf_real)c->u[0];
        u[1] = (gf_real)c->u[1];
        // R at the mean's heading (a PF with no summary: heading 0)
        gf_node_model_robot(
            &t->mdl, isfinite((double)mu.v[2]) ? mu.v[2] : GF_R(0.0), u, &mot);
        if (t->filter == FILTER_UKF3) {
            s = gf_ukf3_predict(&t->f.ukf3, &mot, u);
        } else if (t->filter == FILTER_PF3) {
            s = gf_pf3_predict(track_pf(node, t), &mot, u);
            t->f.pf3.resampled = 0;
            if (s == GF_OK && pf_summary(t) != GF_NODE_APPLIED) {
                s = GF_NODE_STATUS_NO_SUMMARY;
            }
        } else {
            s = gf_ekf3_predict(&t->f.ekf3, &mot, u);
        }
    }
    t->belief_seq++;
    belief_fill(node, t, &b);
    b.utime = c->utime;
    b.input_seq = c->seq;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
    b.status = (int8_t)s;
    publish_step(node, t, &b);
    step_failed(node, t, &in, s);
    return from_status(s);
}

// A linear track's correction by C (its model's, or a sensor's) with the
// noise q; a sensor with an angle mask wraps those residuals (gf_ekf on
// the same belief, h = C x).
static int linear_correct(gf_node *node, gf_node_track *t,
                          const gf_node_sensor *sen, const node_meas *z,
                          const double q[GF_NODE_NMAX][GF_NODE_NMAX],
                          gf_kf_innovation *kinfo)
{
    const gf_node_linear *l = t->mdl.lin;
    const double *C = sen != NULL ? sen->C : l->C;
    unsigned i, j, n = l->n, m = sen != NULL ? sen->m : l->m;
    gf_real gate = (gf_real)(sen != NULL ? sen->gate : t->mdl.gate);
    for (i = 0; i < m * n; i++) {
        node->lin[3][i] = (gf_real)C[i];
    }
    for (i = 0; i < m; i++) {
        node->vec[1][i] = (gf_real)z->z[i];
        for (j = 0; j < m; j++) {
            node->lin[4][i * m + j] = (gf_real)q[i][j];
        }
    }
    if (l->gen != NULL || (sen != NULL && sen->angle_mask != 0u)) {
        // a generated model's sensor (always named: its library's h, in
        // the order of the descriptor), or C x with angles wrapped
        gf_ekf_meas em;
        em.m = m;
        em.h = linear_h;
        em.ctx = node->lin[3];
        if (l->gen != NULL) {
            em.h = l->gen->desc->sensors[sen - t->mdl.sensors->s].h;
            em.ctx = (void *)(uintptr_t)l->gen->params;
        }
        em.Q = node->lin[4];
        em.angle_mask = sen->angle_mask;
        em.gate = gate;
        return gf_ekf_update(&t->f.kf, &em, node->vec[1], kinfo, &node->work);
    }
    {
        gf_kf_meas km;
        km.m = m;
        km.C = node->lin[3];
        km.Q = node->lin[4];
        km.c = NULL;
        km.gate = gate;
        // K = Sigma_bar C^T (C Sigma_bar C^T + Q)^-1, mu = mu_bar + K (z -
        // C mu_bar), on the factors
        return gf_kf_update(&t->f.kf, &km, node->vec[1], kinfo, &node->work);
    }
}

// The sensor a message on GF_MEAS_<id>_<name> names in the model of track
// id (mdl: the track's, or the one it would be made with), or NULL: said
// once per track id.
static const gf_node_sensor *model_sensor(gf_node *node, int32_t id,
                                          const gf_node_model *mdl,
                                          const char *name, unsigned *stream)
{
    const gf_node_sensor *sen = gf_node_model_sensor(mdl, name);
    if (sen != NULL) {
        *stream = 1u + (unsigned)(sen - mdl->sensors->s);
        return sen;
    }
    if (!say_first(node, id, SAY_SENSOR)) {
        return NULL;
    }
    say(node,
        "track %ld: a measurement on %s%ld_%s: its model %s has no sensor "
        "%s (bad_field)",
        (long)id, GF_CHANNEL_MEAS, (long)id, name, mdl->name, name);
    return NULL;
}

static gf_node_result handle_meas(gf_node *node, int32_t id, const node_meas *z,
                                  const char *sensor, int64_t now)
{
    gf_node_result r = GF_NODE_APPLIED;
    gf_node_track *t;
    const gf_node_model *mdl;
    const gf_node_sensor *sen = NULL;
    gaussfilt_lcm_belief_t b;
    gf_innovation info;
    gf_kf_innovation kinfo;
    node_in in;
    double q[GF_NODE_NMAX][GF_NODE_NMAX], dt;
    int64_t time0;
    int s = GF_OK, measure = 0, has_time0, named;
    unsigned i, m, stream = 0;
    in.what = "measurement";
    in.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
    in.utime = z->utime;
    in.seq = z->seq;
    in.session = z->session;
    in.sensor = NULL;
    if (z->track != id) {
        return refuse_field(node, id, SAY_TRACK, &in, -1,
                            "a measurement on %s%ld%s%s says track %ld",
                            GF_CHANNEL_MEAS, (long)id,
                            sensor != NULL ? "_" : "",
                            sensor != NULL ? sensor : "", (long)z->track);
    }
    if (sensor != NULL && z->model == MODEL_CAR) {
        return refuse_field(node, id, SAY_SENSOR, &in, -1,
                            "a measurement on %s%ld_%s says model 1 (car): "
                            "a car has no sensors",
                            GF_CHANNEL_MEAS, (long)id, sensor);
    }
    r = check_kind(node, id, z->model, &in);
    if (r != GF_NODE_APPLIED) {
        return r;
    }
    t = track_of(node, id);
    mdl = t != NULL ? &t->mdl : model_for(node, id, z->model, &named);
    if (sensor != NULL && mdl != NULL) {
        // a named sensor: the track's model says what it measures
        sen = model_sensor(node, id, mdl, sensor, &stream);
        if (sen == NULL) {
            return refuse_field(node, id, SAY_SENSOR, &in, -1, "no sensor %s",
                                sensor);
        }
        in.sensor = sen->name;
    }
    if (z->m < 1 || z->m > GF_NODE_NMAX ||
        (z->model != MODEL_LINEAR && z->m > 2)) {
        return refuse_field(node, id, SAY_SIZE_M, &in, (int)stream,
                            "a measurement has m = %d, %s", (int)z->m,
                            z->m < 1 ? "at least 1 is measured"
                            : z->m > GF_NODE_NMAX
                                ? "more than any model measures "
                                  "(" GF_NODE_NMAX_STR ")"
                                : "a car or robot measures 1 or 2");
    }
    m = (unsigned)z->m;
    if (sen != NULL && m != sen->m) {
        return refuse_field(node, id, SAY_SIZE_M, &in, (int)stream,
                            "a measurement of sensor %s has m = %u, the "
                            "sensor measures m = %u",
                            sen->name, m, sen->m);
    }
    if (sen == NULL && mdl != NULL && z->model == MODEL_LINEAR) {
        if (mdl->lin->m == 0) {
            return refuse_field(node, id, SAY_SIZE_M, &in, 0,
                                "a measurement on %s%ld: its model %s "
                                "measures on its sensors' channels only (%s%ld_"
                                "<sensor>)",
                                GF_CHANNEL_MEAS, (long)id, mdl->name,
                                GF_CHANNEL_MEAS, (long)id);
        }
        if (m != mdl->lin->m) {
            return refuse_field(node, id, SAY_SIZE_M, &in, 0,
                                "a measurement has m = %u, its model %s "
                                "measures m = %u (C's rows)",
                                m, mdl->name, mdl->lin->m);
        }
    } else if (sen == NULL && mdl != NULL) {
        measure = gf_node_model_measure(mdl, m);
        if (measure < 0) {
            return refuse_field(
                node, id, SAY_SIZE_M, &in, 0,
                "a measurement has m = %u, its model %s measures m = %u", m,
                mdl->name, gf_node_measure_m(mdl->kind, mdl->measure));
        }
    }
    // (a track that would be refused: no_model from here)
    t = track_get(node, id, z->model, z->utime, &r);
    if (t == NULL) {
        return r;
    }
    r = admit(node, t, stream, z->session, z->seq, z->utime);
    if (r != GF_NODE_APPLIED) {
        return refuse_order(node, t, r, &in, stream);
    }
    time0 = t->time;
    has_time0 = t->has_time;
    dt = consume(node, t, stream, z->session, z->seq, z->utime, now);
    memset(&info, 0, sizeof(info));
    memset(&kinfo, 0, sizeof(kinfo));
    meas_noise(sen, z, m, q);
    if (t->model == MODEL_LINEAR) {
        // in time: predicted to the measurement's utime first. A gated
        // measurement leaves the prediction (the belief at its time); any
        // other failure the track where it was, its belief and its time
        if (timed(t) && dt > 0.0) {
            node->ahead.kf = t->f.kf;
            s = linear_predict(node, t, &t->f.kf, dt, 0);
        }
        if (s == GF_OK) {
            s = linear_correct(node, t, sen, z,
                               (const double(*)[GF_NODE_NMAX])q, &kinfo);
        }
        if (s != GF_OK && s != GF_ERR_GATED && timed(t)) {
            if (dt > 0.0) {
                t->f.kf = node->ahead.kf;
            }
            t->time = time0;
            t->has_time = has_time0;
        }
    } else if (t->model == MODEL_CAR) {
        gf_kf2_meas mm;
        gf_vec2 zz;
        double q3[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        for (i = 0; i < m; i++) {
            for (unsigned j = 0; j < m; j++) {
                q3[i][j] = q[i][j];
            }
        }
        gf_node_model_car_meas(&t->mdl, measure, (const double(*)[3])q3, &mm);
        for (i = 0; i < m; i++) {
            zz.v[i] = (gf_real)z->z[i];
        }
        if (m == 1) {
            zz.v[1] = GF_R(0.0);
        }
        s = gf_kf2_update(&t->f.kf2, &mm, &zz, &info);
    } else {
        gf_ekf3_meas mm;
        gf_vec3 zz;
        double q3[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        for (i = 0; i < m; i++) {
            for (unsigned j = 0; j < m; j++) {
                q3[i][j] = q[i][j];
            }
        }
        memset(&zz, 0, sizeof(zz));
        if (sen != NULL) {
            gf_node_sensor_robot_meas(sen, (const double(*)[3])q3, &mm);
        } else {
            gf_node_model_robot_meas(&t->mdl, measure, (const double(*)[3])q3,
                                     &mm);
        }
        for (i = 0; i < m; i++) {
            zz.v[i] = (gf_real)z->z[i];
        }
        if (t->filter == FILTER_UKF3) {
            s = gf_ukf3_update(&t->f.ukf3, &mm, &zz, &info);
        } else if (t->filter == FILTER_PF3) {
            s = pf_correct(node, t, &mm, &zz);
        } else {
            s = gf_ekf3_update(&t->f.ekf3, &mm, &zz, &info);
        }
    }
    t->belief_seq++;
    belief_fill(node, t, &b);
    b.utime = z->utime;
    b.input_seq = z->seq;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
    b.status = (int8_t)s;
    if (sen != NULL) {
        b.sensor = (char *)(uintptr_t)sen->name;
    }
    if ((s == GF_OK || s == GF_ERR_GATED) && t->filter == FILTER_KF) {
        b.m = (int8_t)kinfo.m;
        for (i = 0; i < kinfo.m; i++) {
            node->innovation[i] = (double)kinfo.y[i];
        }
        b.nis = (double)kinfo.nis;
    } else if ((s == GF_OK || s == GF_ERR_GATED) && t->filter != FILTER_PF3) {
        b.m = (int8_t)info.m;
        for (i = 0; i < info.m && i < 3; i++) {
            node->innovation[i] = (double)info.y[i];
        }
        b.nis = (double)info.nis;
    }
    publish_step(node, t, &b);
    update_seen(node, t, &b, s, sen != NULL ? sen->gate : t->mdl.gate);
    step_failed(node, t, &in, s);
    return from_status(s);
}

// A model_t refused (bad_field): said every time (a model_t is an
// operator's command, and rare), with a status belief of the track when
// the node holds it (stage STAGE_INIT, input_seq -1).
static gf_node_result refuse_model(gf_node *node, int32_t id,
                                   const gaussfilt_lcm_model_t *mm,
                                   const char *fmt, ...)
{
    gf_node_track *t = track_of(node, id);
    node_in in;
    char why[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    say(node, "track %ld: a model_t refused: %s (bad_field)", (long)id, why);
    if (t != NULL) {
        in.what = "model_t";
        in.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
        in.utime = mm->utime;
        in.seq = -1;
        in.session = 0;
        in.sensor = NULL;
        publish_refused(node, t, &in, GF_NODE_STATUS_BAD_FIELD);
    }
    return GF_NODE_BAD_FIELD;
}

// Restarts a track's belief from its model's prior, published as a
// STAGE_INIT belief (at the track's time: its sequence and time go on).
static void track_reset(gf_node *node, gf_node_track *t, int64_t utime)
{
    gaussfilt_lcm_belief_t b;
    track_prior(node, t);
    t->updates = 0;
    t->gated_run = 0;
    t->belief_seq++;
    belief_fill(node, t, &b);
    b.utime = utime;
    b.input_seq = -1;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
    publish_step(node, t, &b);
}

// A model_t: checks it, then sets a car's or robot's model (creating the
// track from it if new), or resets a linear track (whose model is the
// configuration's); reset or a new track restarts the belief from its
// prior.
static gf_node_result handle_model(gf_node *node, int32_t id,
                                   const gaussfilt_lcm_model_t *mm)
{
    gf_node_model mdl;
    gf_node_track *t;
    gf_node_result r = GF_NODE_APPLIED;
    const gf_node_track *old;
    const char *why = NULL;
    unsigned i, j;
    if (mm->track != id) {
        return refuse_model(node, id, mm, "it says track %ld", (long)mm->track);
    }
    if (!good_kind(mm->model)) {
        return refuse_model(node, id, mm,
                            "it says model %d (MODEL_CAR 1, MODEL_ROBOT 2 or "
                            "MODEL_LINEAR 3)",
                            (int)mm->model);
    }
    old = gf_node_find(node, id);
    if (old != NULL && old->model != mm->model) {
        return refuse_model(node, id, mm,
                            "it says model %d (%s), the track is %s (model "
                            "%s)",
                            (int)mm->model, kind_name(mm->model),
                            kind_name(old->model), old->mdl.name);
    }
    if (mm->model == MODEL_LINEAR) {
        // a linear model's numbers are the configuration's: reset only
        if (!mm->reset) {
            return refuse_model(node, id, mm,
                                "a linear model's numbers come from the "
                                "configuration: a model_t resets a linear "
                                "track (reset = 1) and sets nothing");
        }
        if (old == NULL) { // made from its configured model, at its prior
            t = track_get(node, id, MODEL_LINEAR, mm->utime, &r);
        } else {
            t = track_of(node, id);
            track_reset(node, t, mm->utime);
        }
        if (t == NULL) {
            return r;
        }
        node->counts.models++;
        return GF_NODE_APPLIED;
    }
    memset(&mdl, 0, sizeof(mdl));
    snprintf(mdl.name, sizeof mdl.name, "%s%ld", GF_CHANNEL_MODEL, (long)id);
    mdl.kind = mm->model;
    mdl.measure = mm->measure;
    mdl.dt = mm->dt;
    mdl.accel_var = mm->accel_var;
    for (i = 0; i < 4; i++) {
        mdl.odometry[i] = mm->odometry[i];
    }
    mdl.landmark[0] = mm->landmark[0];
    mdl.landmark[1] = mm->landmark[1];
    mdl.gate = mm->gate;
    mdl.late_window = GF_NODE_LATE_WINDOW;
    for (i = 0; i < 3; i++) {
        mdl.prior_mean[i] = mm->prior_mean[i];
        for (j = 0; j < 3; j++) {
            mdl.prior_cov[i][j] = mm->prior_cov[i][j];
        }
    }
    if (mdl.kind == MODEL_CAR) { // only the leading 2 x 2 block counts
        mdl.prior_mean[2] = 0.0;
        for (i = 0; i < 3; i++) {
            mdl.prior_cov[2][i] = mdl.prior_cov[i][2] = 0.0;
        }
    }
    // the sensor's noise is the measurements' own: leave meas_cov zero
    if (gf_node_model_check(&mdl, &why) != 0) {
        return refuse_model(node, id, mm, "%s", why);
    }
    if (old == NULL) {
        t = track_get_with(node, id, mm->model, mm->utime, &mdl, &r);
        if (t == NULL) {
            return r;
        }
        node->counts.models++;
        return GF_NODE_APPLIED;
    }
    node->counts.models++;
    t = track_of(node, id);
    mdl.sensors = t->mdl.sensors; // a robot's configured sensors stay
    t->mdl = mdl;
    if (mm->reset) {
        track_reset(node, t, mm->utime);
    }
    return GF_NODE_APPLIED;
}

// The name of the type a channel of this kind carries.
static const char *kind_type(int kind)
{
    return kind == KIND_CTRL   ? "control_t"
           : kind == KIND_MEAS ? "measurement_t"
                               : "model_t";
}

static gf_node_result dispatch(gf_node *node, int kind, int32_t id,
                               const char *sensor, const void *data, size_t len,
                               int64_t now)
{
    gf_node_result r;
    // (a whole control or measurement with n or m beyond GF_NODE_NMAX
    // decodes as bad_field, its header read: its handler says so)
    if (kind == KIND_CTRL) {
        static const node_ctrl zero;
        node_ctrl c = zero;
        r = check_fingerprint(data, len, __gaussfilt_lcm_control_t_get_hash());
        if (r == GF_NODE_APPLIED) {
            r = decode_ctrl(data, len, &c);
        }
        if (r != GF_NODE_APPLIED && r != GF_NODE_BAD_FIELD) {
            return r;
        }
        return handle_ctrl(node, id, &c, now);
    }
    if (kind == KIND_MEAS) {
        static const node_meas zero;
        node_meas z = zero;
        r = check_fingerprint(data, len,
                              __gaussfilt_lcm_measurement_t_get_hash());
        if (r == GF_NODE_APPLIED) {
            r = decode_meas(data, len, &z);
        }
        if (r != GF_NODE_APPLIED && r != GF_NODE_BAD_FIELD) {
            return r;
        }
        return handle_meas(node, id, &z, sensor, now);
    }
    if (kind == KIND_MODEL) {
        gaussfilt_lcm_model_t mm;
        r = check_fingerprint(data, len, __gaussfilt_lcm_model_t_get_hash());
        if (r != GF_NODE_APPLIED) {
            return r;
        }
        if (gaussfilt_lcm_model_t_decode(data, 0, (int)len, &mm) != (int)len) {
            return GF_NODE_MALFORMED;
        }
        return handle_model(node, id, &mm);
    }
    return GF_NODE_UNKNOWN_CHANNEL;
}

gf_node_result gf_node_handle(gf_node *node, const char *channel,
                              const void *data, size_t len, int64_t now)
{
    gf_node_result r;
    int32_t id = 0;
    const char *sensor = NULL;
    int kind;
    gf_node_track *t;
    if (node == NULL) {
        return GF_NODE_MALFORMED;
    }
    kind = channel_kind(channel, &id, &sensor);
    r = dispatch(node, kind, id, sensor, data, len, now);
    node->counts.received++;
    node->counts.by_result[r]++;
    if (kind == KIND_NONE) {
        if (!node->said_channel) {
            node->said_channel = 1;
            say(node,
                "a message on %.64s: not a track's channel (%s<id>[_<sensor>], "
                "%s<id>, %s<id>, the id in its one decimal spelling) "
                "(unknown_channel; said once)",
                channel != NULL ? channel : "(none)", GF_CHANNEL_MEAS,
                GF_CHANNEL_CTRL, GF_CHANNEL_MODEL);
        }
        return r;
    }
    if (r == GF_NODE_MALFORMED && say_first(node, id, SAY_MALFORMED)) {
        say(node,
            "track %ld: a message on %.64s of %zu bytes is not a whole %s "
            "(malformed)",
            (long)id, channel, len, kind_type(kind));
    } else if (r == GF_NODE_TYPE_MISMATCH && say_first(node, id, SAY_TYPE)) {
        say(node,
            "track %ld: a message on %.64s is another gaussfilt type than %s "
            "(type_mismatch)",
            (long)id, channel, kind_type(kind));
    }
    t = track_of(node, id);
    if (t != NULL) {
        t->by_result[r]++;
    }
    return r;
}

unsigned gf_node_tick(gf_node *node, int64_t now)
{
    unsigned i, k = 0;
    if (node == NULL) {
        return 0;
    }
    for (i = 0; i < node->ntracks; i++) {
        gf_node_track *t = &node->tracks[i];
        gaussfilt_lcm_belief_t b;
        int64_t ahead = now > t->last_rx ? now - t->last_rx : 0;
        double dt = (double)ahead / 1e6;
        int s = GF_OK;
        if (!t->has_time) {
            continue;
        }
        // the belief as it is, then (a track in time, a car) predicted
        // over dt on a copy
        belief_fill(node, t, &b);
        if (timed(t) && dt > 0.0) {
            node->ahead.kf = t->f.kf;
            s = linear_predict(node, t, &node->ahead.kf, dt, 0);
            if (s == GF_OK) {
                gf_node_track copy_hdr = *t; // belief_fill reads f.kf
                copy_hdr.f.kf = node->ahead.kf;
                belief_fill(node, &copy_hdr, &b);
            }
        } else if (t->model == MODEL_CAR && dt > 0.0) {
            gf_node_model car = t->mdl;
            gf_kf2_model km;
            car.dt = dt;
            gf_node_model_car(&car, &km);
            node->ahead.kf2 = t->f.kf2;
            s = gf_kf2_predict(&node->ahead.kf2, &km, NULL);
            if (s == GF_OK) {
                gf_node_track copy_hdr = *t;
                copy_hdr.f.kf2 = node->ahead.kf2;
                belief_fill(node, &copy_hdr, &b);
            }
        }
        t->belief_seq++;
        b.utime = t->time <= INT64_MAX - ahead ? t->time + ahead : INT64_MAX;
        b.input_seq = t->input_seq;
        b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
        b.status = (int8_t)s;
        b.trigger = GAUSSFILT_LCM_BELIEF_T_TRIGGER_RATE;
        publish_belief(node, t, &b);
        k++;
    }
    return k;
}

// ---- the node's status -----------------------------------------------------

// node_results_t has a field per result: a result added there too.
typedef char gf_node_results_fields[GF_NODE_RESULT_COUNT == 16 ? 1 : -1];

static void results_fill(const uint64_t *by, gaussfilt_lcm_node_results_t *r)
{
    r->applied = (int64_t)by[GF_NODE_APPLIED];
    r->duplicate = (int64_t)by[GF_NODE_DUPLICATE];
    r->out_of_order = (int64_t)by[GF_NODE_OUT_OF_ORDER];
    r->malformed = (int64_t)by[GF_NODE_MALFORMED];
    r->type_mismatch = (int64_t)by[GF_NODE_TYPE_MISMATCH];
    r->bad_field = (int64_t)by[GF_NODE_BAD_FIELD];
    r->unknown_channel = (int64_t)by[GF_NODE_UNKNOWN_CHANNEL];
    r->track_limit = (int64_t)by[GF_NODE_TRACK_LIMIT];
    r->nonfinite = (int64_t)by[GF_NODE_NONFINITE];
    r->filter_error = (int64_t)by[GF_NODE_FILTER_ERROR];
    r->stale_session = (int64_t)by[GF_NODE_STALE_SESSION];
    r->no_summary = (int64_t)by[GF_NODE_NO_SUMMARY];
    r->gated = (int64_t)by[GF_NODE_GATED];
    r->no_model = (int64_t)by[GF_NODE_NO_MODEL];
    r->late = (int64_t)by[GF_NODE_LATE];
    r->too_old = (int64_t)by[GF_NODE_TOO_OLD];
}

static void track_status_fill(const gf_node_track *t,
                              const gf_node_status_info *info,
                              gaussfilt_lcm_track_status_t *ts)
{
    uint64_t inputs = 0;
    unsigned r;
    memset(ts, 0, sizeof(*ts));
    for (r = 0; r < GF_NODE_RESULT_COUNT; r++) {
        inputs += t->by_result[r];
    }
    ts->track = t->id;
    ts->model = t->model;
    ts->model_name = (char *)(uintptr_t)t->mdl.name;
    ts->filter = t->filter;
    ts->inputs = (int64_t)inputs;
    results_fill(t->by_result, &ts->results);
    ts->input_seq = t->has_time ? t->input_seq : -1;
    ts->utime = t->time;
    ts->age = t->has_time && info->rx_now >= 0
                  ? (double)(info->rx_now - t->last_rx) / 1e6
                  : -1.0;
    ts->updates = (int64_t)t->updates;
    ts->gated_run = (int32_t)t->gated_run;
    ts->nis_last = t->nis_last;
    ts->m_last = (int8_t)t->m_last;
    ts->nis_updates = (int32_t)t->nis_n;
    ts->nis_mean = t->nis_n > 0 ? t->nis_sum / (double)t->nis_n : 0.0;
    ts->nis_per_dof = t->nis_dof > 0 ? t->nis_sum / (double)t->nis_dof : 0.0;
}

int gf_node_status(gf_node *node, const gf_node_status_info *info, uint8_t *buf,
                   size_t size)
{
    gaussfilt_lcm_node_status_t s;
    gaussfilt_lcm_track_status_t ts;
    const gf_node_counts *c;
    int len, head, k, max;
    unsigned i;
    if (node == NULL || info == NULL || buf == NULL) {
        return -1;
    }
    c = &node->counts;
    max = size > (size_t)INT32_MAX ? INT32_MAX : (int)size;
    memset(&s, 0, sizeof s);
    s.utime = info->utime;
    s.node = node->id;
    s.host = node->host;
    s.pid = node->pid;
    s.start_utime = node->start_utime;
    s.seq = node->status_seq;
    s.stopping = (int8_t)(info->stopping != 0);
    s.period = node->status_seq > 0
                   ? (double)(info->utime - node->status_utime) / 1e6
                   : 0.0;
    s.received = (int64_t)c->received;
    results_fill(c->by_result, &s.results);
    s.published = (int64_t)c->published;
    s.publish_failed = (int64_t)c->publish_failed;
    s.gaps = (int64_t)c->gaps;
    s.dropped = (int64_t)c->dropped;
    s.kernel_drops = info->kernel_drops;
    s.lost_before_first = (int64_t)c->lost_before_first;
    s.peer_beliefs = (int64_t)c->peer_beliefs;
    s.name_clashes = (int64_t)c->name_clashes;
    s.queue_depth = info->queue_depth;
    s.queue_peak = info->queue_peak;
    // Encoded without its tracks, then each track after it: LCM encodes an
    // array of structs as their encodings one after the other (no
    // fingerprint of their own), and tracks[ntracks] is the last field,
    // so ntracks is the int32 just before them. One track_status_t at a
    // time: nothing sized by the tracks is held.
    s.ntracks = 0;
    len = gaussfilt_lcm_node_status_t_encode(buf, 0, max, &s);
    head = len;
    for (i = 0; i < node->ntracks && len >= 0; i++) {
        track_status_fill(&node->tracks[i], info, &ts);
        k = __gaussfilt_lcm_track_status_t_encode_array(buf, len, max - len,
                                                        &ts, 1);
        len = k < 0 ? -1 : len + k;
    }
    if (len < 0) {
        node->counts.publish_failed++;
        return -1;
    }
    buf[head - 4] = (uint8_t)(node->ntracks >> 24);
    buf[head - 3] = (uint8_t)(node->ntracks >> 16);
    buf[head - 2] = (uint8_t)(node->ntracks >> 8);
    buf[head - 1] = (uint8_t)node->ntracks;
    for (i = 0; i < node->ntracks; i++) { // the NIS since this status
        node->tracks[i].nis_sum = 0.0;
        node->tracks[i].nis_dof = 0;
        node->tracks[i].nis_n = 0;
    }
    node->status_seq++;
    node->status_utime = info->utime;
    if (node->publish != NULL &&
        node->publish(node->ctx, GF_CHANNEL_STATUS, buf, (size_t)len) != 0) {
        node->counts.publish_failed++;
        return -1;
    }
    return 0;
}

// A string as LCM encodes it (int32 length with its NUL, the bytes), into
// out cut to size - 1: 0, or -1 if it is not there.
static int wire_str(wire *w, char *out, size_t size)
{
    int32_t n = wire_i32(w);
    size_t k;
    if (w->short_read || n < 1 || (size_t)n > w->len - w->pos ||
        w->p[w->pos + (size_t)n - 1] != '\0') {
        return -1;
    }
    k = (size_t)n - 1 < size - 1 ? (size_t)n - 1 : size - 1;
    memcpy(out, w->p + w->pos, k);
    out[k] = '\0';
    w->pos += (size_t)n;
    return 0;
}

int gf_node_peer_status(gf_node *node, const void *data, size_t len)
{
    // node_status_t: fingerprint, utime, node, host, pid, start_utime
    wire w = {(const uint8_t *)data, len, 0, 0};
    char id[GF_NODE_ID_MAX], host[GF_NODE_HOST_MAX];
    int32_t pid;
    int64_t start;
    if (node == NULL || data == NULL ||
        wire_i64(&w) != __gaussfilt_lcm_node_status_t_get_hash()) {
        return 0;
    }
    (void)wire_i64(&w);
    if (wire_str(&w, id, sizeof id) != 0 ||
        wire_str(&w, host, sizeof host) != 0) {
        return 0;
    }
    pid = wire_i32(&w);
    start = wire_i64(&w);
    if (w.short_read || strcmp(id, node->id) != 0 ||
        (pid == node->pid && start == node->start_utime &&
         strcmp(host, node->host) == 0)) {
        return 0; // another node's, or this one's own
    }
    node->counts.name_clashes++;
    if (!node->clash_warned) {
        double after = ((double)start - (double)node->start_utime) / 1e6;
        node->clash_warned = 1;
        say(node,
            "warning: another node is named \"%s\" (host %s, pid %ld, "
            "started %.3f s %s this one): beliefs of two nodes of one name "
            "cannot be told apart, and neither sees the other's; give each "
            "its own --name",
            id, host, (long)pid, after < 0.0 ? -after : after,
            after < 0.0 ? "before" : "after");
    }
    return 1;
}

int gf_node_summary(const gf_node *node, char *out, size_t size)
{
    const gf_node_counts *c = &node->counts;
    int n, k;
    unsigned r;
    if (out == NULL || size == 0) {
        return -1;
    }
    n = snprintf(
        out, size,
        "received=%llu applied=%llu published=%llu "
        "publish_failed=%llu gaps=%llu dropped=%llu tracks=%u "
        "resyncs=%llu seq_resyncs=%llu models=%llu lost_before_first=%llu "
        "peer_beliefs=%llu name_clashes=%llu",
        (unsigned long long)c->received,
        (unsigned long long)c->by_result[GF_NODE_APPLIED],
        (unsigned long long)c->published, (unsigned long long)c->publish_failed,
        (unsigned long long)c->gaps, (unsigned long long)c->dropped,
        node->ntracks, (unsigned long long)c->resyncs,
        (unsigned long long)c->seq_resyncs, (unsigned long long)c->models,
        (unsigned long long)c->lost_before_first,
        (unsigned long long)c->peer_beliefs,
        (unsigned long long)c->name_clashes);
    for (r = 1; r < GF_NODE_RESULT_COUNT && n >= 0 && (size_t)n < size; r++) {
        k = snprintf(out + n, size - (size_t)n, " %s=%llu",
                     gf_node_result_str((gf_node_result)r),
                     (unsigned long long)c->by_result[r]);
        if (k < 0) {
            return k;
        }
        n += k;
    }
    return n;
}
