// SPDX-License-Identifier: MIT
// Verdicts do not depend on units: for s = 2^k, k = -K..K (K = 60 in
// float, 500 in double: every entry of s M and every product of two of
// them stays a normal number, products of three do not), s M gets the
// verdict of M from gf_mat2_check_psd, gf_mat3_check_psd, gf_mat2_spd_inv,
// gf_mat3_chol, gf_kf2_init and gf_ekf3_init, on definite, semidefinite
// and indefinite 2x2 and 3x3 matrices (among them the ones whose verdicts once moved with units); and
// the update's verdicts: Sigma = s M, Q = s q gives the posterior s times
// M's (GF_OK at every s), and a semidefinite Sigma measured along its null
// direction with Q = 0 is GF_ERR_SINGULAR at every s.
#include "gf_test.h"

#ifdef GF_SINGLE_PRECISION
#define KMAX 60
#else
#define KMAX 500
#endif

// Scale-invariance tolerance of the update's results: relative, a few ulps
// of a short computation (the posterior of s M is s times M's up to
// rounding, exactly so where no square root intervenes).
#ifdef GF_SINGLE_PRECISION
#define SCALE_TOL 1e-5
#else
#define SCALE_TOL 1e-13
#endif

static gf_real pow2(int k)
{
    return (gf_real)ldexp(1.0, k);
}

enum kind { DEF, SEMI, INDEF };

typedef struct case2 {
    enum kind kind;
    gf_mat2 m;
} case2;

typedef struct case3 {
    enum kind kind;
    gf_mat3 m;
} case3;

#define E10 GF_R(0.0009765625) // 2^-10

static const case2 CASES2[] = {
    {DEF, {{{2, 1}, {1, 2}}}},
    {DEF, {{{1, 1 - E10}, {1 - E10, 1}}}},          // correlation 1 - 2^-10
    {DEF, {{{1024, GF_R(0.5)}, {GF_R(0.5), E10}}}}, // spread 2^20, corr 0.5
    {SEMI, {{{1, 1}, {1, 1}}}},
    {SEMI, {{{4, -2}, {-2, 1}}}},
    {SEMI, {{{0, 0}, {0, 1}}}}, // a zero leading variance
    {SEMI, {{{0, 0}, {0, 0}}}},
    {INDEF, {{{1, 2}, {2, 1}}}},
    {INDEF, {{{1, 1 + E10}, {1 + E10, 1}}}}, // correlation 1 + 2^-10
    {INDEF, {{{-1, 0}, {0, 1}}}},
    {INDEF, {{{0, 1}, {1, 0}}}},
};

static const case3 CASES3[] = {
    // Item 2's positive definite matrix (refused at 2^44 in float).
    {DEF,
     {{{1, GF_R(0.5), GF_R(0.3)},
       {GF_R(0.5), 1, GF_R(0.4)},
       {GF_R(0.3), GF_R(0.4), 1}}}},
    {DEF, {{{4, 1, 0}, {1, 3, 1}, {0, 1, 2}}}},
    {DEF, {{{1024, 1, 0}, {1, 1, GF_R(0.015625)}, {0, GF_R(0.015625), E10}}}},
    {SEMI, {{{1, 2, -1}, {2, 4, -2}, {-1, -2, 1}}}}, // rank 1
    {SEMI, {{{1, 0, 1}, {0, 1, 1}, {1, 1, 2}}}},     // rank 2
    {SEMI, {{{1, 0, 0}, {0, 0, 0}, {0, 0, 2}}}},     // a zero variance
    // G G^T, G = ((0.75, 0.5), (0.25, 1.125), (0.25, 1)): rank 2, every
    // entry and product exact in binary (eighths).
    {SEMI,
     {{{GF_R(0.8125), GF_R(0.75), GF_R(0.6875)},
       {GF_R(0.75), GF_R(1.328125), GF_R(1.1875)},
       {GF_R(0.6875), GF_R(1.1875), GF_R(1.0625)}}}},
    // Item 2's indefinite matrix (accepted at 1e13 in float).
    {INDEF,
     {{{1, GF_R(0.9), GF_R(0.9)},
       {GF_R(0.9), 1, GF_R(-0.9)},
       {GF_R(0.9), GF_R(-0.9), 1}}}},
    {INDEF, {{{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}}},
    {INDEF, {{{1, 1, 0}, {1, 1, E10}, {0, E10, 0}}}}, // det -2^-20
};

static gf_mat2 scale2(const gf_mat2 *m, gf_real s)
{
    gf_mat2 r;
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 2; j++) {
            r.m[i][j] = s * m->m[i][j];
        }
    }
    return r;
}

