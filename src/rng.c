// SPDX-License-Identifier: MIT
#include "gaussfilt/rng.h"

#include "gf_internal.h"

static uint32_t rotl(uint32_t x, unsigned k)
{
    return (x << k) | (x >> (32u - k));
}

// A 32-bit integer hash with full avalanche ("lowbias32", C. Wellons), used
// only to spread the seed over the state.
static uint32_t mix32(uint32_t seed)
{
    uint32_t x = seed;
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

gf_status gf_rng_seed(gf_rng *rng, uint32_t seed)
{
    if (!rng) {
        return GF_ERR_ARG;
    }
    // Weyl sequence through the hash: four distinct, well-mixed words.
    uint32_t w = seed;
    uint32_t any = 0;
    for (unsigned i = 0; i < 4; i++) {
        w += 0x9e3779b9u;
        rng->s[i] = mix32(w);
        any |= rng->s[i];
    }
    if (any == 0) { // xoshiro's one forbidden state
        rng->s[0] = 1;
    }
    rng->spare = 0;
    rng->has_spare = 0;
    return GF_OK;
}

uint32_t gf_rng_u32(gf_rng *rng)
{
    if (!rng) {
        return 0;
    }
    uint32_t *s = rng->s;
    const uint32_t out = rotl(s[1] * 5u, 7) * 9u;
    const uint32_t t = s[1] << 9;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 11);
    return out;
}

gf_real gf_rng_uniform(gf_rng *rng)
{
    if (!rng) {
        return 0;
    }
#ifdef GF_SINGLE_PRECISION
    // top 24 bits times 2^-24
    return (gf_real)(gf_rng_u32(rng) >> 8) * GF_R(5.9604644775390625e-8);
#else
    // 32 bits times 2^-32
    return (gf_real)gf_rng_u32(rng) * GF_R(2.3283064365386962890625e-10);
#endif
}

gf_real gf_rng_normal(gf_rng *rng)
{
    if (!rng) {
        return 0;
    }
    if (rng->has_spare) {
        rng->has_spare = 0;
        return rng->spare;
    }
    // Box-Muller: r = sqrt(-2 ln u1), u1 in (0, 1]; a uniform angle, here
    // 2 pi u2 - pi in [-pi, pi) (the range gf_sincos keeps).
    const gf_real u1 = GF_R(1.0) - gf_rng_uniform(rng);
    const gf_real u2 = gf_rng_uniform(rng);
    const gf_real r = GF_SQRT(GF_R(-2.0) * gf_log(u1));
    const gf_real a = GF_R(2.0) * GF_PI * u2 - GF_PI;
    gf_real s, c;
    gf_sincos(a, &s, &c);
    rng->spare = r * s;
    rng->has_spare = 1;
    return r * c;
}

void gf_rng_mvn3(gf_rng *rng, const gf_vec3 *mu, const gf_mat3 *l, gf_vec3 *x)
{
    if (!rng || !mu || !l || !x) {
        return;
    }
    // x = mu + L n, n ~ N(0, I); row i of L n as gf_mat3_mulv sums it,
    // with no second temporary (x may be mu).
    gf_vec3 n;
    for (unsigned i = 0; i < 3; i++) {
        n.v[i] = gf_rng_normal(rng);
    }
    for (unsigned i = 0; i < 3; i++) {
        x->v[i] = mu->v[i] + (l->m[i][0] * n.v[0] + l->m[i][1] * n.v[1] +
                              l->m[i][2] * n.v[2]);
    }
}
