// SPDX-License-Identifier: MIT
// The node's models as data (node_model.h) and its edges (node_core.h), in
// process: the configuration file and its errors (each naming the line of
// the key at fault), linear models (dt-built axes, a track against gf_kf
// run directly), strict refusal, another node's beliefs, a run-time model_t
// between two steps against the core run directly with the new model, the
// range-bearing measurement against the core with a callback written
// here, one channel spelling per track, sequence resync at the range's
// edges, and a PF summary that cannot be computed.
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gaussfilt_lcm_model_t.h"
#include "gf_msgs.h"
#include "node_core.h"

#define TOL GF_SIM_TOL

static void check_close(double got, double want)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= TOL * scale)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

// Beliefs and particle clouds as published.
typedef struct catch_ {
    gf_sink sink;
    int clouds, inf_in_cloud;
} catch_;

static int on_publish(void *ctx, const char *channel, const void *data,
                      size_t len)
{
    catch_ *c = ctx;
    if (strncmp(channel, GF_CHANNEL_PARTICLES, strlen(GF_CHANNEL_PARTICLES)) ==
        0) {
        gaussfilt_lcm_particles_t p;
        int i;
        if (gaussfilt_lcm_particles_t_decode(data, 0, (int)len, &p) ==
            (int)len) {
            c->clouds++;
            for (i = 0; i < p.count; i++) {
                if (isinf(p.x[i]) || isinf(p.y[i]) || isinf(p.theta[i]) ||
                    isinf(p.w[i])) {
                    c->inf_in_cloud++;
                }
            }
            gaussfilt_lcm_particles_t_decode_cleanup(&p);
        }
        return 0;
    }
    gf_sink_add(&c->sink, channel, data, len);
    return 0;
}

typedef struct fixture {
    gf_node node;
    catch_ c;
    gf_node_config cfg;
    gf_node_pf_pool pool;
} fixture;

static fixture fx;

static const char test_conf[] = "# comment\n"
                                "[model car100]\n"
                                "type = car\n"
                                "channels = GF_(MEAS|CTRL|MODEL)_1[0-9][0-9]\n"
                                "dt = 0.01\n"
                                "accel_var = 4   # (m/s^2)^2\n"
                                "prior_cov = 0.01 0.01\n"
                                "measure = position velocity\n"
                                "meas_cov = 0.0025 0.01\n"
                                "\n"
                                "[model lm]\n"
                                "type = robot\n"
                                "channels = GF_(MEAS|CTRL)_3[0-9]\n"
                                "odometry = 0.0025 0 0 0.0001\n"
                                "prior_mean = 1 2 0.5\n"
                                "prior_cov = 0.01 0.02 0.03\n"
                                "measure = range bearing\n"
                                "landmark = 5 3\n"
                                "[model lm2]\n"
                                "base = lm\n"
                                "gate = 9.2\n";

static int setup(void **state)
{
    char err[128];
    memset(&fx, 0, sizeof(fx));
    gf_node_init(&fx.node, on_publish, &fx.c);
    assert_int_equal(gf_node_config_parse(&fx.cfg, test_conf, err, sizeof err),
                     0);
    gf_node_set_models(&fx.node,
                       (gf_node_model_fn)(void (*)(void))gf_node_config_lookup,
                       &fx.cfg);
    *state = &fx;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    gf_node_config_free(&fx.cfg);
    return 0;
}

static gf_node_result feed(gf_msg m)
{
    assert_true(m.len > 0);
    return gf_node_handle(&fx.node, m.channel, m.data, (size_t)m.len, 0);
}

static gf_node_result feed_on(const char *channel, gf_msg m)
{
    return gf_node_handle(&fx.node, channel, m.data, (size_t)m.len, 0);
}

static gf_msg msg_meas2(int32_t track, int8_t model, int64_t seq, int64_t utime,
                        double z0, double z1, double q0, double q1)
{
    const double z[2] = {z0, z1}, q[2] = {q0, q1};
    return gf_msg_meas_m(track, model, seq, utime, 2, z, q);
}

static gf_msg msg_model(const gaussfilt_lcm_model_t *mm)
{
    gf_msg m;
    memset(&m, 0, sizeof(m));
    snprintf(m.channel, sizeof(m.channel), "%s%ld", GF_CHANNEL_MODEL,
             (long)mm->track);
    m.len = gaussfilt_lcm_model_t_encode(m.data, 0, (int)sizeof(m.data), mm);
    return m;
}

// ---- the configuration file -------------------------------------------------

static void config_and_lookup(void **state)
{
    const gf_node_model *m;
    (void)state;
    assert_int_equal(fx.cfg.count, 3);
    m = gf_node_config_lookup(&fx.cfg, 150, GF_NODE_KIND_CAR);
    assert_string_equal(m->name, "car100");
    check_close(m->dt, 0.01);
    check_close(m->prior_cov[1][1], 0.01);
    assert_int_equal(m->measure, GF_NODE_MEASURE_XV);
    // another kind on the same pattern, or no pattern: the presets
    assert_string_equal(
        gf_node_config_lookup(&fx.cfg, 150, GF_NODE_KIND_ROBOT)->name,
        "book-robot");
    assert_string_equal(
        gf_node_config_lookup(&fx.cfg, 7, GF_NODE_KIND_CAR)->name, "book-car");
    assert_string_equal(
        gf_node_config_lookup(&fx.cfg, 1500, GF_NODE_KIND_CAR)->name,
        "book-car"); // anchored
    assert_string_equal(gf_node_config_lookup(NULL, 1, GF_NODE_KIND_CAR)->name,
                        "book-car");
    m = gf_node_config_find(&fx.cfg, "lm2"); // base = lm, then its own gate
    assert_non_null(m);
    check_close(m->landmark[0], 5.0);
    check_close(m->gate, 9.2);
    check_close(m->prior_mean[2], 0.5);
}

