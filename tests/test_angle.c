// SPDX-License-Identifier: MIT
// gf_sincos against long double sinl/cosl over (-GF_PI, GF_PI], the range
// gf_angle_wrap returns (every heading the filters keep): the error
// relative to the true value (in ulps of it) and absolute, worst case over
// an even sweep, the neighbours of every multiple of pi/4 (where the
// quadrant changes and where sin or cos vanishes), the ends of the range
// and tiny arguments; then the absolute error beyond it.
#include <float.h>

#include "gf_test.h"

#ifdef GF_SINGLE_PRECISION
#define GF_NEXTAFTER nextafterf
#else
#define GF_NEXTAFTER nextafter
#endif

typedef struct worst {
    double ulp, abs;
    double at_ulp, at_abs;
    unsigned n;
} worst;

static void measure(worst *w, gf_real a)
{
    gf_real s, c;
    gf_sincos(a, &s, &c);
    const long double ts = sinl((long double)a), tc = cosl((long double)a);
    const long double es = fabsl((long double)s - ts);
    const long double ec = fabsl((long double)c - tc);
    const double u = (double)(es / gf_test_ulp_of(ts) > ec / gf_test_ulp_of(tc)
                                  ? es / gf_test_ulp_of(ts)
                                  : ec / gf_test_ulp_of(tc));
    const double ab = (double)(es > ec ? es : ec);
    if (u > w->ulp) {
        w->ulp = u;
        w->at_ulp = (double)a;
    }
    if (ab > w->abs) {
        w->abs = ab;
        w->at_abs = (double)a;
    }
    w->n++;
}

// The n gf_reals each side of x (x included); with wrapped set, only
// those in (-GF_PI, GF_PI], the range gf_sincos takes without wrapping.
static void around(worst *w, gf_real x, int n, int wrapped)
{
    gf_real lo = x, hi = x;
    for (int k = 0; k < n; k++) {
        lo = GF_NEXTAFTER(lo, -(gf_real)INFINITY);
        hi = GF_NEXTAFTER(hi, (gf_real)INFINITY);
    }
    for (gf_real a = lo; a <= hi; a = GF_NEXTAFTER(a, (gf_real)INFINITY)) {
        if (!wrapped || (a > -GF_PI && a <= GF_PI)) {
            measure(w, a);
        }
    }
}

// The stated bounds (mat.h): absolute error within ABS_TOL over the
// wrapped range, and within ULP_TOL ulps of the true value.
#ifdef GF_SINGLE_PRECISION
#define ABS_TOL 1.2e-7
#else
#define ABS_TOL 2.3e-16
#endif
#define ULP_TOL 2.0

static void test_sincos_error(void **state)
{
    (void)state;
    worst w = {0, 0, 0, 0, 0};
    const int steps = 50000;
    for (int i = -steps + 1; i <= steps; i++) { // -GF_PI is not in range
        measure(&w,
                (gf_real)((long double)i * 3.14159265358979323846L / steps));
    }
    for (int q = -4; q <= 4; q++) {
        around(&w, (gf_real)(q * 0.78539816339744830962L), 300, 1);
    }
    around(&w, GF_PI, 1000, 1); // the ends of the range
    around(&w, -GF_PI, 1000, 1);
    around(&w, 0, 1000, 1);
    // tiny arguments, down to the subnormals: sin(a) = a
    for (gf_real a = GF_R(1e-3); a > 0; a *= GF_R(0.37)) {
        measure(&w, a);
        measure(&w, -a);
    }
    print_message("  gf_sincos over %u angles: worst %.3g ulp (at %.17g), "
                  "worst absolute %.3g (at %.17g)\n",
                  w.n, w.ulp, w.at_ulp, w.abs, w.at_abs);
    assert_true(w.abs <= ABS_TOL);
    assert_true(w.ulp <= ULP_TOL);
}

// Beyond (-GF_PI, GF_PI] the angle is wrapped first, and the wrap's rounding, a
// few ulps of pi (2 pi k is subtracted in two parts), is an absolute error
// that no later step can undo: near a multiple of pi, where sin vanishes,
// it is many ulps of the result. The stated bound there is absolute:
// BEYOND_TOL over 1000 turns.
#ifdef GF_SINGLE_PRECISION
#define BEYOND_TOL 6e-7
#else
#define BEYOND_TOL 1e-15
#endif

static void test_sincos_beyond(void **state)
{
    (void)state;
    worst w = {0, 0, 0, 0, 0};
    const int steps = 50000;
    const long double turns = 1000;
    for (int i = -steps; i <= steps; i++) {
        measure(&w, (gf_real)((long double)i * 6.28318530717958647692L * turns /
                              steps));
    }
    for (int k = -8; k <= 8; k++) { // the multiples of pi themselves
        around(&w, (gf_real)((long double)k * 3.14159265358979323846L), 8, 0);
    }
    print_message("  gf_sincos within %.0Lf turns: worst absolute %.3g "
                  "(at %.17g), %.3g ulp (at %.17g)\n",
                  turns, w.abs, w.at_abs, w.ulp, w.at_ulp);
    assert_true(w.abs <= BEYOND_TOL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sincos_error),
        cmocka_unit_test(test_sincos_beyond),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
