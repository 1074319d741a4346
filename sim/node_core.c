// gaussfilt sim: the filter node's message handling (see node_core.h).
// Only message checking and bookkeeping live here; every filter step is a
// call into the core (gf_kf2_*, gf_ekf3_*, gf_ukf3_*, gf_pf3_*).
#include "node_core.h"

#include <stdio.h>
#include <string.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_groundtruth_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gaussfilt_lcm_particles_t.h"

#define MODEL_CAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
#define MODEL_ROBOT GAUSSFILT_LCM_MEASUREMENT_T_MODEL_ROBOT
#define FILTER_KF2 GAUSSFILT_LCM_BELIEF_T_FILTER_KF2
#define FILTER_EKF3 GAUSSFILT_LCM_BELIEF_T_FILTER_EKF3
#define FILTER_UKF3 GAUSSFILT_LCM_BELIEF_T_FILTER_UKF3
#define FILTER_PF3 GAUSSFILT_LCM_BELIEF_T_FILTER_PF3

// The largest message the node decodes; anything longer is malformed.
#define GF_NODE_MAX_LEN 4096

const char *gf_node_result_str(gf_node_result r)
{
    switch (r) {
    case GF_NODE_APPLIED: return "applied";
    case GF_NODE_DUPLICATE: return "duplicate";
    case GF_NODE_OUT_OF_ORDER: return "out_of_order";
    case GF_NODE_MALFORMED: return "malformed";
    case GF_NODE_TYPE_MISMATCH: return "type_mismatch";
    case GF_NODE_BAD_FIELD: return "bad_field";
    case GF_NODE_UNKNOWN_CHANNEL: return "unknown_channel";
    case GF_NODE_TRACK_LIMIT: return "track_limit";
    case GF_NODE_NONFINITE: return "nonfinite";
    case GF_NODE_FILTER_ERROR: return "filter_error";
    case GF_NODE_STALE_SESSION: return "stale_session";
    case GF_NODE_RESULT_COUNT: break;
    }
    return "unknown";
}

int gf_node_init(gf_node *node, gf_node_publish_fn publish, void *ctx)
{
    if (node == NULL)
        return -1;
    memset(node, 0, sizeof(*node));
    node->publish = publish;
    node->ctx = ctx;
    return 0;
}

int gf_node_set_filter(gf_node *node, gf_node_filter filter,
                       gf_node_pf_pool *pool, uint32_t seed)
{
    if (node == NULL || (filter != GF_NODE_FILTER_EKF &&
                         filter != GF_NODE_FILTER_UKF &&
                         filter != GF_NODE_FILTER_PF))
        return -1;
    if (filter == GF_NODE_FILTER_PF && pool == NULL)
        return -1;
    node->robot_filter = filter;
    node->pf_pool = pool;
    node->pf_seed = seed;
    if (pool != NULL)
        pool->used = 0;
    return 0;
}

int gf_node_filter_parse(const char *name, gf_node_filter *out)
{
    if (name == NULL || out == NULL)
        return -1;
    if (strcmp(name, "ekf") == 0)
        *out = GF_NODE_FILTER_EKF;
    else if (strcmp(name, "ukf") == 0)
        *out = GF_NODE_FILTER_UKF;
    else if (strcmp(name, "pf") == 0)
        *out = GF_NODE_FILTER_PF;
    else
        return -1;
    return 0;
}

const gf_node_track *gf_node_find(const gf_node *node, int32_t id)
{
    unsigned i;
    if (node == NULL)
        return NULL;
    for (i = 0; i < node->ntracks; i++)
        if (node->tracks[i].id == id)
            return &node->tracks[i];
    return NULL;
}

// ---- channel and fingerprint ----------------------------------------------

enum { KIND_NONE, KIND_MEAS, KIND_CTRL };

// Parses "<prefix><decimal int32>" exactly; returns 1 and the track id.
static int parse_track(const char *channel, const char *prefix, int32_t *id)
{
    size_t n = strlen(prefix);
    const char *p;
    int neg = 0;
    int64_t v = 0;
    if (strncmp(channel, prefix, n) != 0)
        return 0;
    p = channel + n;
    if (*p == '-') {
        neg = 1;
        p++;
    }
    if (*p == '\0')
        return 0;
    for (; *p != '\0'; p++) {
        if (*p < '0' || *p > '9')
            return 0;
        v = v * 10 + (*p - '0');
        if (v > (int64_t)INT32_MAX + 1)
            return 0;
    }
    v = neg ? -v : v;
    if (v > INT32_MAX)
        return 0;
    *id = (int32_t)v;
    return 1;
}