static void config_errors(void **state)
{
    static const struct {
        const char *text, *err;
    } bad[] = {
        {"dt = 1\n", "line 1: a key before the first [model NAME]"},
        {"[model a]\ntype = boat\n",
         "line 2: type is car, robot, linear or generated"},
        // a generated model: its library first, then what it sizes
        {"[model a]\ntype = generated\nchannels = GF_MEAS_1\n",
         "line 1: model a: a generated model needs library = PATH"},
        {"[model a]\ntype = generated\nprior_mean = 0\n",
         "line 3: model a: library before prior_mean"},
        {"[model a]\ntype = generated\nparams = 1\n",
         "line 3: model a: library before params"},
        {"[model a]\ntype = generated\nmotion = cv\n",
         "line 3: a generated model has no motion (its library gives the "
         "states, the motion and the sensors)"},
        {"[model a]\ntype = generated\n[sensor gps]\n",
         "line 3: model a: its library has no sensor gps (it has: none: "
         "library first)"},
        {"[model a]\ntype = generated\nlibrary = ./no/such.so\n",
         "line 3: model a: library does not load: ././no/such.so: cannot "
         "open shared object file: No such file or directory"},
        {"[model a]\ntype = linear\nn = 1\nC = 1\nchannels = GF_MEAS_1\n"
         "[model b]\nbase = a\ntype = generated\n",
         "line 8: model b: type generated after the type of its base"},
        {"[model a]\ndt = 1\n", "line 2: type or base first"},
        {"[model a]\ntype = car\nspeed = 3\n", "line 3: unknown key speed"},
        {"[model a]\ntype = car\ndt = 0\n",
         "line 3: model a: dt must be a finite number > 0"},
        {"[model a]\ntype = car\nprior_cov = 1 2 3 1\n",
         "line 3: model a: prior_cov must be symmetric positive semidefinite"},
        {"[model a]\ntype = robot\nprior_cov = 1 1\n",
         "line 3: prior_cov takes 3 or 9 numbers"},
        {"[model a]\ntype = robot\nodometry = 1 2 3\n",
         "line 3: odometry takes 4 numbers"},
        {"[model a]\ntype = car\nmeasure = x y\n",
         "line 3: a car measures position, velocity or position velocity"},
        {"[model a]\ntype = car\nlandmark = 1 2\n",
         "line 3: a car has no landmark"},
        {"[model a]\ntype = car\nchannels = GF_(\n",
         "line 3: model a: bad channels regex GF_("},
        {"[model a]\ntype = car\n[model a]\n", "line 3: model a defined twice"},
        {"[model a]\nbase = nothing\n", "line 2: no model nothing before this"},
        {"[model a]\ntype = car\ndt = 1x\n", "line 3: dt takes 1 number"},
    };
    gf_node_config cfg;
    char err[256];
    unsigned i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (gf_node_config_parse(&cfg, bad[i].text, err, sizeof err) == 0) {
            fail_msg("accepted: %s", bad[i].text);
        }
        if (strcmp(err, bad[i].err) != 0) {
            fail_msg("for %s\n said: %s\n want: %s", bad[i].text, err,
                     bad[i].err);
        }
        gf_node_config_free(&cfg);
    }
}

// ---- a model set between two steps ---------------------------------------

static void model_between_steps(void **state)
{
    gaussfilt_lcm_model_t mm;
    gf_kf2 kf;
    gf_kf2_model mot;
    gf_kf2_meas meas;
    gf_vec2 z;
    const gf_wire_belief *b;
    const double dt = 0.1, q = 2.0;
    const gf_vec2 mu0 = {{GF_R(0.0), GF_R(0.0)}};
    const gf_mat2 sigma0 = {{{GF_R(0.0), GF_R(0.0)}, {GF_R(0.0), GF_R(0.0)}}};
    gf_mat2 sigma;
    int n;
    (void)state;
    // track 5: the book's car for one step and one position
    assert_int_equal(feed(gf_msg_ctrl(5, GF_CAR, 1, 1, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(gf_msg_meas(5, GF_CAR, 2, 1, 0.5, 10)),
                     GF_NODE_APPLIED);
    // now dt = 0.1, accel_var = 2, position and velocity measured
    memset(&mm, 0, sizeof mm);
    mm.track = 5;
    mm.model = GF_CAR;
    mm.measure = GAUSSFILT_LCM_MODEL_T_MEASURE_XV;
    mm.dt = dt;
    mm.accel_var = q;
    n = fx.c.sink.n;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_APPLIED);
    assert_int_equal(fx.c.sink.n, n); // kept the belief: nothing published
    assert_int_equal(fx.node.counts.models, 1);
    // a position alone no longer fits the model: its status belief, the
    // belief as it was; its seq arrived (the next is no gap)
    assert_int_equal(feed(gf_msg_meas(5, GF_CAR, 3, 2, 0.5, 10)),
                     GF_NODE_BAD_FIELD);
    assert_int_equal(fx.c.sink.n, n + 1);
    b = &fx.c.sink.b[n];
    assert_int_equal(b->status, GF_NODE_STATUS_BAD_FIELD);
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE);
    assert_int_equal(b->input_seq, 3);
    assert_memory_equal(b->mean, fx.c.sink.b[n - 1].mean, sizeof b->mean);
    assert_int_equal(feed(gf_msg_ctrl(5, GF_CAR, 4, 2, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(msg_meas2(5, GF_CAR, 5, 2, 0.7, 0.2, 0.5, 0.25)),
                     GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.gaps, 0);

    // The core directly: the book's step, then the new model, written
    // out here, from the book car's prior N(0, 0).
    assert_int_equal(gf_kf2_init(&kf, &mu0, &sigma0), GF_OK);
    memset(&mot, 0, sizeof mot);
    mot.A.m[0][0] = mot.A.m[0][1] = mot.A.m[1][1] = GF_R(1.0);
    mot.B.m[0][0] = mot.B.m[1][1] = GF_R(1.0);
    mot.R.m[0][0] = GF_R(0.25);
    mot.R.m[0][1] = mot.R.m[1][0] = GF_R(0.5);
    mot.R.m[1][1] = GF_R(1.0);
    assert_int_equal(gf_kf2_predict(&kf, &mot, NULL), GF_OK);
    memset(&meas, 0, sizeof meas);
    meas.m = 1;
    meas.C.m[0][0] = GF_R(1.0);
    meas.Q.m[0][0] = GF_R(10.0);
    z.v[0] = GF_R(0.5);
    z.v[1] = GF_R(0.0);
    assert_int_equal(gf_kf2_update(&kf, &meas, &z, NULL), GF_OK);
    mot.A.m[0][1] = (gf_real)dt;
    mot.R.m[0][0] = (gf_real)(q * dt * dt * dt * dt / 4);
    mot.R.m[0][1] = mot.R.m[1][0] = (gf_real)(q * dt * dt * dt / 2);
    mot.R.m[1][1] = (gf_real)(q * dt * dt);
    assert_int_equal(gf_kf2_predict(&kf, &mot, NULL), GF_OK);
    meas.m = 2;
    meas.C.m[1][1] = GF_R(1.0);
    meas.Q.m[0][0] = GF_R(0.5);
    meas.Q.m[1][1] = GF_R(0.25);
    z.v[0] = GF_R(0.7);
    z.v[1] = GF_R(0.2);
    assert_int_equal(gf_kf2_update(&kf, &meas, &z, NULL), GF_OK);

    b = &fx.c.sink.b[fx.c.sink.n - 1];
    assert_int_equal(b->m, 2);
    check_close(b->mean[0], (double)kf.mu.v[0]);
    check_close(b->mean[1], (double)kf.mu.v[1]);
    assert_int_equal(gf_kf2_cov(&kf, &sigma), GF_OK);
    check_close(b->cov[0][0], (double)sigma.m[0][0]);
    check_close(b->cov[0][1], (double)sigma.m[0][1]);
    check_close(b->cov[1][1], (double)sigma.m[1][1]);

    // reset: the belief restarts from the message's prior
    mm.reset = 1;
    mm.prior_mean[0] = 3.0;
    mm.prior_cov[0][0] = 2.0;
    mm.prior_cov[1][1] = 1.0;
    mm.utime = 7;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_APPLIED);
    b = &fx.c.sink.b[fx.c.sink.n - 1];
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_INIT);
    check_close(b->mean[0], 3.0);
    check_close(b->cov[0][0], 2.0);
    assert_int_equal(b->utime, 7);

    // refused, nothing changed: another kind, a negative variance, a
    // measure the kind cannot take, a prior that is not PSD
    mm.model = GF_ROBOT;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_BAD_FIELD);
    mm.model = GF_CAR;
    mm.accel_var = -1.0;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_BAD_FIELD);
    mm.accel_var = q;
    mm.measure = GAUSSFILT_LCM_MODEL_T_MEASURE_RANGE_BEARING;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_BAD_FIELD);
    mm.measure = GAUSSFILT_LCM_MODEL_T_MEASURE_X;
    mm.prior_cov[0][1] = mm.prior_cov[1][0] = 5.0;
    assert_int_equal(feed(msg_model(&mm)), GF_NODE_BAD_FIELD);
    assert_int_equal(fx.node.counts.models, 2);
    check_close(gf_node_find(&fx.node, 5)->mdl.accel_var, q);
}

