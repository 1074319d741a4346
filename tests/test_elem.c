// SPDX-License-Identifier: MIT
// gf_exp, gf_log and gf_atan2 against long double expl, logl and atan2l: the
// worst error in ulps of the true value over even sweeps, the neighbours of
// the points where the reductions change branch, tiny, huge and subnormal
// arguments, and random bit patterns from a fixed seed; then the special
// values (zeros, infinities, NaN, negative arguments).
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "gf_test.h"

#ifdef GF_SINGLE_PRECISION
#define GF_NEXTAFTER nextafterf
#define REAL_MAX FLT_MAX
#define REAL_TRUE_MIN 1.40129846e-45f
#else
#define GF_NEXTAFTER nextafter
#define REAL_MAX DBL_MAX
#define REAL_TRUE_MIN 4.9406564584124654e-324
#endif

// The stated bounds (mat.h): exp and log within 1 ulp of the true value;
// atan2 within 1.5, the rounding of y / x included (fdlibm's reduction).
#define ULP_TOL 1.0
#define ATAN2_ULP_TOL 1.5

typedef struct worst {
    double ulp, at_x, at_y;
    unsigned n;
} worst;

enum fn { EXP, LOG, ATAN2 };

// The error of one call in ulps of the true value, the worst kept. Results
// beyond the largest gf_real must be inf, and are not counted in ulps.
static void measure(worst *w, enum fn f, gf_real y, gf_real x)
{
    gf_real got;
    long double want;
    switch (f) {
    case EXP:
        got = gf_exp(x);
        want = expl((long double)x);
        break;
    case LOG:
        got = gf_log(x);
        want = logl((long double)x);
        break;
    default:
        got = gf_atan2(y, x);
        want = atan2l((long double)y, (long double)x);
        break;
    }
    if (fabsl(want) > (long double)REAL_MAX * (1 + LDBL_EPSILON)) {
        assert_true(isinf(got));
        return;
    }
    const double u =
        (double)(fabsl((long double)got - want) / gf_test_ulp_of(want));
    if (!(u <= w->ulp)) {
        w->ulp = u;
        w->at_x = (double)x;
        w->at_y = (double)y;
    }
    w->n++;
}

// The n gf_reals each side of x, x included.
static void around(worst *w, enum fn f, gf_real y, gf_real x, int n)
{
    for (int k = 0; k < n; k++) {
        x = GF_NEXTAFTER(x, -(gf_real)INFINITY);
    }
    for (int k = 0; k <= 2 * n; k++) {
        measure(w, f, y, x);
        x = GF_NEXTAFTER(x, (gf_real)INFINITY);
    }
}

// A seeded xorshift64*: the same inputs in every run.
static uint64_t next(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 2685821657736338717ULL;
}

// A finite positive gf_real from random bits: every exponent equally
// likely, subnormals included.
static gf_real random_positive(uint64_t *s)
{
    for (;;) {
        gf_real x;
#ifdef GF_SINGLE_PRECISION
        uint32_t b = (uint32_t)(next(s) >> 33); // sign bit clear
        memcpy(&x, &b, sizeof x);
#else
        uint64_t b = next(s) >> 1;
        memcpy(&x, &b, sizeof x);
#endif
        if (x > 0 && x <= REAL_MAX) {
            return x;
        }
    }
}

// A uniform gf_real in [lo, hi].
static gf_real random_in(uint64_t *s, long double lo, long double hi)
{
    const long double u = (long double)(next(s) >> 11) / 9007199254740992.0L;
    return (gf_real)(lo + (hi - lo) * u);
}

static void report(const char *what, const worst *w)
{
    print_message("  %s over %u arguments: worst %.3f ulp (at y %.9g, x "
                  "%.17g)\n",
                  what, w->n, w->ulp, w->at_y, w->at_x);
}

#ifdef GF_SINGLE_PRECISION
#define EXP_LO -103.9L
#define EXP_HI 88.7L
#else
#define EXP_LO -745.1L
#define EXP_HI 709.7L
#endif

