// SPDX-License-Identifier: MIT
// The node's message handling without sockets (node_core.c): the exercise
// tables through gf_node_handle, and every way a message can be refused.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gaussfilt_lcm_node_status_t.h"
#include "gf_msgs.h"
#include "node_core.h"

#define TOL GF_SIM_TOL

typedef struct fixture {
    gf_node node;
    gf_sink sink;
    unsigned nsaid; // the node's log lines
    char said[16][256];
    uint8_t status[GF_NODE_STATUS_BYTES]; // the last status published
    size_t status_len;
} fixture;

static int sink_publish(void *ctx, const char *channel, const void *data,
                        size_t len)
{
    fixture *f = ctx;
    if (strcmp(channel, GF_CHANNEL_STATUS) == 0) {
        assert_true(len <= sizeof f->status);
        memcpy(f->status, data, len);
        f->status_len = len;
        return 0;
    }
    gf_sink_add(&f->sink, channel, data, len);
    return 0;
}

static void keep_line(void *ctx, const char *line)
{
    fixture *f = ctx;
    if (f->nsaid < 16) {
        snprintf(f->said[f->nsaid], sizeof f->said[0], "%s", line);
    }
    f->nsaid++;
}

static int setup(void **state)
{
    static fixture f; // large; one test at a time
    memset(&f, 0, sizeof(f));
    gf_node_init(&f.node, sink_publish, &f);
    gf_node_set_log(&f.node, keep_line, &f);
    *state = &f;
    return 0;
}

static gf_node_result feed(fixture *f, gf_msg m)
{
    assert_true(m.len > 0);
    return gf_node_handle(&f->node, m.channel, m.data, (size_t)m.len, 0);
}

// received == sum of the results, applied == by_result[APPLIED].
static void check_counts(const gf_node *node)
{
    uint64_t sum = 0;
    unsigned r;
    for (r = 0; r < GF_NODE_RESULT_COUNT; r++) {
        sum += node->counts.by_result[r];
    }
    assert_true(sum == node->counts.received);
}

static void check_close(double got, double want)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= TOL * scale)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

static void exercise_2(fixture *f, int32_t track)
{
    int64_t t;
    for (t = 1; t <= 5; t++) {
        assert_int_equal(
            feed(f, gf_msg_ctrl(track, GF_CAR, t, t * 1000000, 0, 0, 0)),
            GF_NODE_APPLIED);
    }
    assert_int_equal(feed(f, gf_msg_meas(track, GF_CAR, 6, 5000000, 5, 10)),
                     GF_NODE_APPLIED);
}

static void table_2_1_in_process(void **state)
{
    fixture *f = *state;
    const gf_wire_belief *b;
    const double s = 51.25;
    int i;
    exercise_2(f, 2);
    assert_int_equal(f->sink.n, 7); // init + 5 predictions + 1 update
    for (i = 0; i < 7; i++) {
        assert_string_equal(f->sink.channel[i], "GF_BELIEF_2");
        assert_int_equal(f->sink.b[i].seq, i);
        assert_int_equal(f->sink.b[i].input_seq, i == 0 ? -1 : i);
        assert_int_equal(f->sink.b[i].status, 0);
    }
    b = &f->sink.b[5]; // before z = 5
    check_close(b->cov[0][0], 41.25);
    check_close(b->cov[0][1], 12.5);
    check_close(b->cov[1][1], 5.0);
    b = &f->sink.b[6]; // after
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE);
    check_close(b->mean[0], 41.25 * 5 / s);
    check_close(b->mean[1], 12.5 * 5 / s);
    check_close(b->cov[0][0], 41.25 * 10 / s);
    check_close(b->cov[1][0], 12.5 * 10 / s);
    check_close(b->cov[1][1], 5 - 12.5 * 12.5 / s);
    assert_int_equal(b->m, 1);
    check_close(b->innovation[0], 5.0);
    check_close(b->nis, 25.0 / s);
    check_counts(&f->node);
}

static void table_4_2_in_process(void **state)
{
    fixture *f = *state;
    const gf_wire_belief *b;
    assert_int_equal(feed(f, gf_msg_ctrl(4, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(f, gf_msg_meas(4, GF_ROBOT, 2, 1, -0.7, 0.01)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->sink.n, 3);
    b = &f->sink.b[2];
    assert_int_equal(b->n, 3);
    check_close(b->mean[0], 0.15);
    check_close(b->mean[1], 0.0);
    check_close(b->cov[0][0], 0.005);
    check_close(b->cov[1][1], 10000.01);
    check_close(b->cov[1][2], 10000.0);
    check_close(b->cov[2][2], 10000.0);
    check_counts(&f->node);
}

static void duplicates_and_out_of_order(void **state)
{
    fixture *f = *state;
    gf_node_track before;
    const gf_node_track *t;
    int i;
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 10, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->sink.n, 2);
    memcpy(&before, gf_node_find(&f->node, 1), sizeof(before));
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 10, 0, 0, 0)),
                     GF_NODE_DUPLICATE);
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 0, 10, 0, 0, 0)),
                     GF_NODE_OUT_OF_ORDER);
    assert_int_equal(feed(f, gf_msg_meas(1, GF_CAR, 1, 10, 1, 10)),
                     GF_NODE_DUPLICATE);
    // Newer seq but older utime: out of order too.
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 2, 9, 0, 0, 0)),
                     GF_NODE_OUT_OF_ORDER);
    // the filter and the sequence as they were; the count of
    // out_of_order in a row moved
    t = gf_node_find(&f->node, 1);
    assert_int_equal(t->rejected, 2);
    assert_memory_equal(&before.f, &t->f, sizeof(before.f));
    assert_true(t->seq[0] == 1 && t->input_seq == 1 && t->time == 10);
    // a status belief for each: the belief as it was, the input's seq,
    // utime and stage
    assert_int_equal(f->sink.n, 6);
    for (i = 2; i < 6; i++) {
        static const int8_t st[4] = {
            GF_NODE_STATUS_DUPLICATE, GF_NODE_STATUS_OUT_OF_ORDER,
            GF_NODE_STATUS_DUPLICATE, GF_NODE_STATUS_OUT_OF_ORDER};
        static const int64_t seq[4] = {1, 0, 1, 2}, utime[4] = {10, 10, 10, 9};
        const gf_wire_belief *b = &f->sink.b[i];
        assert_int_equal(b->status, st[i - 2]);
        assert_int_equal(b->input_seq, seq[i - 2]);
        assert_int_equal(b->utime, utime[i - 2]);
        assert_int_equal(b->seq, i);
        assert_int_equal(b->stage, i == 4
                                       ? GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE
                                       : GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT);
        assert_memory_equal(b->mean, f->sink.b[1].mean, sizeof(b->mean));
        assert_memory_equal(b->cov, f->sink.b[1].cov, sizeof(b->cov));
    }
    // seq 2 and 3 lost: counted as a gap of 2, then 2 is late.
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 4, 11, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->node.counts.gaps, 2);
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 2, 12, 0, 0, 0)),
                     GF_NODE_OUT_OF_ORDER);
    assert_int_equal(f->node.counts.by_result[GF_NODE_DUPLICATE], 2);
    assert_int_equal(f->node.counts.by_result[GF_NODE_OUT_OF_ORDER], 3);
    assert_int_equal(f->node.counts.by_result[GF_NODE_APPLIED], 2);
    assert_int_equal(f->node.counts.received, 7);
    check_counts(&f->node);
}

static void malformed_and_type_mismatch(void **state)
{
    fixture *f = *state;
    gf_msg good = gf_msg_meas(1, GF_CAR, 1, 0, 1.0, 10.0), m;
    gf_msg ctrl = gf_msg_ctrl(1, GF_CAR, 1, 0, 0, 0, 0);
    uint8_t junk[300];
    uint32_t x = 12345;
    int i, j, cut, malformed = 0;
    gaussfilt_lcm_belief_t b;

    assert_int_equal(gf_node_handle(&f->node, "GF_MEAS_1", NULL, 0, 0),
                     GF_NODE_MALFORMED);
    malformed++;
    for (cut = 0; cut < good.len; cut++) { // every truncation
        assert_int_equal(
            gf_node_handle(&f->node, good.channel, good.data, (size_t)cut, 0),
            GF_NODE_MALFORMED);
        malformed++;
    }
    m = good; // one trailing byte
    assert_int_equal(
        gf_node_handle(&f->node, m.channel, m.data, (size_t)m.len + 1, 0),
        GF_NODE_MALFORMED);
    malformed++;
    for (i = 0; i < 8; i++) { // wrong fingerprint, any of its bytes
        m = good;
        m.data[i] ^= 0x10;
        assert_int_equal(feed(f, m), GF_NODE_MALFORMED);
        malformed++;
    }
    for (i = 0; i < 1000; i++) { // random bytes, random lengths
        size_t len;
        x = x * 1664525u + 1013904223u;
        len = (x >> 8) % sizeof(junk);
        for (j = 0; j < (int)len; j++) {
            x = x * 1664525u + 1013904223u;
            junk[j] = (uint8_t)(x >> 24);
        }
        assert_int_equal(gf_node_handle(&f->node,
                                        i % 2 ? "GF_MEAS_1" : "GF_CTRL_1", junk,
                                        len, 0),
                         GF_NODE_MALFORMED);
        malformed++;
    }
    // Our other types on the wrong channel.
    assert_int_equal(
        gf_node_handle(&f->node, "GF_CTRL_1", good.data, (size_t)good.len, 0),
        GF_NODE_TYPE_MISMATCH);
    assert_int_equal(
        gf_node_handle(&f->node, "GF_MEAS_1", ctrl.data, (size_t)ctrl.len, 0),
        GF_NODE_TYPE_MISMATCH);
    memset(&b, 0, sizeof(b));
    b.node = (char *)"";
    b.sensor = (char *)"";
    m.len = gaussfilt_lcm_belief_t_encode(m.data, 0, (int)sizeof(m.data), &b);
    assert_int_equal(
        gf_node_handle(&f->node, "GF_MEAS_1", m.data, (size_t)m.len, 0),
        GF_NODE_TYPE_MISMATCH);

    assert_int_equal(f->node.counts.by_result[GF_NODE_MALFORMED], malformed);
    assert_int_equal(f->node.counts.by_result[GF_NODE_TYPE_MISMATCH], 3);
    assert_int_equal(f->node.ntracks, 0);
    assert_int_equal(f->sink.n, 0);
    // ... and the node still answers.
    assert_int_equal(feed(f, good), GF_NODE_APPLIED);
    assert_int_equal(f->sink.n, 2);
    check_counts(&f->node);
}

static void bad_fields_and_channels(void **state)
{
    fixture *f = *state;
    gf_msg m;
    // Track in the message is not the channel's.
    m = gf_msg_meas(1, GF_CAR, 1, 0, 1.0, 10.0);
    snprintf(m.channel, sizeof(m.channel), "GF_MEAS_2");
    assert_int_equal(feed(f, m), GF_NODE_BAD_FIELD);
    assert_int_equal(feed(f, gf_msg_ctrl(1, 4, 1, 0, 0, 0, 0)),
                     GF_NODE_BAD_FIELD); // no model 4
    assert_int_equal(feed(f, gf_msg_ctrl(1, 3, 1, 0, 0, 0, 0)),
                     GF_NODE_NO_MODEL); // linear: no preset, none named
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 0, 1, 0, 0)),
                     GF_NODE_BAD_FIELD); // car takes n = 0 or 2
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_ROBOT, 1, 0, 0, 0, 0)),
                     GF_NODE_BAD_FIELD); // robot needs u = (d, phi)
    {
        const double z3[3] = {1, 2, 3}, q3[3] = {1, 1, 1};
        m = gf_msg_meas_m(1, GF_CAR, 1, 0, 3, z3, q3);
        assert_int_equal(feed(f, m), GF_NODE_BAD_FIELD); // m = 3
    }
    {
        // m = 13 (beyond GF_NODE_NMAX), a whole message: bad_field; the
        // same bytes with m = -1: malformed
        static uint8_t big[64 + 8 * (13 + 169)];
        double z[13], q[13][13], *rows[13];
        gaussfilt_lcm_measurement_t x;
        int len, k;
        memset(&x, 0, sizeof(x));
        memset(q, 0, sizeof q);
        for (k = 0; k < 13; k++) {
            z[k] = k;
            q[k][k] = 1.0;
            rows[k] = q[k];
        }
        x.track = 1;
        x.model = 3;
        x.m = 13;
        x.z = z;
        x.q = rows;
        len = gaussfilt_lcm_measurement_t_encode(big, 0, (int)sizeof big, &x);
        assert_true(len > 0);
        assert_int_equal(
            gf_node_handle(&f->node, "GF_MEAS_1", big, (size_t)len, 0),
            GF_NODE_BAD_FIELD);
        big[8 + 8 + 8 + 8 + 4 + 1] = 0xff; // m = -1
        assert_int_equal(
            gf_node_handle(&f->node, "GF_MEAS_1", big, (size_t)len, 0),
            GF_NODE_MALFORMED);
    }
    assert_int_equal(f->node.ntracks, 0);
    // A track keeps its model.
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(f, gf_msg_meas(1, GF_ROBOT, 2, 0, 1.0, 0.01)),
                     GF_NODE_BAD_FIELD);
    // Channels the node does not serve.
    m = gf_msg_ctrl(1, GF_CAR, 3, 0, 0, 0, 0);
    assert_int_equal(
        gf_node_handle(&f->node, "GF_BELIEF_1", m.data, (size_t)m.len, 0),
        GF_NODE_UNKNOWN_CHANNEL);
    assert_int_equal(
        gf_node_handle(&f->node, "GF_CTRL_", m.data, (size_t)m.len, 0),
        GF_NODE_UNKNOWN_CHANNEL);
    assert_int_equal(
        gf_node_handle(&f->node, "GF_CTRL_1x", m.data, (size_t)m.len, 0),
        GF_NODE_UNKNOWN_CHANNEL);
    assert_int_equal(gf_node_handle(&f->node, "GF_CTRL_99999999999", m.data,
                                    (size_t)m.len, 0),
                     GF_NODE_UNKNOWN_CHANNEL);
    assert_int_equal(gf_node_handle(&f->node, NULL, m.data, (size_t)m.len, 0),
                     GF_NODE_UNKNOWN_CHANNEL);
    assert_int_equal(f->node.counts.by_result[GF_NODE_BAD_FIELD], 7);
    assert_int_equal(f->node.counts.by_result[GF_NODE_UNKNOWN_CHANNEL], 5);
    check_counts(&f->node);
}

