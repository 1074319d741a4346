// SPDX-License-Identifier: MIT
// gaussfilt: the factored covariance of the Kalman filters, one
// implementation for any number of states n (defined in udu.c;
// docs/numerics.md has the derivations).
//
// A belief carries Sigma = P U D U^T P^T: U unit upper triangular, D
// diagonal and >= 0, P a permutation of the states (perm[k] is the state
// of the factors' index k). Every step works on the factors and never
// forms Sigma:
//   init        gf_udu_factor: the factors of a checked covariance;
//   prediction  gf_udu_predict: Sigma_bar = (A P U) D (A P U)^T + R,
//               triangularised again by Thornton's modified weighted
//               Gram-Schmidt, each d_j a weighted sum of squares;
//   correction  gf_udu_correct: Bierman's scalar update, one whitened
//               measured quantity at a time, each d_j scaled by a ratio
//               of innovation variances in [0, 1];
//   accessor    gf_udu_to_cov: Sigma, exactly symmetric.
//
// Packed storage, n (n + 1) / 2 numbers, column by column: U_ij (i < j) at
// GF_UD(i, j), d_j at GF_UD(j, j). Matrices passed in are row-major and
// indexed by state. Scratch is the caller's, its size given below.
#ifndef GAUSSFILT_SRC_UDU_H
#define GAUSSFILT_SRC_UDU_H

#include "gf_internal.h"

#define GF_UD(i, j) ((j) * ((j) + 1u) / 2u + (i))
#define GF_UD_SIZE(n) ((n) * ((n) + 1u) / 2u)

// The scratch (gf_real entries) of gf_udu_factor, gf_udu_predict and
// gf_udu_correct for n states.
#define GF_UDU_FACTOR_WORK(n) GF_UD_SIZE(n)
#define GF_UDU_PREDICT_WORK(n) (2u * (n) * (n) + 4u * (n))
#define GF_UDU_CORRECT_WORK(n) ((n) * (n) + 4u * (n))

// The factors of a covariance s (rows of stride) that gf_cov_factor
// accepted, for a new belief: perm is the states reversed (state 0, most
// often the measured position, at the root), then column j from the last,
// with t_k = d_k U_jk:
//   d_j  = s_jj - sum_(k>j) U_jk t_k,
//   U_ij = (s_ij - sum_(k>j) U_ik t_k) / d_j,
// each sum and quotient in about twice gf_real's precision, each factor
// rounded once. A pivot below GF_REAL_MIN is zero, with a zero column of
// U. (Here and in every step a NaN is kept, never taken for a number below
// GF_REAL_MIN: the filters' test of the result refuses it.) perm's entries n.. up to sizeof(gf_real) are set to 0. work: scratch
// of GF_UDU_FACTOR_WORK(n).
void gf_udu_factor(const gf_real *s, unsigned stride, unsigned n, gf_real *ud,
                   unsigned char *perm, gf_real *work);

// Sigma = P U D U^T P^T into s (rows of stride), exactly symmetric:
//   Sigma_(perm i)(perm j) = sum_(k >= max(i, j)) U_ik d_k U_jk,  U_kk = 1.
// A variance below GF_REAL_MIN is zero, with its row and column.
void gf_udu_to_cov(const gf_real *ud, const unsigned char *perm, unsigned n,
                   gf_real *s, unsigned stride);

// 1 if mu (n entries), the factors ud and every variance they give are
// finite.
int gf_belief_finite(const gf_real *mu, const gf_real *ud, unsigned n);

// The prediction's covariance (Thornton's time update) into ud_new (ud
// itself, or another array):
//   Sigma_bar = W diag(w_d) W^T,  W = [P^T A P U | P^T F_R],  w_d = [D | d_R],
// with R = F_R diag(d_R) F_R^T given by its factors (gf_cov_factor: Rf n x
// n, rows of n), A n x n (rows of n), then triangularised (modified
// weighted Gram-Schmidt). work: scratch of GF_UDU_PREDICT_WORK(n). A, Rf
// and Rd are read only while W is formed, before anything is written to
// ud_new or to work's last 2n entries: they may lie there.
void gf_udu_predict(unsigned n, const gf_real *ud, gf_real *ud_new,
                    const unsigned char *perm, const gf_real *A,
                    const gf_real *Rf, const gf_real *Rd, gf_real *work);

// x <- F^-1 x for m measured quantities whose noise is Q = F diag(e) F^T
// (gf_cov_factor: F m x m, rows of m, unit lower triangular in its pivots'
// order), x m rows of `cols` (a quantity's row, then the next), by
// substitution in that order (no division):
//   x_i <- x_i - sum_(k before i) F_ik x_k.
// The rows F^-1 x then have independent noises e.
void gf_udu_whiten(const gf_real *F, const unsigned *order, unsigned m,
                   gf_real *x, unsigned cols);

// Swaps the factors' indices k and k + 1: the same Sigma, with the state
// perm[k + 1] at index k and perm[k] at k + 1 (a correction moves the
// state a quantity measures most to the root, the last index, this way).
// With a = U_k(k+1),
//   d'_(k+1) = d_k + a^2 d_(k+1),  r = d_(k+1) / d'_(k+1),
//   U'_k(k+1) = a r,  d'_k = d_k r,
//   U'_ik = U_i(k+1) - a U_ik,  U'_i(k+1) = (d_k / d'_(k+1)) U_ik + a r U_i(k+1)
// (i < k), and the rows k, k + 1 of the later columns swapped: the two
// columns' d u u^T terms refactored, with no subtraction of variances. A
// d' below GF_REAL_MIN is zero, with its column.
void gf_udu_swap(unsigned n, unsigned k, gf_real *ud, unsigned char *perm);

// The correction with m whitened quantities (hw: m rows of n, by state;
// e: their noises; yw: their whitened innovations at mu_bar), in place on
// ud and perm, one quantity after another, each innovation taken at the
// mean the earlier ones gave (an exact quantity is singular when its
// innovation variance is zero relative to its terms or, after others of
// the update, to its h Sigma h^T on the update's prior, S's correlation
// form: one along an earlier one's direction always is):
//   y_i = yw_i - hw_i . dx,  then Bierman's scalar update (an exact
//   quantity, e_i = 0, whose first state's share of its innovation
//   variance is a rounding residue: the Joseph form on the factors).
// The step mu - mu_bar is added to x (n entries, by state), *nis receives
// y^T S^-1 y. GF_ERR_NONFINITE if an innovation variance overflows;
// GF_ERR_SINGULAR for a zero-noise quantity whose innovation variance is
// zero relative to its terms; ud, perm and x are partly written then.
// work: scratch of GF_UDU_CORRECT_WORK(n).
gf_status gf_udu_correct(unsigned n, gf_real *ud, unsigned char *perm,
                         unsigned m, const gf_real *hw, const gf_real *e,
                         const gf_real *yw, gf_real *x, gf_real *nis,
                         gf_real *work);

#endif