static void test_exp_error(void **state)
{
    (void)state;
    worst w = {0, 0, 0, 0};
    uint64_t seed = 0x9e3779b97f4a7c15ULL;
    const int steps = 200000;
    for (int i = 0; i <= steps; i++) { // the whole range, evenly
        measure(&w, EXP, 0, (gf_real)(EXP_LO + (EXP_HI - EXP_LO) * i / steps));
    }
    for (int i = 0; i <= steps; i++) { // |x| <= 1, where most calls are
        measure(&w, EXP, 0, (gf_real)(-1.0L + 2.0L * i / steps));
    }
    for (int i = 0; i < steps; i++) {
        measure(&w, EXP, 0, random_in(&seed, EXP_LO, EXP_HI));
    }
    // the ends of the reduction's intervals, (k + 1/2) ln 2
    for (int k = -20; k <= 20; k++) {
        around(&w, EXP, 0, (gf_real)((k + 0.5L) * 0.693147180559945309417L),
               50);
    }
    around(&w, EXP, 0, 0, 200);
    // tiny arguments, both signs: e^x = 1 + x
    for (gf_real x = GF_R(1e-3); x > 0; x *= GF_R(0.37)) {
        measure(&w, EXP, 0, x);
        measure(&w, EXP, 0, -x);
    }
    // near overflow and through the subnormal results
    around(&w, EXP, 0, (gf_real)EXP_HI, 300);
    for (int i = 0; i <= 20000; i++) {
        measure(&w, EXP, 0,
                (gf_real)(EXP_LO + (EXP_LO + 40 - EXP_LO) * i / 20000));
    }
    report("gf_exp", &w);
    assert_true(w.ulp <= ULP_TOL);
}

static void test_log_error(void **state)
{
    (void)state;
    worst w = {0, 0, 0, 0};
    uint64_t seed = 0x2545f4914f6cdd1dULL;
    const int steps = 200000;
    for (int i = 1; i <= steps; i++) { // (0, 2]: the weights, 1 - p
        measure(&w, LOG, 0, (gf_real)(2.0L * i / steps));
    }
    for (int i = 0; i < 4 * steps; i++) { // every exponent, subnormals too
        measure(&w, LOG, 0, random_positive(&seed));
    }
    // near 1 (log x = x - 1 - ...), near sqrt(2) and sqrt(2)/2 where the
    // reduction changes its exponent
    around(&w, LOG, 0, 1, 3000);
    around(&w, LOG, 0, GF_R(1.41421356237309504880), 300);
    around(&w, LOG, 0, GF_R(0.70710678118654752440), 300);
    for (gf_real d = GF_R(1e-2); d > GF_REAL_EPSILON; d *= GF_R(0.7)) {
        measure(&w, LOG, 0, 1 + d);
        measure(&w, LOG, 0, 1 - d);
    }
    // powers of two, the extremes, the smallest subnormals
    for (gf_real x = REAL_TRUE_MIN; x <= REAL_MAX / 2; x *= 2) {
        around(&w, LOG, 0, x * 2, 2);
    }
    around(&w, LOG, 0, REAL_MAX, 20);
    around(&w, LOG, 0, (gf_real)(REAL_TRUE_MIN * 21), 20);
    around(&w, LOG, 0, GF_REAL_MIN, 50);
    report("gf_log", &w);
    assert_true(w.ulp <= ULP_TOL);
}

