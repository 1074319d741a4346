// SPDX-License-Identifier: MIT
// The examples' simulated truth: a splitmix64 generator and Box-Muller
// normals in double, the same numbers whichever gf_real the filter is
// built for (so a float and a double build see the same truth). Example
// code, not the library's (the library's generator is gaussfilt/rng.h,
// in gf_real).
#ifndef GF_EXAMPLES_SIM_RNG_H
#define GF_EXAMPLES_SIM_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct sim_rng {
    uint64_t state;
} sim_rng;

// Uniform in [0, 1), 53 bits.
static inline double sim_unif(sim_rng *r)
{
    uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

// Standard normal (Box-Muller).
static inline double sim_normal(sim_rng *r)
{
    double u1 = 1.0 - sim_unif(r), u2 = sim_unif(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif
