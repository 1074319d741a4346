// SPDX-License-Identifier: MIT
// In-process publish/subscribe through LCM's memq:// provider: the node's
// handler subscribed by channel regex, a belief listener, and the
// exercises published as encoded messages. Real liblcm, no sockets.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <lcm/lcm.h>

#include "gf_msgs.h"
#include "node_core.h"

typedef struct world {
    lcm_t *lcm;
    gf_node node;
    gf_sink beliefs;
    int published;
} world;

static int publish_lcm(void *ctx, const char *channel, const void *data,
                       size_t len)
{
    return lcm_publish((lcm_t *)ctx, channel, data, (unsigned)len);
}

static void on_input(const lcm_recv_buf_t *rbuf, const char *channel,
                     void *user)
{
    gf_node_handle((gf_node *)user, channel, rbuf->data, rbuf->data_size,
                   rbuf->recv_utime);
}

static void on_belief(const lcm_recv_buf_t *rbuf, const char *channel,
                      void *user)
{
    gf_sink_add((gf_sink *)user, channel, rbuf->data, rbuf->data_size);
}

static void check_close(double got, double want)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= GF_SIM_TOL * scale)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

static void send(world *w, gf_msg m)
{
    assert_int_equal(lcm_publish(w->lcm, m.channel, m.data, (unsigned)m.len),
                     0);
    w->published++;
}

// Dispatches until the queue is empty (beliefs published from inside a
// handler are queued too).
static void drain(world *w)
{
    int guard = 0;
    while (lcm_handle_timeout(w->lcm, 0) > 0 && guard++ < 10000)
        ;
}

static int setup(void **state)
{
    static world w;
    memset(&w, 0, sizeof(w));
    w.lcm = lcm_create("memq://");
    if (w.lcm == NULL) {
        return -1;
    }
    gf_node_init(&w.node, publish_lcm, w.lcm);
    lcm_subscribe(w.lcm, GF_CHANNEL_NODE_DEFAULT, on_input, &w.node);
    lcm_subscribe(w.lcm, GF_CHANNEL_BELIEF ".*", on_belief, &w.beliefs);
    *state = &w;
    return 0;
}

static int teardown(void **state)
{
    world *w = *state;
    lcm_destroy(w->lcm);
    return 0;
}

static void exercises_through_memq(void **state)
{
    world *w = *state;
    const gf_wire_belief *b;
    int64_t t;
    int i, found2 = 0, found4 = 0;
    for (t = 1; t <= 5; t++) {
        send(w, gf_msg_ctrl(2, GF_CAR, t, t, 0, 0, 0));
    }
    send(w, gf_msg_meas(2, GF_CAR, 6, 5, 5.0, 10.0));
    send(w, gf_msg_ctrl(4, GF_ROBOT, 1, 1, 2, 1.0, 0.0));
    send(w, gf_msg_meas(4, GF_ROBOT, 2, 1, -0.7, 0.01));
    drain(w); // the node's beliefs go round the same LCM; its regex skips them

    assert_int_equal(w->node.counts.received, 8);
    assert_int_equal(w->node.counts.by_result[GF_NODE_APPLIED], 8);
    assert_int_equal(w->beliefs.undecodable, 0);
    assert_int_equal(w->beliefs.n, 7 + 3);
    for (i = 0; i < w->beliefs.n; i++) {
        b = &w->beliefs.b[i];
        if (b->track == 2 && b->seq == 6) {
            found2 = 1;
            assert_string_equal(w->beliefs.channel[i], "GF_BELIEF_2");
            check_close(b->mean[0], 41.25 * 5 / 51.25);
            check_close(b->cov[0][0], 41.25 * 10 / 51.25);
            check_close(b->cov[1][1], 5 - 12.5 * 12.5 / 51.25);
        }
        if (b->track == 4 && b->seq == 2) {
            found4 = 1;
            assert_string_equal(w->beliefs.channel[i], "GF_BELIEF_4");
            check_close(b->mean[0], 0.15);
            check_close(b->cov[0][0], 0.005);
            check_close(b->cov[1][1], 10000.01);
        }
    }
    assert_true(found2 && found4);
}

static void channel_regex_splits_tracks(void **state)
{
    world *w = *state;
    lcm_t *lcm = w->lcm;
    static gf_node low, high;
    gf_sink sink;
    int i;
    memset(&sink, 0, sizeof(sink));
    // Two more nodes on the same LCM: one takes tracks 10-14, one 15-19.
    gf_node_init(&low, publish_lcm, lcm);
    gf_node_init(&high, publish_lcm, lcm);
    lcm_subscribe(lcm, "GF_(MEAS|CTRL)_1[0-4]", on_input, &low);
    lcm_subscribe(lcm, "GF_(MEAS|CTRL)_1[5-9]", on_input, &high);
    for (i = 10; i < 20; i++) {
        send(w, gf_msg_ctrl(i, GF_CAR, 1, 1, 0, 0, 0));
    }
    drain(w);
    assert_int_equal(low.ntracks, 5);
    assert_int_equal(high.ntracks, 5);
    assert_non_null(gf_node_find(&low, 12));
    assert_null(gf_node_find(&low, 17));
    assert_non_null(gf_node_find(&high, 17));
    assert_int_equal(w->node.ntracks, 10); // the catch-all node took all
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(exercises_through_memq, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(channel_regex_splits_tracks, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