static gf_mat3 scale3(const gf_mat3 *m, gf_real s)
{
    gf_mat3 r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            r.m[i][j] = s * m->m[i][j];
        }
    }
    return r;
}

static void fail_at(const char *what, unsigned c, int k, int got, int want)
{
    print_error("%s: case %u at s = 2^%d: %d, want %d\n", what, c, k, got,
                want);
}

#define VERDICT(what, c, k, got, want)                                         \
    do {                                                                       \
        int g_ = (int)(got), w_ = (int)(want);                                 \
        if (g_ != w_) {                                                        \
            fail_at(what, c, k, g_, w_);                                       \
            _fail(__FILE__, __LINE__);                                         \
        }                                                                      \
    } while (0)

// got (rows of n) is the covariance m read back from a belief's factors:
// exactly symmetric, each entry within 8 ulps of sqrt(m_ii m_jj) of m's
// (exact where that is zero: a state known exactly stays so).
static void near_cov(const gf_real *got, const gf_real *m, int n)
{
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            const double sc = sqrt((double)m[i * n + i] * (double)m[j * n + j]);
            assert_true(got[i * n + j] == got[j * n + i]);
            assert_true(fabs((double)got[i * n + j] - (double)m[i * n + j]) <=
                        8.0 * (double)GF_REAL_EPSILON * sc);
        }
    }
}

static void verdicts_2x2(void **state)
{
    (void)state;
    const gf_vec2 mu = {{0, 0}};
    for (unsigned c = 0; c < sizeof CASES2 / sizeof CASES2[0]; c++) {
        const enum kind kd = CASES2[c].kind;
        for (int k = -KMAX; k <= KMAX; k++) {
            gf_mat2 m = scale2(&CASES2[c].m, pow2(k)), inv;
            VERDICT("gf_mat2_check_psd", c, k, gf_mat2_check_psd(&m),
                    kd == INDEF ? GF_ERR_NOT_PSD : GF_OK);
            gf_status st = gf_mat2_spd_inv(&m, &inv);
            VERDICT("gf_mat2_spd_inv", c, k, st,
                    kd == DEF ? GF_OK : GF_ERR_SINGULAR);
            if (st == GF_OK) { // inv (s M) = I within the tolerance
                gf_mat2 p;
                gf_mat2_mul(&inv, &m, &p);
                for (int i = 0; i < 2; i++) {
                    for (int j = 0; j < 2; j++) {
                        assert_true(fabs((double)p.m[i][j] - (i == j)) <
                                    1e4 * (double)GF_REAL_EPSILON);
                    }
                }
            }
            gf_kf2 kf;
            st = gf_kf2_init(&kf, &mu, &m);
            VERDICT("gf_kf2_init", c, k, st,
                    kd == INDEF ? GF_ERR_NOT_PSD : GF_OK);
            if (st == GF_OK) {
                // The belief holds Sigma's factors: read back, Sigma is
                // m within the factorisation's rounding, exactly symmetric.
                const gf_mat2 got = gf_test_kf2_sigma(&kf);
                near_cov(got.m[0], m.m[0], 2);
            }
            // As the leading block of a 3x3 (third variance 1).
            gf_mat3 m3 = {{{m.m[0][0], m.m[0][1], 0},
                           {m.m[1][0], m.m[1][1], 0},
                           {0, 0, 1}}};
            VERDICT("gf_mat3_check_psd n=2", c, k, gf_mat3_check_psd(&m3, 2),
                    kd == INDEF ? GF_ERR_NOT_PSD : GF_OK);
            gf_mat3 l;
            VERDICT("gf_mat3_chol n=2", c, k, gf_mat3_chol(&m3, 2, &l),
                    kd == DEF ? GF_OK : GF_ERR_SINGULAR);
        }
    }
}

