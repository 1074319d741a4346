// SPDX-License-Identifier: MIT
// Shared by the sim tests: building encoded controls and measurements, and
// catching the beliefs a node publishes.
#ifndef GF_MSGS_H
#define GF_MSGS_H

#include <stdint.h>
#include <string.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_groundtruth_t.h"
#include "gaussfilt_lcm_measurement_t.h"
#include "gaussfilt_lcm_particles_t.h"
#include "gf_channels.h"
#include "gf_wire.h"

// Tolerance of the sim tests, relative to max(1, |want|): the node's filter
// runs in gf_real (as the core's tests: 1e-12 double, 2e-5 float).
#ifdef GF_SINGLE_PRECISION
#define GF_SIM_TOL 2e-5
#else
#define GF_SIM_TOL 1e-12
#endif

#define GF_CAR GAUSSFILT_LCM_MEASUREMENT_T_MODEL_CAR
#define GF_ROBOT GAUSSFILT_LCM_MEASUREMENT_T_MODEL_ROBOT

typedef struct gf_msg {
    char channel[GF_CHANNEL_MAX];
    uint8_t data[64 + 8 * (GF_WIRE_NMAX + GF_WIRE_NMAX * GF_WIRE_NMAX)];
    int len;
} gf_msg;

// A control of `track`: n entries of u.
static inline gf_msg gf_msg_ctrl(int32_t track, int8_t model, int64_t seq,
                                 int64_t utime, int n, double u0, double u1)
{
    gf_msg m;
    gf_wire_ctrl c;
    memset(&m, 0, sizeof(m));
    memset(&c, 0, sizeof(c));
    c.utime = utime;
    c.seq = seq;
    c.track = track;
    c.model = model;
    c.n = (int8_t)n;
    c.u[0] = u0;
    c.u[1] = u1;
    snprintf(m.channel, sizeof(m.channel), "%s%ld", GF_CHANNEL_CTRL,
             (long)track);
    m.len = gf_wire_ctrl_encode(m.data, (int)sizeof(m.data), &c);
    return m;
}

// A measurement of m = 1..GF_WIRE_NMAX quantities z with independent
// variances q of `track`.
static inline gf_msg gf_msg_meas_m(int32_t track, int8_t model, int64_t seq,
                                   int64_t utime, int m, const double *z,
                                   const double *q)
{
    gf_msg msg;
    gf_wire_meas x;
    memset(&msg, 0, sizeof(msg));
    memset(&x, 0, sizeof(x));
    x.utime = utime;
    x.seq = seq;
    x.track = track;
    x.model = model;
    x.m = (int8_t)m;
    for (int i = 0; i < m; i++) {
        x.z[i] = z[i];
        x.q[i][i] = q[i];
    }
    snprintf(msg.channel, sizeof(msg.channel), "%s%ld", GF_CHANNEL_MEAS,
             (long)track);
    msg.len = gf_wire_meas_encode(msg.data, (int)sizeof(msg.data), &x);
    return msg;
}

// A scalar measurement z with variance q of `track`.
static inline gf_msg gf_msg_meas(int32_t track, int8_t model, int64_t seq,
                                 int64_t utime, double z, double q)
{
    return gf_msg_meas_m(track, model, seq, utime, 1, &z, &q);
}

// The beliefs a node published, in order.
#define GF_SINK_MAX 256
typedef struct gf_sink {
    gf_wire_belief b[GF_SINK_MAX];
    char channel[GF_SINK_MAX][GF_CHANNEL_MAX];
    int n;
    int undecodable;
} gf_sink;

static inline void gf_sink_add(gf_sink *s, const char *channel,
                               const void *data, size_t len)
{
    if (s->n >= GF_SINK_MAX) {
        return;
    }
    if (gf_wire_belief_decode(data, len, &s->b[s->n]) != 0) {
        s->undecodable++;
        return;
    }
    snprintf(s->channel[s->n], GF_CHANNEL_MAX, "%s", channel);
    s->n++;
}

#endif