static int channel_kind(const char *channel, int32_t *id)
{
    if (channel == NULL)
        return KIND_NONE;
    if (parse_track(channel, GF_CHANNEL_MEAS, id))
        return KIND_MEAS;
    if (parse_track(channel, GF_CHANNEL_CTRL, id))
        return KIND_CTRL;
    return KIND_NONE;
}

// The 8-byte big-endian fingerprint an LCM message starts with.
static int64_t fingerprint(const uint8_t *b)
{
    uint64_t v = 0;
    unsigned i;
    for (i = 0; i < 8; i++)
        v = (v << 8) | b[i];
    return (int64_t)v;
}

// Checks the fingerprint against the expected type: GF_NODE_APPLIED when it
// matches, TYPE_MISMATCH when it is another of our types, else MALFORMED.
static gf_node_result check_fingerprint(const void *data, size_t len,
                                        int64_t want)
{
    int64_t got;
    if (data == NULL || len < 8 || len > GF_NODE_MAX_LEN)
        return GF_NODE_MALFORMED;
    got = fingerprint((const uint8_t *)data);
    if (got == want)
        return GF_NODE_APPLIED;
    if (got == __gaussfilt_lcm_measurement_t_get_hash() ||
        got == __gaussfilt_lcm_control_t_get_hash() ||
        got == __gaussfilt_lcm_belief_t_get_hash() ||
        got == __gaussfilt_lcm_groundtruth_t_get_hash() ||
        got == __gaussfilt_lcm_particles_t_get_hash())
        return GF_NODE_TYPE_MISMATCH;
    return GF_NODE_MALFORMED;
}

// ---- tracks ----------------------------------------------------------------

// The robot's prior in any filter: N(mu0, sigma0) (see track_prior).
static const gf_ukf3_params ukf_params = {GF_R(1.0), GF_R(2.0), GF_R(0.0)};

// The robot's moments as the belief carries them: the filter's own, or
// the particles' last weighted summary.
static void robot_moments(const gf_node_track *t, const gf_vec3 **mu,
                          const gf_mat3 **sigma)
{
    if (t->filter == FILTER_UKF3) {
        *mu = &t->f.ukf3.mu;
        *sigma = &t->f.ukf3.sigma;
    } else if (t->filter == FILTER_PF3) {
        *mu = &t->f.pf3.mu;
        *sigma = &t->f.pf3.sigma;
    } else {
        *mu = &t->f.ekf3.mu;
        *sigma = &t->f.ekf3.sigma;
    }
}

// Points a PF track's filter at its particles (the node may have moved).
static gf_pf3 *track_pf(gf_node *node, gf_node_track *t)
{
    t->f.pf3.pf.p = node->pf_pool->p[t->f.pf3.slot];
    return &t->f.pf3.pf;
}

// The PF track's summary after a successful step: its weighted moments and
// effective sample size. GF_ERR_UNDEFINED (headings with no mean direction)
// keeps the previous summary.
static gf_status pf_summary(gf_node_track *t)
{
    gf_vec3 mu;
    gf_mat3 sigma;
    gf_status s = gf_pf3_estimate(&t->f.pf3.pf, &mu, &sigma);
    if (s != GF_OK)
        return s;
    t->f.pf3.mu = mu;
    t->f.pf3.sigma = sigma;
    return gf_pf3_neff(&t->f.pf3.pf, &t->f.pf3.neff);
}

