// SPDX-License-Identifier: MIT
// NULL safety of every public function of every header in
// include/gaussfilt/: each pointer argument (and each pointer a call reads
// through: a model's callback, a filter's particle array) NULL in turn.
// A function returning gf_status returns GF_ERR_ARG; a void function does
// nothing; a function returning a value returns the one its header states
// for NULL. In every case nothing the call could reach changes, bit for
// bit: every argument lives in one fixture, compared whole before and
// after. Arguments a header allows to be NULL (a control u with no use for
// it, the info of an update, one of two outputs) are not failures and are
// left out, but checked to succeed.
#include "gf_test.h"

#define N_PART 8

// Everything the calls below are given, valid, in one place.
typedef struct fixture {
    gf_vec2 v2, x2;
    gf_mat2 a2, b2, o2;
    gf_vec3 v3, x3;
    gf_mat3 a3, b3, o3;
    gf_real r, s, c;
    gf_innovation info;
    gf_ellipse e;
    gf_rng rng;
    gf_kf2 kf;
    gf_kf2_model model;
    gf_kf2_meas meas2;
    gf_kf2_pmodel pm;
    gf_kf2_pmeas pq;
    gf_ekf3 ekf;
    gf_ekf3_motion motion;
    gf_ekf3_meas meas3;
    gf_ekf3_pmotion epm;
    gf_ekf3_pmeas epq;
    gf_real u[2];
    gf_if2 inf;
    gf_ukf3 ukf;
    gf_ukf3_params up;
    gf_pf3 pf;
    gf_pf3_particle part[N_PART];
    gf_kf kfn;
    gf_kf_work work;
    gf_kf_model kmodel;
    gf_kf_meas kmeas;
    gf_kf_pmodel kpm;
    gf_kf_pmeas kpq;
    gf_ekf_motion emotion;
    gf_ekf_meas emeas;
    gf_ekf_pmotion epmn;
    gf_ekf_pmeas epqn;
    gf_kf_innovation kinfo;
    gf_ekf_check check;
    gf_real kz[2];
} fixture;

static fixture fx;
static fixture before; // static: the emulated target's stack is small

static void setup_fixture(void)
{
    static const gf_mat2 spd2 = {{{2, GF_R(0.5)}, {GF_R(0.5), 1}}};
    static const gf_mat3 spd3 = {
        {{2, GF_R(0.5), 0}, {GF_R(0.5), 1, 0}, {0, 0, GF_R(0.5)}}};
    memset(&fx, 0, sizeof fx); // padding included: memcmp sees all of it
    fx.v2.v[0] = 1;
    fx.v2.v[1] = -1;
    fx.x2 = fx.v2;
    fx.a2 = spd2;
    fx.b2 = spd2;
    fx.o2 = spd2;
    fx.v3.v[0] = 1;
    fx.v3.v[1] = 2;
    fx.v3.v[2] = GF_R(0.5);
    fx.x3 = fx.v3;
    fx.a3 = spd3;
    fx.b3 = spd3;
    fx.o3 = spd3;
    fx.r = fx.s = fx.c = GF_R(0.25);
    memset(&fx.info, 0x5a, sizeof fx.info);
    assert_int_equal(gf_rng_seed(&fx.rng, 7), GF_OK);

    fx.model.A.m[0][0] = fx.model.A.m[1][1] = 1;
    fx.model.A.m[0][1] = 1;
    fx.model.B.m[1][1] = 1;
    fx.model.R.m[0][0] = fx.model.R.m[1][1] = GF_R(0.1);
    fx.meas2.m = 1;
    fx.meas2.C.m[0][0] = 1;
    fx.meas2.Q.m[0][0] = 1;
    assert_int_equal(gf_kf2_init(&fx.kf, &fx.v2, &spd2), GF_OK);
    assert_int_equal(gf_kf2_prepare_model(&fx.pm, &fx.model), GF_OK);
    assert_int_equal(gf_kf2_prepare_meas(&fx.pq, &fx.meas2), GF_OK);

    fx.motion.g = gf_ekf3_motion_forward_turn;
    fx.motion.R.m[0][0] = fx.motion.R.m[1][1] = GF_R(0.01);
    fx.motion.R.m[2][2] = GF_R(0.01);
    fx.meas3.m = 2;
    fx.meas3.h = gf_ekf3_meas_xy;
    fx.meas3.Q.m[0][0] = fx.meas3.Q.m[1][1] = GF_R(0.1);
    fx.u[0] = 1;
    fx.u[1] = GF_R(0.1);
    assert_int_equal(gf_ekf3_init(&fx.ekf, &fx.v3, &spd3), GF_OK);
    assert_int_equal(gf_ekf3_prepare_motion(&fx.epm, &fx.motion), GF_OK);
    assert_int_equal(gf_ekf3_prepare_meas(&fx.epq, &fx.meas3), GF_OK);
    assert_int_equal(gf_if2_init(&fx.inf, &spd2, &fx.v2), GF_OK);
    fx.up.alpha = 1;
    fx.up.beta = 2;
    assert_int_equal(gf_ukf3_init(&fx.ukf, &fx.v3, &spd3, &fx.up), GF_OK);
    assert_int_equal(gf_pf3_init(&fx.pf, fx.part, N_PART, 3, &fx.v3, &spd3),
                     GF_OK);
}

