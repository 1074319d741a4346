// SPDX-License-Identifier: MIT
// gaussfilt: UKF3, the unscented Kalman filter (Table 3.4 of Probabilistic
// Robotics) on EKF3's state x = (x, y, theta), with EKF3's motion and
// measurement callbacks (their Jacobian outputs are ignored: the UKF
// needs none). Instead of linearizing g at the mean, it pushes 2n + 1 = 7
// sigma points through g and h and takes their weighted moments, so the
// predicted mean sees the curvature of g: on exercise 4 it lies inside the
// unit circle, where the EKF's stays at (1, 0).
//
// The heading is an angle: sigma-point means of it are taken as wrapped
// residuals about the first sigma point, and every heading residual (and
// every measurement residual flagged in meas->angle_mask) is wrapped to
// (-pi, pi]. Nothing is allocated; the caller owns the struct.
#ifndef GAUSSFILT_UKF3_H
#define GAUSSFILT_UKF3_H

#include "gaussfilt/ekf3.h"

#ifdef __cplusplus
extern "C" {
#endif

// The scaling parameters of Table 3.4 (Julier and Uhlmann; van der Merwe):
// lambda = alpha^2 (n + kappa) - n, sigma points at mu +- sqrt(n + lambda)
// times the columns of a square root of Sigma. alpha in
// [GF_UKF3_ALPHA_MIN, 1] spreads them, beta folds in prior knowledge of the
// distribution (2 is optimal for a Gaussian), kappa >= 0 is a secondary
// spread (3 - n = 0 here).
// alpha = 1, beta = 2, kappa = 0 puts the points at sqrt(3) sigma.
//
// GF_UKF3_ALPHA_MIN, the smallest alpha gf_ukf3_init takes (2^-5 in
// float, 2^-20 in double; GF_ERR_ARG below): a small alpha weighs the
// points' differences by 1 / alpha^2, and with them the rounding of g's
// and h's outputs. Above it, predict and update refuse with
// GF_ERR_UNDEFINED a step whose rounding could move the moments by a
// quarter of a sigma. docs/ukf3.md has the error analysis and the figures.
#ifdef GF_SINGLE_PRECISION
#define GF_UKF3_ALPHA_MIN GF_R(0.03125)
#else
#define GF_UKF3_ALPHA_MIN GF_R(9.5367431640625e-7)
#endif

typedef struct gf_ukf3_params {
    gf_real alpha;
    gf_real beta;
    gf_real kappa;
} gf_ukf3_params;

// The belief N(mu, sigma) and the sigma-point weights derived from the
// parameters by gf_ukf3_init. The centre's own weights (w_m,0 = lambda /
// (n + lambda), w_c,0 = w_m,0 + 1 - alpha^2 + beta, about -1/alpha^2 for a
// small alpha) are folded into the sums (see gf_ukf3_predict) and not kept.
typedef struct gf_ukf3 {
    gf_vec3 mu;
    gf_mat3 sigma;
    gf_real gamma; // sqrt(n + lambda)
    gf_real
        wi; // weight of the 2n points about the centre, 1 / (2 (n + lambda))
    gf_real wfold; // beta - alpha^2, what the centre's weights leave in Sigma
} gf_ukf3;

// Sets the belief to N(mu, sigma) (heading wrapped, sigma symmetric PSD,
// zero allowed) and the weights from p. GF_ERR_ARG on NULL, or on
// parameters out of range (alpha not in [GF_UKF3_ALPHA_MIN, 1], beta < 0,
// kappa < 0);
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD; ukf is untouched on failure.
gf_status gf_ukf3_init(gf_ukf3 *ukf, const gf_vec3 *mu, const gf_mat3 *sigma,
                       const gf_ukf3_params *p);

// Prediction (Table 3.4, lines 2-5):
//   chi = (mu, mu + gamma sqrt(Sigma)_i, mu - gamma sqrt(Sigma)_i),
//   chi_bar*_i = g(u, chi_i),  mu_bar = sum_i w_m,i chi_bar*_i,
//   Sigma_bar = sum_i w_c,i (chi_bar*_i - mu_bar)(chi_bar*_i - mu_bar)^T + R,
// evaluated about the centre's image, e_i = chi_bar*_i - chi_bar*_0, as
//   m = sum_{i>0} w_i e_i,  mu_bar = chi_bar*_0 + m,
//   Sigma_bar = sum_{i>0} w_i e_i e_i^T + (beta - alpha^2) m m^T + R
// (the same sums, the centre's weights folded in), so that no weight of
// -1/alpha^2 multiplies the rounding of the points.
// The callback is called 7 times; its G output is discarded.
// GF_ERR_ARG (NULL), GF_ERR_NOT_PSD (R, or a Sigma_bar that a negative
// beta - alpha^2 made indefinite), GF_ERR_NONFINITE, GF_ERR_UNDEFINED
// (the points too close for the precision: the images' rounding, summed
// with weight w_i, could move an entry of mu_bar by more than a quarter of
// its predicted sigma; a larger alpha resolves them), or the callback's
// own error; the belief is untouched on failure.
gf_status gf_ukf3_predict(gf_ukf3 *ukf, const gf_ekf3_motion *motion,
                          const gf_real *u);

// Correction (Table 3.4, lines 6-13):
//   chi_bar = (mu_bar, mu_bar +- gamma sqrt(Sigma_bar)_i),
//   Z_i = h(chi_bar_i),  z_hat = sum_i w_m,i Z_i,
//   S = sum_i w_c,i (Z_i - z_hat)(Z_i - z_hat)^T + Q,
//   Sigma^xz = sum_i w_c,i (chi_bar_i - mu_bar)(Z_i - z_hat)^T,
// the sums folded about Z_0 as in gf_ukf3_predict (dz_i = Z_i - Z_0,
// m_z = sum_{i>0} w_i dz_i, z_hat = Z_0 + m_z, S = sum_{i>0} w_i dz_i
// dz_i^T + (beta - alpha^2) m_z m_z^T + Q, Sigma^xz = sum_{i>0} w_i
// (chi_bar_i - mu_bar) dz_i^T),
//   K = Sigma^xz S^-1,  mu = mu_bar + K (z - z_hat),
//   Sigma = Sigma_bar - K S K^T,
// with S = L L^T: K S K^T = W^T W, W = L^-1 (Sigma^xz)^T (symmetric as
// computed), K (z - z_hat) = W^T L^-1 (z - z_hat), and the NIS is
// |L^-1 (z - z_hat)|^2.
// The callback is called 7 times, once per sigma point, the centre first;
// its H output is discarded. Status, gate and info rules as gf_ekf3_update
// (angle_mask wraps the flagged entries of z_hat's mean and of every
// residual); GF_ERR_NOT_PSD also when the posterior Sigma comes out
// indefinite, GF_ERR_UNDEFINED as in gf_ukf3_predict for z_hat against
// sqrt(S_kk).
gf_status gf_ukf3_update(gf_ukf3 *ukf, const gf_ekf3_meas *meas,
                         const gf_vec3 *z, gf_innovation *info);

#ifdef __cplusplus
}
#endif

#endif