static void nonfinite_reported_nothing_changed(void **state)
{
    fixture *f = *state;
    gf_node_track before;
    const gf_wire_belief *prev, *b;
    int n;
    exercise_2(f, 2);
    memcpy(&before, gf_node_find(&f->node, 2), sizeof(before));
    n = f->sink.n;
    assert_int_equal(
        feed(f, gf_msg_meas(2, GF_CAR, 7, 6000000, (double)NAN, 10.0)),
        GF_NODE_NONFINITE);
    assert_int_equal(
        feed(f, gf_msg_ctrl(2, GF_CAR, 8, 6000000, 2, (double)INFINITY, 0.0)),
        GF_NODE_NONFINITE);
    assert_int_equal(feed(f, gf_msg_meas(2, GF_CAR, 9, 6000000, 1.0, -1.0)),
                     GF_NODE_FILTER_ERROR); // Q not PSD
    assert_int_equal(f->sink.n, n + 3);
    prev = &f->sink.b[n - 1];
    for (; n < f->sink.n; n++) {
        b = &f->sink.b[n];
        assert_int_equal(b->status, n == f->sink.n - 1 ? GF_ERR_NOT_PSD
                                                       : GF_ERR_NONFINITE);
        assert_memory_equal(b->mean, prev->mean, sizeof(b->mean));
        assert_memory_equal(b->cov, prev->cov, sizeof(b->cov));
    }
    // The filter itself is bit-for-bit as it was (only the input bookkeeping
    // moved on).
    assert_memory_equal(&before.f, &gf_node_find(&f->node, 2)->f,
                        sizeof(before.f));
    // Robot: a NaN heading change.
    assert_int_equal(
        feed(f, gf_msg_ctrl(4, GF_ROBOT, 1, 1, 2, 1.0, (double)NAN)),
        GF_NODE_NONFINITE);
    assert_int_equal(f->sink.b[f->sink.n - 1].status, GF_ERR_NONFINITE);
    check_counts(&f->node);
}