static void verdicts_3x3(void **state)
{
    (void)state;
    const gf_vec3 mu = {{0, 0, 0}};
    for (unsigned c = 0; c < sizeof CASES3 / sizeof CASES3[0]; c++) {
        const enum kind kd = CASES3[c].kind;
        for (int k = -KMAX; k <= KMAX; k++) {
            gf_real s = pow2(k);
            gf_mat3 m = scale3(&CASES3[c].m, s), l;
            VERDICT("gf_mat3_check_psd", c, k, gf_mat3_check_psd(&m, 3),
                    kd == INDEF ? GF_ERR_NOT_PSD : GF_OK);
            gf_status st = gf_mat3_chol(&m, 3, &l);
            VERDICT("gf_mat3_chol", c, k, st,
                    kd == DEF ? GF_OK : GF_ERR_SINGULAR);
            if (st == GF_OK) { // l l^T = s M within the tolerance
                for (int i = 0; i < 3; i++) {
                    for (int j = 0; j < 3; j++) {
                        double v = 0;
                        for (int a = 0; a < 3; a++) {
                            v += (double)l.m[i][a] * (double)l.m[j][a];
                        }
                        double want = (double)CASES3[c].m.m[i][j];
                        double sc = sqrt((double)CASES3[c].m.m[i][i] *
                                         (double)CASES3[c].m.m[j][j]);
                        assert_true(fabs(v / (double)s - want) <
                                    1e3 * (double)GF_REAL_EPSILON * sc);
                    }
                }
            }
            gf_ekf3 ekf;
            st = gf_ekf3_init(&ekf, &mu, &m);
            VERDICT("gf_ekf3_init", c, k, st,
                    kd == INDEF ? GF_ERR_NOT_PSD : GF_OK);
            if (st == GF_OK) {
                const gf_mat3 got = gf_test_ekf3_sigma(&ekf);
                near_cov(got.m[0], m.m[0], 3);
            }
        }
    }
}

