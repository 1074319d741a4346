// SPDX-License-Identifier: MIT
// gaussfilt: PF3, a particle filter (Tables 4.3 and 4.4 of Probabilistic
// Robotics) on EKF3's state x = (x, y, theta) with EKF3's callbacks: a
// particle moves by g(u, x) plus a draw of N(0, R), and is weighted by the
// Gaussian likelihood N(z; h(x), Q). It can hold what no Gaussian can: the
// two modes of exercise 4.
//
// The caller owns the particle array and chooses its size at compile time
// (static gf_pf3_particle p[512]); nothing is allocated, and resampling
// works in place, without a second array. The random stream is the
// filter's own gf_rng, seeded by the caller: same seed, same run.
//
// A failing call leaves the belief (the struct, its generator and every
// particle) bit-for-bit as it was. To keep that promise without scratch
// memory, predict and update make a dry run over all particles first and
// commit in a second pass: the callbacks run twice per particle and must
// be pure functions of their inputs (the built-ins are).
#ifndef GAUSSFILT_PF3_H
#define GAUSSFILT_PF3_H

#include "gaussfilt/ekf3.h"
#include "gaussfilt/rng.h"

#ifdef __cplusplus
extern "C" {
#endif

// Largest particle count: resampling counts copies in the weight field,
// exact up to 2^24 in float.
#define GF_PF3_MAX_N 16777216u

typedef struct gf_pf3_particle {
    gf_vec3 x; // (x, y, theta), theta in (-pi, pi]
    gf_real w; // importance weight; the weights sum to 1
} gf_pf3_particle;

typedef struct gf_pf3 {
    gf_pf3_particle *p; // caller-owned array of n particles
    unsigned n;
    gf_rng rng; // the filter's random stream
} gf_pf3;

// Takes the caller's array of n particles (1..GF_PF3_MAX_N), seeds the
// generator with seed and draws the n particles from N(mu, sigma) (sigma
// symmetric PSD; zero gives n copies of mu), weights 1/n.
// GF_ERR_ARG (NULL, n out of range), GF_ERR_NONFINITE, GF_ERR_NOT_PSD;
// neither pf nor the array is touched on failure.
gf_status gf_pf3_init(gf_pf3 *pf, gf_pf3_particle *particles, unsigned n,
                      uint32_t seed, const gf_vec3 *mu, const gf_mat3 *sigma);

// Prediction, sampling the motion model (Table 4.3, line 4):
//   x_t^[k] = g(u, x_{t-1}^[k]) + eps^[k],  eps^[k] ~ N(0, R),
// heading wrapped; the weights are kept. G is ignored.
// GF_ERR_ARG (NULL), GF_ERR_NOT_PSD (R), GF_ERR_NONFINITE, or the
// callback's own error; the belief is untouched on failure. u must not
// point into the particle array: it is read again for every particle
// while the particles are rewritten (its length is the callback's).
gf_status gf_pf3_predict(gf_pf3 *pf, const gf_ekf3_motion *motion,
                         const gf_real *u);

// Correction by importance weights (Table 4.3, line 5), then normalised:
//   w^[k] <- w^[k] exp(-1/2 r_k^T Q^-1 r_k),  r_k = z - h(x^[k]),
// the flagged residuals of meas->angle_mask wrapped. Computed in the log
// domain, scaled by the best particle, so no measurement underflows every
// weight to zero. H is ignored. meas->gate > 0 rejects z (GF_ERR_GATED,
// nothing changed) when even the closest particle has r^T Q^-1 r above
// it. GF_ERR_ARG, GF_ERR_NONFINITE, GF_ERR_NOT_PSD (Q), GF_ERR_SINGULAR
// (Q not positive definite: a noiseless measurement weighs nothing), or
// the callback's own error; the belief is untouched on failure.
gf_status gf_pf3_update(gf_pf3 *pf, const gf_ekf3_meas *meas, const gf_vec3 *z);

// Low-variance resampling (Table 4.4): one uniform draw r in [0, W/n),
// particle i is copied once for each of the n points r + k W/n (W the
// total weight) that falls in its slice of the cumulative weight. In
// place: the copy counts replace the weights, then over-represented
// particles overwrite the ones that drew none. Weights become 1/n.
// GF_ERR_ARG on NULL, GF_ERR_NONFINITE or GF_ERR_UNDEFINED (a negative
// weight or a total that is not positive); untouched then.
gf_status gf_pf3_resample(gf_pf3 *pf);

// Effective sample size 1 / sum_k (w^[k] / W)^2, from 1 (one particle holds
// all the weight) to n (uniform weights). GF_ERR_ARG on NULL,
// GF_ERR_UNDEFINED if the total weight is not positive.
gf_status gf_pf3_neff(const gf_pf3 *pf, gf_real *neff);

// Weighted mean and covariance of the particles, the heading averaged on
// the circle (atan2 of the weighted sines and cosines) and its residuals
// wrapped. Either output may be NULL. A multimodal belief has a mean where
// no particle is: this is a summary, not the belief. GF_ERR_ARG on NULL,
// GF_ERR_UNDEFINED if the total weight is not positive or the headings
// cancel out (no mean direction).
gf_status gf_pf3_estimate(const gf_pf3 *pf, gf_vec3 *mu, gf_mat3 *sigma);

#ifdef __cplusplus
}
#endif

#endif
