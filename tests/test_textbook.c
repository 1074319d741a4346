// SPDX-License-Identifier: MIT
// KF2's and EKF3's steps (the factored steps of src/udu.h) against a
// plain textbook implementation written here: full matrix products, the
// Joseph form (I - K H) Sigma (I - K H)^T + K Q K^T, and a general G.
// Random beliefs, headings all round the circle, and the edge inputs (R
// symmetric only within tolerance, R not diagonally dominant, a Jacobian
// not of the built-in shape, gated and overflowing updates).
#include "gf_test.h"

// The reference works in double from the filter's gf_real values on
// purpose (in the float build too): promotion is what is wanted here.
#pragma GCC diagnostic ignored "-Wdouble-promotion"

// The steps against the textbook: relative to the largest entry involved.
#ifdef GF_SINGLE_PRECISION
#define FP_TOL 2e-4
#else
#define FP_TOL 1e-10
#endif

// The random inputs (each random test seeds it first).
static gf_rng rng;

static double urand(double lo, double hi)
{
    return gf_test_uniform(&rng, lo, hi);
}

static void check_rel(double got, double want, double scale, const char *what)
{
    if (!(fabs(got - want) <= FP_TOL * (scale > 1 ? scale : 1))) {
        print_error("%s: got %.17g, want %.17g\n", what, got, want);
        fail();
    }
}

// ---- textbook reference, n x n with n <= 3, m = 1 --------------------------

typedef struct ref_belief {
    double mu[3];
    double S[3][3];
} ref_belief;

// S = F S F^T + R, full products.
static void ref_sandwich(int n, double F[3][3], double S[3][3], double R[3][3])
{
    double T[3][3] = {{0}}, O[3][3] = {{0}};
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            for (int k = 0; k < n; k++) {
                T[i][j] += F[i][k] * S[k][j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            for (int k = 0; k < n; k++) {
                O[i][j] += T[i][k] * F[j][k];
            }
            O[i][j] += R[i][j];
        }
    }
    memcpy(S, O, sizeof O);
}

// Scalar update with row h, factored Joseph form; returns y and NIS.
static void ref_update1(int n, ref_belief *b, const double h[3], double q,
                        double y, double *nis)
{
    double p[3] = {0}, s = q, K[3], L[3][3], Z[3][3] = {{0}};
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < n; k++) {
            p[i] += b->S[i][k] * h[k];
        }
    }
    for (int i = 0; i < n; i++) {
        s += h[i] * p[i];
    }
    for (int i = 0; i < n; i++) {
        K[i] = p[i] / s;
        b->mu[i] += K[i] * y;
        for (int j = 0; j < n; j++) {
            L[i][j] = (i == j) - K[i] * h[j];
        }
    }
    ref_sandwich(n, L, b->S, Z);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            b->S[i][j] += K[i] * q * K[j];
        }
    }
    *nis = y * y / s;
}

static double maxabs(int n, const double S[3][3])
{
    double m = 0;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            m = fabs(S[i][j]) > m ? fabs(S[i][j]) : m;
        }
    }
    return m;
}

// ---- KF2 ------------------------------------------------------------------

static void kf2_check(const gf_kf2 *kf, const ref_belief *r)
{
    double sc = maxabs(2, r->S);
    const gf_mat2 sigma = gf_test_kf2_sigma(kf);
    for (int i = 0; i < 2; i++) {
        check_rel(kf->mu.v[i], r->mu[i], fabs(r->mu[i]) + sc, "kf2 mu");
        for (int j = 0; j < 2; j++) {
            check_rel(sigma.m[i][j], r->S[i][j], sc, "kf2 sigma");
        }
    }
    // exactly symmetric
    assert_memory_equal(&sigma.m[0][1], &sigma.m[1][0], sizeof(gf_real));
}

static void kf2_random(void **state)
{
    (void)state;
    (void)gf_rng_seed(&rng, 1u);
    for (int trial = 0; trial < 200; trial++) {
        gf_kf2_model model;
        gf_kf2_meas meas;
        memset(&model, 0, sizeof model);
        memset(&meas, 0, sizeof meas);
        double F[3][3] = {{0}}, R[3][3] = {{0}};
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) {
                model.A.m[i][j] = (gf_real)urand(-1.5, 1.5);
            }
        }
        double g0 = urand(-1, 1), g1 = urand(-1, 1), rd = urand(0, 0.5);
        // R = g g^T + rd I: correlated, sometimes nearly singular
        model.R.m[0][0] = (gf_real)(g0 * g0 + rd);
        model.R.m[1][1] = (gf_real)(g1 * g1 + rd);
        model.R.m[0][1] = model.R.m[1][0] = (gf_real)(g0 * g1);
        model.c.v[0] = (gf_real)urand(-1, 1);
        meas.m = 1;
        meas.C.m[0][0] = (gf_real)urand(-2, 2);
        meas.C.m[0][1] = (gf_real)urand(-2, 2);
        meas.Q.m[0][0] = (gf_real)urand(0.01, 5);
        meas.c.v[0] = (gf_real)urand(-1, 1);
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) {
                F[i][j] = model.A.m[i][j];
                R[i][j] = model.R.m[i][j];
            }
        }
        gf_kf2 kf;
        gf_vec2 mu0 = {{(gf_real)urand(-5, 5), (gf_real)urand(-5, 5)}};
        gf_mat2 s0 = {{{2, (gf_real)0.3}, {(gf_real)0.3, 1}}};
        assert_int_equal(gf_kf2_init(&kf, &mu0, &s0), GF_OK);
        for (int t = 0; t < 5; t++) {
            const gf_mat2 s = gf_test_kf2_sigma(&kf);
            ref_belief r = {{kf.mu.v[0], kf.mu.v[1], 0},
                            {{s.m[0][0], s.m[0][1], 0},
                             {s.m[1][0], s.m[1][1], 0},
                             {0, 0, 0}}};
            gf_vec2 u = {{(gf_real)urand(-1, 1), (gf_real)urand(-1, 1)}};
            model.B.m[0][0] = (gf_real)urand(-1, 1);
            model.B.m[1][1] = (gf_real)urand(-1, 1);
            int with_u = t % 2;
            assert_int_equal(gf_kf2_predict(&kf, &model, with_u ? &u : NULL),
                             GF_OK);
            double m0 = F[0][0] * r.mu[0] + F[0][1] * r.mu[1] + model.c.v[0];
            double m1 = F[1][0] * r.mu[0] + F[1][1] * r.mu[1] + model.c.v[1];
            if (with_u) {
                m0 += (double)model.B.m[0][0] * (double)u.v[0] +
                      (double)model.B.m[0][1] * (double)u.v[1];
                m1 += (double)model.B.m[1][0] * (double)u.v[0] +
                      (double)model.B.m[1][1] * (double)u.v[1];
            }
            r.mu[0] = m0;
            r.mu[1] = m1;
            ref_sandwich(2, F, r.S, R);
            kf2_check(&kf, &r);

            gf_vec2 z = {{(gf_real)urand(-10, 10), 0}};
            gf_innovation info;
            assert_int_equal(gf_kf2_update(&kf, &meas, &z, &info), GF_OK);
            double h[3] = {meas.C.m[0][0], meas.C.m[0][1], 0}, nis;
            double y = (double)z.v[0] - (double)meas.c.v[0] -
                       (h[0] * r.mu[0] + h[1] * r.mu[1]);
            ref_update1(2, &r, h, meas.Q.m[0][0], y, &nis);
            kf2_check(&kf, &r);
            check_rel(info.y[0], y, fabs(y), "kf2 y");
            check_rel(info.nis, nis, nis, "kf2 nis");
            assert_true(info.m == 1 && info.y[1] == 0 && info.y[2] == 0);
        }
    }
}

