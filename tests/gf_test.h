// SPDX-License-Identifier: MIT
// Shared by the gaussfilt tests: the tolerances, stated once, and the
// checks built on them.
#ifndef GF_TEST_H
#define GF_TEST_H

#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "gaussfilt/gaussfilt.h"

// Uniform in [lo, hi), in double, from the library's generator: the
// tests' random inputs (each test seeds its own gf_rng, so it draws the
// same inputs whatever runs before it).
static inline double gf_test_uniform(gf_rng *rng, double lo, double hi)
{
    return lo + (hi - lo) * (double)gf_rng_uniform(rng);
}

// ulp(y) of the build's precision, y the true value (zero and subnormals
// in the ulp of the smallest normal exponent): the unit of the tests that
// hold the library's own elementary functions to a bound in ulps.
static inline long double gf_test_ulp_of(long double y)
{
    int e;
    (void)frexpl(y, &e); // |y| = f 2^e, f in [0.5, 1)
#ifdef GF_SINGLE_PRECISION
    const int p = FLT_MANT_DIG, emin = FLT_MIN_EXP;
#else
    const int p = DBL_MANT_DIG, emin = DBL_MIN_EXP;
#endif
    if (y == 0 || e < emin) {
        e = emin;
    }
    return ldexpl(1, e - p);
}

// Golden tolerance: |got - want| <= GF_TEST_TOL * max(1, |want|).
// Double: 1e-12 (the exercise tables are exact binary fractions or short
// rationals). Float: 2e-5, a few ulps of the float accumulated over the
// short runs of the exercises.
#ifdef GF_SINGLE_PRECISION
#define GF_TEST_TOL 2e-5
#else
#define GF_TEST_TOL 1e-12
#endif

// The worked solutions (docs/exercises.md) print two decimals: a value
// agrees with them "to the digits printed" when it rounds to theirs.
#define GF_PRINTED_TOL 0.005

static inline void gf_check_close_(double got, double want, double tol,
                                   const char *what, const char *file, int line)
{
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= tol * scale)) {
        print_error("%s: got %.17g, want %.17g (tol %g)\n", what, got, want,
                    tol * scale);
        _fail(file, line);
    }
}

// got equals want within the golden tolerance.
#define CHECK_CLOSE(got, want)                                                 \
    gf_check_close_((double)(got), (double)(want), GF_TEST_TOL, #got,          \
                    __FILE__, __LINE__)
// got agrees with the worked solutions' printed (rounded) value.
#define CHECK_PRINTED(got, printed)                                            \
    do {                                                                       \
        double g_ = (double)(got), p_ = (double)(printed);                     \
        if (!(fabs(g_ - p_) <= GF_PRINTED_TOL)) {                              \
            print_error("%s: got %.6f, the worked solutions print %.2f\n",     \
                        #got, g_, p_);                                         \
            _fail(__FILE__, __LINE__);                                         \
        }                                                                      \
    } while (0)

// A call that must fail with `status` and leave *obj bit-for-bit as it was.
#define CHECK_FAILS_UNCHANGED(status, obj, call)                               \
    do {                                                                       \
        unsigned char before_[sizeof(*(obj))];                                 \
        memcpy(before_, (obj), sizeof(*(obj)));                                \
        assert_int_equal((call), (status));                                    \
        assert_memory_equal(before_, (obj), sizeof(*(obj)));                   \
    } while (0)

// The covariance of a belief, read through its accessor, which must
// succeed.
static inline gf_mat2 gf_test_kf2_sigma(const gf_kf2 *kf)
{
    gf_mat2 sigma;
    assert_int_equal(gf_kf2_cov(kf, &sigma), GF_OK);
    return sigma;
}

static inline gf_mat3 gf_test_ekf3_sigma(const gf_ekf3 *ekf)
{
    gf_mat3 sigma;
    assert_int_equal(gf_ekf3_cov(ekf, &sigma), GF_OK);
    return sigma;
}

// ekf3.h's promise to a motion callback, for every filter that calls one:
// mu_bar arrives as a copy of mu and G as the identity. This model counts
// the calls that broke it in *(unsigned *)ctx, then moves like the
// built-in (which it calls with ctx NULL).
static inline gf_status gf_test_motion_checks_args(void *ctx, const gf_vec3 *mu,
                                                   const gf_real *u,
                                                   gf_vec3 *mu_bar, gf_mat3 *G)
{
    static const gf_mat3 eye = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    if (memcmp(mu_bar, mu, sizeof *mu) != 0 ||
        memcmp(G, &eye, sizeof eye) != 0) {
        ++*(unsigned *)ctx;
    }
    return gf_ekf3_motion_forward_turn(NULL, mu, u, mu_bar, G);
}

// The set-up of the tests of that promise: a motion with that model
// counting into *broken (and a little noise), a belief N(mu, sig) with a
// correlated sig, and the control u (1 forward, turn 0.3).
typedef struct gf_test_args {
    gf_ekf3_motion mo;
    gf_vec3 mu;
    gf_mat3 sig;
    gf_real u[2];
} gf_test_args;

static inline gf_test_args gf_test_args_make(unsigned *broken)
{
    const gf_test_args a = {
        {gf_test_motion_checks_args,
         broken,
         {{{GF_R(0.01), 0, 0}, {0, GF_R(0.01), 0}, {0, 0, GF_R(0.01)}}}},
        {{1, 2, GF_R(0.5)}},
        {{{1, GF_R(0.1), 0}, {GF_R(0.1), 1, 0}, {0, 0, 1}}},
        {1, GF_R(0.3)}};
    return a;
}

#endif