// ---- range and bearing ----------------------------------------------------

// h for a landmark at (5, 3), written here apart from node_model.c.
static gf_status rb_here(void *ctx, const gf_vec3 *x, gf_vec3 *z_hat,
                         gf_mat3 *H)
{
    double dx = 5.0 - (double)x->v[0], dy = 3.0 - (double)x->v[1];
    double q = dx * dx + dy * dy, r = sqrt(q);
    (void)ctx;
    z_hat->v[0] = (gf_real)r;
    z_hat->v[1] = (gf_real)(atan2(dy, dx) - (double)x->v[2]);
    H->m[0][0] = (gf_real)(-dx / r);
    H->m[0][1] = (gf_real)(-dy / r);
    H->m[0][2] = GF_R(0.0);
    H->m[1][0] = (gf_real)(dy / q);
    H->m[1][1] = (gf_real)(-dx / q);
    H->m[1][2] = GF_R(-1.0);
    return GF_OK;
}

static void range_bearing(void **state)
{
    gf_ekf3 ekf;
    gf_ekf3_motion mot;
    gf_ekf3_meas meas;
    gf_vec3 z;
    gf_real u[2] = {GF_R(1.0), GF_R(0.2)};
    const gf_vec3 mu0 = {{GF_R(1.0), GF_R(2.0), GF_R(0.5)}};
    const gf_mat3 sigma0 = {{{GF_R(0.01), GF_R(0.0), GF_R(0.0)},
                             {GF_R(0.0), GF_R(0.02), GF_R(0.0)},
                             {GF_R(0.0), GF_R(0.0), GF_R(0.03)}}};
    gf_mat3 sigma;
    const gf_wire_belief *b;
    double vd = 0.0025, vp = 0.0001 * 0.2 * 0.2, c = cos(0.5), s = sin(0.5);
    int i, j;
    (void)state;
    // track 31 runs "lm": prior (1, 2, 0.5), landmark (5, 3). A bearing
    // of 3.1 rad against a predicted one near -3.1 must wrap.
    assert_int_equal(feed(gf_msg_ctrl(31, GF_ROBOT, 1, 1, 2, 1.0, 0.2)),
                     GF_NODE_APPLIED);
    assert_int_equal(
        feed(msg_meas2(31, GF_ROBOT, 2, 1, 3.2, 0.3, 0.0025, 0.0001)),
        GF_NODE_APPLIED);
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &sigma0), GF_OK);
    memset(&mot, 0, sizeof mot);
    mot.g = gf_ekf3_motion_forward_turn;
    mot.R.m[0][0] = (gf_real)(c * c * vd);
    mot.R.m[0][1] = mot.R.m[1][0] = (gf_real)(c * s * vd);
    mot.R.m[1][1] = (gf_real)(s * s * vd);
    mot.R.m[2][2] = (gf_real)vp;
    assert_int_equal(gf_ekf3_predict(&ekf, &mot, u), GF_OK);
    memset(&meas, 0, sizeof meas);
    meas.m = 2;
    meas.h = rb_here;
    meas.angle_mask = 2u;
    meas.Q.m[0][0] = GF_R(0.0025);
    meas.Q.m[1][1] = GF_R(0.0001);
    z.v[0] = GF_R(3.2);
    z.v[1] = GF_R(0.3);
    z.v[2] = GF_R(0.0);
    assert_int_equal(gf_ekf3_update(&ekf, &meas, &z, NULL), GF_OK);
    b = &fx.c.sink.b[fx.c.sink.n - 1];
    assert_int_equal(b->status, 0);
    assert_int_equal(gf_ekf3_cov(&ekf, &sigma), GF_OK);
    for (i = 0; i < 3; i++) {
        check_close(b->mean[i], (double)ekf.mu.v[i]);
        for (j = 0; j < 3; j++) {
            check_close(b->cov[i][j], (double)sigma.m[i][j]);
        }
    }
    // the wrap: a bearing one turn off gives the same innovation
    assert_int_equal(feed(gf_msg_ctrl(32, GF_ROBOT, 1, 1, 2, 1.0, 0.2)),
                     GF_NODE_APPLIED);
    assert_int_equal(
        feed(msg_meas2(32, GF_ROBOT, 2, 1, 3.2,
                       0.3 - 2.0 * 3.14159265358979323846, 0.0025, 0.0001)),
        GF_NODE_APPLIED);
    check_close(fx.c.sink.b[fx.c.sink.n - 1].innovation[1], b->innovation[1]);
    check_close(fx.c.sink.b[fx.c.sink.n - 1].mean[0], b->mean[0]);
    // m = 1 does not fit a range-bearing model
    assert_int_equal(feed(gf_msg_meas(31, GF_ROBOT, 3, 2, 1.0, 0.1)),
                     GF_NODE_BAD_FIELD);
}

