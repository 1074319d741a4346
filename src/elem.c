// SPDX-License-Identifier: MIT
// exp, log and atan2 without libm: the same bits on every IEEE-754 target.
//
// Only + - * / and comparisons, each rounded to nearest (no excess
// precision, nothing fused: gf_internal.h), so the result is a function of
// the argument's bits alone, not of the target's libm. The algorithms and
// the coefficients are fdlibm's (e_exp.c, e_log.c, s_atan.c, e_atan2.c) and,
// for the float build, FreeBSD's float versions of them (e_expf.c,
// e_logf.c, s_atanf.c), whose minimax polynomials are as short as float
// allows. Where fdlibm reads or writes an exponent field, powers of two are
// multiplied in instead, which is exact. docs/accuracy.md has the measured
// errors (tests/test_elem.c checks them).
#include "gaussfilt/mat.h"

#include "gf_internal.h"

#ifdef GF_SINGLE_PRECISION
#define MAGIC GF_R(12582912.0)            // 1.5 * 2^23
#define EXP_LN2_HI GF_R(6.9314575195e-01) // e_expf.c (16 bits)
#define EXP_LN2_LO GF_R(1.4286067653e-06) // ln 2 - EXP_LN2_HI
#define LN2_HI GF_R(6.9313812256e-01)     // e_logf.c (17 bits)
#define LN2_LO GF_R(9.0580006145e-06)     // ln 2 - LN2_HI
#define EXP_MAX GF_R(89.0)                // e^89 > FLT_MAX
#define EXP_MIN GF_R(-104.0)              // e^-104 < 2^-150
#define POW2_STEPS 7                      // 2^1 .. 2^64
#define POW2_TOP 64
#define REAL_MAX FLT_MAX
#define ATAN_BIG GF_R(67108864.0)     // 2^26: atan = pi/2 to float
#define PI_LO GF_R(-8.7422776573e-08) // pi - GF_PI (e_atan2f.c)
#else
#define MAGIC 6755399441055744.0          // 1.5 * 2^52
#define LN2_HI 6.93147180369123816490e-01 // e_exp.c, e_log.c (32 bits)
#define LN2_LO 1.90821492927058770002e-10 // ln 2 - LN2_HI
#define EXP_LN2_HI LN2_HI
#define EXP_LN2_LO LN2_LO
#define EXP_MAX 710.0    // e^710 > DBL_MAX
#define EXP_MIN (-746.0) // e^-746 < 2^-1075
#define POW2_STEPS 10    // 2^1 .. 2^512
#define POW2_TOP 512
#define REAL_MAX DBL_MAX
#define ATAN_BIG 7.3786976294838206464e+19 // 2^66
#define PI_LO 1.2246467991473531772e-16    // pi - GF_PI (e_atan2.c)
#endif
#define INV_LN2 GF_R(1.44269504088896338700)
#define SQRT2 GF_R(1.41421356237309504880)

// 2^n for |n| below 2^POW2_STEPS, by binary powering: every product is a
// power of two in range, so exact.
static gf_real pow2(int n)
{
    gf_real b = n < 0 ? GF_R(0.5) : GF_R(2.0), p = GF_R(1.0);
    unsigned m = n < 0 ? (unsigned)-n : (unsigned)n;
    while (m) {
        if (m & 1U) {
            p *= b;
        }
        m >>= 1;
        if (m) {
            b *= b;
        }
    }
    return p;
}

gf_real gf_exp(gf_real a)
{
    if (!(a > EXP_MIN)) {
        return a < EXP_MIN ? GF_R(0.0) : a + a; // NaN stays NaN
    }
    // beyond EXP_MAX, 2^k below overflows to inf, as it should
    const gf_real x = a > EXP_MAX ? EXP_MAX : a;
    // x = k ln 2 + r, |r| <= ln 2 / 2: k EXP_LN2_HI is exact (|k| < 2^11
    // in double, 2^8 in float), so hi - lo carries r to within a rounding.
    const gf_real k = (x * INV_LN2 + MAGIC) - MAGIC;
    const gf_real hi = x - k * EXP_LN2_HI, lo = k * EXP_LN2_LO;
    const gf_real r = hi - lo;
    // e^r = 1 + r + r c / (2 - c), c = r - r^2 P(r^2) (the Remez
    // polynomial of r (e^r + 1) / (e^r - 1) = 2 + r^2 / 6 + ...)
    const gf_real t = r * r;
    // Horner's scheme, a term per line
    // clang-format off
#ifdef GF_SINGLE_PRECISION
    const gf_real c = r - t * (GF_R(1.6666625440e-1) +
        t * GF_R(-2.7667332906e-3));
#else
    const gf_real c = r - t * (1.66666666666666019037e-01 +
        t * (-2.77777777770155933842e-03 +
        t * (6.61375632143793436117e-05 +
        t * (-1.65339022054652515390e-06 +
        t * 4.13813679705723846039e-08))));
#endif
    // clang-format on
    const gf_real y = GF_R(1.0) - ((lo - (r * c) / (GF_R(2.0) - c)) - hi);
    // y 2^k in two factors, each a power of two in range: the first
    // product is exact, the second rounds once (to a subnormal or inf when
    // the result is one).
    const int n = (int)k, n1 = n / 2;
    return (y * pow2(n1)) * pow2(n - n1);
}