// gf_ekf's models for the fixture: x' = x (G = I, as preset), z = x_0
// (H = (1 0)).
static gf_status ekf_still(void *ctx, unsigned n, const gf_real *mu,
                           const gf_real *u, gf_real *mu_bar, gf_real *G)
{
    (void)ctx;
    (void)n;
    (void)mu;
    (void)u;
    (void)mu_bar;
    (void)G;
    return GF_OK;
}

static gf_status ekf_first(void *ctx, unsigned n, unsigned m,
                           const gf_real *mu_bar, gf_real *z_hat, gf_real *H)
{
    (void)ctx;
    (void)n;
    (void)m;
    z_hat[0] = mu_bar[0];
    H[0] = 1;
    return GF_OK;
}

// The any-size filters' part of the fixture: n = 2, models in the
// fixture's own 2x2 matrices.
static void setup_kfn(void)
{
    fx.kmodel.A = fx.model.A.m[0];
    fx.kmodel.R = fx.model.R.m[0];
    fx.kmeas.m = 1;
    fx.kmeas.C = fx.meas2.C.m[0];
    fx.kmeas.Q = fx.meas2.Q.m[0];
    fx.emotion.g = ekf_still;
    fx.emotion.R = fx.model.R.m[0];
    fx.emeas.m = 1;
    fx.emeas.h = ekf_first;
    fx.emeas.Q = fx.meas2.Q.m[0];
    fx.kz[0] = 1;
    assert_int_equal(gf_kf_init(&fx.kfn, 2, fx.v2.v, fx.a2.m[0], &fx.work),
                     GF_OK);
    assert_int_equal(gf_kf_prepare_model(&fx.kpm, 2, &fx.kmodel, &fx.work),
                     GF_OK);
    assert_int_equal(gf_kf_prepare_meas(&fx.kpq, 2, &fx.kmeas, &fx.work),
                     GF_OK);
    assert_int_equal(gf_ekf_prepare_motion(&fx.epmn, 2, &fx.emotion, &fx.work),
                     GF_OK);
    assert_int_equal(gf_ekf_prepare_meas(&fx.epqn, 2, &fx.emeas, &fx.work),
                     GF_OK);
}

// The call, with a NULL in it, returns GF_ERR_ARG and changes nothing.
#define NULL_FAILS(call)                                                       \
    do {                                                                       \
        memcpy(&before, &fx, sizeof fx);                                       \
        assert_int_equal((call), GF_ERR_ARG);                                  \
        assert_memory_equal(&before, &fx, sizeof fx);                          \
    } while (0)

// A void call, with a NULL in it, changes nothing.
#define NULL_NOTHING(call)                                                     \
    do {                                                                       \
        memcpy(&before, &fx, sizeof fx);                                       \
        call;                                                                  \
        assert_memory_equal(&before, &fx, sizeof fx);                          \
    } while (0)

// A value-returning call, with a NULL in it, returns want and changes
// nothing.
#define NULL_RETURNS(call, want)                                               \
    do {                                                                       \
        memcpy(&before, &fx, sizeof fx);                                       \
        assert_true((call) == (want));                                         \
        assert_memory_equal(&before, &fx, sizeof fx);                          \
    } while (0)

// The same call with nothing NULL succeeds (so the NULL is what fails).
#define VALID(call) assert_int_equal((call), GF_OK)

static void test_mat2(void **state)
{
    (void)state;
    setup_fixture();
    gf_mat2_mul(&fx.a2, &fx.b2, &fx.o2);
    gf_mat2_mulv(&fx.a2, &fx.v2, &fx.x2);
    gf_mat2_sandwich(&fx.a2, &fx.b2, &fx.o2);
    VALID(gf_mat2_check_psd(&fx.a2));
    VALID(gf_mat2_spd_inv(&fx.a2, &fx.o2));
    VALID(gf_mat2_eig_sym(&fx.a2, &fx.x2, &fx.r));
    setup_fixture();

    NULL_FAILS(gf_mat2_mul(NULL, &fx.b2, &fx.o2));
    NULL_FAILS(gf_mat2_mul(&fx.a2, NULL, &fx.o2));
    NULL_FAILS(gf_mat2_mul(&fx.a2, &fx.b2, NULL));
    NULL_FAILS(gf_mat2_mulv(NULL, &fx.v2, &fx.x2));
    NULL_FAILS(gf_mat2_mulv(&fx.a2, NULL, &fx.x2));
    NULL_FAILS(gf_mat2_mulv(&fx.a2, &fx.v2, NULL));
    NULL_FAILS(gf_mat2_sandwich(NULL, &fx.b2, &fx.o2));
    NULL_FAILS(gf_mat2_sandwich(&fx.a2, NULL, &fx.o2));
    NULL_FAILS(gf_mat2_sandwich(&fx.a2, &fx.b2, NULL));
    NULL_FAILS(gf_mat2_symmetrize(NULL));
    NULL_RETURNS(gf_mat2_is_finite(NULL), 0);
    NULL_FAILS(gf_mat2_check_psd(NULL));
    NULL_FAILS(gf_mat2_spd_inv(NULL, &fx.o2));
    NULL_FAILS(gf_mat2_spd_inv(&fx.a2, NULL));
    NULL_FAILS(gf_mat2_eig_sym(NULL, &fx.x2, &fx.r));
    NULL_FAILS(gf_mat2_eig_sym(&fx.a2, NULL, &fx.r));
    NULL_FAILS(gf_mat2_eig_sym(&fx.a2, &fx.x2, NULL));
}