// ---- one channel name per track and kind ---------------------------------

static void one_channel_spelling(void **state)
{
    static const char *bad[] = {"GF_MEAS_0007", "GF_MEAS_07", "GF_MEAS_-0",
                                "GF_MEAS_+7",   "GF_MEAS_7 ", "GF_CTRL_00",
                                "GF_MODEL_-07", "GF_MEAS_"};
    unsigned i;
    gf_msg m = gf_msg_meas(7, GF_CAR, 1, 0, 1.0, 10.0);
    gf_msg z = gf_msg_meas(0, GF_CAR, 1, 0, 1.0, 10.0);
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (feed_on(bad[i], strncmp(bad[i], "GF_MEAS_0", 9) == 0 ||
                                    strcmp(bad[i], "GF_MEAS_-0") == 0 ||
                                    strcmp(bad[i], "GF_CTRL_00") == 0
                                ? z
                                : m) != GF_NODE_UNKNOWN_CHANNEL) {
            fail_msg("%s was taken", bad[i]);
        }
    }
    assert_int_equal(fx.node.ntracks, 0);
    assert_int_equal(feed_on("GF_MEAS_7", m), GF_NODE_APPLIED);
    assert_int_equal(feed_on("GF_MEAS_0", z), GF_NODE_APPLIED);
    assert_int_equal(fx.node.ntracks, 2);
}

// ---- seq and utime at the edges of their range ------------------------------

static void sequence_resync(void **state)
{
    int64_t seq;
    int i;
    (void)state;
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, 1, 10, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, INT64_MAX, 20, 0, 0, 0)),
                     GF_NODE_APPLIED);
    // the real stream goes on: rejected GF_NODE_RESYNC_AFTER times, then
    // taken as the new reference
    for (i = 0, seq = 2; i < GF_NODE_RESYNC_AFTER; i++, seq++) {
        assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, seq, 20 + seq, 0, 0, 0)),
                         GF_NODE_OUT_OF_ORDER);
    }
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, seq, 20 + seq, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.seq_resyncs, 1);
    seq++;
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, seq, 20 + seq, 0, 0, 0)),
                     GF_NODE_APPLIED);
    // gaps: none for INT64_MAX - 1 (the old bound) nor for the jump
    assert_int_equal(fx.node.counts.gaps, INT64_MAX - 2);
    // utime at INT64_MAX: the same rule
    seq++;
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, seq, INT64_MAX, 0, 0, 0)),
                     GF_NODE_APPLIED);
    for (i = 0; i < GF_NODE_RESYNC_AFTER; i++) {
        assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, ++seq, 100, 0, 0, 0)),
                         GF_NODE_OUT_OF_ORDER);
    }
    assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, ++seq, 100, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.seq_resyncs, 2);
    // duplicates do not count towards a resync
    for (i = 0; i < 3 * GF_NODE_RESYNC_AFTER; i++) {
        assert_int_equal(feed(gf_msg_ctrl(9, GF_CAR, seq, 100, 0, 0, 0)),
                         GF_NODE_DUPLICATE);
    }
    assert_int_equal(fx.node.counts.seq_resyncs, 2);
}

// ---- a PF summary that cannot be computed ---------------------------------

