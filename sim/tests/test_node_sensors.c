// SPDX-License-Identifier: MIT
// A model's named sensors and tracks in time (node_model.h, node_core.h),
// in process: the sensor sections of a configuration and their errors;
// a vehicle's sensors each updating the one belief, predicted to each
// input's utime, against gf_kf stepped here with A(dt), R(dt) written out;
// a control's own dt; a constant axis; a sensor's default Q; late and too old inputs, out
// of order and duplicates per sensor, each with its counter; a refused
// input leaving the track's belief and time, a gated one the prediction; a robot's
// heading and range sensors against EKF3 with callbacks written here;
// gf_node_tick's belief predicted to now.
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gf_msgs.h"
#include "node_core.h"

#define GF_LINEAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_LINEAR

static void check_close(double got, double want)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= GF_SIM_TOL * scale)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

static const char vehicle_conf[] =
    "[model vehicle]\n"
    "type = linear\n"
    "channels = GF_(MEAS|CTRL|MODEL)_7[0-9][0-9]\n"
    "motion = cv cv\n"
    "dt = 0.01\n"
    "accel_var = 0.5 0.1\n"
    "prior_mean = 0 10 0 0\n"
    "prior_cov = 1 1 0.01 0.01\n"
    "late_window = 0.2\n"
    "[sensor wheel]\n"
    "C = 0 1 0 0\n"
    "Q = 0.0025\n"
    "rate = 50\n"
    "[sensor gyro]\n"
    "C = 0 0 0 1\n"
    "Q = 0.0001\n"
    "[sensor gnss]\n"
    "C = 1 0 0 0 ; 0 0 1 0\n"
    "Q = 1 0.0025\n"
    "angles = 1\n"
    "gate = 18.4\n"
    "# a control of the speed, in time: B as given\n"
    "[model pushed]\n"
    "type = linear\n"
    "channels = GF_(MEAS|CTRL|MODEL)_8[0-9][0-9]\n"
    "motion = cv\n"
    "dt = 0.1\n"
    "accel_var = 2\n"
    "B = 0 ; 1\n"
    "C = 1 0\n"
    "Q = 0.5\n"
    "prior_mean = 1 2\n"
    "prior_cov = 1 0.5\n"
    "# a constant-velocity axis and a constant (a bias), in time\n"
    "[model biased]\n"
    "type = linear\n"
    "channels = GF_(MEAS|CTRL|MODEL)_6[0-9][0-9]\n"
    "motion = cv c\n"
    "dt = 0.05\n"
    "accel_var = 1.5 0.2\n"
    "C = 1 0 1\n"
    "Q = 0.04\n"
    "prior_mean = 0 1 0.5\n"
    "prior_cov = 1 1 0.25\n"
    "# a robot with a compass and a range finder to (4, 3)\n"
    "[model rover]\n"
    "type = robot\n"
    "channels = GF_(MEAS|CTRL|MODEL)_9[0-9][0-9]\n"
    "odometry = 0.01 0 0 0.001\n"
    "prior_mean = 0 0 0.3\n"
    "prior_cov = 0.1 0.1 0.05\n"
    "[sensor compass]\n"
    "measure = heading\n"
    "Q = 0.0004\n"
    "[sensor ranger]\n"
    "measure = range\n"
    "landmark = 4 3\n"
    "Q = 0.01\n"
    "[sensor finder]\n"
    "measure = bearing\n"
    "landmark = 4 3\n"
    "Q = 0.001\n";

typedef struct said_ {
    unsigned n;
    char line[16][256];
} said_;

static void keep_line(void *ctx, const char *line)
{
    said_ *s = ctx;
    if (s->n < 16) {
        snprintf(s->line[s->n++], sizeof s->line[0], "%s", line);
    }
}

typedef struct fixture {
    gf_node_config cfg;
    gf_node node;
    gf_sink sink;
    said_ said;
    gf_kf_work work;
} fixture;

static fixture fx;

static int on_publish(void *ctx, const char *channel, const void *data,
                      size_t len)
{
    gf_sink_add(ctx, channel, data, len);
    return 0;
}

static const gf_node_model *named(const void *ctx, int32_t id, int8_t kind)
{
    return gf_node_config_named((const gf_node_config *)ctx, id, kind);
}

static int setup(void **state)
{
    char err[200];
    (void)state;
    memset(&fx, 0, sizeof fx);
    if (gf_node_config_parse(&fx.cfg, vehicle_conf, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    gf_node_init(&fx.node, on_publish, &fx.sink);
    gf_node_set_models(&fx.node, named, &fx.cfg);
    gf_node_set_strict(&fx.node, 1);
    gf_node_set_log(&fx.node, keep_line, &fx.said);
    gf_node_set_id(&fx.node, "t");
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    gf_node_config_free(&fx.cfg);
    return 0;
}

// A measurement of `sensor` (NULL: GF_MEAS_<id>) with noise q (diagonal).
static gf_msg sensor_msg(int32_t track, int8_t model, const char *sensor,
                         int64_t seq, int64_t utime, int m, const double *z,
                         const double *q)
{
    gf_msg msg = gf_msg_meas_m(track, model, seq, utime, m, z, q);
    if (sensor != NULL) {
        snprintf(msg.channel, sizeof msg.channel, "%s%ld_%s", GF_CHANNEL_MEAS,
                 (long)track, sensor);
    }
    return msg;
}

static gf_node_result feed(gf_msg m, int64_t now)
{
    return gf_node_handle(&fx.node, m.channel, m.data, (size_t)m.len, now);
}

static const gf_wire_belief *last(void)
{
    assert_true(fx.sink.n > 0);
    return &fx.sink.b[fx.sink.n - 1];
}

// A(dt) and R(dt) of a cv axis at k (n states), written out.
static void cv_block(gf_real *A, gf_real *R, unsigned n, unsigned k, double dt,
                     double q)
{
    A[k * n + k] = A[(k + 1) * n + k + 1] = GF_R(1.0);
    A[k * n + k + 1] = (gf_real)dt;
    R[k * n + k] = (gf_real)(q * dt * dt * dt * dt / 4.0);
    R[k * n + k + 1] = R[(k + 1) * n + k] = (gf_real)(q * dt * dt * dt / 2.0);
    R[(k + 1) * n + k + 1] = (gf_real)(q * dt * dt);
}

// The vehicle's prediction over dt, in gf_kf directly.
static void vehicle_predict(gf_kf *kf, double dt)
{
    gf_real A[16], R[16];
    gf_kf_model km = {0, A, NULL, R, NULL};
    memset(A, 0, sizeof A);
    memset(R, 0, sizeof R);
    cv_block(A, R, 4, 0, dt, 0.5);
    cv_block(A, R, 4, 2, dt, 0.1);
    assert_int_equal(gf_kf_predict(kf, &km, NULL, &fx.work), GF_OK);
}

static void vehicle_update(gf_kf *kf, const gf_real *C, unsigned m,
                           const gf_real *Q, const gf_real *z)
{
    gf_kf_meas mm = {m, C, Q, NULL, GF_R(0.0)};
    gf_kf_innovation info;
    assert_int_equal(gf_kf_update(kf, &mm, z, &info, &fx.work), GF_OK);
}

static void check_belief(const gf_wire_belief *b, const gf_kf *kf)
{
    gf_real sigma[GF_KF_NMAX * GF_KF_NMAX];
    unsigned i, j;
    assert_int_equal(b->n, (int)kf->n);
    assert_int_equal(gf_kf_cov(kf, sigma), GF_OK);
    for (i = 0; i < kf->n; i++) {
        check_close(b->mean[i], (double)kf->mu[i]);
        for (j = 0; j < kf->n; j++) {
            check_close(b->cov[i][j], (double)sigma[i * kf->n + j]);
        }
    }
}

// ---- the configuration --------------------------------------------------

static void sensor_config(void **state)
{
    const gf_node_model *v = gf_node_config_find(&fx.cfg, "vehicle");
    const gf_node_model *r = gf_node_config_find(&fx.cfg, "rover");
    const gf_node_sensor *g;
    (void)state;
    assert_non_null(v);
    assert_non_null(v->sensors);
    assert_int_equal(v->sensors->count, 3);
    assert_int_equal(v->lin->m, 0); // measured by its sensors only
    g = gf_node_model_sensor(v, "gnss");
    assert_non_null(g);
    assert_int_equal(g->m, 2);
    assert_int_equal(g->angle_mask, 2u);
    check_close(g->C[2 * 0 + 0], 1.0);
    check_close(g->C[4 + 2], 1.0);
    check_close(g->Q[3], 0.0025);
    check_close(g->gate, 18.4);
    check_close(gf_node_model_sensor(v, "wheel")->rate, 50.0);
    assert_null(gf_node_model_sensor(v, "lidar"));
    check_close(v->late_window, 0.2);
    check_close(gf_node_config_find(&fx.cfg, "pushed")->late_window,
                GF_NODE_LATE_WINDOW);
    assert_int_equal(r->sensors->count, 3);
    assert_int_equal(gf_node_model_sensor(r, "compass")->measure,
                     GF_NODE_MEASURE_HEADING);
    assert_int_equal(gf_node_model_sensor(r, "compass")->angle_mask, 1u);
    assert_int_equal(gf_node_model_sensor(r, "ranger")->angle_mask, 0u);
    check_close(gf_node_model_sensor(r, "ranger")->landmark[1], 3.0);
}

static void sensor_errors(void **state)
{
    static const struct {
        const char *text, *err;
    } bad[] = {
        {"[sensor a]\n", "line 1: [sensor a] belongs to a linear or robot "
                         "model: after its [model NAME] and keys"},
        {"[model c]\ntype = car\n[sensor a]\n",
         "line 3: [sensor a] belongs to a linear or robot model: after its "
         "[model NAME] and keys"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor 1a]\n",
         "line 4: a sensor's name is a letter, then letters or digits, at "
         "most 15 characters"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nC = 1 0\n"
         "[sensor a]\n",
         "line 6: model v: sensor a defined twice"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nQ = 1\n",
         "line 5: Q after C (it gives m)"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nlandmark = 1 "
         "2\n",
         "line 5: a sensor of a linear model has no landmark: it measures C "
         "x (range, bearing and heading are a robot model's sensors)"},
        {"[model v]\ntype = linear\nmotion = cv cv\n[sensor a]\nmeasure = "
         "range\n",
         "line 5: a sensor of a linear model has no measure: it measures C x "
         "(range, bearing and heading are a robot model's sensors)"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nC = 1 0 0\n",
         "line 5: C takes m*n numbers, one row of n = 2 per measured quantity "
         "(m <= n)"},
        {"[model r]\ntype = robot\n[sensor a]\nmeasure = z\n",
         "line 4: a robot's sensor measures x, x y, range bearing, range, "
         "bearing or heading"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nangles = 0.5\n",
         "line 5: angles takes the rows (from 0) whose residual is an angle"},
        // found when the model ends: the line of the sensor's key at fault
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nC = 1 0\n"
         "# x\nQ = -1\n",
         "line 7: model v: sensor a: Q must be symmetric positive "
         "semidefinite (and C finite)"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nrate = 5\n",
         "line 4: model v: sensor a: C: a sensor of a linear model gives C "
         "(m rows of n)"},
        {"[model v]\ntype = linear\nmotion = cv\n[sensor a]\nC = 1 0\n"
         "angles = 1\n",
         "line 6: model v: sensor a: angles: a row beyond the sensor's m"},
        {"[model r]\ntype = robot\n[sensor a]\nmeasure = range\nQ = 1\n"
         "gate = -1\n",
         "line 6: model r: sensor a: gate must be finite and >= 0"},
        {"[model v]\ntype = linear\nmotion = cv\nlate_window = -1\n"
         "C = 1 0\n",
         "line 4: model v: late_window must be finite and >= 0 (seconds)"},
        // a linear model with neither C nor a sensor
        {"[model v]\ntype = linear\nmotion = cv\n",
         "line 2: model v: C: a linear model measures 1 to n quantities (C = "
         "m*n numbers)"},
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
    // a base's sensors are the new model's own
    assert_int_equal(gf_node_config_parse(&cfg,
                                          "[model v]\ntype = linear\nmotion "
                                          "= cv\n[sensor a]\nC = 1 0\nQ = 1\n"
                                          "[model w]\nbase = v\n"
                                          "channels = GF_MEAS_1\n"
                                          "[sensor b]\nC = 0 1\nQ = 2\n",
                                          err, sizeof err),
                     0);
    assert_int_equal(gf_node_config_find(&cfg, "v")->sensors->count, 1);
    assert_int_equal(gf_node_config_find(&cfg, "w")->sensors->count, 2);
    gf_node_config_free(&cfg);
}

// ---- a linear track in time ---------------------------------------------

// Three sensors at irregular times, one belief: each update equals gf_kf
// predicted over the same dt (the model's dt before the first input) and
// corrected with that sensor's C and the message's q (the sensor's Q for
// a q of zeros).
static void sensors_in_time(void **state)
{
    static const gf_real Cw[4] = {0, 1, 0, 0}, Cg[4] = {0, 0, 0, 1},
                         Cn[8] = {1, 0, 0, 0, 0, 0, 1, 0};
    const gf_real mu0[4] = {0, 10, 0, 0},
                  P0[16] = {1, 0, 0,    0, 0, 1, 0, 0,
                            0, 0, 0.01, 0, 0, 0, 0, 0.01};
    gf_kf kf;
    const double zw = 10.2, qw = 0.01, zg = 0.05, qg = 0.0004;
    const double zn[2] = {25.4, 0.1}, zero[2] = {0, 0};
    gf_real Q[4];
    gf_real zr[2];
    (void)state;
    assert_int_equal(gf_kf_init(&kf, 4, mu0, P0, &fx.work), GF_OK);
    // wheel at 1.000 s: the first input, dt = 0.01
    assert_int_equal(
        feed(sensor_msg(700, GF_LINEAR, "wheel", 1, 1000000, 1, &zw, &qw), 1),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 0.01);
    Q[0] = GF_R(0.01);
    zr[0] = (gf_real)zw;
    vehicle_update(&kf, Cw, 1, Q, zr);
    assert_int_equal(fx.sink.n, 2); // init, update
    check_belief(last(), &kf);
    assert_string_equal(last()->sensor, "wheel");
    assert_int_equal(last()->trigger, GAUSSFILT_LCM_BELIEF_T_TRIGGER_INPUT);
    assert_int_equal(last()->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE);
    // gyro 7.3 ms later, at the same time again, 31.9 ms later
    assert_int_equal(
        feed(sensor_msg(700, GF_LINEAR, "gyro", 1, 1007300, 1, &zg, &qg), 2),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 0.0073);
    Q[0] = GF_R(0.0004);
    zr[0] = (gf_real)zg;
    vehicle_update(&kf, Cg, 1, Q, zr);
    check_belief(last(), &kf);
    assert_int_equal(
        feed(sensor_msg(700, GF_LINEAR, "gyro", 2, 1007300, 1, &zg, &qg), 3),
        GF_NODE_APPLIED);
    vehicle_update(&kf, Cg, 1, Q, zr); // dt = 0: no prediction
    check_belief(last(), &kf);
    // gnss after 2.5 s of silence, its q all zero: the sensor's Q; the
    // course's residual in (-pi, pi]: as gf_kf
    assert_int_equal(
        feed(sensor_msg(700, GF_LINEAR, "gnss", 1, 3507300, 2, zn, zero), 4),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 2.5);
    Q[0] = GF_R(1.0);
    Q[1] = Q[2] = GF_R(0.0);
    Q[3] = GF_R(0.0025);
    {
        // gf_ekf with h = C x wraps the course; the same numbers as gf_kf
        // when the residual is in (-pi, pi]
        gf_real z2[2] = {(gf_real)zn[0], (gf_real)zn[1]};
        vehicle_update(&kf, Cn, 2, Q, z2);
    }
    check_belief(last(), &kf);
    assert_string_equal(last()->sensor, "gnss");
    assert_int_equal(last()->m, 2);
    // each sensor its own seq: gyro 2 -> 3, wheel 1 -> 2: no gap
    assert_int_equal(
        feed(sensor_msg(700, GF_LINEAR, "wheel", 2, 3510000, 1, &zw, &qw), 5),
        GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.gaps, 0);
    // a course 2 pi away is the same course
    {
        double z3[2] = {25.5, 0.1 - 2.0 * 3.14159265358979323846};
        gf_kf a, b2;
        const gf_wire_belief *b;
        double mean_wrapped[4];
        a = gf_node_find(&fx.node, 700)->f.kf;
        assert_int_equal(
            feed(sensor_msg(700, GF_LINEAR, "gnss", 2, 3510000, 2, z3, zero),
                 6),
            GF_NODE_APPLIED);
        b = last();
        for (unsigned i = 0; i < 4; i++) {
            mean_wrapped[i] = b->mean[i];
        }
        // against the unwrapped course on the same prior
        b2 = a;
        {
            gf_real z2[2] = {GF_R(25.5), GF_R(0.1)};
            vehicle_update(&b2, Cn, 2, Q, z2);
        }
        for (unsigned i = 0; i < 4; i++) {
            if (!(fabs(mean_wrapped[i] - (double)b2.mu[i]) < 1e-9)) {
                fail_msg("state %u: wrapped %.17g, want %.17g", i,
                         mean_wrapped[i], (double)b2.mu[i]);
            }
        }
    }
}

// A control carries its own dt: A(dt), R(dt) for the time since the
// track's last input, B u as given.
static void control_in_time(void **state)
{
    const gf_real mu0[2] = {1, 2}, P0[4] = {1, 0, 0, 0.5}, B[2] = {0, 1},
                  u[1] = {GF_R(0.7)};
    gf_real A[4], R[4];
    gf_kf kf;
    gf_kf_model km = {1, A, B, R, NULL};
    (void)state;
    assert_int_equal(gf_kf_init(&kf, 2, mu0, P0, &fx.work), GF_OK);
    assert_int_equal(
        feed(gf_msg_ctrl(800, GF_LINEAR, 1, 5000000, 1, 0.7, 0), 0),
        GF_NODE_APPLIED);
    memset(A, 0, sizeof A);
    memset(R, 0, sizeof R);
    cv_block(A, R, 2, 0, 0.1, 2.0); // the first: the model's dt
    assert_int_equal(gf_kf_predict(&kf, &km, u, &fx.work), GF_OK);
    check_belief(last(), &kf);
    assert_int_equal(
        feed(gf_msg_ctrl(800, GF_LINEAR, 2, 5230000, 1, 0.7, 0), 0),
        GF_NODE_APPLIED);
    memset(A, 0, sizeof A);
    memset(R, 0, sizeof R);
    cv_block(A, R, 2, 0, 0.23, 2.0);
    assert_int_equal(gf_kf_predict(&kf, &km, u, &fx.work), GF_OK);
    check_belief(last(), &kf);
    assert_int_equal(last()->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT);
}

// A constant axis (c): A = 1, R = q dt, beside a cv axis; the model's own
// C on GF_MEAS_<id>, in time.
static void constant_axis(void **state)
{
    const gf_real mu0[3] = {0, 1, GF_R(0.5)},
                  P0[9] = {1, 0, 0, 0, 1, 0, 0, 0, GF_R(0.25)},
                  C[3] = {1, 0, 1}, Q[1] = {GF_R(0.04)};
    gf_real A[9], R[9], z[1];
    gf_kf kf;
    gf_kf_model km = {0, A, NULL, R, NULL};
    gf_kf_meas mm = {1, C, Q, NULL, 0};
    const double zs[2] = {0.62, 1.4}, q = 0.04;
    const int64_t ut[2] = {7000000, 7730000};
    const double dts[2] = {0.05, 0.73};
    (void)state;
    assert_int_equal(gf_kf_init(&kf, 3, mu0, P0, &fx.work), GF_OK);
    for (int k = 0; k < 2; k++) {
        assert_int_equal(
            feed(gf_msg_meas(600, GF_LINEAR, k + 1, ut[k], zs[k], q), 0),
            GF_NODE_APPLIED);
        memset(A, 0, sizeof A);
        memset(R, 0, sizeof R);
        cv_block(A, R, 3, 0, dts[k], 1.5);
        A[8] = GF_R(1.0);
        R[8] = (gf_real)(0.2 * dts[k]);
        assert_int_equal(gf_kf_predict(&kf, &km, NULL, &fx.work), GF_OK);
        z[0] = (gf_real)zs[k];
        assert_int_equal(gf_kf_update(&kf, &mm, z, NULL, &fx.work), GF_OK);
        check_belief(last(), &kf);
        assert_string_equal(last()->sensor, "");
    }
}

// Late and too old inputs, out of order and duplicates: each its counter;
// a late one's status belief; no false gap.
static void late_and_old(void **state)
{
    const double z = 10, q = 0.0025;
    gf_node_track before;
    const gf_node_track *t;
    int n;
    (void)state;
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "gyro", 1, 2000000, 1, &z, &q), 0),
        GF_NODE_APPLIED);
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 1, 2010000, 1, &z, &q), 0),
        GF_NODE_APPLIED);
    t = gf_node_find(&fx.node, 701);
    memcpy(&before, t, sizeof before);
    n = fx.sink.n;
    // 0.1 s older than the track's time, within its late_window of 0.2 s
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 2, 1910000, 1, &z, &q), 0),
        GF_NODE_LATE);
    assert_int_equal(fx.sink.n, n + 1);
    assert_int_equal(last()->status, GF_NODE_STATUS_LATE);
    assert_int_equal(last()->input_seq, 2);
    assert_int_equal(last()->utime, 1910000);
    assert_string_equal(last()->sensor, "wheel");
    assert_memory_equal(&before.f.kf, &t->f.kf, sizeof t->f.kf); // unchanged
    // 0.5 s older: too old, its status belief
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 3, 1510000, 1, &z, &q), 0),
        GF_NODE_TOO_OLD);
    assert_int_equal(fx.sink.n, n + 2);
    assert_int_equal(last()->status, GF_NODE_STATUS_TOO_OLD);
    assert_int_equal(last()->input_seq, 3);
    assert_string_equal(last()->sensor, "wheel");
    assert_memory_equal(&before.f.kf, &t->f.kf, sizeof t->f.kf);
    // the wheel's seq 3 again, and 1: duplicate, out of order
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 3, 2020000, 1, &z, &q), 0),
        GF_NODE_DUPLICATE);
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 1, 2020000, 1, &z, &q), 0),
        GF_NODE_OUT_OF_ORDER);
    // the gyro's own seq goes on; the wheel's 4: no gap (2 and 3 came)
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "gyro", 2, 2020000, 1, &z, &q), 0),
        GF_NODE_APPLIED);
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "wheel", 4, 2030000, 1, &z, &q), 0),
        GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.gaps, 0);
    // the gyro's 5 after 2: a gap of 2
    assert_int_equal(
        feed(sensor_msg(701, GF_LINEAR, "gyro", 5, 2040000, 1, &z, &q), 0),
        GF_NODE_APPLIED);
    assert_int_equal(fx.node.counts.gaps, 2);
    assert_int_equal(fx.node.counts.by_result[GF_NODE_LATE], 1);
    assert_int_equal(fx.node.counts.by_result[GF_NODE_TOO_OLD], 1);
    assert_int_equal(fx.node.counts.by_result[GF_NODE_DUPLICATE], 1);
    assert_int_equal(fx.node.counts.by_result[GF_NODE_OUT_OF_ORDER], 1);
    // a sensor its model lacks, a wrong m, a car's sensor, spellings
    {
        const double z2[2] = {1, 2}, q2[2] = {1, 1};
        assert_int_equal(
            feed(sensor_msg(701, GF_LINEAR, "lidar", 1, 2050000, 1, &z, &q), 0),
            GF_NODE_BAD_FIELD);
        assert_int_equal(
            feed(sensor_msg(701, GF_LINEAR, "lidar", 2, 2050000, 1, &z, &q), 0),
            GF_NODE_BAD_FIELD);
        // a track it would make: not made by it, and said once too
        assert_int_equal(
            feed(sensor_msg(703, GF_LINEAR, "lidar", 1, 2050000, 1, &z, &q), 0),
            GF_NODE_BAD_FIELD);
        assert_null(gf_node_find(&fx.node, 703));
        // the track's line, each refusal's once, the sensor's once each
        assert_int_equal(fx.said.n, 7);
        assert_string_equal(fx.said.line[1],
                            "track 701: a measurement of sensor wheel 0.1 s "
                            "older than the track's time, its model vehicle's "
                            "late_window 0.2 s (late)");
        assert_string_equal(fx.said.line[2],
                            "track 701: a measurement of sensor wheel 0.5 s "
                            "older than the track's time, its model vehicle's "
                            "late_window 0.2 s (too_old)");
        assert_string_equal(fx.said.line[3],
                            "track 701: a measurement of sensor wheel with "
                            "seq 3 came again (duplicate)");
        assert_string_equal(fx.said.line[4],
                            "track 701: a measurement of sensor wheel with "
                            "seq 1, utime 2020000: its stream is at seq 3, "
                            "the track at utime 2010000 (out_of_order)");
        assert_string_equal(fx.said.line[5],
                            "track 701: a measurement on GF_MEAS_701_lidar: "
                            "its model vehicle has no sensor lidar "
                            "(bad_field)");
        assert_int_equal(
            feed(sensor_msg(701, GF_LINEAR, "wheel", 5, 2050000, 2, z2, q2), 0),
            GF_NODE_BAD_FIELD);
        assert_int_equal(
            feed(sensor_msg(1, GF_CAR, "wheel", 1, 0, 1, &z, &q), 0),
            GF_NODE_BAD_FIELD);
        assert_int_equal(fx.said.n, 9);
        assert_string_equal(fx.said.line[7],
                            "track 701: a measurement of sensor wheel has "
                            "m = 2, the sensor measures m = 1 (bad_field)");
        assert_string_equal(fx.said.line[8],
                            "track 1: a measurement on GF_MEAS_1_wheel says "
                            "model 1 (car): a car has no sensors (bad_field)");
    }
    {
        gf_msg m = sensor_msg(701, GF_LINEAR, "gyro", 9, 2060000, 1, &z, &q);
        assert_int_equal(
            gf_node_handle(&fx.node, "GF_MEAS_701_", m.data, (size_t)m.len, 0),
            GF_NODE_UNKNOWN_CHANNEL);
        assert_int_equal(gf_node_handle(&fx.node, "GF_MEAS_0701_gyro", m.data,
                                        (size_t)m.len, 0),
                         GF_NODE_UNKNOWN_CHANNEL);
        assert_int_equal(gf_node_handle(&fx.node, "GF_CTRL_701_gyro", m.data,
                                        (size_t)m.len, 0),
                         GF_NODE_UNKNOWN_CHANNEL);
    }
}

