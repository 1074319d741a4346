// SPDX-License-Identifier: MIT
// The node's robot filters beyond the EKF (gf_node_set_filter, gf_node
// --filter): exercise 4 through UKF3 and PF3 tracks, checked on the bytes
// the node published (beliefs and particles_t clouds); the PF pool's
// limits; reproducible PF runs; a failing PF step changes nothing.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "ex4_modes.h"
#include "gf_msgs.h"
#include "node_core.h"

#define MAX_CLOUDS 8

// Beliefs (gf_sink) and clouds, as they came out of the node.
typedef struct catcher {
    gf_sink sink;
    int nclouds, bad;
    gaussfilt_lcm_particles_t cloud[MAX_CLOUDS]; // headers
    char cloud_channel[MAX_CLOUDS][GF_CHANNEL_MAX];
    float x[MAX_CLOUDS][GF_NODE_PF_CLOUD], y[MAX_CLOUDS][GF_NODE_PF_CLOUD],
        w[MAX_CLOUDS][GF_NODE_PF_CLOUD];
    uint64_t hash; // FNV-1a of every published byte, in order
} catcher;

static int catch_publish(void *ctx, const char *channel, const void *data,
                         size_t len)
{
    catcher *c = (catcher *)ctx;
    const uint8_t *p = (const uint8_t *)data;
    size_t i;
    for (i = 0; i < len; i++) {
        c->hash = (c->hash ^ p[i]) * 1099511628211u;
    }
    if (strncmp(channel, GF_CHANNEL_PARTICLES, strlen(GF_CHANNEL_PARTICLES)) ==
        0) {
        gaussfilt_lcm_particles_t m;
        int k = c->nclouds;
        if (gaussfilt_lcm_particles_t_decode(data, 0, (int)len, &m) !=
            (int)len) {
            c->bad++;
            return 0;
        }
        if (k < MAX_CLOUDS && m.count <= GF_NODE_PF_CLOUD) {
            memcpy(c->x[k], m.x, sizeof(float) * (size_t)m.count);
            memcpy(c->y[k], m.y, sizeof(float) * (size_t)m.count);
            memcpy(c->w[k], m.w, sizeof(float) * (size_t)m.count);
            c->cloud[k] = m;
            c->cloud[k].x = c->cloud[k].y = c->cloud[k].theta = c->cloud[k].w =
                NULL;
            snprintf(c->cloud_channel[k], GF_CHANNEL_MAX, "%s", channel);
            c->nclouds++;
        }
        gaussfilt_lcm_particles_t_decode_cleanup(&m);
        return 0;
    }
    gf_sink_add(&c->sink, channel, data, len);
    return 0;
}

typedef struct fixture {
    gf_node node;
    gf_node_pf_pool pool;
    catcher c;
} fixture;

static fixture fx; // large: the pool holds 4 x 2000 particles

static fixture *fresh(gf_node_filter filter, uint32_t seed)
{
    memset(&fx, 0, sizeof(fx));
    fx.c.hash = 14695981039346656037u;
    gf_node_init(&fx.node, catch_publish, &fx.c);
    assert_int_equal(gf_node_set_filter(&fx.node, filter, &fx.pool, seed), 0);
    return &fx;
}

static gf_node_result feed(fixture *f, gf_msg m)
{
    return gf_node_handle(&f->node, m.channel, m.data, (size_t)m.len, 0);
}