static void pf_no_summary(void **state)
{
    const gf_wire_belief *b;
    const gf_node_track *t;
    char line[1024];
    (void)state;
    assert_int_equal(
        gf_node_set_filter(&fx.node, GF_NODE_FILTER_PF, &fx.pool, 1), 0);
    assert_int_equal(feed(gf_msg_ctrl(4, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
                     GF_NODE_APPLIED);
    // 1e155 forward (1e20 in float): the particles move, their covariance
    // overflows
    assert_int_equal(
        feed(gf_msg_ctrl(4, GF_ROBOT, 2, 2, 2,
                         sizeof(gf_real) == sizeof(float) ? 1e20 : 1e155, 0.0)),
        GF_NODE_NO_SUMMARY);
    b = &fx.c.sink.b[fx.c.sink.n - 1];
    assert_int_equal(b->status, GF_NODE_STATUS_NO_SUMMARY);
    assert_int_equal(b->status, GAUSSFILT_LCM_BELIEF_T_STATUS_NO_SUMMARY);
    assert_int_equal(b->input_seq, 2);
    assert_true(isnan(b->mean[0]) && isnan(b->cov[0][0]));
    // what the track holds is what was published
    t = gf_node_find(&fx.node, 4);
    assert_true(t->f.pf3.no_summary);
    assert_true(isnan((double)t->f.pf3.mu.v[0]));
    assert_int_equal(fx.c.inf_in_cloud, 0);
    assert_true(fx.c.clouds >= 3);
    // later steps are taken (not non-finite): each says no_summary while
    // the cloud stays beyond reach
    assert_int_equal(feed(gf_msg_ctrl(4, GF_ROBOT, 3, 3, 2, 1.0, 0.0)),
                     GF_NODE_NO_SUMMARY);
    assert_int_equal(fx.node.counts.by_result[GF_NODE_NONFINITE], 0);
    assert_int_equal(fx.c.inf_in_cloud, 0);
    // a new simulator session starts the track afresh, with a summary
    {
        gf_msg m = gf_msg_ctrl(4, GF_ROBOT, 1, 4, 2, 1.0, 0.0);
        gaussfilt_lcm_control_t c;
        gaussfilt_lcm_control_t_decode(m.data, 0, m.len, &c);
        c.session = 2;
        m.len =
            gaussfilt_lcm_control_t_encode(m.data, 0, (int)sizeof m.data, &c);
        gaussfilt_lcm_control_t_decode_cleanup(&c);
        assert_int_equal(feed(m), GF_NODE_APPLIED);
    }
    b = &fx.c.sink.b[fx.c.sink.n - 1];
    assert_int_equal(b->status, 0);
    assert_true(isfinite(b->mean[0]));
    assert_true(gf_node_summary(&fx.node, line, sizeof line) > 0);
    assert_non_null(strstr(line, " no_summary=2"));
}

// ---- linear models --------------------------------------------------------

// The node's log lines, kept.
typedef struct said_ {
    char line[8][256];
    int n;
} said_;

static void keep_line(void *ctx, const char *line)
{
    said_ *s = ctx;
    if (s->n < 8) {
        snprintf(s->line[s->n], sizeof s->line[0], "%s", line);
    }
    s->n++;
}

static const char linear_conf[] =
    "[model cvca]\n"
    "type = linear\n"
    "channels = GF_(MEAS|CTRL|MODEL)_4[0-9][0-9]\n"
    "motion = cv ca\n"
    "dt = 0.5\n"
    "accel_var = 2 3\n"
    "C = 1 0 0 0 0 ; 0 0 1 0 0\n"
    "Q = 0.09 0.04\n"
    "prior_cov = 1 1 1 1 1\n"
    "[model pushed]\n"
    "type = linear\n"
    "channels = GF_(MEAS|CTRL)_5[0-9][0-9]\n"
    "n = 2\n"
    "A = 1 0.1 ; 0 1\n"
    "B = 0.005 ; 0.1\n"
    "R = 0.001 0.0005 0.0005 0.002\n"
    "C = 1 0\n"
    "Q = 0.25\n"
    "prior_mean = 1 -1\n"
    "prior_cov = 0.5 0.1 0.1 0.3\n"
    "gate = 9\n"
    "[model pushed2]\n"
    "base = pushed\n"
    "channels = GF_(MEAS|CTRL)_6[0-9][0-9]\n"
    "Q = 4\n";

static void linear_config(void **state)
{
    static gf_node_config cfg;
    char err[256];
    const gf_node_model *m;
    const gf_node_linear *l;
    const double dt = 0.5, h = 0.5 * dt * dt;
    // cv block (x, vx): A = ((1, dt), (0, 1)), R = 2 g g^T, g = (h, dt);
    // ca block (y, vy, ay): A = ((1, dt, h), (0, 1, dt), (0, 0, 1)),
    // R = 3 g g^T, g = (h, dt, 1)
    const double A[25] = {1,  dt, 0, 0, 0, 0, 1,  0, 0, 0, 0, 0, 1,
                          dt, h,  0, 0, 0, 1, dt, 0, 0, 0, 0, 1};
    const double g[5] = {h, dt, h, dt, 1}, q[5] = {2, 2, 3, 3, 3};
    unsigned i, j;
    (void)state;
    assert_int_equal(gf_node_config_parse(&cfg, linear_conf, err, sizeof err),
                     0);
    m = gf_node_config_named(&cfg, 401, GF_NODE_KIND_LINEAR);
    assert_non_null(m);
    assert_string_equal(m->name, "cvca");
    l = m->lin;
    assert_int_equal(l->n, 5);
    assert_int_equal(l->m, 2);
    assert_int_equal(l->nu, 0);
    for (i = 0; i < 5; i++) {
        for (j = 0; j < 5; j++) {
            int same = (i < 2) == (j < 2);
            check_close(l->A[i * 5 + j], A[i * 5 + j]);
            check_close(l->R[i * 5 + j], same ? q[i] * g[i] * g[j] : 0.0);
        }
    }
    check_close(l->C[0 * 5 + 0], 1.0);
    check_close(l->C[1 * 5 + 2], 1.0);
    check_close(l->Q[3], 0.04);
    // explicit numbers, B, and a model on its base with its own Q
    m = gf_node_config_named(&cfg, 650, GF_NODE_KIND_LINEAR);
    assert_non_null(m);
    assert_string_equal(m->name, "pushed2");
    assert_int_equal(m->lin->nu, 1);
    check_close(m->lin->B[1], 0.1);
    check_close(m->lin->Q[0], 4.0);
    check_close(gf_node_config_find(&cfg, "pushed")->lin->Q[0], 0.25);
    check_close(m->gate, 9.0);
    // no preset stands in for a linear track
    assert_null(gf_node_config_lookup(&cfg, 7, GF_NODE_KIND_LINEAR));
    assert_null(gf_node_config_named(&cfg, 7, GF_NODE_KIND_CAR));
    gf_node_config_free(&cfg);
}

static void linear_errors(void **state)
{
    static const struct {
        const char *text, *err;
    } bad[] = {
        {"[model a]\ntype = linear\nA = 1\n", "line 3: n (or motion) first"},
        {"[model a]\ntype = linear\nn = 2\nA = 1 0 0\n",
         "line 4: A takes 4 numbers (n = 2)"},
        {"[model a]\ntype = linear\nn = 13\n",
         "line 3: n takes a number 1..12"},
        {"[model a]\ntype = linear\nn = 2\nQ = 1\n",
         "line 4: Q after C (its rows give m)"},
        {"[model a]\ntype = linear\nn = 2\naccel_var = 1\n",
         "line 4: accel_var needs motion first"},
        {"[model a]\ntype = linear\nmotion = cv xx\n",
         "line 3: motion takes axes: cv (position, velocity), ca "
         "(position, velocity, acceleration) or c (a constant)"},
        {"[model a]\ntype = linear\nodometry = 1 2 3 4\n",
         "line 3: a linear model has no odometry"},
        {"[model a]\ntype = linear\nn = 2\nC = 1 0 0\n",
         "line 4: C takes m*n numbers, one row of n = 2 per measured quantity "
         "(m <= n)"},
        // found when the section ends: the line of the key at fault
        {"[model a]\ntype = linear\nn = 2\nR = 1 2 3 1\nC = 1 0\nQ = 1\n",
         "line 4: model a: R must be symmetric positive semidefinite (and A, "
         "B, R finite)"},
        {"[model a]\ntype = linear\nn = 2\nC = 1 0\n\nQ = -1\n",
         "line 6: model a: Q must be symmetric positive semidefinite (and C "
         "finite)"},
        {"[model a]\ntype = linear\nn = 2\nC = 1 0\nprior_cov = 1 -1\n",
         "line 5: model a: prior_cov must be symmetric positive semidefinite "
         "(as gf_kf_init takes it)"},
        {"[model a]\ntype = linear\nn = 2\n",
         "line 2: model a: C: a linear model measures 1 to n quantities (C = "
         "m*n numbers)"},
        {"[model a]\ntype = linear\nmotion = cv\nA = 1 0 0 1\nC = 1 0\n",
         "line 4: model a: A or motion, not both"},
        // a linear model no pattern names runs nothing, unless a base
        {"[model a]\ntype = car\n[model b]\ntype = linear\nn = 2\nC = 1 0\n"
         "[model c]\nbase = b\nchannels = GF_MEAS_1\n[model d]\nbase = c\n",
         "line 10: model d: a linear model needs channels (the tracks that run "
         "it: no preset stands in for a linear track), or another model "
         "taking it as its base"},
        // a key the model keeps from its base: the base line
        {"[model a]\ntype = car\n[model b]\nbase = a\n# x\ndt = 0\n",
         "line 6: model b: dt must be a finite number > 0"},
        {"[model a]\ntype = car\nmeasure = position\n[model b]\nbase = a\n"
         "meas_cov = -1\n",
         "line 6: model b: meas_cov must be symmetric positive semidefinite"},
    };
    static gf_node_config cfg;
    char err[200];
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        if (gf_node_config_parse(&cfg, bad[i].text, err, sizeof err) == 0) {
            fail_msg("no error for %s", bad[i].text);
        }
        if (strcmp(err, bad[i].err) != 0) {
            fail_msg("for %s\n said: %s\n want: %s", bad[i].text, err,
                     bad[i].err);
        }
        gf_node_config_free(&cfg);
    }
}

static const gf_node_model *named_lookup(const void *ctx, int32_t id,
                                         int8_t kind)
{
    return gf_node_config_named((const gf_node_config *)ctx, id, kind);
}

// A linear track through the node equals gf_kf run directly with the
// model's A, B, R, C and the measurement's z, Q; its first input after
// two never seen is counted and said.
static void linear_track(void **state)
{
    static gf_node_config cfg;
    static gf_node node;
    static catch_ c;
    static gf_kf_work work;
    said_ said;
    char err[160], line[1024];
    gf_kf kf;
    const gf_real mu0[2] = {GF_R(1.0), GF_R(-1.0)},
                  P0[4] = {GF_R(0.5), GF_R(0.1), GF_R(0.1), GF_R(0.3)},
                  A[4] = {GF_R(1.0), GF_R(0.1), GF_R(0.0), GF_R(1.0)},
                  B[2] = {GF_R(0.005), GF_R(0.1)},
                  R[4] = {GF_R(0.001), GF_R(0.0005), GF_R(0.0005), GF_R(0.002)},
                  C[2] = {GF_R(1.0), GF_R(0.0)}, Q[1] = {GF_R(0.3)};
    const gf_real u[1] = {GF_R(2.0)}, z[1] = {GF_R(1.4)};
    gf_kf_model km = {1, A, B, R, NULL};
    gf_kf_meas mm = {1, C, Q, NULL, GF_R(9.0)};
    gf_kf_innovation info;
    gf_real sigma[4];
    const gf_wire_belief *b;
    const double zq = 0.3, zz = 1.4;
    unsigned i, j;
    (void)state;
    memset(&c, 0, sizeof c);
    memset(&said, 0, sizeof said);
    assert_int_equal(gf_node_config_parse(&cfg, linear_conf, err, sizeof err),
                     0);
    gf_node_init(&node, on_publish, &c);
    gf_node_set_models(&node, named_lookup, &cfg);
    gf_node_set_log(&node, keep_line, &said);
    gf_node_set_id(&node, "test-node");
    // seq 3 first: 1 and 2 never arrived
    {
        gf_msg m = gf_msg_ctrl(500, 3, 3, 100, 1, 2.0, 0.0);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_APPLIED);
        m = gf_msg_meas_m(500, 3, 4, 100, 1, &zz, &zq);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_APPLIED);
        // m = 2 for a model of m = 1 (twice), a control of 2 for nu = 1:
        // each a status belief, each field said once with both sizes;
        // their seqs arrived: no gap before the next
        m = msg_meas2(500, 3, 5, 100, 1, 1, 1, 1);
        for (i = 0; i < 2; i++) {
            assert_int_equal(
                gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                GF_NODE_BAD_FIELD);
        }
        m = gf_msg_ctrl(500, 3, 6, 100, 2, 2.0, 0.0);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_BAD_FIELD);
        m = gf_msg_ctrl(500, 3, 7, 100, 0, 0.0, 0.0);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_APPLIED);
        assert_int_equal(node.counts.gaps, 0);
        // a linear track nothing names: refused, said once
        m = gf_msg_ctrl(7, 3, 1, 0, 0, 0, 0);
        for (i = 0; i < 2; i++) {
            assert_int_equal(
                gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                GF_NODE_NO_MODEL);
        }
    }
    assert_int_equal(gf_kf_init(&kf, 2, mu0, P0, &work), GF_OK);
    assert_int_equal(gf_kf_predict(&kf, &km, u, &work), GF_OK);
    assert_int_equal(gf_kf_update(&kf, &mm, z, &info, &work), GF_OK);
    assert_int_equal(gf_kf_cov(&kf, sigma), GF_OK);
    // init, predict, update, the status beliefs of three bad_field, then
    // a prediction
    assert_int_equal(c.sink.n, 7);
    for (i = 3; i < 6; i++) {
        b = &c.sink.b[i];
        assert_int_equal(b->status, GF_NODE_STATUS_BAD_FIELD);
        assert_int_equal(b->stage, i < 5
                                       ? GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE
                                       : GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT);
        assert_int_equal(b->input_seq, i < 5 ? 5 : 6);
        assert_int_equal(b->seq, i);
        assert_memory_equal(b->mean, c.sink.b[2].mean, sizeof b->mean);
        assert_memory_equal(b->cov, c.sink.b[2].cov, sizeof b->cov);
    }
    b = &c.sink.b[2];
    assert_string_equal(b->node, "test-node");
    assert_int_equal(b->model, 3);
    assert_int_equal(b->filter, GAUSSFILT_LCM_BELIEF_T_FILTER_KF);
    assert_int_equal(b->n, 2);
    assert_int_equal(b->m, 1);
    for (i = 0; i < 2; i++) {
        check_close(b->mean[i], (double)kf.mu[i]);
        for (j = 0; j < 2; j++) {
            check_close(b->cov[i][j], (double)sigma[i * 2 + j]);
        }
    }
    check_close(b->innovation[0], (double)info.y[0]);
    check_close(b->nis, (double)info.nis);
    assert_int_equal(node.counts.lost_before_first, 2);
    assert_int_equal(said.n, 5);
    assert_string_equal(said.line[0],
                        "track 500 (linear, gf_kf): model pushed, its "
                        "channels GF_(MEAS|CTRL)_5[0-9][0-9] name it");
    assert_string_equal(said.line[1],
                        "track 500: its first input has seq 3: 2 earlier "
                        "inputs never reached this node (sent before it was "
                        "ready?)");
    assert_string_equal(said.line[2],
                        "track 500: a measurement has m = 2, its model pushed "
                        "measures m = 1 (C's rows) (bad_field)");
    assert_string_equal(said.line[3],
                        "track 500: a control has n = 2, its model pushed "
                        "takes n = 0 or 1 (B's columns) (bad_field)");
    assert_string_equal(said.line[4],
                        "track 7 (linear) refused: no configured linear "
                        "model's channels name GF_MEAS_7 or GF_CTRL_7 (a "
                        "linear track has no preset)");
    assert_true(gf_node_summary(&node, line, sizeof line) > 0);
    assert_non_null(strstr(line, " lost_before_first=2 "));
    assert_non_null(strstr(line, " no_model=2"));
    gf_node_config_free(&cfg);
}