// A failed input of a track in time leaves the track where it was, its
// belief and its time; a gated one leaves the prediction to its time.
static void failed_in_time(void **state)
{
    const gf_real mu0[4] = {0, 10, 0, 0},
                  P0[16] = {1, 0, 0,    0, 0, 1, 0, 0,
                            0, 0, 0.01, 0, 0, 0, 0, 0.01};
    static const gf_real Cw[4] = {0, 1, 0, 0};
    const double zw = 10.0, qw = 0.0025, bad = NAN;
    const double zn[2] = {1000.0, 0.0}, zero[2] = {0, 0};
    gf_real Q[1] = {GF_R(0.0025)}, zr[1] = {GF_R(10.0)};
    const gf_node_track *t;
    gf_kf kf, before;
    int64_t time;
    (void)state;
    assert_int_equal(gf_kf_init(&kf, 4, mu0, P0, &fx.work), GF_OK);
    assert_int_equal(
        feed(sensor_msg(704, GF_LINEAR, "wheel", 1, 1000000, 1, &zw, &qw), 0),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 0.01);
    vehicle_update(&kf, Cw, 1, Q, zr);
    t = gf_node_find(&fx.node, 704);
    before = t->f.kf;
    time = t->time;
    // a NaN 0.3 s later: refused by the core, the track as it was
    assert_int_equal(
        feed(sensor_msg(704, GF_LINEAR, "wheel", 2, 1300000, 1, &bad, &qw), 0),
        GF_NODE_NONFINITE);
    assert_memory_equal(&before, &t->f.kf, sizeof before);
    assert_int_equal(t->time, time);
    assert_int_equal(last()->status, GF_ERR_NONFINITE);
    // the next one predicts over the whole 0.5 s since the last applied
    assert_int_equal(
        feed(sensor_msg(704, GF_LINEAR, "wheel", 3, 1500000, 1, &zw, &qw), 0),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 0.5);
    vehicle_update(&kf, Cw, 1, Q, zr);
    check_belief(last(), &kf);
    // a wild gnss fix, gated: the belief predicted to its time, kept
    assert_int_equal(
        feed(sensor_msg(704, GF_LINEAR, "gnss", 1, 1700000, 2, zn, zero), 0),
        GF_NODE_GATED);
    vehicle_predict(&kf, 0.2);
    check_belief(last(), &kf);
    assert_int_equal(last()->status, GF_ERR_GATED);
    assert_int_equal(t->time, 1700000);
    assert_int_equal(
        feed(sensor_msg(704, GF_LINEAR, "wheel", 4, 1800000, 1, &zw, &qw), 0),
        GF_NODE_APPLIED);
    vehicle_predict(&kf, 0.1);
    vehicle_update(&kf, Cw, 1, Q, zr);
    check_belief(last(), &kf);
}