gf_real gf_log(gf_real a)
{
    if (a < 0) {
        const gf_real zero = a - a;       // NaN for -inf
        return (GF_R(1.0) / zero) * zero; // inf times 0: NaN
    }
    if (!(a > 0)) {
        // -inf for +-0; a NaN stays NaN
        return a >= 0 ? GF_R(-1.0) / (a * a) : a + a;
    }
    if (a > REAL_MAX) {
        return a; // +inf
    }
    // x = 2^k m, m in [1, 2), by dividing or multiplying by 2^(2^i) from
    // the largest down (exact); a subnormal x is first brought up by the
    // largest. p[i] = 2^(2^i).
    gf_real p[POW2_STEPS];
    p[0] = GF_R(2.0);
    for (int i = 1; i < POW2_STEPS; i++) {
        p[i] = p[i - 1] * p[i - 1];
    }
    gf_real x = a;
    int k = 0, e = POW2_TOP; // p[i] = 2^e
    if (x < GF_REAL_MIN) {
        x *= p[POW2_STEPS - 1];
        k = -POW2_TOP;
    }
    for (int i = POW2_STEPS - 1; i >= 0; i--) {
        if (x >= p[i]) {
            x /= p[i]; // then x p[i] >= 2: the next test fails
            k += e;
        }
        if (x * p[i] < GF_R(2.0)) {
            x *= p[i];
            k -= e;
        }
        e /= 2;
    }
    // m in [sqrt(2)/2, sqrt(2)): f = m - 1 is exact
    if (x > SQRT2) {
        x *= GF_R(0.5);
        k++;
    }
    const gf_real f = x - GF_R(1.0);
    // log(1 + f) = f - f^2 / 2 + s (f^2 / 2 + R(s^2)), s = f / (2 + f),
    // R the Remez polynomial of log((1 + s) / (1 - s)) = 2 s + s^3 R / ...
    const gf_real s = f / (GF_R(2.0) + f);
    const gf_real z = s * s, w = z * z;
    // clang-format off
#ifdef GF_SINGLE_PRECISION
    const gf_real t1 = w * (GF_R(4.0000972152e-01) +
        w * GF_R(2.4279078841e-01));
    const gf_real t2 = z * (GF_R(6.6666662693e-01) +
        w * GF_R(2.8498786688e-01));
#else
    const gf_real t1 = w * (3.999999999940941908e-01 +
        w * (2.222219843214978396e-01 +
        w * 1.531383769920937332e-01));
    const gf_real t2 = z * (6.666666666666735130e-01 +
        w * (2.857142874366239149e-01 +
        w * (1.818357216161805012e-01 +
        w * 1.479819860511658591e-01)));
#endif
    // clang-format on
    const gf_real hfsq = GF_R(0.5) * f * f, dk = (gf_real)k;
    // log x = k ln 2 + log(1 + f), ln 2 in two parts
    return dk * LN2_HI - ((hfsq - (s * (hfsq + (t2 + t1)) + dk * LN2_LO)) - f);
}

