// SPDX-License-Identifier: MIT
// gaussfilt: the pivoted LDL^T verdict on a covariance passed in and its
// factors (defined in ldl.c), below the factored steps of udu.h. Not
// installed, not part of the API.
#ifndef GAUSSFILT_SRC_LDL_H
#define GAUSSFILT_SRC_LDL_H

#include "gf_internal.h"

// 1 if x^2 <= y z for y, z >= 0, without a product that could overflow
// or a square root: (x / y) x <= z, and for y = 0 only x = 0. The same
// answer for any power of two times x, y and z.
static inline int gf_coupled_ok(gf_real x, gf_real y, gf_real z)
{
    if (!(y > 0)) {
        return !(GF_FABS(x) > 0);
    }
    return (x / y) * x <= z;
}

// The verdict on a covariance passed in and its factors, by pivoting
// (defined in ldl.c, one copy): M = F diag(d) F^T for the leading n x n
// block of a symmetric s (upper triangle read), F unit lower triangular in
// the order of its pivots: each pivot the state whose variance left (once
// the earlier pivots' states are known) is the largest relative to its own
// variance, the pivots of the correlation form D^-1/2 M D^-1/2, in [0, 1],
// the same in any units. order[t] is the state of step t; column order[t]
// of F is 1 there and zero on the earlier pivots' rows. F (rows of n), d
// and order may be NULL (a verdict only). A pivot up to GF_PD_RTOL times
// its variance is zero, and then so is every state left (none is larger):
// each variance left must be >= -GF_PD_RTOL times its own and each entry
// left coupling two of them within the 2x2 bound a_ik^2 <= a_ii a_kk, both
// sides widened by GF_PD_RTOL times their variance; else GF_ERR_NOT_PSD.
// a (n x n) and p (n) are scratch; NULL for n <= 3 (GF_ERR_ARG beyond).
// Two forms, defined in ldl.c: gf_ldl_core, the loop for any n on the
// scratch, and gf_ldl_small, n <= 3 in scalars; gf_ldl picks one inline,
// so a caller that never passes scratch (the filters of 2 and 3 states)
// links only the second.
gf_status gf_ldl_core(const gf_real *s, unsigned stride, unsigned n, gf_real *F,
                      gf_real *d, unsigned *order, gf_real *a, unsigned *p);
gf_status gf_ldl_small(const gf_real *s, unsigned stride, unsigned n,
                       gf_real *F, gf_real *d, unsigned *order);

static inline gf_status gf_ldl(const gf_real *s, unsigned stride, unsigned n,
                               gf_real *F, gf_real *d, unsigned *order,
                               gf_real *a, unsigned *p)
{
    if (a && p) {
        return gf_ldl_core(s, stride, n, F, d, order, a, p);
    }
    return gf_ldl_small(s, stride, n, F, d, order);
}

#endif