// ---- a robot's sensors -----------------------------------------------------

static gf_status my_heading(void *ctx, const gf_vec3 *mu, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    (void)ctx;
    memset(z_hat, 0, sizeof *z_hat);
    memset(H, 0, sizeof *H);
    z_hat->v[0] = mu->v[2];
    H->m[0][2] = GF_R(1.0);
    return GF_OK;
}

static gf_status my_range(void *ctx, const gf_vec3 *mu, gf_vec3 *z_hat,
                          gf_mat3 *H)
{
    double dx = 4.0 - (double)mu->v[0], dy = 3.0 - (double)mu->v[1];
    double r = sqrt(dx * dx + dy * dy);
    (void)ctx;
    memset(z_hat, 0, sizeof *z_hat);
    memset(H, 0, sizeof *H);
    z_hat->v[0] = (gf_real)r;
    H->m[0][0] = (gf_real)(-dx / r);
    H->m[0][1] = (gf_real)(-dy / r);
    return GF_OK;
}

static gf_status my_bearing(void *ctx, const gf_vec3 *mu, gf_vec3 *z_hat,
                            gf_mat3 *H)
{
    double dx = 4.0 - (double)mu->v[0], dy = 3.0 - (double)mu->v[1];
    double q = dx * dx + dy * dy;
    (void)ctx;
    memset(z_hat, 0, sizeof *z_hat);
    memset(H, 0, sizeof *H);
    z_hat->v[0] = gf_angle_wrap((gf_real)(atan2(dy, dx) - (double)mu->v[2]));
    H->m[0][0] = (gf_real)(dy / q);
    H->m[0][1] = (gf_real)(-dx / q);
    H->m[0][2] = GF_R(-1.0);
    return GF_OK;
}

