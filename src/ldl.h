// SPDX-License-Identifier: MIT
// gaussfilt: the verdict on a covariance passed in (a prior, R, Q) and its
// factors F diag(d) F^T (defined in ldl.c), for any n. Not installed, not
// part of the API.
#ifndef GAUSSFILT_SRC_LDL_H
#define GAUSSFILT_SRC_LDL_H

#include "gf_internal.h"

// The verdict on the leading n x n block of s (rows of `stride`) and its
// factors:
//   GF_ERR_NONFINITE  an entry is not finite;
//   GF_ERR_NOT_PSD    not symmetric within GF_SYM_RTOL
//                     (|s_ij - s_ji| <= GF_SYM_RTOL (|s_ij| + |s_ji|), the
//                     same for any scale), a negative variance, or the
//                     pivoted LDL^T below finds it indefinite;
//   GF_OK             s = F diag(d) F^T, F (n x n, rows of n) unit lower
//                     triangular in the order of its pivots order[0..n-1].
// A diagonal s (the usual noise) is its own factorisation: F = I. Else the
// pivoted LDL^T of the upper triangle: each pivot the state whose variance
// left (once the earlier pivots' states are known) is the largest relative
// to its own variance, a pivot of the correlation form D^-1/2 s D^-1/2, in
// [0, 1], so that units never change a verdict. A pivot up to GF_PD_RTOL
// times its variance is zero, and so is every state left (none is larger):
// each must have a variance left >= -GF_PD_RTOL times its own, and each
// pair of them the 2 x 2 bound s_ik^2 <= s_ii s_kk, both sides widened by
// GF_PD_RTOL times their variance. F, d and order are written on failure
// too (a caller that wants the verdict alone passes scratch).
gf_status gf_cov_factor(const gf_real *s, unsigned stride, unsigned n,
                        gf_real *F, gf_real *d, unsigned *order);

#endif