// Inputs the checks must accept (R symmetric only within tolerance) or
// find (a NaN or inf that reaches no output), and failures found only
// after the step was computed.
static void kf2_edge_inputs(void **state)
{
    (void)state;
    const gf_kf2_model car = {{{{1, 1}, {0, 1}}},
                              {{{0, 0}, {0, 0}}},
                              {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), 1}}},
                              {{0, 0}}};
    const gf_kf2_meas gps = {
        1, {{{1, 0}, {0, 0}}}, {{{10, 0}, {0, 0}}}, {{0, 0}}, 0};
    gf_vec2 mu = {{1, 2}};
    gf_mat2 s = {{{3, 1}, {1, 2}}};
    gf_kf2 a, b;
    assert_int_equal(gf_kf2_init(&a, &mu, &s), GF_OK);
    b = a;
    // R symmetric within GF_SYM_RTOL only: accepted, same result.
    gf_kf2_model m = car;
    m.R.m[1][0] = GF_R(0.5) * (1 + 4 * GF_REAL_EPSILON);
    assert_int_equal(gf_kf2_predict(&a, &m, NULL), GF_OK);
    assert_int_equal(gf_kf2_predict(&b, &car, NULL), GF_OK);
    assert_memory_equal(&a, &b, sizeof a);
    // A NaN in R's lower entry reaches no output: still found.
    m.R.m[1][0] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &a, gf_kf2_predict(&a, &m, NULL));
    // inf in B with a control: found through the outputs.
    m = car;
    m.B.m[0][0] = (gf_real)INFINITY;
    const gf_vec2 u = {{1, 1}};
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &a, gf_kf2_predict(&a, &m, &u));
    // Q = inf: K would be 0 and the outputs finite, yet it is an error.
    gf_kf2_meas q = gps;
    gf_vec2 z = {{3, 0}};
    gf_innovation info;
    q.Q.m[0][0] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &a,
                          gf_kf2_update(&a, &q, &z, &info));
    // gate = inf is non-finite, gate = NaN too.
    q = gps;
    q.gate = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &a,
                          gf_kf2_update(&a, &q, &z, &info));
    // Gated: info written, belief untouched.
    q = gps;
    q.gate = GF_R(1e-6);
    z.v[0] = 5; // mu_bar is (3, 2): y = 2
    memset(&info, 0, sizeof info);
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &a, gf_kf2_update(&a, &q, &z, &info));
    assert_true(info.m == 1 && info.nis > GF_R(1e-6));
    // s = +0 (known state, no noise): singular.
    gf_kf2 known;
    gf_mat2 zero = {{{0, 0}, {0, 0}}};
    assert_int_equal(gf_kf2_init(&known, &mu, &zero), GF_OK);
    q = gps;
    q.Q.m[0][0] = 0;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &known,
                          gf_kf2_update(&known, &q, &z, &info));
    // A huge but finite z whose update overflows.
    z.v[0] = (gf_real)(sizeof(gf_real) == 4 ? 3e38 : 1.7e308);
    q = gps;
    s.m[0][0] = s.m[1][1] = GF_R(1e6);
    s.m[0][1] = s.m[1][0] = 0;
    mu.v[0] = -z.v[0];
    assert_int_equal(gf_kf2_init(&a, &mu, &s), GF_OK);
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &a,
                          gf_kf2_update(&a, &q, &z, &info));
}

// ---- EKF3 -----------------------------------------------------------------

// A motion whose Jacobian is not of the built-in shape: a heading-dependent
// drift that also scales x. ctx unused.
static gf_status motion_general(void *ctx, const gf_vec3 *mu, const gf_real *u,
                                gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)ctx;
    const gf_real th = mu->v[2];
    gf_real s, c;
    gf_sincos(th, &s, &c);
    mu_bar->v[0] = GF_R(0.9) * mu->v[0] + u[0] * c;
    mu_bar->v[1] = mu->v[1] + u[0] * s + GF_R(0.1) * mu->v[0];
    mu_bar->v[2] = th + u[1];
    G->m[0][0] = GF_R(0.9);
    G->m[0][1] = 0;
    G->m[0][2] = -u[0] * s;
    G->m[1][0] = GF_R(0.1);
    G->m[1][1] = 1;
    G->m[1][2] = u[0] * c;
    G->m[2][0] = 0;
    G->m[2][1] = 0;
    G->m[2][2] = 1;
    return GF_OK;
}

// A general measurement row: h(x) = a x + b y + theta (theta an angle when
// the mask says so). ctx points at (a, b).
static gf_status meas_row(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                          gf_mat3 *H)
{
    const gf_real *ab = ctx;
    z_hat->v[0] = ab[0] * mu_bar->v[0] + ab[1] * mu_bar->v[1] + mu_bar->v[2];
    H->m[0][0] = ab[0];
    H->m[0][1] = ab[1];
    H->m[0][2] = 1;
    return GF_OK;
}

static double wrapd(double a)
{
    const double pi = 3.14159265358979323846;
    while (a > pi) {
        a -= 2 * pi;
    }
    while (a <= -pi) {
        a += 2 * pi;
    }
    return a;
}