// atan(t), t >= 0 and not NaN: atan(t) = atan(c) + atan((t - c) / (1 + t c))
// for c in {0, 1/2, 1, 3/2, inf} as t lies below 7/16, 11/16, 19/16, 39/16
// or above; atan(c) in two parts, then the odd Remez polynomial.
static gf_real atan_pos(gf_real a)
{
    gf_real hi = 0, lo = 0, t = a;
    if (t >= ATAN_BIG) {
        return GF_R(0.5) * GF_PI + GF_R(0.5) * PI_LO;
    }
    int reduced = 1;
    // clang-format off
#ifdef GF_SINGLE_PRECISION
    if (t < GF_R(0.4375)) {
        reduced = 0;
    } else if (t < GF_R(0.6875)) {
        hi = GF_R(4.6364760399e-01); lo = GF_R(5.0121582440e-09);
        t = (GF_R(2.0) * t - GF_R(1.0)) / (GF_R(2.0) + t);
    } else if (t < GF_R(1.1875)) {
        hi = GF_R(7.8539812565e-01); lo = GF_R(3.7748947079e-08);
        t = (t - GF_R(1.0)) / (t + GF_R(1.0));
    } else if (t < GF_R(2.4375)) {
        hi = GF_R(9.8279368877e-01); lo = GF_R(3.4473217170e-08);
        t = (t - GF_R(1.5)) / (GF_R(1.0) + GF_R(1.5) * t);
    } else {
        hi = GF_R(1.5707962513e+00); lo = GF_R(7.5497894159e-08);
        t = GF_R(-1.0) / t;
    }
    const gf_real z = t * t, w = z * z;
    const gf_real s1 = z * (GF_R(3.3333328366e-01) +
        w * (GF_R(1.4253635705e-01) +
        w * GF_R(6.1687607318e-02)));
    const gf_real s2 = w * (GF_R(-1.9999158382e-01) +
        w * GF_R(-1.0648017377e-01));
#else
    if (t < 0.4375) {
        reduced = 0;
    } else if (t < 0.6875) {
        hi = 4.63647609000806093515e-01; lo = 2.26987774529616870924e-17;
        t = (2.0 * t - 1.0) / (2.0 + t);
    } else if (t < 1.1875) {
        hi = 7.85398163397448278999e-01; lo = 3.06161699786838301793e-17;
        t = (t - 1.0) / (t + 1.0);
    } else if (t < 2.4375) {
        hi = 9.82793723247329054082e-01; lo = 1.39033110312309984516e-17;
        t = (t - 1.5) / (1.0 + 1.5 * t);
    } else {
        hi = 1.57079632679489655800e+00; lo = 6.12323399573676603587e-17;
        t = -1.0 / t;
    }
    const gf_real z = t * t, w = z * z;
    const gf_real s1 = z * (3.33333333333329318027e-01 +
        w * (1.42857142725034663711e-01 +
        w * (9.09088713343650656196e-02 +
        w * (6.66107313738753120669e-02 +
        w * (4.97687799461593236017e-02 +
        w * 1.62858201153657823623e-02)))));
    const gf_real s2 = w * (-1.99999999998764832476e-01 +
        w * (-1.11111104054623557880e-01 +
        w * (-7.69187620504482999495e-02 +
        w * (-5.83357013379057348645e-02 +
        w * -3.65315727442169155270e-02))));
#endif
    // clang-format on
    if (!reduced) {
        return t - t * (s1 + s2);
    }
    return hi - ((t * (s1 + s2) - lo) - t);
}

// True for x < 0 and for -0 (1 / -0 = -inf), x not NaN.
static int negative(gf_real x)
{
    return x < 0 || (!(x > 0) && GF_R(1.0) / x < 0);
}

// True for a NaN: neither finite nor infinite.
static int is_nan(gf_real x)
{
    return !GF_ISFINITE(x) && !(GF_FABS(x) > REAL_MAX);
}

gf_real gf_atan2(gf_real y, gf_real x)
{
    if (is_nan(x) || is_nan(y)) {
        return x + y; // NaN stays NaN
    }
    const int ny = negative(y), nx = negative(x);
    const gf_real ay = ny ? -y : y, ax = nx ? -x : x;
    gf_real z;
    if (!(ay > 0) || (ax > REAL_MAX && !(ay > REAL_MAX))) {
        z = 0; // on the x axis: +-0 or +-pi, as C99 Annex F says
    } else if (ax > REAL_MAX) {
        z = GF_R(0.25) * GF_PI + GF_R(0.25) * PI_LO; // both infinite
    } else if (!(ax > 0) || ay > REAL_MAX) {
        z = GF_R(0.5) * GF_PI + GF_R(0.5) * PI_LO; // on the y axis
        return ny ? -z : z;
    } else {
        z = atan_pos(ay / ax);
    }
    // pi - z in two parts: (pi - GF_PI) + (GF_PI - z)
    if (nx) {
        z = GF_PI - (z - PI_LO);
    }
    return ny ? -z : z;
}