// The exercise priors every new track starts from, and a resynced track
// again. A new track (filter 0) takes the node's robot filter; a resynced
// one keeps its own filter, and a PF track its pool slot.
static void track_prior(gf_node *node, gf_node_track *t)
{
    gf_vec3 mu0;
    gf_mat3 sigma0;
    int8_t filter = t->filter;
    if (filter == 0)
        filter = node->robot_filter == GF_NODE_FILTER_UKF  ? FILTER_UKF3
                 : node->robot_filter == GF_NODE_FILTER_PF ? FILTER_PF3
                                                           : FILTER_EKF3;
    if (t->model == MODEL_CAR) {
        // Exercise 1: the car starts at rest at 0, known exactly.
        memset(&t->f.kf2, 0, sizeof(t->f.kf2));
        t->filter = FILTER_KF2;
        return;
    }
    // Exercise 4: at the origin, heading unknown.
    memset(&mu0, 0, sizeof(mu0));
    memset(&sigma0, 0, sizeof(sigma0));
    sigma0.m[0][0] = GF_R(0.01);
    sigma0.m[1][1] = GF_R(0.01);
    sigma0.m[2][2] = GF_R(10000.0);
    if (filter == FILTER_UKF3) {
        t->filter = FILTER_UKF3;
        (void)gf_ukf3_init(&t->f.ukf3, &mu0, &sigma0, &ukf_params);
    } else if (filter == FILTER_PF3) {
        if (t->filter != FILTER_PF3)
            t->f.pf3.slot = node->pf_pool->used++;
        t->filter = FILTER_PF3;
        (void)gf_pf3_init(&t->f.pf3.pf, node->pf_pool->p[t->f.pf3.slot],
                          GF_NODE_PF_PARTICLES,
                          node->pf_seed + (uint32_t)t->id, &mu0, &sigma0);
        t->f.pf3.mu = mu0; // until the particles' own summary
        t->f.pf3.sigma = sigma0;
        (void)pf_summary(t);
    } else {
        t->filter = FILTER_EKF3;
        t->f.ekf3.mu = mu0;
        t->f.ekf3.sigma = sigma0;
    }
}

static void belief_fill(const gf_node_track *t, gaussfilt_lcm_belief_t *b)
{
    unsigned i, j, n = t->model == MODEL_CAR ? 2u : 3u;
    const gf_vec3 *mu3 = NULL;
    const gf_mat3 *s3 = NULL;
    if (n == 3)
        robot_moments(t, &mu3, &s3);
    memset(b, 0, sizeof(*b));
    b->track = t->id;
    b->model = t->model;
    b->filter = t->filter;
    b->n = (int8_t)n;
    for (i = 0; i < n; i++) {
        b->mean[i] = (double)(n == 2 ? t->f.kf2.mu.v[i] : mu3->v[i]);
        for (j = 0; j < n; j++)
            b->cov[i][j] = (double)(n == 2 ? t->f.kf2.sigma.m[i][j]
                                           : s3->m[i][j]);
    }
}

static void publish_belief(gf_node *node, gf_node_track *t,
                           gaussfilt_lcm_belief_t *b)
{
    char channel[GF_CHANNEL_MAX];
    int len;
    b->seq = t->belief_seq;
    len = gaussfilt_lcm_belief_t_encode(node->buf, 0, (int)sizeof(node->buf),
                                        b);
    if (len < 0) {
        node->counts.publish_failed++;
        return;
    }
    snprintf(channel, sizeof(channel), "%s%ld", GF_CHANNEL_BELIEF,
             (long)t->id);
    node->counts.published++;
    if (node->publish != NULL &&
        node->publish(node->ctx, channel, node->buf, (size_t)len) != 0)
        node->counts.publish_failed++;
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
        pool->x[i] = (float)pf->p[k].x.v[0];
        pool->y[i] = (float)pf->p[k].x.v[1];
        pool->theta[i] = (float)pf->p[k].x.v[2];
        pool->w[i] = (float)pf->p[k].w;
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
    len = gaussfilt_lcm_particles_t_encode(pool->buf, 0,
                                           (int)sizeof(pool->buf), &m);
    if (len < 0) {
        node->counts.publish_failed++;
        return;
    }
    snprintf(channel, sizeof(channel), "%s%ld", GF_CHANNEL_PARTICLES,
             (long)t->id);
    node->counts.published++;
    if (node->publish != NULL &&
        node->publish(node->ctx, channel, pool->buf, (size_t)len) != 0)
        node->counts.publish_failed++;
}

// Publishes a track's belief, and a PF track's cloud after it.
static void publish_step(gf_node *node, gf_node_track *t,
                         gaussfilt_lcm_belief_t *b)
{
    publish_belief(node, t, b);
    if (t->filter == FILTER_PF3)
        publish_particles(node, t, b);
}

