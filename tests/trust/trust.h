// SPDX-License-Identifier: MIT
// Shared by the trust tests (consistency, endurance): a deterministic
// random number generator with a Gaussian sampler, the chi-square and
// binomial quantiles the consistency bounds come from, and small
// double-precision linear algebra that does not use the library under test.
//
// Test code only: everything is double, whatever gf_real is.
#ifndef GF_TRUST_H
#define GF_TRUST_H

#include <math.h>
#include <stdint.h>

// ---- random numbers --------------------------------------------------------

// xoshiro256** (Blackman and Vigna), seeded through splitmix64, so one
// 64-bit seed gives the same stream on every machine.
typedef struct trust_rng {
    uint64_t s[4];
} trust_rng;

static inline uint64_t trust_rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static inline void trust_rng_seed(trust_rng *r, uint64_t seed)
{
    for (int i = 0; i < 4; i++) {
        uint64_t z = (seed += UINT64_C(0x9e3779b97f4a7c15));
        z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
        r->s[i] = z ^ (z >> 31);
    }
}

static inline uint64_t trust_rng_next(trust_rng *r)
{
    uint64_t *s = r->s;
    uint64_t out = trust_rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = trust_rotl(s[3], 45);
    return out;
}

// Uniform on the open interval (0, 1): 53 random bits, centred in their cell.
static inline double trust_uniform(trust_rng *r)
{
    return ((double)(trust_rng_next(r) >> 11) + 0.5) * 0x1.0p-53;
}

// Standard normal, Box-Muller (one of the pair is used: simple and
// stateless, speed does not matter here).
static inline double trust_normal(trust_rng *r)
{
    double u1 = trust_uniform(r), u2 = trust_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586476925 * u2);
}

// ---- chi-square and binomial quantiles ------------------------------------

// Regularized lower incomplete gamma P(a, x): the series for x < a + 1,
// Lentz's continued fraction for Q = 1 - P otherwise (Numerical Recipes
// 6.2). Relative accuracy about 1e-14 for the a and x used here.
static inline double trust_gamma_p(double a, double x)
{
    if (x <= 0.0) {
        return 0.0;
    }
    double lg = a * log(x) - x - lgamma(a);
    if (x < a + 1.0) {
        double ap = a, term = 1.0 / a, sum = term;
        for (int n = 0; n < 10000 && fabs(term) > fabs(sum) * 1e-16; n++) {
            ap += 1.0;
            term *= x / ap;
            sum += term;
        }
        return sum * exp(lg);
    }
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; i++) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < tiny) {
            d = tiny;
        }
        c = b + an / c;
        if (fabs(c) < tiny) {
            c = tiny;
        }
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1.0) < 1e-16) {
            break;
        }
    }
    return 1.0 - exp(lg) * h;
}

// Chi-square CDF with k degrees of freedom: P(k/2, x/2).
static inline double trust_chi2_cdf(double x, double k)
{
    return trust_gamma_p(0.5 * k, 0.5 * x);
}

// The chi-square quantile: the x with CDF(x; k) = p, by bisection to the
// last bit (the CDF is monotonic; 200 halvings of [0, k + 100 sqrt(2k) +
// 100] are more than enough), so its accuracy is that of trust_gamma_p.
static inline double trust_chi2_inv(double p, double k)
{
    double lo = 0.0, hi = k + 100.0 * sqrt(2.0 * k) + 100.0;
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (trust_chi2_cdf(mid, k) < p) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

// The smallest k with P(X <= k) >= q for X ~ Binomial(n, p), from the exact
// probability mass function (log space, so n in the thousands is fine).
static inline int trust_binom_quantile(int n, double p, double q)
{
    double cdf = 0.0;
    for (int k = 0; k <= n; k++) {
        double lpmf = lgamma(n + 1.0) - lgamma(k + 1.0) - lgamma(n - k + 1.0) +
                      k * log(p) + (n - k) * log1p(-p);
        cdf += exp(lpmf);
        if (cdf >= q) {
            return k;
        }
    }
    return n;
}

// ---- small double-precision linear algebra --------------------------------

// x^T S^-1 x for a symmetric n x n S (n = 1..3, row-major, stride 3), by
// Cholesky. Returns NAN when S is not positive definite.
static inline double trust_quad_form(double s[3][3], const double *x, int n)
{
    double l[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int j = 0; j < n; j++) {
        double d = s[j][j];
        for (int k = 0; k < j; k++) {
            d -= l[j][k] * l[j][k];
        }
        if (!(d > 0.0)) {
            return (double)NAN;
        }
        l[j][j] = sqrt(d);
        for (int i = j + 1; i < n; i++) {
            double v = s[i][j];
            for (int k = 0; k < j; k++) {
                v -= l[i][k] * l[j][k];
            }
            l[i][j] = v / l[j][j];
        }
    }
    // Solve l w = x; then x^T S^-1 x = w^T w.
    double w[3] = {0, 0, 0}, q = 0.0;
    for (int i = 0; i < n; i++) {
        double v = x[i];
        for (int k = 0; k < i; k++) {
            v -= l[i][k] * w[k];
        }
        w[i] = v / l[i][i];
        q += w[i] * w[i];
    }
    return q;
}

// The angle a wrapped to (-pi, pi], in double, independent of the library.
static inline double trust_wrap(double a)
{
    const double pi = 3.14159265358979323846;
    double w = fmod(a + pi, 2.0 * pi);
    if (w <= 0.0) {
        w += 2.0 * pi;
    }
    return w - pi;
}

#endif