static void test_mat3(void **state)
{
    (void)state;
    setup_fixture();
    gf_mat3_mul(&fx.a3, &fx.b3, &fx.o3);
    gf_mat3_mulv(&fx.a3, &fx.v3, &fx.x3);
    gf_mat3_sandwich(&fx.a3, &fx.b3, &fx.o3);
    VALID(gf_mat3_check_psd(&fx.a3, 3));
    VALID(gf_mat3_chol(&fx.a3, 3, &fx.o3));
    gf_mat3_chol_solve(&fx.o3, 3, &fx.v3, &fx.x3);
    VALID(gf_mat3_sqrt_psd(&fx.a3, 3, &fx.o3));
    setup_fixture();

    NULL_FAILS(gf_mat3_mul(NULL, &fx.b3, &fx.o3));
    NULL_FAILS(gf_mat3_mul(&fx.a3, NULL, &fx.o3));
    NULL_FAILS(gf_mat3_mul(&fx.a3, &fx.b3, NULL));
    NULL_FAILS(gf_mat3_mulv(NULL, &fx.v3, &fx.x3));
    NULL_FAILS(gf_mat3_mulv(&fx.a3, NULL, &fx.x3));
    NULL_FAILS(gf_mat3_mulv(&fx.a3, &fx.v3, NULL));
    NULL_FAILS(gf_mat3_sandwich(NULL, &fx.b3, &fx.o3));
    NULL_FAILS(gf_mat3_sandwich(&fx.a3, NULL, &fx.o3));
    NULL_FAILS(gf_mat3_sandwich(&fx.a3, &fx.b3, NULL));
    NULL_FAILS(gf_mat3_symmetrize(NULL));
    NULL_RETURNS(gf_mat3_is_finite(NULL), 0);
    NULL_FAILS(gf_mat3_check_psd(NULL, 3));
    NULL_FAILS(gf_mat3_chol(NULL, 3, &fx.o3));
    NULL_FAILS(gf_mat3_chol(&fx.a3, 3, NULL));
    NULL_FAILS(gf_mat3_chol_solve(NULL, 3, &fx.v3, &fx.x3));
    NULL_FAILS(gf_mat3_chol_solve(&fx.a3, 3, NULL, &fx.x3));
    NULL_FAILS(gf_mat3_chol_solve(&fx.a3, 3, &fx.v3, NULL));
    NULL_FAILS(gf_mat3_sqrt_psd(NULL, 3, &fx.o3));
    NULL_FAILS(gf_mat3_sqrt_psd(&fx.a3, 3, NULL));
}

static void test_angle(void **state)
{
    (void)state;
    setup_fixture();
    NULL_NOTHING(gf_sincos(GF_R(0.5), NULL, &fx.c));
    NULL_NOTHING(gf_sincos(GF_R(0.5), &fx.s, NULL));
    NULL_NOTHING(gf_sincos(GF_R(0.5), NULL, NULL));
    // gf_angle_wrap, gf_exp, gf_log, gf_atan2 and gf_status_str take no
    // pointer.
    assert_non_null(gf_status_str((gf_status)-99));
}

static void test_rng(void **state)
{
    (void)state;
    setup_fixture();
    gf_rng_mvn3(&fx.rng, &fx.v3, &fx.a3, &fx.x3);
    setup_fixture();
    NULL_FAILS(gf_rng_seed(NULL, 1));
    NULL_RETURNS(gf_rng_u32(NULL), 0u);
    NULL_RETURNS(gf_rng_uniform(NULL), 0);
    NULL_RETURNS(gf_rng_normal(NULL), 0);
    NULL_NOTHING(gf_rng_mvn3(NULL, &fx.v3, &fx.a3, &fx.x3));
    NULL_NOTHING(gf_rng_mvn3(&fx.rng, NULL, &fx.a3, &fx.x3));
    NULL_NOTHING(gf_rng_mvn3(&fx.rng, &fx.v3, NULL, &fx.x3));
    NULL_NOTHING(gf_rng_mvn3(&fx.rng, &fx.v3, &fx.a3, NULL));
}

static void test_cov2(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_cov2_correlation(&fx.a2, &fx.r));
    VALID(gf_cov2_ellipse(&fx.a2, GF_R(0.68), &fx.e));
    VALID(gf_cov2_marginal(&fx.a3, 0, 1, &fx.o2));
    setup_fixture();
    NULL_FAILS(gf_cov2_correlation(NULL, &fx.r));
    NULL_FAILS(gf_cov2_correlation(&fx.a2, NULL));
    NULL_FAILS(gf_cov2_ellipse(NULL, GF_R(0.68), &fx.e));
    NULL_FAILS(gf_cov2_ellipse(&fx.a2, GF_R(0.68), NULL));
    NULL_FAILS(gf_cov2_marginal(NULL, 0, 1, &fx.o2));
    NULL_FAILS(gf_cov2_marginal(&fx.a3, 0, 1, NULL));
}