static gf_node_track *track_get(gf_node *node, int32_t id, int8_t model,
                                int64_t utime, gf_node_result *why)
{
    gf_node_track *t;
    gaussfilt_lcm_belief_t b;
    unsigned i;
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
    if (node->ntracks >= GF_NODE_MAX_TRACKS ||
        (model == MODEL_ROBOT && node->robot_filter == GF_NODE_FILTER_PF &&
         (node->pf_pool == NULL || node->pf_pool->used >= GF_NODE_PF_TRACKS))) {
        *why = GF_NODE_TRACK_LIMIT;
        return NULL;
    }
    t = &node->tracks[node->ntracks++];
    memset(t, 0, sizeof(*t));
    t->id = id;
    t->model = model;
    track_prior(node, t);
    node->counts.tracks_created++;
    belief_fill(t, &b);
    b.utime = utime;
    b.input_seq = -1;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
    publish_step(node, t, &b);
    return t;
}

// Sequence rules: seq strictly increasing per track (equal = duplicate,
// lower = out of order), utime never decreasing.
static gf_node_result check_order(const gf_node_track *t, int64_t seq,
                                  int64_t utime)
{
    if (!t->has_input)
        return GF_NODE_APPLIED;
    if (seq == t->last_seq)
        return GF_NODE_DUPLICATE;
    if (seq < t->last_seq || utime < t->last_utime)
        return GF_NODE_OUT_OF_ORDER;
    return GF_NODE_APPLIED;
}

// Session rule (see node_core.h): a larger session re-initialises the
// track from the prior, a smaller one is stale; then the sequence rules.
static gf_node_result admit(gf_node *node, gf_node_track *t, int64_t session,
                            int64_t seq, int64_t utime)
{
    gaussfilt_lcm_belief_t b;
    if (t->has_input && session != t->session) {
        if (session < t->session)
            return GF_NODE_STALE_SESSION;
        t->has_input = 0;
        track_prior(node, t);
        node->counts.resyncs++;
        t->belief_seq++;
        belief_fill(t, &b);
        b.utime = utime;
        b.input_seq = -1;
        b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_INIT;
        publish_step(node, t, &b);
    }
    return check_order(t, seq, utime);
}

static void consume(gf_node *node, gf_node_track *t, int64_t session,
                    int64_t seq, int64_t utime, int64_t now)
{
    // seq > last_seq here; unsigned arithmetic cannot overflow.
    if (t->has_input)
        node->counts.gaps += (uint64_t)seq - (uint64_t)t->last_seq - 1u;
    t->has_input = 1;
    t->session = session;
    t->last_seq = seq;
    t->last_utime = utime;
    t->last_rx = now;
}

static gf_node_result from_status(gf_status s)
{
    if (s == GF_OK)
        return GF_NODE_APPLIED;
    return s == GF_ERR_NONFINITE ? GF_NODE_NONFINITE : GF_NODE_FILTER_ERROR;
}

// ---- the two inputs ---------------------------------------------------------

// Model constants of the exercises (configuration, not math).
static void car_model(gf_kf2_model *mdl)
{
    memset(mdl, 0, sizeof(*mdl));
    // A = ((1, 1), (0, 1)): position += velocity over one step.
    mdl->A.m[0][0] = GF_R(1.0);
    mdl->A.m[0][1] = GF_R(1.0);
    mdl->A.m[1][1] = GF_R(1.0);
    // B = I: a control, if sent, adds u to the state (the car gets none).
    mdl->B.m[0][0] = GF_R(1.0);
    mdl->B.m[1][1] = GF_R(1.0);
    // R = G G^T, G = (0.5, 1)^T: acceleration of variance 1 (Table 1.1).
    mdl->R.m[0][0] = GF_R(0.25);
    mdl->R.m[0][1] = GF_R(0.5);
    mdl->R.m[1][0] = GF_R(0.5);
    mdl->R.m[1][1] = GF_R(1.0);
}