// A linear track: its first 5 updates gated say once that its prior may be
// wrong, 5 more in a row later that it may be lost; a model_t resets it
// to its configured prior (and makes a track from its configuration),
// and refuses to set a linear model's numbers; a car's measurement on a
// track a linear model names is refused, naming that model.
static void linear_reset_and_gates(void **state)
{
    static gf_node_config cfg;
    static gf_node node;
    static catch_ c;
    said_ said;
    char err[256];
    gaussfilt_lcm_model_t mm;
    const gf_wire_belief *b;
    const double far = 100.0, near = 1.0, q = 0.3;
    gf_msg m;
    int64_t seq = 1;
    int i, n;
    (void)state;
    memset(&c, 0, sizeof c);
    memset(&said, 0, sizeof said);
    assert_int_equal(gf_node_config_parse(&cfg, linear_conf, err, sizeof err),
                     0);
    gf_node_init(&node, on_publish, &c);
    gf_node_set_models(&node, named_lookup, &cfg);
    gf_node_set_log(&node, keep_line, &said);
    // z = 100 against the prior x = 1 +- 0.71: NIS 99^2 / 0.8 > gate 9
    for (i = 0; i < GF_NODE_GATED_WARN + 1; i++) {
        m = gf_msg_meas_m(500, 3, seq++, 0, 1, &far, &q);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_GATED);
        assert_int_equal(said.n, i + 1 < GF_NODE_GATED_WARN ? 1 : 2);
    }
    assert_string_equal(said.line[1],
                        "track 500: its first 5 updates were all gated (the "
                        "last NIS 1.225e+04 > gate 9 of model pushed): prior "
                        "too tight or wrong?");
    // a model_t cannot set a linear model's numbers (a status belief)...
    memset(&mm, 0, sizeof mm);
    mm.track = 500;
    mm.model = 3;
    mm.utime = 9;
    n = c.sink.n;
    m = msg_model(&mm);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_BAD_FIELD);
    assert_int_equal(c.sink.n, n + 1);
    assert_int_equal(c.sink.b[n].status, GF_NODE_STATUS_BAD_FIELD);
    assert_int_equal(c.sink.b[n].stage, GAUSSFILT_LCM_BELIEF_T_STAGE_INIT);
    assert_string_equal(said.line[2],
                        "track 500: a model_t refused: a linear model's "
                        "numbers come from the configuration: a model_t "
                        "resets a linear track (reset = 1) and sets nothing "
                        "(bad_field)");
    // ... and resets it to its configured prior, N((1, -1), P0)
    mm.reset = 1;
    m = msg_model(&mm);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_APPLIED);
    assert_int_equal(node.counts.models, 1);
    b = &c.sink.b[c.sink.n - 1];
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_INIT);
    assert_int_equal(b->status, 0);
    assert_int_equal(b->utime, 9);
    check_close(b->mean[0], 1.0);
    check_close(b->mean[1], -1.0);
    check_close(b->cov[0][0], 0.5);
    check_close(b->cov[0][1], 0.1);
    check_close(b->cov[1][1], 0.3);
    // taken at once; then 5 gated in a row: the track may be lost
    m = gf_msg_meas_m(500, 3, seq++, 0, 1, &near, &q);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_APPLIED);
    for (i = 0; i < GF_NODE_GATED_WARN; i++) {
        m = gf_msg_meas_m(500, 3, seq++, 0, 1, &far, &q);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_GATED);
    }
    assert_int_equal(said.n, 4);
    assert_string_equal(said.line[3],
                        "track 500: 5 updates in a row gated (the last NIS "
                        "2.01e+04 > gate 9 of model pushed): has the track "
                        "been lost? (a model_t with reset = 1 restarts it)");
    // a reset of a track not made yet: made from its configured model
    mm.track = 501;
    m = msg_model(&mm);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_APPLIED);
    assert_non_null(gf_node_find(&node, 501));
    b = &c.sink.b[c.sink.n - 1];
    assert_int_equal(b->track, 501);
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_INIT);
    check_close(b->cov[1][1], 0.3);
    // a car's measurement on a track the linear model pushed names
    n = c.sink.n;
    m = gf_msg_meas(502, GF_CAR, 1, 0, near, q);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_BAD_FIELD);
    assert_null(gf_node_find(&node, 502));
    assert_int_equal(c.sink.n, n);
    assert_int_equal(said.n, 6);
    assert_string_equal(said.line[5],
                        "track 502: a measurement says model 1 (car), but the "
                        "configured model pushed (linear) names the track: "
                        "its messages say model 3 (bad_field)");
    gf_node_config_free(&cfg);
}

