// SPDX-License-Identifier: MIT
// gf_wire.h: gaussfilt's LCM messages with fixed arrays, for the tools and
// tests that read and write them. Header-only.
//
// belief_t, groundtruth_t, control_t and measurement_t carry variable-length
// arrays, which LCM's C code keeps behind pointers (allocated by its
// decoder, to be freed with *_decode_cleanup; pointed at the caller's
// arrays to encode). These structs hold up to GF_WIRE_NMAX entries in
// place, with the field names of the messages, so a reader indexes
// b.mean[i] and b.cov[i][j] as before:
//
//   gf_wire_belief_decode(data, len, &b)   0, or -1 (not a belief_t, or
//                                          n or m beyond GF_WIRE_NMAX)
//   gf_wire_truth_decode(data, len, &g)    the same for groundtruth_t
//   gf_wire_ctrl_encode(buf, size, &c)     the encoded length, or < 0
//   gf_wire_meas_encode(buf, size, &z)     the same for measurement_t
#ifndef GF_WIRE_H
#define GF_WIRE_H

#include <stdint.h>
#include <string.h>

#include "gaussfilt_lcm_belief_t.h"
#include "gaussfilt_lcm_control_t.h"
#include "gaussfilt_lcm_groundtruth_t.h"
#include "gaussfilt_lcm_measurement_t.h"

// The most states and measured quantities a tool reads: gf_kf's default
// GF_KF_NMAX.
#define GF_WIRE_NMAX 12

typedef struct gf_wire_belief {
    int64_t utime, seq, input_seq;
    int32_t track;
    int8_t model, stage, status, filter;
    char node[64];
    int8_t n;
    double mean[GF_WIRE_NMAX];
    double cov[GF_WIRE_NMAX][GF_WIRE_NMAX];
    int8_t m;
    double innovation[GF_WIRE_NMAX];
    double nis;
    int8_t trigger;
    char sensor[32];
} gf_wire_belief;

typedef struct gf_wire_truth {
    int64_t utime, seq;
    int32_t track;
    int8_t model, n;
    double state[GF_WIRE_NMAX];
} gf_wire_truth;

typedef struct gf_wire_ctrl {
    int64_t utime, seq, session;
    int32_t track;
    int8_t model, n;
    double u[GF_WIRE_NMAX];
} gf_wire_ctrl;

typedef struct gf_wire_meas {
    int64_t utime, seq, session;
    int32_t track;
    int8_t model, m;
    double z[GF_WIRE_NMAX];
    double q[GF_WIRE_NMAX][GF_WIRE_NMAX];
} gf_wire_meas;

static inline int gf_wire_belief_decode(const void *data, size_t len,
                                        gf_wire_belief *out)
{
    gaussfilt_lcm_belief_t b;
    int i, j, ok;
    memset(out, 0, sizeof(*out));
    memset(&b, 0, sizeof(b));
    if (gaussfilt_lcm_belief_t_decode(data, 0, (int)len, &b) != (int)len) {
        return -1; // what it allocated before failing is lost (LCM's C)
    }
    ok = b.n >= 0 && b.n <= GF_WIRE_NMAX && b.m >= 0 && b.m <= GF_WIRE_NMAX;
    if (ok) {
        out->utime = b.utime;
        out->seq = b.seq;
        out->input_seq = b.input_seq;
        out->track = b.track;
        out->model = b.model;
        out->stage = b.stage;
        out->status = b.status;
        out->filter = b.filter;
        if (b.node != NULL) {
            strncpy(out->node, b.node, sizeof out->node - 1);
            out->node[sizeof out->node - 1] = '\0';
        }
        out->n = b.n;
        for (i = 0; i < b.n; i++) {
            out->mean[i] = b.mean[i];
            for (j = 0; j < b.n; j++) {
                out->cov[i][j] = b.cov[i][j];
            }
        }
        out->m = b.m;
        for (i = 0; i < b.m; i++) {
            out->innovation[i] = b.innovation[i];
        }
        out->nis = b.nis;
        out->trigger = b.trigger;
        if (b.sensor != NULL) {
            strncpy(out->sensor, b.sensor, sizeof out->sensor - 1);
            out->sensor[sizeof out->sensor - 1] = '\0';
        }
    }
    gaussfilt_lcm_belief_t_decode_cleanup(&b);
    return ok ? 0 : -1;
}

static inline int gf_wire_truth_decode(const void *data, size_t len,
                                       gf_wire_truth *out)
{
    gaussfilt_lcm_groundtruth_t g;
    int i, ok;
    memset(out, 0, sizeof(*out));
    memset(&g, 0, sizeof(g));
    if (gaussfilt_lcm_groundtruth_t_decode(data, 0, (int)len, &g) != (int)len) {
        return -1;
    }
    ok = g.n >= 0 && g.n <= GF_WIRE_NMAX;
    if (ok) {
        out->utime = g.utime;
        out->seq = g.seq;
        out->track = g.track;
        out->model = g.model;
        out->n = g.n;
        for (i = 0; i < g.n; i++) {
            out->state[i] = g.state[i];
        }
    }
    gaussfilt_lcm_groundtruth_t_decode_cleanup(&g);
    return ok ? 0 : -1;
}

static inline int gf_wire_ctrl_encode(void *buf, int size,
                                      const gf_wire_ctrl *c)
{
    gaussfilt_lcm_control_t x;
    double u[GF_WIRE_NMAX];
    int i;
    if (c->n < 0 || c->n > GF_WIRE_NMAX) {
        return -1;
    }
    memset(&x, 0, sizeof(x));
    for (i = 0; i < c->n; i++) {
        u[i] = c->u[i];
    }
    x.utime = c->utime;
    x.seq = c->seq;
    x.session = c->session;
    x.track = c->track;
    x.model = c->model;
    x.n = c->n;
    x.u = u;
    return gaussfilt_lcm_control_t_encode(buf, 0, size, &x);
}

static inline int gf_wire_meas_encode(void *buf, int size,
                                      const gf_wire_meas *z)
{
    gaussfilt_lcm_measurement_t x;
    double zz[GF_WIRE_NMAX], q[GF_WIRE_NMAX][GF_WIRE_NMAX], *rows[GF_WIRE_NMAX];
    int i;
    if (z->m < 0 || z->m > GF_WIRE_NMAX) {
        return -1;
    }
    memset(&x, 0, sizeof(x));
    for (i = 0; i < z->m; i++) {
        zz[i] = z->z[i];
        memcpy(q[i], z->q[i], sizeof q[i]);
        rows[i] = q[i];
    }
    x.utime = z->utime;
    x.seq = z->seq;
    x.session = z->session;
    x.track = z->track;
    x.model = z->model;
    x.m = z->m;
    x.z = zz;
    x.q = rows;
    return gaussfilt_lcm_measurement_t_encode(buf, 0, size, &x);
}

#endif