static void robot_sensors(void **state)
{
    const gf_vec3 mu0 = {{0, 0, GF_R(0.3)}};
    const gf_mat3 s0 = {
        {{GF_R(0.1), 0, 0}, {0, GF_R(0.1), 0}, {0, 0, GF_R(0.05)}}};
    gf_ekf3 ekf;
    gf_ekf3_motion mot;
    gf_ekf3_meas mm;
    gf_mat3 sigma;
    const gf_real u[2] = {GF_R(1.0), GF_R(0.1)};
    const double zh = 0.45 - 2.0 * 3.14159265358979323846, qh = 0.0004;
    const double zr = 3.9, qr = 0.01, zb = 0.2, qb = 0.001;
    const gf_wire_belief *b;
    unsigned i, j;
    (void)state;
    assert_int_equal(gf_ekf3_init(&ekf, &mu0, &s0), GF_OK);
    assert_int_equal(feed(gf_msg_ctrl(900, GF_ROBOT, 1, 1, 2, 1.0, 0.1), 0),
                     GF_NODE_APPLIED);
    gf_node_model_robot(gf_node_config_find(&fx.cfg, "rover"), ekf.mu.v[2], u,
                        &mot);
    assert_int_equal(gf_ekf3_predict(&ekf, &mot, u), GF_OK);
    // the compass, its heading 2 pi away: the residual wrapped
    assert_int_equal(
        feed(sensor_msg(900, GF_ROBOT, "compass", 1, 1, 1, &zh, &qh), 0),
        GF_NODE_APPLIED);
    memset(&mm, 0, sizeof mm);
    mm.m = 1;
    mm.h = my_heading;
    mm.Q.m[0][0] = GF_R(0.0004);
    mm.angle_mask = 1u;
    {
        gf_vec3 z = {{(gf_real)zh, 0, 0}};
        assert_int_equal(gf_ekf3_update(&ekf, &mm, &z, NULL), GF_OK);
    }
    mm.h = my_range;
    mm.Q.m[0][0] = GF_R(0.01);
    mm.angle_mask = 0u;
    assert_int_equal(
        feed(sensor_msg(900, GF_ROBOT, "ranger", 1, 1, 1, &zr, &qr), 0),
        GF_NODE_APPLIED);
    {
        gf_vec3 z = {{(gf_real)zr, 0, 0}};
        assert_int_equal(gf_ekf3_update(&ekf, &mm, &z, NULL), GF_OK);
    }
    mm.h = my_bearing;
    mm.Q.m[0][0] = GF_R(0.001);
    mm.angle_mask = 1u;
    assert_int_equal(
        feed(sensor_msg(900, GF_ROBOT, "finder", 1, 1, 1, &zb, &qb), 0),
        GF_NODE_APPLIED);
    {
        gf_vec3 z = {{(gf_real)zb, 0, 0}};
        assert_int_equal(gf_ekf3_update(&ekf, &mm, &z, NULL), GF_OK);
    }
    b = last();
    assert_string_equal(b->sensor, "finder");
    assert_int_equal(gf_ekf3_cov(&ekf, &sigma), GF_OK);
    for (i = 0; i < 3; i++) {
        check_close(b->mean[i], (double)ekf.mu.v[i]);
        for (j = 0; j < 3; j++) {
            check_close(b->cov[i][j], (double)sigma.m[i][j]);
        }
    }
}