// The update: Sigma = s M, Q = s q, mu and z scaled by sqrt(s) (k even):
// GF_OK at every s, the posterior s times the one at s = 1, the NIS the
// same. And S = 0 (Sigma semidefinite, C along its null direction, Q =
// 0): GF_ERR_SINGULAR at every s, the belief unchanged.
static void update_verdicts(void **state)
{
    (void)state;
    const gf_mat2 sig = {{{4, 1}, {1, 3}}};
    const gf_vec2 mu = {{1, -1}}, z = {{2, GF_R(0.5)}};
    gf_kf2_meas me;
    memset(&me, 0, sizeof me);
    me.m = 2;
    me.C.m[0][0] = 1;
    me.C.m[1][0] = GF_R(0.5);
    me.C.m[1][1] = 1;
    const gf_mat2 q = {{{1, GF_R(0.25)}, {GF_R(0.25), 2}}};
    gf_kf2 base;
    gf_innovation ib;
    assert_int_equal(gf_kf2_init(&base, &mu, &sig), GF_OK);
    me.Q = q;
    assert_int_equal(gf_kf2_update(&base, &me, &z, &ib), GF_OK);
    const gf_mat2 base_sigma = gf_test_kf2_sigma(&base);

    const gf_mat2 semi = {{{1, 1}, {1, 1}}}; // null direction (1, -1)
    gf_kf2_meas null_me;
    memset(&null_me, 0, sizeof null_me);
    null_me.m = 1;
    null_me.C.m[0][0] = 1;
    null_me.C.m[0][1] = -1;

    for (int k = -KMAX; k <= KMAX; k += 2) {
        gf_real s = pow2(k), r = pow2(k / 2);
        gf_mat2 ss = scale2(&sig, s);
        gf_vec2 ms = {{r * mu.v[0], r * mu.v[1]}};
        gf_vec2 zs = {{r * z.v[0], r * z.v[1]}};
        me.Q = scale2(&q, s);
        gf_kf2 kf;
        gf_innovation info;
        assert_int_equal(gf_kf2_init(&kf, &ms, &ss), GF_OK);
        gf_status st = gf_kf2_update(&kf, &me, &zs, &info);
        VERDICT("gf_kf2_update, Sigma = s M, Q = s q", 0, k, st, GF_OK);
        const gf_mat2 sigma = gf_test_kf2_sigma(&kf);
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) {
                double got = (double)sigma.m[i][j] / (double)s;
                double want = (double)base_sigma.m[i][j];
                assert_true(fabs(got - want) <= SCALE_TOL * fabs(want) + 0.0);
            }
            double gm = (double)kf.mu.v[i] / (double)r;
            assert_true(fabs(gm - (double)base.mu.v[i]) <=
                        SCALE_TOL * (1 + fabs((double)base.mu.v[i])));
        }
        assert_true(fabs((double)info.nis - (double)ib.nis) <=
                    SCALE_TOL * (double)ib.nis);

        gf_mat2 sm = scale2(&semi, s);
        assert_int_equal(gf_kf2_init(&kf, &ms, &sm), GF_OK);
        const gf_vec2 z0 = {{0, 0}};
        gf_kf2 keep = kf;
        st = gf_kf2_update(&kf, &null_me, &z0, NULL);
        VERDICT("gf_kf2_update, S = 0", 0, k, st, GF_ERR_SINGULAR);
        assert_memory_equal(&keep, &kf, sizeof kf);
    }

    // EKF3, the same with gf_ekf3_meas_xy and a correlated Q.
    const gf_mat3 sig3 = {{{4, 1, 0}, {1, 3, 1}, {0, 1, 2}}};
    const gf_vec3 mu3 = {{1, -1, 0}}, z3 = {{2, GF_R(0.5), 0}};
    gf_ekf3_meas em;
    memset(&em, 0, sizeof em);
    em.m = 2;
    em.h = gf_ekf3_meas_xy;
    const gf_mat3 q3 = {{{1, GF_R(0.25), 0}, {GF_R(0.25), 2, 0}, {0, 0, 0}}};
    em.Q = q3;
    gf_ekf3 b3;
    gf_innovation i3;
    assert_int_equal(gf_ekf3_init(&b3, &mu3, &sig3), GF_OK);
    assert_int_equal(gf_ekf3_update(&b3, &em, &z3, &i3), GF_OK);
    const gf_mat3 b3_sigma = gf_test_ekf3_sigma(&b3);
    for (int k = -KMAX; k <= KMAX; k += 2) {
        gf_real s = pow2(k), r = pow2(k / 2);
        gf_mat3 ss = scale3(&sig3, s);
        // The heading is an angle: its mean stays 0, its variance scales
        // with the rest (a unit of the heading's own).
        gf_vec3 ms = {{r * mu3.v[0], r * mu3.v[1], 0}};
        gf_vec3 zs = {{r * z3.v[0], r * z3.v[1], 0}};
        em.Q = scale3(&q3, s);
        gf_ekf3 e;
        gf_innovation info;
        assert_int_equal(gf_ekf3_init(&e, &ms, &ss), GF_OK);
        gf_status st = gf_ekf3_update(&e, &em, &zs, &info);
        VERDICT("gf_ekf3_update, Sigma = s M, Q = s q", 0, k, st, GF_OK);
        const gf_mat3 sigma = gf_test_ekf3_sigma(&e);
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                double got = (double)sigma.m[i][j] / (double)s;
                double want = (double)b3_sigma.m[i][j];
                assert_true(fabs(got - want) <=
                            SCALE_TOL * sqrt((double)b3_sigma.m[i][i] *
                                             (double)b3_sigma.m[j][j]));
            }
        }
        assert_true(fabs((double)info.nis - (double)i3.nis) <=
                    SCALE_TOL * (double)i3.nis);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(verdicts_2x2),
        cmocka_unit_test(verdicts_3x3),
        cmocka_unit_test(update_verdicts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
