// SPDX-License-Identifier: MIT
// gaussfilt: a small deterministic random number generator the caller owns
// and seeds, for the particle filter and for tests that sample.
//
// xoshiro128** (Blackman and Vigna, 2018): 128 bits of state, 32-bit
// operations only (cheap on Cortex-M0 and RV32 alike), period 2^128 - 1.
// No globals: two generators seeded alike give the same stream, anywhere.
// Gaussian draws use Box-Muller on <math.h>, never libc rand().
#ifndef GAUSSFILT_RNG_H
#define GAUSSFILT_RNG_H

#include <stdint.h>

#include "gaussfilt/mat.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gf_rng {
    uint32_t s[4]; // xoshiro128** state, never all zero
    gf_real spare; // second Box-Muller variate, valid if has_spare
    int has_spare;
} gf_rng;

// Seeds the generator. Every seed (0 included) gives a valid, distinct
// stream: the state is expanded from the seed by a 32-bit mixing hash.
// GF_ERR_ARG on NULL.
gf_status gf_rng_seed(gf_rng *rng, uint32_t seed);

// The next 32 random bits. 0 for a NULL rng.
uint32_t gf_rng_u32(gf_rng *rng);

// Uniform in [0, 1). 24 random bits in the float build, 32 in the double
// build; every value is exactly representable, so 1 is never returned.
// 0 for a NULL rng.
gf_real gf_rng_uniform(gf_rng *rng);

// Standard normal N(0, 1), by Box-Muller: two uniforms give two normals,
// the second is kept for the next call. 0 for a NULL rng.
gf_real gf_rng_normal(gf_rng *rng);

// x ~ N(mu, l l^T): x = mu + l n with n ~ N(0, I_3), l a square root as
// from gf_mat3_sqrt_psd (lower triangular; other shapes work too). Does
// nothing (no draw, x untouched) if any pointer is NULL.
void gf_rng_mvn3(gf_rng *rng, const gf_vec3 *mu, const gf_mat3 *l, gf_vec3 *x);

#ifdef __cplusplus
}
#endif

#endif