// The same sensors on a UKF3 track (gf_node --filter ukf) against gf_ukf3
// with the test's callbacks, and on a PF3 track (--filter pf): each
// applied, its belief the sensor's, the PF's mean pulled to the compass.
static void robot_sensors_ukf_pf(void **state)
{
    static const gf_ukf3_params p = {GF_R(1.0), GF_R(2.0), GF_R(0.0)};
    static gf_node_pf_pool pool;
    const gf_vec3 mu0 = {{0, 0, GF_R(0.3)}};
    const gf_mat3 s0 = {
        {{GF_R(0.1), 0, 0}, {0, GF_R(0.1), 0}, {0, 0, GF_R(0.05)}}};
    const gf_real u[2] = {GF_R(1.0), GF_R(0.1)};
    const double zh = 0.45, qh = 0.0004, zr = 3.9, qr = 0.01, zb = 0.2,
                 qb = 0.001;
    gf_ekf3_meas_fn h[3] = {my_heading, my_range, my_bearing};
    const char *name[3] = {"compass", "ranger", "finder"};
    const double *z[3] = {&zh, &zr, &zb}, *q[3] = {&qh, &qr, &qb};
    const unsigned mask[3] = {1u, 0u, 1u};
    gf_ukf3 ukf;
    gf_ekf3_motion mot;
    gf_ekf3_meas mm;
    const gf_wire_belief *b;
    unsigned i, j, k;
    (void)state;
    assert_int_equal(gf_node_set_filter(&fx.node, GF_NODE_FILTER_UKF, NULL, 1),
                     0);
    assert_int_equal(gf_ukf3_init(&ukf, &mu0, &s0, &p), GF_OK);
    assert_int_equal(feed(gf_msg_ctrl(901, GF_ROBOT, 1, 1, 2, 1.0, 0.1), 0),
                     GF_NODE_APPLIED);
    gf_node_model_robot(gf_node_config_find(&fx.cfg, "rover"), ukf.mu.v[2], u,
                        &mot);
    assert_int_equal(gf_ukf3_predict(&ukf, &mot, u), GF_OK);
    for (k = 0; k < 3; k++) {
        gf_vec3 zz = {{(gf_real)*z[k], 0, 0}};
        assert_int_equal(
            feed(sensor_msg(901, GF_ROBOT, name[k], 1, 1, 1, z[k], q[k]), 0),
            GF_NODE_APPLIED);
        memset(&mm, 0, sizeof mm);
        mm.m = 1;
        mm.h = h[k];
        mm.Q.m[0][0] = (gf_real)*q[k];
        mm.angle_mask = mask[k];
        assert_int_equal(gf_ukf3_update(&ukf, &mm, &zz, NULL), GF_OK);
        b = last();
        assert_int_equal(b->filter, GAUSSFILT_LCM_BELIEF_T_FILTER_UKF3);
        assert_string_equal(b->sensor, name[k]);
        assert_int_equal(b->status, GF_OK);
        for (i = 0; i < 3; i++) {
            check_close(b->mean[i], (double)ukf.mu.v[i]);
            for (j = 0; j < 3; j++) {
                check_close(b->cov[i][j], (double)ukf.sigma.m[i][j]);
            }
        }
    }
    assert_int_equal(gf_node_set_filter(&fx.node, GF_NODE_FILTER_PF, &pool, 1),
                     0);
    assert_int_equal(feed(gf_msg_ctrl(902, GF_ROBOT, 1, 1, 2, 1.0, 0.1), 0),
                     GF_NODE_APPLIED);
    for (k = 0; k < 3; k++) {
        double before = last()->cov[2][2];
        assert_int_equal(
            feed(sensor_msg(902, GF_ROBOT, name[k], 1, 1, 1, z[k], q[k]), 0),
            GF_NODE_APPLIED);
        b = last();
        assert_int_equal(b->filter, GAUSSFILT_LCM_BELIEF_T_FILTER_PF3);
        assert_string_equal(b->sensor, name[k]);
        assert_int_equal(b->status, GF_OK);
        if (k == 0) { // the compass: theta's spread narrows, towards 0.45
            assert_true(b->cov[2][2] < 0.1 * before);
            assert_true(fabs(b->mean[2] - zh) < 0.05);
        }
    }
}

