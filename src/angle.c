// SPDX-License-Identifier: MIT
// Angles without libm: wrapping to (-pi, pi] and sin/cos by polynomials.
//
// Nearest-integer rounding uses the "magic number" trick: for |q| below
// 2^(p-2), (q + 1.5 * 2^(p-1)) - 1.5 * 2^(p-1) is q rounded to the nearest
// integer in IEEE arithmetic with p-bit significands (round to nearest, no
// excess precision: C99 FLT_EVAL_METHOD 0, as on Arm, RISC-V and x86-64).
// Multiples of 2 pi (in two parts) and pi / 2 (in three) are subtracted
// Cody-Waite style: the high part has few significant bits, so k * hi is
// exact for the small k that occur here.
#include "gaussfilt/mat.h"

#include "gf_internal.h"

#ifdef GF_SINGLE_PRECISION
#define MAGIC GF_R(12582912.0)    // 1.5 * 2^23
#define TURNS_MAX GF_R(4194304.0) // 2^22
#define TWO_PI_HI GF_R(6.28125)   // 201 / 32
#define TWO_PI_LO GF_R(1.9353071795864769e-3)
#define PIO2_HI GF_R(1.5703125) // 201 / 128
#define PIO2_LO GF_R(4.83826792333275079727e-4)
#define PIO2_LO2 GF_R(2.56334415159451890170e-12)
#else
#define MAGIC 6755399441055744.0             // 1.5 * 2^52
#define TURNS_MAX 2251799813685248.0         // 2^51
#define TWO_PI_HI 6.28318530693650245668e+00 // 4 * fdlibm's pio2_1
#define TWO_PI_LO 2.43084020260247689973e-10
#define PIO2_HI 1.57079632673412561417e+00 // fdlibm's pio2_1 (33 bits)
#define PIO2_LO 6.07710050650619224932e-11 // fdlibm's pio2_1t
#define PIO2_LO2 3.52155986518320018165e-27
#endif
#define INV_TWO_PI GF_R(0.15915494309189533577)
#define TWO_OVER_PI GF_R(0.63661977236758134308)

static gf_real round_nearest(gf_real q)
{
    return (q + MAGIC) - MAGIC;
}

gf_real gf_angle_wrap(gf_real a)
{
    if (a > -GF_PI && a <= GF_PI) {
        return a;
    }
    gf_real q = a * INV_TWO_PI;
    if (!(GF_FABS(q) < TURNS_MAX)) {
        return GF_ISFINITE(a) ? GF_R(0.0) : a - a; // NaN for NaN and inf
    }
    // a - 2 pi round(a / 2 pi) lies in [-pi, pi] up to rounding; the two
    // tests below settle the ends.
    gf_real k = round_nearest(q);
    gf_real w = (a - k * TWO_PI_HI) - k * TWO_PI_LO;
    if (w > GF_PI) {
        w -= GF_R(2.0) * GF_PI;
    }
    if (w <= -GF_PI) {
        w += GF_R(2.0) * GF_PI;
    }
    return w;
}

// sin and cos on [-pi/4, pi/4]: fdlibm's minimax coefficients
// (k_sin.c, k_cos.c); the float build keeps the terms its precision needs
// (truncation below 2e-9 there).
static gf_real sin_kernel(gf_real x)
{
    const gf_real z = x * x;
    // Horner's scheme, a term per line
    // clang-format off
#ifdef GF_SINGLE_PRECISION
    const gf_real p = GF_R(-1.66666666666666324348e-01) +
        z * (GF_R(8.33333333332248946124e-03) +
        z * (GF_R(-1.98412698298579493134e-04) +
        z * GF_R(2.75573137070700676789e-06)));
#else
    const gf_real p = -1.66666666666666324348e-01 +
        z * (8.33333333332248946124e-03 +
        z * (-1.98412698298579493134e-04 +
        z * (2.75573137070700676789e-06 +
        z * (-2.50507602534068634195e-08 +
        z * 1.58969099521155010221e-10))));
#endif
    // clang-format on
    return x + x * z * p;
}

static gf_real cos_kernel(gf_real x)
{
    const gf_real z = x * x;
    // Horner's scheme, a term per line
    // clang-format off
#ifdef GF_SINGLE_PRECISION
    const gf_real p = GF_R(4.16666666666666019037e-02) +
        z * (GF_R(-1.38888888888741095749e-03) +
        z * GF_R(2.48015872894767294178e-05));
#else
    const gf_real p = 4.16666666666666019037e-02 +
        z * (-1.38888888888741095749e-03 +
        z * (2.48015872894767294178e-05 +
        z * (-2.75573143513906633035e-07 +
        z * (2.08757232129817482790e-09 +
        z * -1.13596475577881948265e-11))));
#endif
    // clang-format on
    return GF_R(1.0) - GF_R(0.5) * z + z * z * p;
}

void gf_sincos(gf_real a, gf_real *s, gf_real *c)
{
    if (!s || !c) {
        return;
    }
    // a = k pi/2 + r, |r| <= pi/4, k in -2..2 once a is wrapped.
    const gf_real w = gf_angle_wrap(a);
    const gf_real k = round_nearest(w * TWO_OVER_PI);
    // pi/2 in three parts: near a multiple of pi/2, where r is far
    // smaller than pi/2, the first two subtractions are exact (Sterbenz)
    // and the third's error is relative to r, so sin(pi - 1 ulp) comes out
    // right to the last bit, not to 2.4e-16 absolute as with two parts.
    const gf_real r = ((w - k * PIO2_HI) - k * PIO2_LO) - k * PIO2_LO2;
    const gf_real sr = sin_kernel(r), cr = cos_kernel(r);
    // (int)k is exact: k is a small whole number (or NaN, handled below).
    const int quadrant = GF_ISFINITE(k) ? ((int)k & 3) : 0;
    switch (quadrant) {
    case 0:
        *s = sr;
        *c = cr;
        break;
    case 1:
        *s = cr;
        *c = -sr;
        break;
    case 2:
        *s = -sr;
        *c = -cr;
        break;
    default:
        *s = -cr;
        *c = sr;
        break;
    }
}