// --strict refuses what no pattern names (said once per track); without
// it the preset runs, and says so. Another node's belief of one of its
// tracks is counted and warned about once.
static void strict_and_peers(void **state)
{
    static gf_node node;
    static catch_ c;
    said_ said;
    gf_msg m;
    uint8_t buf[512];
    gaussfilt_lcm_belief_t b;
    int len, strict;
    (void)state;
    for (strict = 1; strict >= 0; strict--) {
        memset(&c, 0, sizeof c);
        memset(&said, 0, sizeof said);
        gf_node_init(&node, on_publish, &c);
        gf_node_set_models(&node, named_lookup, &fx.cfg);
        gf_node_set_log(&node, keep_line, &said);
        gf_node_set_strict(&node, strict);
        m = gf_msg_ctrl(7, GF_CAR, 1, 0, 0, 0, 0);
        {
            gf_node_result r1 =
                gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0);
            m = gf_msg_ctrl(7, GF_CAR, 2, 1, 0, 0, 0);
            gf_node_result r2 =
                gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0);
            assert_int_equal(r1, strict ? GF_NODE_NO_MODEL : GF_NODE_APPLIED);
            assert_int_equal(r2, strict ? GF_NODE_NO_MODEL : GF_NODE_APPLIED);
        }
        m = gf_msg_ctrl(150, GF_CAR, 1, 0, 0, 0, 0);
        assert_int_equal(
            gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
            GF_NODE_APPLIED);
        assert_int_equal(said.n, 2);
        assert_string_equal(
            said.line[0],
            strict ? "track 7 (car) refused (strict): no configured model's "
                     "channels name GF_MEAS_7 or GF_CTRL_7"
                   : "track 7 (car): the preset book-car: no configured "
                     "model's channels name GF_MEAS_7 or GF_CTRL_7 (strict "
                     "refuses such a track)");
        assert_string_equal(said.line[1],
                            "track 150 (car): model car100, its channels "
                            "GF_(MEAS|CTRL|MODEL)_1[0-9][0-9] name it");
        assert_int_equal(node.counts.by_result[GF_NODE_NO_MODEL],
                         strict ? 2 : 0);
    }
    // peers: this node is "me"; beliefs of track 150 from "other"
    gf_node_set_id(&node, "me");
    memset(&b, 0, sizeof b);
    b.track = 150;
    b.node = (char *)"other";
    b.sensor = (char *)"";
    len = gaussfilt_lcm_belief_t_encode(buf, 0, (int)sizeof buf, &b);
    assert_true(len > 0);
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len), 1);
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len), 1);
    assert_int_equal(node.counts.peer_beliefs, 2);
    assert_int_equal(said.n, 3); // once per track
    assert_string_equal(said.line[2],
                        "warning: node \"other\" also publishes beliefs of "
                        "track 150 (this node is \"me\"): two nodes filter "
                        "the same track; give each its own tracks "
                        "(--channels)");
    // its own, a track it does not hold, junk: not counted
    b.node = (char *)"me";
    len = gaussfilt_lcm_belief_t_encode(buf, 0, (int)sizeof buf, &b);
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len), 0);
    b.node = (char *)"other";
    b.track = 151;
    len = gaussfilt_lcm_belief_t_encode(buf, 0, (int)sizeof buf, &b);
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len), 0);
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len - 1), 0);
    buf[0] ^= 1;
    assert_int_equal(gf_node_peer_belief(&node, buf, (size_t)len), 0);
    assert_int_equal(node.counts.peer_beliefs, 2);
    assert_int_equal(said.n, 3);
    // the two beliefs of track 151 whose origin could be read (the whole
    // one and the one cut short: its track and node come first) came
    // before this node made the track: counted and said when it does
    m = gf_msg_ctrl(151, GF_CAR, 1, 0, 0, 0, 0);
    assert_int_equal(gf_node_handle(&node, m.channel, m.data, (size_t)m.len, 0),
                     GF_NODE_APPLIED);
    assert_int_equal(node.counts.peer_beliefs, 4);
    assert_int_equal(said.n, 5);
    assert_string_equal(said.line[4],
                        "warning: node \"other\" also publishes beliefs of "
                        "track 151 (this node is \"me\"): two nodes filter "
                        "the same track; give each its own tracks "
                        "(--channels)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(config_and_lookup, setup, teardown),
        cmocka_unit_test_setup_teardown(config_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(linear_reset_and_gates, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(model_between_steps, setup, teardown),
        cmocka_unit_test_setup_teardown(range_bearing, setup, teardown),
        cmocka_unit_test_setup_teardown(one_channel_spelling, setup, teardown),
        cmocka_unit_test_setup_teardown(sequence_resync, setup, teardown),
        cmocka_unit_test_setup_teardown(pf_no_summary, setup, teardown),
        cmocka_unit_test(linear_config),
        cmocka_unit_test(linear_errors),
        cmocka_unit_test(linear_track),
        cmocka_unit_test_setup_teardown(strict_and_peers, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