// ---- gf_node_tick ------------------------------------------------------------

static void tick(void **state)
{
    const double z = 10.1, q = 0.0025;
    gf_kf kf;
    gf_node_track before;
    int n;
    (void)state;
    assert_int_equal(gf_node_tick(&fx.node, 5), 0); // no track yet
    assert_int_equal(
        feed(sensor_msg(702, GF_LINEAR, "wheel", 3, 4000000, 1, &z, &q),
             1000000000),
        GF_NODE_APPLIED);
    // its first input says two never came, and whose they were
    assert_int_equal(fx.node.counts.lost_before_first, 2);
    assert_string_equal(fx.said.line[1],
                        "track 702: its first input of sensor wheel has seq "
                        "3: 2 earlier inputs never reached this node (sent "
                        "before it was ready?)");
    kf = gf_node_find(&fx.node, 702)->f.kf;
    memcpy(&before, gf_node_find(&fx.node, 702), sizeof before);
    n = fx.sink.n;
    // 50 ms after the input was received: predicted over 0.05 s
    assert_int_equal(gf_node_tick(&fx.node, 1000050000), 1);
    assert_int_equal(fx.sink.n, n + 1);
    vehicle_predict(&kf, 0.05);
    check_belief(last(), &kf);
    assert_int_equal(last()->trigger, GAUSSFILT_LCM_BELIEF_T_TRIGGER_RATE);
    assert_int_equal(last()->utime, 4050000);
    assert_int_equal(last()->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT);
    assert_int_equal(last()->input_seq, 3);
    assert_int_equal(last()->status, 0);
    // the track itself unchanged (its belief number aside)
    before.belief_seq++;
    assert_memory_equal(&before, gf_node_find(&fx.node, 702), sizeof before);
    // a car (the preset book-car): predicted with its A and R over the
    // 0.25 s since its control; a robot as it is
    gf_node_set_strict(&fx.node, 0);
    assert_int_equal(
        feed(gf_msg_ctrl(5, GF_CAR, 1, 3000000, 0, 0, 0), 1000000000),
        GF_NODE_APPLIED);
    assert_int_equal(
        feed(gf_msg_ctrl(6, GF_ROBOT, 1, 3000000, 2, 1, 0), 1000000000),
        GF_NODE_APPLIED);
    {
        gf_node_model car = *gf_node_model_book_car();
        gf_kf2 kf2 = gf_node_find(&fx.node, 5)->f.kf2;
        gf_kf2_model km;
        gf_mat2 sigma;
        gf_vec3 mu3 = gf_node_find(&fx.node, 6)->f.ekf3.mu;
        const gf_wire_belief *b;
        car.dt = 0.25;
        gf_node_model_car(&car, &km);
        assert_int_equal(gf_kf2_predict(&kf2, &km, NULL), GF_OK);
        assert_int_equal(gf_kf2_cov(&kf2, &sigma), GF_OK);
        n = fx.sink.n;
        assert_int_equal(gf_node_tick(&fx.node, 1000250000), 3);
        assert_int_equal(fx.sink.n, n + 3);
        b = &fx.sink.b[n + 1]; // tracks in creation order: 702, 5, 6
        assert_int_equal(b->track, 5);
        assert_int_equal(b->utime, 3250000);
        for (unsigned i = 0; i < 2; i++) {
            check_close(b->mean[i], (double)kf2.mu.v[i]);
            for (unsigned j = 0; j < 2; j++) {
                check_close(b->cov[i][j], (double)sigma.m[i][j]);
            }
        }
        b = &fx.sink.b[n + 2];
        assert_int_equal(b->track, 6);
        for (unsigned i = 0; i < 3; i++) {
            check_close(b->mean[i], (double)mu3.v[i]);
        }
        assert_int_equal(b->trigger, GAUSSFILT_LCM_BELIEF_T_TRIGGER_RATE);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(sensor_config, setup, teardown),
        cmocka_unit_test_setup_teardown(sensor_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(sensors_in_time, setup, teardown),
        cmocka_unit_test_setup_teardown(control_in_time, setup, teardown),
        cmocka_unit_test_setup_teardown(constant_axis, setup, teardown),
        cmocka_unit_test_setup_teardown(late_and_old, setup, teardown),
        cmocka_unit_test_setup_teardown(failed_in_time, setup, teardown),
        cmocka_unit_test_setup_teardown(robot_sensors, setup, teardown),
        cmocka_unit_test_setup_teardown(robot_sensors_ukf_pf, setup, teardown),
        cmocka_unit_test_setup_teardown(tick, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