static void ekf3_check(const gf_ekf3 *e, const ref_belief *r)
{
    double sc = maxabs(3, r->S);
    const gf_mat3 sigma = gf_test_ekf3_sigma(e);
    for (int i = 0; i < 3; i++) {
        check_rel(e->mu.v[i], r->mu[i], fabs(r->mu[i]) + sc, "ekf3 mu");
        for (int j = 0; j < 3; j++) {
            check_rel(sigma.m[i][j], r->S[i][j], sc, "ekf3 sigma");
        }
        for (int j = i + 1; j < 3; j++) {
            assert_memory_equal(&sigma.m[i][j], &sigma.m[j][i],
                                sizeof(gf_real));
        }
    }
}

static void ekf3_random(void **state)
{
    (void)state;
    (void)gf_rng_seed(&rng, 2u);
    for (int trial = 0; trial < 120; trial++) {
        const int general = trial % 3 == 1, angle = trial % 2;
        gf_ekf3_motion mo;
        gf_ekf3_meas me;
        memset(&mo, 0, sizeof mo);
        memset(&me, 0, sizeof me);
        mo.g = general ? motion_general : gf_ekf3_motion_forward_turn;
        // R: diagonal (its own factors), or correlated (factored by pivots).
        double R[3][3] = {{0}};
        double g[3] = {urand(-0.3, 0.3), urand(-0.3, 0.3), urand(-0.1, 0.1)};
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                R[i][j] = (trial % 4 < 2 ? 0 : g[i] * g[j]) +
                          (i == j ? urand(0, 0.01) : 0);
                mo.R.m[i][j] = (gf_real)R[i][j];
                R[i][j] = mo.R.m[i][j];
            }
        }
        gf_real ab[2] = {(gf_real)urand(-1, 1), (gf_real)urand(-1, 1)};
        me.m = 1;
        me.h = trial % 5 == 0 ? gf_ekf3_meas_x : meas_row;
        me.ctx = ab;
        me.Q.m[0][0] = (gf_real)urand(0.001, 0.5);
        me.angle_mask = (me.h == meas_row && angle) ? 1u : 0u;
        gf_ekf3 e;
        gf_vec3 mu0 = {{(gf_real)urand(-3, 3), (gf_real)urand(-3, 3),
                        (gf_real)urand(-3, 3)}};
        gf_mat3 s0 = {{{GF_R(0.5), GF_R(0.1), 0},
                       {GF_R(0.1), GF_R(0.4), GF_R(0.05)},
                       {0, GF_R(0.05), GF_R(0.3)}}};
        assert_int_equal(gf_ekf3_init(&e, &mu0, &s0), GF_OK);
        for (int t = 0; t < 6; t++) {
            ref_belief r;
            const gf_mat3 s = gf_test_ekf3_sigma(&e);
            for (int i = 0; i < 3; i++) {
                r.mu[i] = e.mu.v[i];
                for (int j = 0; j < 3; j++) {
                    r.S[i][j] = s.m[i][j];
                }
            }
            gf_real u[2] = {(gf_real)urand(0.2, 1.5), (gf_real)urand(-3, 3)};
            assert_int_equal(gf_ekf3_predict(&e, &mo, u), GF_OK);
            double th = r.mu[2], d = u[0], c = cos(th), sn = sin(th);
            double F[3][3] = {{1, 0, -d * sn}, {0, 1, d * c}, {0, 0, 1}};
            if (general) {
                F[0][0] = (double)GF_R(0.9);
                F[1][0] = (double)GF_R(0.1);
                double x = r.mu[0];
                r.mu[0] = F[0][0] * x + d * c;
                r.mu[1] += d * sn + F[1][0] * x;
            } else {
                r.mu[0] += d * c;
                r.mu[1] += d * sn;
            }
            r.mu[2] = wrapd(th + (double)u[1]);
            ref_sandwich(3, F, r.S, R);
            ekf3_check(&e, &r);

            gf_vec3 z = {{(gf_real)urand(-5, 5), 0, 0}};
            gf_innovation info;
            assert_int_equal(gf_ekf3_update(&e, &me, &z, &info), GF_OK);
            double h[3] = {1, 0, 0}, zh = r.mu[0], nis;
            if (me.h == meas_row) {
                h[0] = ab[0];
                h[1] = ab[1];
                h[2] = 1;
                zh = h[0] * r.mu[0] + h[1] * r.mu[1] + r.mu[2];
            }
            double y = (double)z.v[0] - zh;
            if (me.angle_mask) {
                y = wrapd(y);
            }
            ref_update1(3, &r, h, me.Q.m[0][0], y, &nis);
            r.mu[2] = wrapd(r.mu[2]);
            ekf3_check(&e, &r);
            check_rel(info.y[0], y, fabs(y), "ekf3 y");
            check_rel(info.nis, nis, nis, "ekf3 nis");
        }
    }
}