static void track_limit(void **state)
{
    fixture *f = *state;
    int32_t id;
    for (id = 100; id < 100 + GF_NODE_MAX_TRACKS; id++) {
        assert_int_equal(feed(f, gf_msg_ctrl(id, GF_CAR, 1, 0, 0, 0, 0)),
                         GF_NODE_APPLIED);
    }
    assert_int_equal(feed(f, gf_msg_ctrl(id, GF_CAR, 1, 0, 0, 0, 0)),
                     GF_NODE_TRACK_LIMIT);
    assert_null(gf_node_find(&f->node, id));
    // The existing tracks go on.
    assert_int_equal(feed(f, gf_msg_meas(100, GF_CAR, 2, 0, 1.0, 10.0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->node.counts.tracks_created, GF_NODE_MAX_TRACKS);
    check_counts(&f->node);
}

// m with its session field set (re-encoded).
static gf_msg in_session(gf_msg m, int64_t session)
{
    gaussfilt_lcm_control_t c;
    gaussfilt_lcm_measurement_t z;
    if (gaussfilt_lcm_control_t_decode(m.data, 0, m.len, &c) == m.len) {
        c.session = session;
        m.len =
            gaussfilt_lcm_control_t_encode(m.data, 0, (int)sizeof(m.data), &c);
        gaussfilt_lcm_control_t_decode_cleanup(&c);
    } else {
        assert_int_equal(
            gaussfilt_lcm_measurement_t_decode(m.data, 0, m.len, &z), m.len);
        z.session = session;
        m.len = gaussfilt_lcm_measurement_t_encode(m.data, 0,
                                                   (int)sizeof(m.data), &z);
        gaussfilt_lcm_measurement_t_decode_cleanup(&z);
    }
    return m;
}

// A restarted simulator: seq 1 again under a larger session re-initialises
// the track from the prior (a STAGE_INIT belief, resyncs + 1), the seq rules
// start afresh; the old session is stale from then on.
static void simulator_restart_resyncs(void **state)
{
    fixture *f = *state;
    const gf_wire_belief *b;
    const gf_node_track *t;
    gf_kf2 before;
    assert_int_equal(
        feed(f, in_session(gf_msg_ctrl(3, GF_CAR, 1, 1, 0, 0, 0), 100)),
        GF_NODE_APPLIED);
    assert_int_equal(
        feed(f, in_session(gf_msg_meas(3, GF_CAR, 2, 1, 5.0, 10.0), 100)),
        GF_NODE_APPLIED);
    assert_int_equal(
        feed(f, in_session(gf_msg_ctrl(3, GF_CAR, 3, 2, 0, 0, 0), 100)),
        GF_NODE_APPLIED);
    assert_int_equal(f->sink.n, 4); // init + 3
    // The restart: seq 1, utime 1 again, session 200.
    assert_int_equal(
        feed(f, in_session(gf_msg_ctrl(3, GF_CAR, 1, 1, 0, 0, 0), 200)),
        GF_NODE_APPLIED);
    assert_true(f->node.counts.resyncs == 1);
    assert_int_equal(f->sink.n, 6);
    b = &f->sink.b[4]; // the re-initialisation: the prior, mu = 0, Sigma = 0
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_INIT);
    assert_true(b->seq == 4 && b->input_seq == -1);
    check_close(b->mean[0], 0.0);
    check_close(b->cov[0][0], 0.0);
    check_close(b->cov[1][1], 0.0);
    b = &f->sink.b[5]; // one prediction from the prior: Sigma = R
    assert_int_equal(b->stage, GAUSSFILT_LCM_BELIEF_T_STAGE_PREDICT);
    assert_true(b->seq == 5 && b->input_seq == 1);
    check_close(b->cov[0][0], 0.25);
    check_close(b->cov[0][1], 0.5);
    check_close(b->cov[1][1], 1.0);
    // The old session is stale, the new one's seq 1 a duplicate; neither
    // touches the belief; each publishes its status belief.
    t = gf_node_find(&f->node, 3);
    assert_non_null(t);
    before = t->f.kf2;
    assert_int_equal(
        feed(f, in_session(gf_msg_meas(3, GF_CAR, 4, 3, 1.0, 10.0), 100)),
        GF_NODE_STALE_SESSION);
    assert_int_equal(
        feed(f, in_session(gf_msg_ctrl(3, GF_CAR, 1, 1, 0, 0, 0), 200)),
        GF_NODE_DUPLICATE);
    assert_memory_equal(&before, &t->f.kf2, sizeof(before));
    assert_int_equal(f->sink.n, 8);
    assert_int_equal(f->sink.b[6].status, GF_NODE_STATUS_STALE_SESSION);
    assert_int_equal(f->sink.b[7].status, GF_NODE_STATUS_DUPLICATE);
    assert_true(f->node.counts.by_result[GF_NODE_STALE_SESSION] == 1);
    assert_true(f->node.counts.gaps == 0);
    assert_true(f->node.counts.resyncs == 1);
    check_counts(&f->node);
}

// A whole measurement with m beyond GF_NODE_NMAX, longer than 4096 bytes:
// bad_field (its header read), said once with its m.
static void too_large_is_bad_field(void **state)
{
    fixture *f = *state;
    static uint8_t big[64 + 8 * (23 + 23 * 23)];
    static double z[23], q[23][23], *rows[23];
    gaussfilt_lcm_measurement_t x;
    int len, k;
    memset(&x, 0, sizeof(x));
    for (k = 0; k < 23; k++) {
        z[k] = k;
        q[k][k] = 1.0;
        rows[k] = q[k];
    }
    x.track = 1;
    x.seq = 2;
    x.model = GF_CAR;
    x.m = 23;
    x.z = z;
    x.q = rows;
    len = gaussfilt_lcm_measurement_t_encode(big, 0, (int)sizeof big, &x);
    assert_true(len > 4096);
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(gf_node_handle(&f->node, "GF_MEAS_1", big, (size_t)len, 0),
                     GF_NODE_BAD_FIELD);
    assert_int_equal(f->sink.n, 3); // init, predict, the status belief
    assert_int_equal(f->sink.b[2].status, GF_NODE_STATUS_BAD_FIELD);
    assert_int_equal(f->sink.b[2].input_seq, 2);
    assert_int_equal(f->nsaid, 2);
    assert_string_equal(f->said[1], "track 1: a measurement has m = 23, more "
                                    "than any model measures (12) (bad_field)");
    // one byte more: malformed, said once for the track
    for (k = 0; k < 2; k++) {
        assert_int_equal(
            gf_node_handle(&f->node, "GF_MEAS_1", big, (size_t)len + 1, 0),
            GF_NODE_MALFORMED);
    }
    assert_int_equal(f->nsaid, 3);
    assert_string_equal(f->said[2], "track 1: a message on GF_MEAS_1 of 4455 "
                                    "bytes is not a whole measurement_t "
                                    "(malformed)");
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 3, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->node.counts.gaps, 0);
    check_counts(&f->node);
}