// A PF track's correction: importance weights, then low-variance
// resampling once fewer than GF_NODE_PF_RESAMPLE_FRACTION of the particles
// are effective. The summary is taken after resampling; the neff the
// cloud reports is the one that decided it.
static gf_status pf_correct(gf_node *node, gf_node_track *t,
                            const gf_ekf3_meas *mm, const gf_vec3 *z)
{
    gf_pf3 *pf = track_pf(node, t);
    gf_real neff = GF_R(0.0);
    gf_status s = gf_pf3_update(pf, mm, z);
    t->f.pf3.resampled = 0;
    if (s != GF_OK)
        return s;
    if (gf_pf3_neff(pf, &neff) == GF_OK &&
        neff < (gf_real)(GF_NODE_PF_RESAMPLE_FRACTION * pf->n)) {
        s = gf_pf3_resample(pf);
        if (s != GF_OK)
            return s;
        t->f.pf3.resampled = 1;
    }
    s = pf_summary(t);
    t->f.pf3.neff = neff;
    return s;
}

static gf_node_result handle_ctrl(gf_node *node, int32_t id,
                                  const gaussfilt_lcm_control_t *c,
                                  int64_t now)
{
    gf_node_result r = GF_NODE_APPLIED;
    gf_node_track *t;
    gaussfilt_lcm_belief_t b;
    gf_status s;
    if (c->track != id || (c->model != MODEL_CAR && c->model != MODEL_ROBOT))
        return GF_NODE_BAD_FIELD;
    if (c->model == MODEL_CAR ? (c->n != 0 && c->n != 2) : c->n != 2)
        return GF_NODE_BAD_FIELD;
    t = track_get(node, id, c->model, c->utime, &r);
    if (t == NULL)
        return r;
    r = admit(node, t, c->session, c->seq, c->utime);
    if (r != GF_NODE_APPLIED)
        return r;
    consume(node, t, c->session, c->seq, c->utime, now);
    if (t->model == MODEL_CAR) {
        gf_kf2_model mdl;
        gf_vec2 u;
        car_model(&mdl);
        u.v[0] = (gf_real)c->u[0];
        u.v[1] = (gf_real)c->u[1];
        s = gf_kf2_predict(&t->f.kf2, &mdl, c->n == 2 ? &u : NULL);
    } else {
        gf_ekf3_motion mot;
        gf_real u[2];
        memset(&mot, 0, sizeof(mot)); // R = 0, as in exercise 4
        mot.g = gf_ekf3_motion_forward_turn;
        u[0] = (gf_real)c->u[0];
        u[1] = (gf_real)c->u[1];
        if (t->filter == FILTER_UKF3) {
            s = gf_ukf3_predict(&t->f.ukf3, &mot, u);
        } else if (t->filter == FILTER_PF3) {
            s = gf_pf3_predict(track_pf(node, t), &mot, u);
            t->f.pf3.resampled = 0;
            if (s == GF_OK)
                s = pf_summary(t);
        } else {
            s = gf_ekf3_predict(&t->f.ekf3, &mot, u);
        }
    }
    t->belief_seq++;
    belief_fill(t, &b);
    b.utime = c->utime;
    b.input_seq = c->seq;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT;
    b.status = (int8_t)s;
    publish_step(node, t, &b);
    return from_status(s);
}

