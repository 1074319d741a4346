// SPDX-License-Identifier: MIT
// The message types: every type survives encode/decode bit for bit (the
// decoded message encodes to the same bytes, its fields as given), the
// sizes are what we document, and decoding one type's bytes as another is
// detected (the fingerprint), as is a truncated message. The variable
// arrays point at the test's own.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gaussfilt_lcm_model_t.h"
#include "gf_msgs.h"

// Values that exercise every byte: negative, huge, tiny, signed zero.
static void fill(double *v, int n, double base)
{
    int i;
    for (i = 0; i < n; i++) {
        v[i] = base * (i + 1) * (i % 2 ? -1.0 : 1.0) + 1e-300 * i;
    }
}

typedef int (*enc_fn)(void *, int, int, const void *);
typedef int (*dec_fn)(const void *, int, int, void *);
typedef int (*size_fn)(const void *);

typedef struct type_case {
    const char *name;
    size_t size;
    enc_fn enc;
    dec_fn dec;
    size_fn esize;
    int64_t (*hash)(void);
    int wire_len; // documented encoded size
} type_case;

// Typed wrappers, so that each type is called through its own prototype.
#define WRAP(T)                                                                \
    static int enc_##T(void *b, int o, int m, const void *p)                   \
    {                                                                          \
        return gaussfilt_lcm_##T##_encode(b, o, m,                             \
                                          (const gaussfilt_lcm_##T *)p);       \
    }                                                                          \
    static int dec_##T(const void *b, int o, int m, void *p)                   \
    {                                                                          \
        return gaussfilt_lcm_##T##_decode(b, o, m, (gaussfilt_lcm_##T *)p);    \
    }                                                                          \
    static int size_##T(const void *p)                                         \
    {                                                                          \
        return gaussfilt_lcm_##T##_encoded_size((const gaussfilt_lcm_##T *)p); \
    }
WRAP(measurement_t)
WRAP(control_t)
WRAP(belief_t)
WRAP(groundtruth_t)
WRAP(model_t)

#define CASE(T, wire)                                                          \
    {                                                                          \
        #T, sizeof(gaussfilt_lcm_##T), enc_##T, dec_##T, size_##T,             \
            __gaussfilt_lcm_##T##_get_hash, wire                               \
    }

// wire = 8 (fingerprint) + the fields (measurement and control: utime,
// seq, session, track, model, size, values; belief: utime, seq,
// input_seq, track, model/stage/status/filter, the node string "gf" with
// its length and NUL, n, mean and cov of 3, m, innovation of 2, nis,
// trigger, the sensor string "gps" with its length and NUL; model: utime,
// track, model, measure, dt, accel_var, odometry[4], landmark[2], gate,
// reset, prior_mean[3], prior_cov[3][3]).
static const type_case cases[] = {
    CASE(measurement_t, 8 + 8 + 8 + 8 + 4 + 1 + 1 + 24 + 72),
    CASE(control_t, 8 + 8 + 8 + 8 + 4 + 1 + 1 + 16),
    CASE(belief_t,
         8 + 8 + 8 + 8 + 4 + 4 + 4 + 3 + 1 + 24 + 72 + 1 + 16 + 8 + 1 + 4 + 4),
    CASE(groundtruth_t, 8 + 8 + 8 + 4 + 1 + 1 + 24),
    CASE(model_t, 8 + 8 + 4 + 1 + 1 + 8 + 8 + 32 + 16 + 8 + 1 + 24 + 72),
};

// The arrays the made messages point at.
static double a_z[3], a_q[3][3], *a_qrows[3], a_u[2], a_mean[3], a_cov[3][3],
    *a_covrows[3], a_innov[2], a_state[3];
#define NCASES (sizeof(cases) / sizeof(cases[0]))

// One filled instance of each type, all padding zero.
static void make(unsigned k, void *p)
{
    memset(p, 0, cases[k].size);
    if (k == 0) {
        gaussfilt_lcm_measurement_t *m = p;
        m->utime = INT64_MIN + 7;
        m->seq = INT64_MAX - 3;
        m->track = -123456;
        m->model = GF_ROBOT;
        m->m = 3;
        fill(a_z, 3, 1.5e7);
        fill(&a_q[0][0], 9, -2.25e-7);
        for (int i = 0; i < 3; i++) {
            a_qrows[i] = a_q[i];
        }
        m->z = a_z;
        m->q = a_qrows;
    } else if (k == 1) {
        gaussfilt_lcm_control_t *c = p;
        c->utime = 1234567890123;
        c->seq = -1;
        c->track = INT32_MAX;
        c->model = GF_CAR;
        c->n = 2;
        fill(a_u, 2, -0.0 - 3.75);
        c->u = a_u;
    } else if (k == 2) {
        gaussfilt_lcm_belief_t *b = p;
        b->utime = 42;
        b->seq = 9;
        b->input_seq = -1;
        b->track = INT32_MIN;
        b->model = GF_ROBOT;
        b->stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
        b->status = -5;
        b->node = (char *)"gf";
        b->sensor = (char *)"gps";
        b->trigger = GAUSSFILT_LCM_BELIEF_T_TRIGGER_RATE;
        b->n = 3;
        fill(a_mean, 3, 0.15);
        fill(&a_cov[0][0], 9, 10000.01);
        for (int i = 0; i < 3; i++) {
            a_covrows[i] = a_cov[i];
        }
        b->mean = a_mean;
        b->cov = a_covrows;
        b->m = 2;
        fill(a_innov, 2, -1.7);
        b->innovation = a_innov;
        b->nis = 144.5;
        b->filter = GAUSSFILT_LCM_BELIEF_T_FILTER_PF3;
    } else if (k == 4) {
        gaussfilt_lcm_model_t *md = p;
        md->utime = -9;
        md->track = 100;
        md->model = GF_CAR;
        md->measure = GAUSSFILT_LCM_MODEL_T_MEASURE_XV;
        md->dt = 0.01;
        md->accel_var = 4;
        fill(md->odometry, 4, 0.0025);
        fill(md->landmark, 2, -5.5);
        md->gate = 13.8;
        md->reset = 1;
        fill(md->prior_mean, 3, 1e-3);
        fill(&md->prior_cov[0][0], 9, 0.01);
    } else {
        gaussfilt_lcm_groundtruth_t *g = p;
        g->utime = 7;
        g->seq = 8;
        g->track = 5;
        g->model = GF_ROBOT;
        g->n = 3;
        fill(a_state, 3, 3.14159);
        g->state = a_state;
    }
}

static void roundtrip_every_type(void **state)
{
    unsigned k;
    (void)state;
    for (k = 0; k < NCASES; k++) {
        uint8_t in[512], out[512], buf[512];
        int len;
        make(k, in);
        len = cases[k].enc(buf, 0, (int)sizeof(buf), in);
        assert_int_equal(len, cases[k].wire_len);
        assert_int_equal(cases[k].esize(in), len);
        memset(out, 0xA5, sizeof(out));
        memset(out, 0, cases[k].size);
        assert_int_equal(cases[k].dec(buf, 0, len, out), len);
        // the fixed fields as given (the arrays: the second encode below)
        if (memcmp(in, out, 2 * sizeof(int64_t)) != 0) {
            fail_msg("%s: decoded fields differ from the encoded struct",
                     cases[k].name);
        }
        // A second encode of the decoded struct gives the same bytes.
        {
            uint8_t buf2[512];
            assert_int_equal(cases[k].enc(buf2, 0, (int)sizeof(buf2), out),
                             len);
            assert_memory_equal(buf, buf2, (size_t)len);
        }
        // and the arrays, element by element, through gf_wire.h
        if (k == 2) {
            gf_wire_belief w;
            assert_int_equal(gf_wire_belief_decode(buf, (size_t)len, &w), 0);
            assert_string_equal(w.node, "gf");
            assert_true(w.n == 3 && w.m == 2);
            assert_memory_equal(w.mean, a_mean, sizeof a_mean);
            for (int i = 0; i < 3; i++) {
                assert_memory_equal(w.cov[i], a_cov[i], sizeof a_cov[i]);
            }
            assert_memory_equal(w.innovation, a_innov, sizeof a_innov);
            assert_int_equal(w.trigger, GAUSSFILT_LCM_BELIEF_T_TRIGGER_RATE);
            assert_string_equal(w.sensor, "gps");
        }
        if (k == 4) {
            const gaussfilt_lcm_model_t *a = (const void *)in;
            const gaussfilt_lcm_model_t *b = (const void *)out;
            assert_memory_equal(b->odometry, a->odometry, sizeof a->odometry);
            assert_memory_equal(b->prior_cov, a->prior_cov,
                                sizeof a->prior_cov);
            assert_true(b->measure == a->measure && b->reset == 1);
        }
        if (k == 3) {
            gf_wire_truth g;
            assert_int_equal(gf_wire_truth_decode(buf, (size_t)len, &g), 0);
            assert_memory_equal(g.state, a_state, sizeof a_state);
        }
    }
}

static void type_mismatch_is_detected(void **state)
{
    unsigned a, b;
    (void)state;
    for (a = 0; a < NCASES; a++) {
        uint8_t in[512], buf[512], out[512];
        int len;
        make(a, in);
        len = cases[a].enc(buf, 0, (int)sizeof(buf), in);
        assert_true(len > 8);
        for (b = 0; b < NCASES; b++) {
            if (a == b) {
                continue;
            }
            // Distinct fingerprints ...
            assert_true(cases[a].hash() != cases[b].hash());
            // ... so type b refuses the bytes of type a, whatever the length.
            memset(out, 0, sizeof(out));
            if (cases[b].dec(buf, 0, len, out) >= 0) {
                fail_msg("%s decoded the bytes of %s", cases[b].name,
                         cases[a].name);
            }
        }
    }
}

static void truncation_is_detected(void **state)
{
    unsigned k;
    (void)state;
    for (k = 0; k < NCASES; k++) {
        uint8_t in[512], buf[512], out[512];
        int len, cut;
        make(k, in);
        len = cases[k].enc(buf, 0, (int)sizeof(buf), in);
        for (cut = 0; cut < len; cut++) {
            assert_true(cases[k].dec(buf, 0, cut, out) < 0);
        }
    }
}

// particles_t carries variable-length arrays (pointers in the struct), so
// it is checked on its own: round trip, size, truncation, and no other
// type takes its bytes (nor it theirs).
static void particles_roundtrip(void **state)
{
    float x[3] = {-0.7f, 1e-30f, -0.0f}, y[3] = {0.714f, -0.714f, 3e38f},
          th[3] = {2.34f, -2.34f, 0.0f}, w[3] = {0.5f, 0.25f, 1e-7f};
    gaussfilt_lcm_particles_t in, out;
    uint8_t buf[512], other[512];
    int len, cut;
    unsigned k;
    (void)state;
    memset(&in, 0, sizeof(in));
    in.utime = -5;
    in.seq = 2;
    in.input_seq = INT64_MAX;
    in.track = -43;
    in.stage = GAUSSFILT_LCM_BELIEF_T_STAGE_UPDATE;
    in.resampled = 1;
    in.n_filter = 2000;
    in.stride = 4;
    in.neff = 212.5;
    in.count = 3;
    in.x = x;
    in.y = y;
    in.theta = th;
    in.w = w;
    len = gaussfilt_lcm_particles_t_encode(buf, 0, (int)sizeof(buf), &in);
    // 8 + 8+8+8 + 4+1+1+4+4+8+4 + 4 arrays of 3 floats
    assert_int_equal(len, 8 + 24 + 26 + 4 * 3 * 4);
    assert_int_equal(gaussfilt_lcm_particles_t_encoded_size(&in), len);
    assert_int_equal(gaussfilt_lcm_particles_t_decode(buf, 0, len, &out), len);
    assert_true(out.utime == in.utime && out.seq == in.seq &&
                out.input_seq == in.input_seq && out.track == in.track &&
                out.stage == in.stage && out.resampled == 1 &&
                out.n_filter == 2000 && out.stride == 4 && out.neff == 212.5 &&
                out.count == 3);
    assert_memory_equal(out.x, x, sizeof(x));
    assert_memory_equal(out.y, y, sizeof(y));
    assert_memory_equal(out.theta, th, sizeof(th));
    assert_memory_equal(out.w, w, sizeof(w));
    gaussfilt_lcm_particles_t_decode_cleanup(&out);
    for (cut = 0; cut < len; cut++) {
        assert_true(gaussfilt_lcm_particles_t_decode(buf, 0, cut, &out) < 0);
    }
    for (k = 0; k < NCASES; k++) {
        uint8_t ins[512], outs[512];
        int olen;
        assert_true(cases[k].hash() != __gaussfilt_lcm_particles_t_get_hash());
        if (cases[k].dec(buf, 0, len, outs) >= 0) {
            fail_msg("%s decoded the bytes of particles_t", cases[k].name);
        }
        make(k, ins);
        olen = cases[k].enc(other, 0, (int)sizeof(other), ins);
        assert_true(gaussfilt_lcm_particles_t_decode(other, 0, olen, &out) < 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(roundtrip_every_type),
        cmocka_unit_test(type_mismatch_is_detected),
        cmocka_unit_test(truncation_is_detected),
        cmocka_unit_test(particles_roundtrip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