// Exercise 4 on `track`: move (1, 0), observe x = -0.7 with Q = 0.01.
static void exercise_4(fixture *f, int32_t track)
{
    assert_int_equal(feed(f, gf_msg_ctrl(track, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
                     GF_NODE_APPLIED);
    assert_int_equal(feed(f, gf_msg_meas(track, GF_ROBOT, 2, 1, -0.7, 0.01)),
                     GF_NODE_APPLIED);
}

static void options_parse(void **state)
{
    gf_node_filter fl = GF_NODE_FILTER_EKF;
    gf_node node;
    (void)state;
    assert_int_equal(gf_node_filter_parse("ukf", &fl), 0);
    assert_int_equal(fl, GF_NODE_FILTER_UKF);
    assert_int_equal(gf_node_filter_parse("pf", &fl), 0);
    assert_int_equal(fl, GF_NODE_FILTER_PF);
    assert_int_equal(gf_node_filter_parse("ekf", &fl), 0);
    assert_int_equal(fl, GF_NODE_FILTER_EKF);
    assert_int_equal(gf_node_filter_parse("kf", &fl), -1);
    assert_int_equal(gf_node_filter_parse(NULL, &fl), -1);
    gf_node_init(&node, NULL, NULL);
    // PF needs a pool; an unknown filter is refused.
    assert_int_equal(gf_node_set_filter(&node, GF_NODE_FILTER_PF, NULL, 1), -1);
    assert_int_equal(gf_node_set_filter(&node, (gf_node_filter)7, NULL, 1), -1);
    assert_int_equal(node.robot_filter, GF_NODE_FILTER_EKF);
}

static void ukf_exercise_4(void **state)
{
    fixture *f = fresh(GF_NODE_FILTER_UKF, 1);
    const gf_wire_belief *b = f->c.sink.b;
    int i;
    (void)state;
    exercise_4(f, 4);
    assert_int_equal(f->c.sink.n, 3);
    assert_int_equal(f->c.nclouds, 0);
    for (i = 0; i < 3; i++) {
        assert_int_equal(b[i].filter, GAUSSFILT_LCM_BELIEF_T_FILTER_UKF3);
        assert_int_equal(b[i].status, 0);
    }
    // (4 + 2 cos(100 sqrt 3)) / 6: the sigma points (tests/test_ex4.c)
    assert_true(fabs(b[1].mean[0] - (4 + 2 * cos(100 * sqrt(3.0))) / 6) < 1e-4);
    assert_int_equal(gf_ex4_check_ukf_pred(b[1].mean[0], b[1].mean[1]), 0);
    assert_int_equal(b[2].m, 1); // the UKF reports its innovation
    assert_true(fabs(b[2].mean[0] + 0.7) < 0.02 && fabs(b[2].mean[1]) < 0.01);
}

static void pf_exercise_4(void **state)
{
    fixture *f = fresh(GF_NODE_FILTER_PF, 1);
    const gf_wire_belief *b = f->c.sink.b;
    const gaussfilt_lcm_particles_t *c = f->c.cloud;
    int i;
    (void)state;
    exercise_4(f, 4);
    assert_int_equal(f->c.bad, 0);
    assert_int_equal(f->c.sink.n, 3);
    assert_int_equal(f->c.nclouds, 3); // one cloud after each belief
    assert_int_equal(f->node.counts.published, 6);
    for (i = 0; i < 3; i++) {
        assert_int_equal(b[i].filter, GAUSSFILT_LCM_BELIEF_T_FILTER_PF3);
        assert_int_equal(b[i].status, 0);
        assert_int_equal(b[i].m, 0);
        assert_string_equal(f->c.cloud_channel[i], "GF_PARTICLES_4");
        assert_true(c[i].seq == b[i].seq && c[i].stage == b[i].stage &&
                    c[i].input_seq == b[i].input_seq && c[i].track == 4);
        assert_int_equal(c[i].n_filter, GF_NODE_PF_PARTICLES);
        assert_int_equal(c[i].count, GF_NODE_PF_CLOUD);
        assert_int_equal(c[i].stride, GF_NODE_PF_PARTICLES / GF_NODE_PF_CLOUD);
    }
    // Predicted: the summary mean is inside the ring the particles form.
    assert_true(hypot(b[1].mean[0], b[1].mean[1]) < 0.5);
    assert_int_equal(c[1].resampled, 0);
    // After z: resampled (neff fell below half), two modes.
    assert_int_equal(c[2].resampled, 1);
    assert_true(c[2].neff > 50 && c[2].neff < 0.5 * GF_NODE_PF_PARTICLES);
    assert_int_equal(
        gf_ex4_check_modes(f->c.x[2], f->c.y[2], f->c.w[2], c[2].count), 0);
    // The Gaussian summary sits between them, where no particle is.
    assert_true(fabs(b[2].mean[0] + 0.7) < 0.05 && fabs(b[2].mean[1]) < 0.15);
    assert_true(b[2].cov[1][1] > 0.4); // y spread over both modes
}

// Not one lucky seed: the modes are there for every seed of 1..20.
static void pf_modes_for_many_seeds(void **state)
{
    uint32_t seed;
    int failed = 0;
    (void)state;
    for (seed = 1; seed <= 20; seed++) {
        fixture *f = fresh(GF_NODE_FILTER_PF, seed);
        exercise_4(f, 4);
        assert_int_equal(f->c.nclouds, 3);
        print_message("seed %u:\n", (unsigned)seed);
        failed += gf_ex4_check_modes(f->c.x[2], f->c.y[2], f->c.w[2],
                                     f->c.cloud[2].count) != 0;
    }
    assert_int_equal(failed, 0);
}

// Same seed, same bytes; another seed (or track id) other particles.
static void pf_reproducible(void **state)
{
    uint64_t h1, h2, h3;
    (void)state;
    exercise_4(fresh(GF_NODE_FILTER_PF, 9), 4);
    h1 = fx.c.hash;
    exercise_4(fresh(GF_NODE_FILTER_PF, 9), 4);
    h2 = fx.c.hash;
    exercise_4(fresh(GF_NODE_FILTER_PF, 10), 4);
    h3 = fx.c.hash;
    assert_true(h1 == h2);
    assert_true(h1 != h3);
}

// GF_NODE_PF_TRACKS PF tracks, then the pool is full: a new robot track is
// refused, a car track (KF2, no particles) still comes.
static void pf_track_limit(void **state)
{
    fixture *f = fresh(GF_NODE_FILTER_PF, 1);
    int32_t t;
    (void)state;
    for (t = 0; t < GF_NODE_PF_TRACKS; t++) {
        assert_int_equal(
            feed(f, gf_msg_ctrl(100 + t, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
            GF_NODE_APPLIED);
    }
    assert_int_equal(feed(f, gf_msg_ctrl(200, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
                     GF_NODE_TRACK_LIMIT);
    assert_null(gf_node_find(&f->node, 200));
    assert_int_equal(feed(f, gf_msg_ctrl(300, GF_CAR, 1, 1, 0, 0, 0)),
                     GF_NODE_APPLIED);
    assert_int_equal(gf_node_find(&f->node, 300)->filter,
                     GAUSSFILT_LCM_BELIEF_T_FILTER_KF2);
    assert_int_equal(f->node.ntracks, GF_NODE_PF_TRACKS + 1);
    // Each PF track has its own slot: their particles differ.
    assert_true(memcmp(f->pool.p[0], f->pool.p[1], sizeof(f->pool.p[0])) != 0);
}

// A step the core refuses (non-finite z, singular Q) leaves the track and
// every particle as they were, and says so in the belief's status.
static void pf_failure_changes_nothing(void **state)
{
    fixture *f = fresh(GF_NODE_FILTER_PF, 1);
    static gf_pf3_particle before[GF_NODE_PF_PARTICLES];
    gf_node_track tb;
    (void)state;
    assert_int_equal(feed(f, gf_msg_ctrl(4, GF_ROBOT, 1, 1, 2, 1.0, 0.0)),
                     GF_NODE_APPLIED);
    memcpy(before, f->pool.p[0], sizeof(before));
    memcpy(&tb, gf_node_find(&f->node, 4), sizeof(tb));
    assert_int_equal(feed(f, gf_msg_meas(4, GF_ROBOT, 2, 1, NAN, 0.01)),
                     GF_NODE_NONFINITE);
    assert_int_equal(feed(f, gf_msg_meas(4, GF_ROBOT, 3, 1, -0.7, 0.0)),
                     GF_NODE_FILTER_ERROR);
    assert_memory_equal(before, f->pool.p[0], sizeof(before));
    assert_memory_equal(&tb.f, &gf_node_find(&f->node, 4)->f, sizeof(tb.f));
    assert_int_equal(f->c.sink.n, 4);
    assert_int_equal(f->c.sink.b[2].status, GF_ERR_NONFINITE);
    assert_int_equal(f->c.sink.b[3].status, GF_ERR_SINGULAR);
    assert_memory_equal(f->c.sink.b[3].mean, f->c.sink.b[1].mean,
                        sizeof(f->c.sink.b[1].mean));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(options_parse),
        cmocka_unit_test(ukf_exercise_4),
        cmocka_unit_test(pf_exercise_4),
        cmocka_unit_test(pf_modes_for_many_seeds),
        cmocka_unit_test(pf_reproducible),
        cmocka_unit_test(pf_track_limit),
        cmocka_unit_test(pf_failure_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