static gf_node_result handle_meas(gf_node *node, int32_t id,
                                  const gaussfilt_lcm_measurement_t *z,
                                  int64_t now)
{
    gf_node_result r = GF_NODE_APPLIED;
    gf_node_track *t;
    gaussfilt_lcm_belief_t b;
    gf_innovation info;
    gf_status s;
    unsigned i, j, m;
    if (z->track != id || (z->model != MODEL_CAR && z->model != MODEL_ROBOT))
        return GF_NODE_BAD_FIELD;
    if (z->m < 1 || z->m > 2) // car: x or (x, v); robot: x or (x, y)
        return GF_NODE_BAD_FIELD;
    m = (unsigned)z->m;
    t = track_get(node, id, z->model, z->utime, &r);
    if (t == NULL)
        return r;
    r = admit(node, t, z->session, z->seq, z->utime);
    if (r != GF_NODE_APPLIED)
        return r;
    consume(node, t, z->session, z->seq, z->utime, now);
    memset(&info, 0, sizeof(info));
    if (t->model == MODEL_CAR) {
        gf_kf2_meas mm;
        gf_vec2 zz;
        memset(&mm, 0, sizeof(mm));
        mm.m = m;
        mm.C.m[0][0] = GF_R(1.0); // C = (1, 0) or I
        mm.C.m[1][1] = m == 2 ? GF_R(1.0) : GF_R(0.0);
        for (i = 0; i < m; i++) {
            zz.v[i] = (gf_real)z->z[i];
            for (j = 0; j < m; j++)
                mm.Q.m[i][j] = (gf_real)z->q[i][j];
        }
        if (m == 1)
            zz.v[1] = GF_R(0.0);
        s = gf_kf2_update(&t->f.kf2, &mm, &zz, &info);
    } else {
        gf_ekf3_meas mm;
        gf_vec3 zz;
        memset(&mm, 0, sizeof(mm));
        memset(&zz, 0, sizeof(zz));
        mm.m = m;
        mm.h = m == 1 ? gf_ekf3_meas_x : gf_ekf3_meas_xy;
        for (i = 0; i < m; i++) {
            zz.v[i] = (gf_real)z->z[i];
            for (j = 0; j < m; j++)
                mm.Q.m[i][j] = (gf_real)z->q[i][j];
        }
        if (t->filter == FILTER_UKF3)
            s = gf_ukf3_update(&t->f.ukf3, &mm, &zz, &info);
        else if (t->filter == FILTER_PF3)
            s = pf_correct(node, t, &mm, &zz);
        else
            s = gf_ekf3_update(&t->f.ekf3, &mm, &zz, &info);
    }
    t->belief_seq++;
    belief_fill(t, &b);
    b.utime = z->utime;
    b.input_seq = z->seq;
    b.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
    b.status = (int8_t)s;
    if ((s == GF_OK || s == GF_ERR_GATED) && t->filter != FILTER_PF3) {
        b.m = (int8_t)info.m;
        for (i = 0; i < info.m && i < 3; i++)
            b.innovation[i] = (double)info.y[i];
        b.nis = (double)info.nis;
    }
    publish_step(node, t, &b);
    return from_status(s);
}

static gf_node_result dispatch(gf_node *node, const char *channel,
                               const void *data, size_t len, int64_t now)
{
    int32_t id = 0;
    gf_node_result r;
    int kind = channel_kind(channel, &id);
    if (kind == KIND_CTRL) {
        gaussfilt_lcm_control_t c;
        r = check_fingerprint(data, len, __gaussfilt_lcm_control_t_get_hash());
        if (r != GF_NODE_APPLIED)
            return r;
        if (gaussfilt_lcm_control_t_decode(data, 0, (int)len, &c) != (int)len)
            return GF_NODE_MALFORMED;
        return handle_ctrl(node, id, &c, now);
    }
    if (kind == KIND_MEAS) {
        gaussfilt_lcm_measurement_t z;
        r = check_fingerprint(data, len,
                              __gaussfilt_lcm_measurement_t_get_hash());
        if (r != GF_NODE_APPLIED)
            return r;
        if (gaussfilt_lcm_measurement_t_decode(data, 0, (int)len, &z) !=
            (int)len)
            return GF_NODE_MALFORMED;
        return handle_meas(node, id, &z, now);
    }
    return GF_NODE_UNKNOWN_CHANNEL;
}

gf_node_result gf_node_handle(gf_node *node, const char *channel,
                              const void *data, size_t len, int64_t now)
{
    gf_node_result r;
    if (node == NULL)
        return GF_NODE_MALFORMED;
    r = dispatch(node, channel, data, len, now);
    node->counts.received++;
    node->counts.by_result[r]++;
    return r;
}

int gf_node_summary(const gf_node *node, char *out, size_t size)
{
    const gf_node_counts *c = &node->counts;
    int n, k;
    unsigned r;
    if (out == NULL || size == 0)
        return -1;
    n = snprintf(out, size,
                 "received=%llu applied=%llu published=%llu "
                 "publish_failed=%llu gaps=%llu tracks=%u resyncs=%llu",
                 (unsigned long long)c->received,
                 (unsigned long long)c->by_result[GF_NODE_APPLIED],
                 (unsigned long long)c->published,
                 (unsigned long long)c->publish_failed,
                 (unsigned long long)c->gaps, node->ntracks,
                 (unsigned long long)c->resyncs);
    for (r = 1; r < GF_NODE_RESULT_COUNT && n >= 0 && (size_t)n < size; r++) {
        k = snprintf(out + n, size - (size_t)n, " %s=%llu",
                     gf_node_result_str((gf_node_result)r),
                     (unsigned long long)c->by_result[r]);
        if (k < 0)
            return k;
        n += k;
    }
    return n;
}