static void test_kf2(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_kf2_init(&fx.kf, &fx.v2, &fx.a2));
    VALID(gf_kf2_cov(&fx.kf, &fx.o2));
    VALID(gf_kf2_predict(&fx.kf, &fx.model, &fx.x2));
    VALID(gf_kf2_predict(&fx.kf, &fx.model, NULL)); // no control
    VALID(gf_kf2_update(&fx.kf, &fx.meas2, &fx.x2, &fx.info));
    VALID(gf_kf2_update(&fx.kf, &fx.meas2, &fx.x2, NULL)); // no info
    VALID(gf_kf2_prepare_model(&fx.pm, &fx.model));
    VALID(gf_kf2_prepare_meas(&fx.pq, &fx.meas2));
    VALID(gf_kf2_predict_prepared(&fx.kf, &fx.pm, &fx.x2));
    VALID(gf_kf2_predict_prepared(&fx.kf, &fx.pm, NULL));
    VALID(gf_kf2_update_prepared(&fx.kf, &fx.pq, &fx.x2, &fx.info));
    VALID(gf_kf2_update_prepared(&fx.kf, &fx.pq, &fx.x2, NULL));
    setup_fixture();

    NULL_FAILS(gf_kf2_init(NULL, &fx.v2, &fx.a2));
    NULL_FAILS(gf_kf2_init(&fx.kf, NULL, &fx.a2));
    NULL_FAILS(gf_kf2_init(&fx.kf, &fx.v2, NULL));
    NULL_FAILS(gf_kf2_cov(NULL, &fx.o2));
    NULL_FAILS(gf_kf2_cov(&fx.kf, NULL));
    NULL_FAILS(gf_kf2_predict(NULL, &fx.model, &fx.x2));
    NULL_FAILS(gf_kf2_predict(&fx.kf, NULL, &fx.x2));
    NULL_FAILS(gf_kf2_update(NULL, &fx.meas2, &fx.x2, &fx.info));
    NULL_FAILS(gf_kf2_update(&fx.kf, NULL, &fx.x2, &fx.info));
    NULL_FAILS(gf_kf2_update(&fx.kf, &fx.meas2, NULL, &fx.info));
    NULL_FAILS(gf_kf2_prepare_model(NULL, &fx.model));
    NULL_FAILS(gf_kf2_prepare_model(&fx.pm, NULL));
    NULL_FAILS(gf_kf2_prepare_meas(NULL, &fx.meas2));
    NULL_FAILS(gf_kf2_prepare_meas(&fx.pq, NULL));
    NULL_FAILS(gf_kf2_predict_prepared(NULL, &fx.pm, &fx.x2));
    NULL_FAILS(gf_kf2_predict_prepared(&fx.kf, NULL, &fx.x2));
    NULL_FAILS(gf_kf2_update_prepared(NULL, &fx.pq, &fx.x2, &fx.info));
    NULL_FAILS(gf_kf2_update_prepared(&fx.kf, NULL, &fx.x2, &fx.info));
    NULL_FAILS(gf_kf2_update_prepared(&fx.kf, &fx.pq, NULL, &fx.info));
}

static void test_ekf3(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_ekf3_motion_forward_turn(NULL, &fx.v3, fx.u, &fx.x3, &fx.o3));
    VALID(gf_ekf3_meas_x(NULL, &fx.v3, &fx.x3, &fx.o3));
    VALID(gf_ekf3_meas_xy(NULL, &fx.v3, &fx.x3, &fx.o3));
    VALID(gf_ekf3_init(&fx.ekf, &fx.v3, &fx.a3));
    VALID(gf_ekf3_cov(&fx.ekf, &fx.o3));
    VALID(gf_ekf3_predict(&fx.ekf, &fx.motion, fx.u));
    VALID(gf_ekf3_update(&fx.ekf, &fx.meas3, &fx.x3, &fx.info));
    VALID(gf_ekf3_update(&fx.ekf, &fx.meas3, &fx.x3, NULL));
    VALID(gf_ekf3_prepare_motion(&fx.epm, &fx.motion));
    VALID(gf_ekf3_prepare_meas(&fx.epq, &fx.meas3));
    VALID(gf_ekf3_predict_prepared(&fx.ekf, &fx.epm, fx.u));
    VALID(gf_ekf3_update_prepared(&fx.ekf, &fx.epq, &fx.x3, &fx.info));
    VALID(gf_ekf3_update_prepared(&fx.ekf, &fx.epq, &fx.x3, NULL));
    setup_fixture();

    // The built-in models (ctx is unused, NULL is its usual value).
    NULL_FAILS(gf_ekf3_motion_forward_turn(NULL, NULL, fx.u, &fx.x3, &fx.o3));
    NULL_FAILS(gf_ekf3_motion_forward_turn(NULL, &fx.v3, NULL, &fx.x3, &fx.o3));
    NULL_FAILS(gf_ekf3_motion_forward_turn(NULL, &fx.v3, fx.u, NULL, &fx.o3));
    NULL_FAILS(gf_ekf3_motion_forward_turn(NULL, &fx.v3, fx.u, &fx.x3, NULL));
    NULL_FAILS(gf_ekf3_meas_x(NULL, NULL, &fx.x3, &fx.o3));
    NULL_FAILS(gf_ekf3_meas_x(NULL, &fx.v3, NULL, &fx.o3));
    NULL_FAILS(gf_ekf3_meas_x(NULL, &fx.v3, &fx.x3, NULL));
    NULL_FAILS(gf_ekf3_meas_xy(NULL, NULL, &fx.x3, &fx.o3));
    NULL_FAILS(gf_ekf3_meas_xy(NULL, &fx.v3, NULL, &fx.o3));
    NULL_FAILS(gf_ekf3_meas_xy(NULL, &fx.v3, &fx.x3, NULL));

    NULL_FAILS(gf_ekf3_init(NULL, &fx.v3, &fx.a3));
    NULL_FAILS(gf_ekf3_init(&fx.ekf, NULL, &fx.a3));
    NULL_FAILS(gf_ekf3_init(&fx.ekf, &fx.v3, NULL));
    NULL_FAILS(gf_ekf3_cov(NULL, &fx.o3));
    NULL_FAILS(gf_ekf3_cov(&fx.ekf, NULL));
    NULL_FAILS(gf_ekf3_predict(NULL, &fx.motion, fx.u));
    NULL_FAILS(gf_ekf3_predict(&fx.ekf, NULL, fx.u));
    NULL_FAILS(gf_ekf3_predict(&fx.ekf, &fx.motion, NULL)); // the built-in's
    fx.motion.g = NULL;
    NULL_FAILS(gf_ekf3_predict(&fx.ekf, &fx.motion, fx.u));
    fx.motion.g = gf_ekf3_motion_forward_turn;
    NULL_FAILS(gf_ekf3_update(NULL, &fx.meas3, &fx.x3, &fx.info));
    NULL_FAILS(gf_ekf3_update(&fx.ekf, NULL, &fx.x3, &fx.info));
    NULL_FAILS(gf_ekf3_update(&fx.ekf, &fx.meas3, NULL, &fx.info));
    fx.meas3.h = NULL;
    NULL_FAILS(gf_ekf3_update(&fx.ekf, &fx.meas3, &fx.x3, &fx.info));
    fx.meas3.h = gf_ekf3_meas_xy;

    NULL_FAILS(gf_ekf3_prepare_motion(NULL, &fx.motion));
    NULL_FAILS(gf_ekf3_prepare_motion(&fx.epm, NULL));
    NULL_FAILS(gf_ekf3_prepare_meas(NULL, &fx.meas3));
    NULL_FAILS(gf_ekf3_prepare_meas(&fx.epq, NULL));
    fx.motion.g = NULL;
    NULL_FAILS(gf_ekf3_prepare_motion(&fx.epm, &fx.motion));
    fx.motion.g = gf_ekf3_motion_forward_turn;
    fx.meas3.h = NULL;
    NULL_FAILS(gf_ekf3_prepare_meas(&fx.epq, &fx.meas3));
    fx.meas3.h = gf_ekf3_meas_xy;
    NULL_FAILS(gf_ekf3_predict_prepared(NULL, &fx.epm, fx.u));
    NULL_FAILS(gf_ekf3_predict_prepared(&fx.ekf, NULL, fx.u));
    // the built-in's u
    NULL_FAILS(gf_ekf3_predict_prepared(&fx.ekf, &fx.epm, NULL));
    NULL_FAILS(gf_ekf3_update_prepared(NULL, &fx.epq, &fx.x3, &fx.info));
    NULL_FAILS(gf_ekf3_update_prepared(&fx.ekf, NULL, &fx.x3, &fx.info));
    NULL_FAILS(gf_ekf3_update_prepared(&fx.ekf, &fx.epq, NULL, &fx.info));
    // A prepared model whose callback was cleared after it was prepared.
    fx.epm.motion.g = NULL;
    NULL_FAILS(gf_ekf3_predict_prepared(&fx.ekf, &fx.epm, fx.u));
    fx.epq.meas.h = NULL;
    NULL_FAILS(gf_ekf3_update_prepared(&fx.ekf, &fx.epq, &fx.x3, &fx.info));
}