// Nothing refused in silence: a status belief for every refused input of
// a track the node holds, its seq counted as arrived (no false gap, no
// false loss before the first); each kind of refusal said once per track,
// naming the field and both sizes.
static void refusals_said_once(void **state)
{
    fixture *f = *state;
    const double z3[3] = {1, 2, 3}, q3[3] = {1, 1, 1};
    gf_msg m;
    int i;
    // a car track, then a measurement of m = 3, twice (seq 2 and 3)
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 1, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    for (i = 2; i <= 3; i++) {
        assert_int_equal(feed(f, gf_msg_meas_m(1, GF_CAR, i, 0, 3, z3, q3)),
                         GF_NODE_BAD_FIELD);
        assert_int_equal(f->sink.b[f->sink.n - 1].status,
                         GF_NODE_STATUS_BAD_FIELD);
        assert_int_equal(f->sink.b[f->sink.n - 1].input_seq, i);
        assert_int_equal(f->sink.b[f->sink.n - 1].stage,
                         GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE);
    }
    assert_int_equal(f->sink.n, 4);
    // all arrived: the next is no gap
    assert_int_equal(feed(f, gf_msg_ctrl(1, GF_CAR, 4, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->node.counts.gaps, 0);
    // a robot's measurement on the car's track; a control naming track 2
    assert_int_equal(feed(f, gf_msg_meas(1, GF_ROBOT, 5, 0, 1.0, 1.0)),
                     GF_NODE_BAD_FIELD);
    m = gf_msg_ctrl(2, GF_CAR, 6, 0, 0, 0, 0);
    snprintf(m.channel, sizeof m.channel, "GF_CTRL_1");
    assert_int_equal(feed(f, m), GF_NODE_BAD_FIELD);
    assert_int_equal(f->sink.n, 7);
    // a new track whose first input is refused: its seq arrived, so its
    // first taken input (seq 2) lost nothing before it
    assert_int_equal(feed(f, gf_msg_meas_m(3, GF_CAR, 1, 0, 3, z3, q3)),
                     GF_NODE_BAD_FIELD);
    assert_null(gf_node_find(&f->node, 3));
    assert_int_equal(feed(f, gf_msg_ctrl(3, GF_CAR, 2, 0, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(f->node.counts.lost_before_first, 0);
    // a NaN: its step fails (a status belief, as always), said once
    for (i = 0; i < 2; i++) {
        assert_int_equal(
            feed(f, gf_msg_meas(3, GF_CAR, 3 + i, 0, (double)NAN, 1.0)),
            GF_NODE_NONFINITE);
    }
    // a channel no track names, twice
    for (i = 0; i < 2; i++) {
        assert_int_equal(
            gf_node_handle(&f->node, "GF_CTRL_x", m.data, (size_t)m.len, 0),
            GF_NODE_UNKNOWN_CHANNEL);
    }
    {
        static const char *const want[] = {
            "track 1 (car): the preset book-car: no configured model's "
            "channels name GF_MEAS_1 or GF_CTRL_1 (strict refuses such a "
            "track)",
            "track 1: a measurement has m = 3, a car or robot measures 1 or 2 "
            "(bad_field)",
            "track 1: a measurement says model 2 (robot), the track is car "
            "(model book-car) (bad_field)",
            "track 1: a control on GF_CTRL_1 says track 2 (bad_field)",
            "track 3: a measurement has m = 3, a car or robot measures 1 or 2 "
            "(bad_field)",
            "track 3 (car): the preset book-car: no configured model's "
            "channels name GF_MEAS_3 or GF_CTRL_3 (strict refuses such a "
            "track)",
            "track 3: a measurement with seq 3: its step failed with status "
            "-2 (non-finite value), published with it (nonfinite)",
            "a message on GF_CTRL_x: not a track's channel "
            "(GF_MEAS_<id>[_<sensor>], GF_CTRL_<id>, GF_MODEL_<id>, the id in "
            "its one decimal spelling) (unknown_channel; said once)",
        };
        unsigned k;
        assert_int_equal(f->nsaid, sizeof want / sizeof want[0]);
        for (k = 0; k < f->nsaid; k++) {
            assert_string_equal(f->said[k], want[k]);
        }
    }
    // per track: what became of the messages on its channels
    assert_int_equal(gf_node_find(&f->node, 1)->by_result[GF_NODE_APPLIED], 2);
    assert_int_equal(gf_node_find(&f->node, 1)->by_result[GF_NODE_BAD_FIELD],
                     4);
    assert_int_equal(gf_node_find(&f->node, 3)->by_result[GF_NODE_NONFINITE],
                     2);
    check_counts(&f->node);
}

// The node's status: its counters, per track the results of its inputs,
// its updates and NIS (since the previous status), decoded by LCM's own
// decoder; another process with the node's id counted and warned once.
static void status_message(void **state)
{
    fixture *f = *state;
    static gf_node other;
    static uint8_t buf[GF_NODE_STATUS_BYTES];
    const double z3[3] = {1, 2, 3}, q3[3] = {1, 1, 1}, s = 51.25;
    gf_node_status_info info = {2000000, 2000000, 7, 3, 9, 0};
    gaussfilt_lcm_node_status_t st;
    const gaussfilt_lcm_track_status_t *t;
    exercise_2(f, 2); // 5 predictions, one update: NIS 25 / 51.25
    assert_int_equal(feed(f, gf_msg_meas_m(2, GF_CAR, 7, 5000000, 3, z3, q3)),
                     GF_NODE_BAD_FIELD);
    assert_int_equal(
        feed(f, gf_msg_meas(2, GF_CAR, 8, 5000000, (double)NAN, 1.0)),
        GF_NODE_NONFINITE);
    gf_node_set_id(&f->node, "n");
    gf_node_set_process(&f->node, "hostA", 100, 5000);
    assert_int_equal(gf_node_status(&f->node, &info, f->status, 64), -1);
    assert_int_equal(f->node.counts.publish_failed, 1); // too small
    assert_int_equal(
        gf_node_status(&f->node, &info, f->status, sizeof f->status), 0);
    assert_int_equal(gaussfilt_lcm_node_status_t_decode(
                         f->status, 0, (int)f->status_len, &st),
                     (int)f->status_len);
    assert_string_equal(st.node, "n");
    assert_string_equal(st.host, "hostA");
    assert_true(st.pid == 100 && st.start_utime == 5000 && st.seq == 0);
    assert_true(st.utime == 2000000 && st.period == 0.0 && !st.stopping);
    assert_true(st.received == 8 && st.results.applied == 6 &&
                st.results.bad_field == 1 && st.results.nonfinite == 1);
    assert_true(st.kernel_drops == 7 && st.queue_depth == 3 &&
                st.queue_peak == 9 && st.publish_failed == 1);
    assert_int_equal(st.ntracks, 1);
    t = &st.tracks[0];
    assert_int_equal(t->track, 2);
    assert_string_equal(t->model_name, "book-car");
    assert_true(t->inputs == 8 && t->results.applied == 6 &&
                t->results.bad_field == 1 && t->results.nonfinite == 1);
    assert_true(t->updates == 1 && t->m_last == 1 && t->nis_updates == 1);
    check_close(t->nis_last, 25.0 / s);
    check_close(t->nis_mean, 25.0 / s);
    check_close(t->nis_per_dof, 25.0 / s);
    check_close(t->age, 2.0); // its last input arrived at 0
    assert_int_equal(t->input_seq, 8);
    gaussfilt_lcm_node_status_t_decode_cleanup(&st);
    // a second later: the NIS since then (none), the period
    info.utime = 3000000;
    info.stopping = 1;
    assert_int_equal(
        gf_node_status(&f->node, &info, f->status, sizeof f->status), 0);
    assert_int_equal(gaussfilt_lcm_node_status_t_decode(
                         f->status, 0, (int)f->status_len, &st),
                     (int)f->status_len);
    assert_true(st.seq == 1 && st.stopping == 1);
    check_close(st.period, 1.0);
    assert_true(st.tracks[0].nis_updates == 0 && st.tracks[0].nis_mean == 0.0);
    check_close(st.tracks[0].nis_last, 25.0 / s);
    gaussfilt_lcm_node_status_t_decode_cleanup(&st);
    // its own status: no clash
    assert_int_equal(gf_node_peer_status(&f->node, f->status, f->status_len),
                     0);
    // another process named n: counted each time, warned once
    {
        size_t len;
        gf_node_init(&other, sink_publish, f);
        gf_node_set_id(&other, "n");
        gf_node_set_process(&other, "hostB", 200, 6000);
        assert_int_equal(
            gf_node_status(&other, &info, f->status, sizeof f->status), 0);
        len = f->status_len;
        memcpy(buf, f->status, len);
        f->nsaid = 0;
        assert_int_equal(gf_node_peer_status(&f->node, buf, len), 1);
        assert_int_equal(gf_node_peer_status(&f->node, buf, len), 1);
        assert_int_equal(f->node.counts.name_clashes, 2);
        assert_int_equal(f->nsaid, 1);
        assert_string_equal(
            f->said[0], "warning: another node is named \"n\" (host hostB, "
                        "pid 200, started 0.001 s after this one): beliefs "
                        "of two nodes of one name cannot be told apart, and "
                        "neither sees the other's; give each its own --name");
        // cut short, or another id: nothing
        assert_int_equal(gf_node_peer_status(&f->node, buf, 20), 0);
        gf_node_set_id(&other, "m");
        assert_int_equal(
            gf_node_status(&other, &info, f->status, sizeof f->status), 0);
        assert_int_equal(
            gf_node_peer_status(&f->node, f->status, f->status_len), 0);
        assert_int_equal(f->node.counts.name_clashes, 2);
    }
}

static void summary_names_every_counter(void **state)
{
    fixture *f = *state;
    char out[512];
    unsigned r;
    exercise_2(f, 3);
    assert_true(gf_node_summary(&f->node, out, sizeof(out)) > 0);
    assert_non_null(strstr(out, "received=6 applied=6 published=7"));
    for (r = 1; r < GF_NODE_RESULT_COUNT; r++) {
        assert_non_null(strstr(out, gf_node_result_str((gf_node_result)r)));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(table_2_1_in_process, setup),
        cmocka_unit_test_setup(table_4_2_in_process, setup),
        cmocka_unit_test_setup(duplicates_and_out_of_order, setup),
        cmocka_unit_test_setup(malformed_and_type_mismatch, setup),
        cmocka_unit_test_setup(bad_fields_and_channels, setup),
        cmocka_unit_test_setup(nonfinite_reported_nothing_changed, setup),
        cmocka_unit_test_setup(track_limit, setup),
        cmocka_unit_test_setup(simulator_restart_resyncs, setup),
        cmocka_unit_test_setup(too_large_is_bad_field, setup),
        cmocka_unit_test_setup(refusals_said_once, setup),
        cmocka_unit_test_setup(status_message, setup),
        cmocka_unit_test_setup(summary_names_every_counter, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