static void test_atan2_error(void **state)
{
    (void)state;
    worst w = {0, 0, 0, 0};
    uint64_t seed = 0xd1b54a32d192ed03ULL;
    const int steps = 100000;
    // the unit circle, all four quadrants and the axes
    for (int i = -steps; i <= steps; i++) {
        const long double a = 3.14159265358979323846L * i / steps;
        measure(&w, ATAN2, (gf_real)sinl(a), (gf_real)cosl(a));
    }
    // y / x through the reduction's breakpoints 7/16, 11/16, 19/16, 39/16
    // and far beyond, both signs of each
    const gf_real bp[] = {
        GF_R(0.4375), GF_R(0.6875), GF_R(1.1875), GF_R(2.4375), 1,
        GF_R(0.5),    GF_R(1.5)};
    for (unsigned i = 0; i < sizeof bp / sizeof bp[0]; i++) {
        for (int sy = -1; sy <= 1; sy += 2) {
            for (int sx = -1; sx <= 1; sx += 2) {
                around(&w, ATAN2, (gf_real)sy * bp[i], (gf_real)sx, 200);
                around(&w, ATAN2, (gf_real)sy, (gf_real)sx / bp[i], 200);
            }
        }
    }
    // random magnitudes of both, every exponent (the ratio under- and
    // overflowing included), random signs
    for (int i = 0; i < 4 * steps; i++) {
        const uint64_t r = next(&seed);
        const gf_real y = random_positive(&seed), x = random_positive(&seed);
        measure(&w, ATAN2, (r & 1) ? -y : y, (r & 2) ? -x : x);
    }
    // random points of the square [-1, 1]^2, where the filters' sums are
    for (int i = 0; i < 4 * steps; i++) {
        measure(&w, ATAN2, random_in(&seed, -1, 1), random_in(&seed, -1, 1));
    }
    // tiny y against x of either sign, near the axes
    for (gf_real y = GF_R(1e-3); y > 0; y *= GF_R(0.37)) {
        measure(&w, ATAN2, y, 1);
        measure(&w, ATAN2, -y, -1);
        measure(&w, ATAN2, 1, y);
        measure(&w, ATAN2, -1, -y);
    }
    report("gf_atan2", &w);
    assert_true(w.ulp <= ATAN2_ULP_TOL);
}

// Bit for bit what C99 Annex F gives, signs of zeros included.
static void same(gf_real got, gf_real want)
{
    if (isnan(want)) {
        assert_true(isnan(got));
        return;
    }
    if (!(got <= want && got >= want)) {
        print_message("  got %a, want %a\n", (double)got, (double)want);
    }
    assert_true(got <= want && got >= want);
    assert_true(!signbit(got) == !signbit(want));
}

static void test_special_values(void **state)
{
    (void)state;
    const gf_real inf = (gf_real)INFINITY, nan = (gf_real)NAN;
    const gf_real pi = GF_PI, pio2 = GF_R(0.5) * GF_PI;
    const gf_real pio4 = GF_R(0.25) * GF_PI;

    same(gf_exp(0), 1);
    same(gf_exp(-(gf_real)0), 1);
    same(gf_exp(inf), inf);
    same(gf_exp(-inf), 0);
    same(gf_exp(nan), nan);
    same(gf_exp(REAL_MAX), inf);
    same(gf_exp(-REAL_MAX), 0);

    same(gf_log(1), 0);
    same(gf_log(0), -inf);
    same(gf_log(-(gf_real)0), -inf);
    same(gf_log(inf), inf);
    same(gf_log(-1), nan);
    same(gf_log(-inf), nan);
    same(gf_log(nan), nan);
    same(gf_log(-REAL_TRUE_MIN), nan);
    same(gf_log(2), GF_R(0.69314718055994530942));

    const gf_real z = 0, nz = -(gf_real)0;
    same(gf_atan2(z, z), 0);
    same(gf_atan2(nz, z), nz);
    same(gf_atan2(z, nz), pi);
    same(gf_atan2(nz, nz), -pi);
    same(gf_atan2(z, 1), 0);
    same(gf_atan2(nz, 1), nz);
    same(gf_atan2(z, -1), pi);
    same(gf_atan2(nz, -1), -pi);
    same(gf_atan2(1, z), pio2);
    same(gf_atan2(-1, nz), -pio2);
    same(gf_atan2(1, 1), pio4);
    same(gf_atan2(-1, -1), -GF_R(3.0) * pio4);
    same(gf_atan2(inf, inf), pio4);
    same(gf_atan2(-inf, -inf), -GF_R(3.0) * pio4);
    same(gf_atan2(inf, 1), pio2);
    same(gf_atan2(-inf, -1), -pio2);
    same(gf_atan2(1, inf), 0);
    same(gf_atan2(-1, inf), nz);
    same(gf_atan2(1, -inf), pi);
    same(gf_atan2(-1, -inf), -pi);
    same(gf_atan2(REAL_MAX, REAL_TRUE_MIN), pio2);
    same(gf_atan2(REAL_TRUE_MIN, -REAL_MAX), pi);
    same(gf_atan2(nan, 1), nan);
    same(gf_atan2(1, nan), nan);
    same(gf_atan2(nan, nan), nan);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exp_error),
        cmocka_unit_test(test_log_error),
        cmocka_unit_test(test_atan2_error),
        cmocka_unit_test(test_special_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