static gf_status motion_fails(void *ctx, const gf_vec3 *mu, const gf_real *u,
                              gf_vec3 *mu_bar, gf_mat3 *G)
{
    (void)ctx;
    (void)mu;
    (void)u;
    (void)mu_bar;
    (void)G;
    return GF_ERR_MODEL;
}

static void ekf3_edge_inputs(void **state)
{
    (void)state;
    gf_ekf3 e, f;
    gf_vec3 mu = {{1, 2, GF_R(0.5)}};
    gf_mat3 s = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    assert_int_equal(gf_ekf3_init(&e, &mu, &s), GF_OK);
    gf_ekf3_motion mo;
    memset(&mo, 0, sizeof mo);
    mo.g = gf_ekf3_motion_forward_turn;
    mo.R.m[0][0] = mo.R.m[1][1] = mo.R.m[2][2] = GF_R(0.1);
    const gf_real u[2] = {1, GF_R(0.3)};
    // R symmetric within tolerance, and R = 0 (exercise 4): accepted.
    f = e;
    gf_ekf3_motion m2 = mo;
    m2.R.m[0][1] = GF_R(0.01);
    m2.R.m[1][0] = GF_R(0.01) * (1 + 4 * GF_REAL_EPSILON);
    assert_int_equal(gf_ekf3_predict(&f, &m2, u), GF_OK);
    memset(&m2.R, 0, sizeof m2.R);
    assert_int_equal(gf_ekf3_predict(&f, &m2, u), GF_OK);
    // inf on R's diagonal is found first, also when the model fails.
    m2 = mo;
    m2.R.m[2][2] = (gf_real)INFINITY;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &e, gf_ekf3_predict(&e, &m2, u));
    m2.g = motion_fails;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &e, gf_ekf3_predict(&e, &m2, u));
    m2.R = mo.R;
    CHECK_FAILS_UNCHANGED(GF_ERR_MODEL, &e, gf_ekf3_predict(&e, &m2, u));
    // R indefinite but not diagonally dominant: refused.
    m2 = mo;
    m2.R.m[0][1] = m2.R.m[1][0] = GF_R(0.2);
    CHECK_FAILS_UNCHANGED(GF_ERR_NOT_PSD, &e, gf_ekf3_predict(&e, &m2, u));
    // Update: Q = inf, gate, s = 0.
    gf_ekf3_meas me;
    memset(&me, 0, sizeof me);
    me.m = 1;
    me.h = gf_ekf3_meas_x;
    me.Q.m[0][0] = (gf_real)INFINITY;
    gf_vec3 z = {{3, 0, 0}};
    gf_innovation info;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &e,
                          gf_ekf3_update(&e, &me, &z, &info));
    me.Q.m[0][0] = GF_R(0.01);
    me.gate = GF_R(1e-6);
    CHECK_FAILS_UNCHANGED(GF_ERR_GATED, &e, gf_ekf3_update(&e, &me, &z, &info));
    assert_true(info.m == 1 && info.nis > GF_R(1e-6));
    me.gate = 0;
    z.v[0] = (gf_real)NAN;
    CHECK_FAILS_UNCHANGED(GF_ERR_NONFINITE, &e,
                          gf_ekf3_update(&e, &me, &z, &info));
    gf_ekf3 known;
    gf_mat3 zero = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    assert_int_equal(gf_ekf3_init(&known, &mu, &zero), GF_OK);
    me.Q.m[0][0] = 0;
    z.v[0] = 3;
    CHECK_FAILS_UNCHANGED(GF_ERR_SINGULAR, &known,
                          gf_ekf3_update(&known, &me, &z, &info));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(kf2_random),
        cmocka_unit_test(kf2_edge_inputs),
        cmocka_unit_test(ekf3_random),
        cmocka_unit_test(ekf3_edge_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