static void test_kfn(void **state)
{
    (void)state;
    setup_fixture();
    setup_kfn();
    VALID(gf_kf_cov(&fx.kfn, fx.o2.m[0]));
    VALID(gf_kf_predict(&fx.kfn, &fx.kmodel, NULL, &fx.work));
    VALID(gf_kf_update(&fx.kfn, &fx.kmeas, fx.kz, &fx.kinfo, &fx.work));
    VALID(gf_kf_update(&fx.kfn, &fx.kmeas, fx.kz, NULL, &fx.work));
    VALID(gf_kf_predict_prepared(&fx.kfn, &fx.kpm, NULL, &fx.work));
    VALID(gf_kf_update_prepared(&fx.kfn, &fx.kpq, fx.kz, &fx.kinfo, &fx.work));
    VALID(gf_ekf_init(&fx.kfn, 2, fx.v2.v, fx.a2.m[0], 1u, &fx.work));
    VALID(gf_ekf_predict(&fx.kfn, &fx.emotion, NULL, &fx.work));
    VALID(gf_ekf_update(&fx.kfn, &fx.emeas, fx.kz, &fx.kinfo, &fx.work));
    VALID(gf_ekf_predict_prepared(&fx.kfn, &fx.epmn, NULL, &fx.work));
    VALID(gf_ekf_update_prepared(&fx.kfn, &fx.epqn, fx.kz, NULL, &fx.work));
    VALID(gf_ekf_check_model(&fx.emotion, &fx.emeas, 2, fx.v2.v, NULL, 0u,
                             &fx.check, &fx.work));
    VALID(gf_ekf_check_model(NULL, &fx.emeas, 2, fx.v2.v, NULL, 0u, &fx.check,
                             &fx.work));
    VALID(gf_ekf_check_model(&fx.emotion, NULL, 2, fx.v2.v, NULL, 0u, &fx.check,
                             &fx.work));
    setup_fixture();
    setup_kfn();

    NULL_FAILS(gf_kf_init(NULL, 2, fx.v2.v, fx.a2.m[0], &fx.work));
    NULL_FAILS(gf_kf_init(&fx.kfn, 2, NULL, fx.a2.m[0], &fx.work));
    NULL_FAILS(gf_kf_init(&fx.kfn, 2, fx.v2.v, NULL, &fx.work));
    NULL_FAILS(gf_kf_init(&fx.kfn, 2, fx.v2.v, fx.a2.m[0], NULL));
    NULL_FAILS(gf_kf_cov(NULL, fx.o2.m[0]));
    NULL_FAILS(gf_kf_cov(&fx.kfn, NULL));
    NULL_FAILS(gf_kf_predict(NULL, &fx.kmodel, NULL, &fx.work));
    NULL_FAILS(gf_kf_predict(&fx.kfn, NULL, NULL, &fx.work));
    NULL_FAILS(gf_kf_predict(&fx.kfn, &fx.kmodel, NULL, NULL));
    fx.kmodel.A = NULL;
    NULL_FAILS(gf_kf_predict(&fx.kfn, &fx.kmodel, NULL, &fx.work));
    fx.kmodel.A = fx.model.A.m[0];
    fx.kmodel.R = NULL;
    NULL_FAILS(gf_kf_predict(&fx.kfn, &fx.kmodel, NULL, &fx.work));
    fx.kmodel.R = fx.model.R.m[0];
    fx.kmodel.nu = 2; // B is read for nu > 0
    NULL_FAILS(gf_kf_predict(&fx.kfn, &fx.kmodel, fx.u, &fx.work));
    fx.kmodel.nu = 0;
    NULL_FAILS(gf_kf_update(NULL, &fx.kmeas, fx.kz, &fx.kinfo, &fx.work));
    NULL_FAILS(gf_kf_update(&fx.kfn, NULL, fx.kz, &fx.kinfo, &fx.work));
    NULL_FAILS(gf_kf_update(&fx.kfn, &fx.kmeas, NULL, &fx.kinfo, &fx.work));
    NULL_FAILS(gf_kf_update(&fx.kfn, &fx.kmeas, fx.kz, &fx.kinfo, NULL));
    fx.kmeas.C = NULL;
    NULL_FAILS(gf_kf_update(&fx.kfn, &fx.kmeas, fx.kz, &fx.kinfo, &fx.work));
    fx.kmeas.C = fx.meas2.C.m[0];
    fx.kmeas.Q = NULL;
    NULL_FAILS(gf_kf_update(&fx.kfn, &fx.kmeas, fx.kz, &fx.kinfo, &fx.work));
    fx.kmeas.Q = fx.meas2.Q.m[0];
    NULL_FAILS(gf_kf_prepare_model(NULL, 2, &fx.kmodel, &fx.work));
    NULL_FAILS(gf_kf_prepare_model(&fx.kpm, 2, NULL, &fx.work));
    NULL_FAILS(gf_kf_prepare_model(&fx.kpm, 2, &fx.kmodel, NULL));
    NULL_FAILS(gf_kf_prepare_meas(NULL, 2, &fx.kmeas, &fx.work));
    NULL_FAILS(gf_kf_prepare_meas(&fx.kpq, 2, NULL, &fx.work));
    NULL_FAILS(gf_kf_prepare_meas(&fx.kpq, 2, &fx.kmeas, NULL));
    NULL_FAILS(gf_kf_predict_prepared(NULL, &fx.kpm, NULL, &fx.work));
    NULL_FAILS(gf_kf_predict_prepared(&fx.kfn, NULL, NULL, &fx.work));
    NULL_FAILS(gf_kf_predict_prepared(&fx.kfn, &fx.kpm, NULL, NULL));
    NULL_FAILS(gf_kf_update_prepared(NULL, &fx.kpq, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_kf_update_prepared(&fx.kfn, NULL, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_kf_update_prepared(&fx.kfn, &fx.kpq, NULL, NULL, &fx.work));
    NULL_FAILS(gf_kf_update_prepared(&fx.kfn, &fx.kpq, fx.kz, NULL, NULL));

    NULL_FAILS(gf_ekf_init(NULL, 2, fx.v2.v, fx.a2.m[0], 0u, &fx.work));
    NULL_FAILS(gf_ekf_init(&fx.kfn, 2, NULL, fx.a2.m[0], 0u, &fx.work));
    NULL_FAILS(gf_ekf_init(&fx.kfn, 2, fx.v2.v, NULL, 0u, &fx.work));
    NULL_FAILS(gf_ekf_init(&fx.kfn, 2, fx.v2.v, fx.a2.m[0], 0u, NULL));
    NULL_FAILS(gf_ekf_predict(NULL, &fx.emotion, NULL, &fx.work));
    NULL_FAILS(gf_ekf_predict(&fx.kfn, NULL, NULL, &fx.work));
    NULL_FAILS(gf_ekf_predict(&fx.kfn, &fx.emotion, NULL, NULL));
    fx.emotion.g = NULL;
    NULL_FAILS(gf_ekf_predict(&fx.kfn, &fx.emotion, NULL, &fx.work));
    NULL_FAILS(gf_ekf_prepare_motion(&fx.epmn, 2, &fx.emotion, &fx.work));
    fx.emotion.g = ekf_still;
    fx.emotion.R = NULL;
    NULL_FAILS(gf_ekf_predict(&fx.kfn, &fx.emotion, NULL, &fx.work));
    fx.emotion.R = fx.model.R.m[0];
    NULL_FAILS(gf_ekf_update(NULL, &fx.emeas, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update(&fx.kfn, NULL, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update(&fx.kfn, &fx.emeas, NULL, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update(&fx.kfn, &fx.emeas, fx.kz, NULL, NULL));
    fx.emeas.h = NULL;
    NULL_FAILS(gf_ekf_update(&fx.kfn, &fx.emeas, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_ekf_prepare_meas(&fx.epqn, 2, &fx.emeas, &fx.work));
    fx.emeas.h = ekf_first;
    fx.emeas.Q = NULL;
    NULL_FAILS(gf_ekf_update(&fx.kfn, &fx.emeas, fx.kz, NULL, &fx.work));
    fx.emeas.Q = fx.meas2.Q.m[0];
    NULL_FAILS(gf_ekf_prepare_motion(NULL, 2, &fx.emotion, &fx.work));
    NULL_FAILS(gf_ekf_prepare_motion(&fx.epmn, 2, NULL, &fx.work));
    NULL_FAILS(gf_ekf_prepare_motion(&fx.epmn, 2, &fx.emotion, NULL));
    NULL_FAILS(gf_ekf_prepare_meas(NULL, 2, &fx.emeas, &fx.work));
    NULL_FAILS(gf_ekf_prepare_meas(&fx.epqn, 2, NULL, &fx.work));
    NULL_FAILS(gf_ekf_prepare_meas(&fx.epqn, 2, &fx.emeas, NULL));
    NULL_FAILS(gf_ekf_predict_prepared(NULL, &fx.epmn, NULL, &fx.work));
    NULL_FAILS(gf_ekf_predict_prepared(&fx.kfn, NULL, NULL, &fx.work));
    NULL_FAILS(gf_ekf_predict_prepared(&fx.kfn, &fx.epmn, NULL, NULL));
    NULL_FAILS(gf_ekf_update_prepared(NULL, &fx.epqn, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update_prepared(&fx.kfn, NULL, fx.kz, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update_prepared(&fx.kfn, &fx.epqn, NULL, NULL, &fx.work));
    NULL_FAILS(gf_ekf_update_prepared(&fx.kfn, &fx.epqn, fx.kz, NULL, NULL));
    NULL_FAILS(gf_ekf_check_model(NULL, NULL, 2, fx.v2.v, NULL, 0u, &fx.check,
                                  &fx.work));
    NULL_FAILS(gf_ekf_check_model(&fx.emotion, &fx.emeas, 2, NULL, NULL, 0u,
                                  &fx.check, &fx.work));
    NULL_FAILS(gf_ekf_check_model(&fx.emotion, &fx.emeas, 2, fx.v2.v, NULL, 0u,
                                  NULL, &fx.work));
    NULL_FAILS(gf_ekf_check_model(&fx.emotion, &fx.emeas, 2, fx.v2.v, NULL, 0u,
                                  &fx.check, NULL));
    fx.emotion.g = NULL;
    NULL_FAILS(gf_ekf_check_model(&fx.emotion, NULL, 2, fx.v2.v, NULL, 0u,
                                  &fx.check, &fx.work));
    fx.emotion.g = ekf_still;
    fx.emeas.h = NULL;
    NULL_FAILS(gf_ekf_check_model(NULL, &fx.emeas, 2, fx.v2.v, NULL, 0u,
                                  &fx.check, &fx.work));
    fx.emeas.h = ekf_first;
    fx.epmn.motion.g = NULL;
    NULL_FAILS(gf_ekf_predict_prepared(&fx.kfn, &fx.epmn, NULL, &fx.work));
    fx.epqn.meas.h = NULL;
    NULL_FAILS(
        gf_ekf_update_prepared(&fx.kfn, &fx.epqn, fx.kz, NULL, &fx.work));
}

static void test_if2(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_if2_init(&fx.inf, &fx.a2, &fx.v2));
    VALID(gf_if2_from_moments(&fx.inf, &fx.v2, &fx.a2));
    VALID(gf_if2_to_moments(&fx.inf, &fx.x2, &fx.o2));
    VALID(gf_if2_to_moments(&fx.inf, NULL, &fx.o2)); // one output
    VALID(gf_if2_to_moments(&fx.inf, &fx.x2, NULL));
    VALID(gf_if2_predict(&fx.inf, &fx.model, &fx.x2));
    VALID(gf_if2_predict(&fx.inf, &fx.model, NULL));
    VALID(gf_if2_update(&fx.inf, &fx.meas2, &fx.x2, &fx.info));
    VALID(gf_if2_update(&fx.inf, &fx.meas2, &fx.x2, NULL));
    setup_fixture();

    NULL_FAILS(gf_if2_init(NULL, &fx.a2, &fx.v2));
    NULL_FAILS(gf_if2_init(&fx.inf, NULL, &fx.v2));
    NULL_FAILS(gf_if2_init(&fx.inf, &fx.a2, NULL));
    NULL_FAILS(gf_if2_from_moments(NULL, &fx.v2, &fx.a2));
    NULL_FAILS(gf_if2_from_moments(&fx.inf, NULL, &fx.a2));
    NULL_FAILS(gf_if2_from_moments(&fx.inf, &fx.v2, NULL));
    NULL_FAILS(gf_if2_to_moments(NULL, &fx.x2, &fx.o2));
    NULL_FAILS(gf_if2_to_moments(&fx.inf, NULL, NULL));
    NULL_FAILS(gf_if2_predict(NULL, &fx.model, &fx.x2));
    NULL_FAILS(gf_if2_predict(&fx.inf, NULL, &fx.x2));
    NULL_FAILS(gf_if2_update(NULL, &fx.meas2, &fx.x2, &fx.info));
    NULL_FAILS(gf_if2_update(&fx.inf, NULL, &fx.x2, &fx.info));
    NULL_FAILS(gf_if2_update(&fx.inf, &fx.meas2, NULL, &fx.info));
}

static void test_ukf3(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_ukf3_init(&fx.ukf, &fx.v3, &fx.a3, &fx.up));
    VALID(gf_ukf3_predict(&fx.ukf, &fx.motion, fx.u));
    VALID(gf_ukf3_update(&fx.ukf, &fx.meas3, &fx.x3, &fx.info));
    VALID(gf_ukf3_update(&fx.ukf, &fx.meas3, &fx.x3, NULL));
    setup_fixture();

    NULL_FAILS(gf_ukf3_init(NULL, &fx.v3, &fx.a3, &fx.up));
    NULL_FAILS(gf_ukf3_init(&fx.ukf, NULL, &fx.a3, &fx.up));
    NULL_FAILS(gf_ukf3_init(&fx.ukf, &fx.v3, NULL, &fx.up));
    NULL_FAILS(gf_ukf3_init(&fx.ukf, &fx.v3, &fx.a3, NULL));
    NULL_FAILS(gf_ukf3_predict(NULL, &fx.motion, fx.u));
    NULL_FAILS(gf_ukf3_predict(&fx.ukf, NULL, fx.u));
    NULL_FAILS(gf_ukf3_predict(&fx.ukf, &fx.motion, NULL)); // the built-in's
    fx.motion.g = NULL;
    NULL_FAILS(gf_ukf3_predict(&fx.ukf, &fx.motion, fx.u));
    fx.motion.g = gf_ekf3_motion_forward_turn;
    NULL_FAILS(gf_ukf3_update(NULL, &fx.meas3, &fx.x3, &fx.info));
    NULL_FAILS(gf_ukf3_update(&fx.ukf, NULL, &fx.x3, &fx.info));
    NULL_FAILS(gf_ukf3_update(&fx.ukf, &fx.meas3, NULL, &fx.info));
    fx.meas3.h = NULL;
    NULL_FAILS(gf_ukf3_update(&fx.ukf, &fx.meas3, &fx.x3, &fx.info));
}

static void test_pf3(void **state)
{
    (void)state;
    setup_fixture();
    VALID(gf_pf3_predict(&fx.pf, &fx.motion, fx.u));
    VALID(gf_pf3_update(&fx.pf, &fx.meas3, &fx.x3));
    VALID(gf_pf3_neff(&fx.pf, &fx.r));
    VALID(gf_pf3_estimate(&fx.pf, &fx.x3, &fx.o3));
    VALID(gf_pf3_estimate(&fx.pf, NULL, &fx.o3)); // one output
    VALID(gf_pf3_estimate(&fx.pf, &fx.x3, NULL));
    VALID(gf_pf3_resample(&fx.pf));
    setup_fixture();

    NULL_FAILS(gf_pf3_init(NULL, fx.part, N_PART, 3, &fx.v3, &fx.a3));
    NULL_FAILS(gf_pf3_init(&fx.pf, NULL, N_PART, 3, &fx.v3, &fx.a3));
    NULL_FAILS(gf_pf3_init(&fx.pf, fx.part, N_PART, 3, NULL, &fx.a3));
    NULL_FAILS(gf_pf3_init(&fx.pf, fx.part, N_PART, 3, &fx.v3, NULL));
    NULL_FAILS(gf_pf3_predict(NULL, &fx.motion, fx.u));
    NULL_FAILS(gf_pf3_predict(&fx.pf, NULL, fx.u));
    NULL_FAILS(gf_pf3_predict(&fx.pf, &fx.motion, NULL)); // the built-in's
    NULL_FAILS(gf_pf3_update(NULL, &fx.meas3, &fx.x3));
    NULL_FAILS(gf_pf3_update(&fx.pf, NULL, &fx.x3));
    NULL_FAILS(gf_pf3_update(&fx.pf, &fx.meas3, NULL));
    NULL_FAILS(gf_pf3_resample(NULL));
    NULL_FAILS(gf_pf3_neff(NULL, &fx.r));
    NULL_FAILS(gf_pf3_neff(&fx.pf, NULL));
    NULL_FAILS(gf_pf3_estimate(NULL, &fx.x3, &fx.o3));
    NULL_FAILS(gf_pf3_estimate(&fx.pf, NULL, NULL));
    fx.motion.g = NULL;
    fx.meas3.h = NULL;
    NULL_FAILS(gf_pf3_predict(&fx.pf, &fx.motion, fx.u));
    NULL_FAILS(gf_pf3_update(&fx.pf, &fx.meas3, &fx.x3));
    fx.motion.g = gf_ekf3_motion_forward_turn;
    fx.meas3.h = gf_ekf3_meas_xy;
    // A filter struct whose particle array is NULL (never initialised).
    fx.pf.p = NULL;
    NULL_FAILS(gf_pf3_predict(&fx.pf, &fx.motion, fx.u));
    NULL_FAILS(gf_pf3_update(&fx.pf, &fx.meas3, &fx.x3));
    NULL_FAILS(gf_pf3_resample(&fx.pf));
    NULL_FAILS(gf_pf3_neff(&fx.pf, &fx.r));
    NULL_FAILS(gf_pf3_estimate(&fx.pf, &fx.x3, &fx.o3));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mat2),  cmocka_unit_test(test_mat3),
        cmocka_unit_test(test_angle), cmocka_unit_test(test_rng),
        cmocka_unit_test(test_cov2),  cmocka_unit_test(test_kf2),
        cmocka_unit_test(test_ekf3),  cmocka_unit_test(test_kfn),
        cmocka_unit_test(test_if2),   cmocka_unit_test(test_ukf3),
        cmocka_unit_test(test_pf3),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
