// SPDX-License-Identifier: MIT
// gaussfilt: the numeric helpers every source shares, on the types of
// gaussfilt/mat.h. The bottom of src/: it includes no filter's header and
// needs no function defined elsewhere (everything here is static inline).
// Not installed, not part of the API; gf_filter.h holds the filters' own.
#ifndef GAUSSFILT_SRC_INTERNAL_H
#define GAUSSFILT_SRC_INTERNAL_H

// No product and sum of the core is fused into one rounding, whatever the
// build's flags: the factorisation computes rounding errors exactly, and
// the same bits on every target need the same roundings. Every source of
// the core includes this header directly (scripts/check-includes). (gcc ignores the standard pragma and
// takes its own; clang takes the standard one, except under
// -ffp-contract=fast, which overrides every pragma: docs/firmware.md. MSVC
// takes its own too, which it obeys under any /fp: option.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#elif defined(_MSC_VER) && !defined(__clang__)
#pragma fp_contract(off)
#else
#pragma STDC FP_CONTRACT OFF
#endif

#include <stddef.h>

#include "gaussfilt/mat.h"

#include "gf_names.h"

// Kept a function of its own: UKF3's steps, whose frames must not sit
// under each other's; EKF3's check of R, whose verdict's scratch must not
// sit under the prediction; Thornton's W (udu.c), whose frame must not sit
// under the Gram-Schmidt's; and gf_kf's belief copies, whose restrict
// pointers then hold (the compiler's memcpy, not memmove).
#if defined(__GNUC__)
#define GF_NOINLINE static __attribute__((noinline))
#else
#define GF_NOINLINE static
#endif

// Finiteness in one pass with no branch: x_i * 0 is 0 for a finite x_i
// and NaN for an infinite or NaN one, and a NaN cannot vanish from a sum
// (nor can the sum overflow: every term is 0). gf_nan_sum adds the n
// entries of x to a running z (start at 0); gf_sum_finite tells whether
// every number added so far was finite (z is +-0 or NaN, and only NaN
// fails z < 1). Needs IEEE arithmetic (no -ffinite-math-only).
static inline gf_real gf_nan_sum(gf_real z, const gf_real *x, unsigned n)
{
    gf_real acc = z;
    for (unsigned i = 0; i < n; i++) {
        acc += x[i] * GF_R(0.0);
    }
    return acc;
}

static inline int gf_sum_finite(gf_real z)
{
    return z < GF_R(1.0);
}

// 1 if the n entries of x are all finite.
static inline int gf_all_finite(const gf_real *x, unsigned n)
{
    return gf_sum_finite(gf_nan_sum(GF_R(0.0), x, n));
}

// Entry i of a predicted mean, mu_bar_i = (A x)_i + (B u)_i + c_i, for
// every linear filter in one order: c_i, the other states' terms and
// (B u)_i first, the state's own term A_ii x_i last (docs/numerics.md,
// "The mean"). a: row i of A (n entries); b: row i of B and u (nu
// entries; no control term when nu is 0 or either is NULL).
static inline gf_real gf_mean_row(const gf_real *a, const gf_real *x,
                                  unsigned n, unsigned i, gf_real c,
                                  const gf_real *b, const gf_real *u,
                                  unsigned nu)
{
    gf_real acc = c;
    for (unsigned j = 0; j < i; j++) {
        acc += a[j] * x[j];
    }
    for (unsigned j = i + 1u; j < n; j++) {
        acc += a[j] * x[j];
    }
    if (nu > 0u && b != NULL && u != NULL) {
        gf_real bu = b[0] * u[0];
        for (unsigned j = 1; j < nu; j++) {
            bu += b[j] * u[j];
        }
        acc += bu;
    }
    return acc + a[i] * x[i];
}

// The tail every update shares once it has the NIS and the new belief
// (finite: 1 if all of it is finite): GF_ERR_NONFINITE for a NIS that is
// not finite, GF_ERR_GATED for a NIS above a set gate (gate > 0; the
// caller still stores the innovation), GF_ERR_NONFINITE for a belief that
// is not finite (the caller keeps the last good one), else GF_OK (the
// caller stores the innovation and the belief).
static inline gf_status gf_update_status(gf_real nis, gf_real gate, int finite)
{
    if (!GF_ISFINITE(nis)) {
        return GF_ERR_NONFINITE;
    }
    if (gate > 0 && nis > gate) {
        return GF_ERR_GATED;
    }
    return finite ? GF_OK : GF_ERR_NONFINITE;
}

// 1 if both entries of x are finite.
static inline int gf_vec2_is_finite(const gf_vec2 *x)
{
    return gf_all_finite(x->v, 2);
}

// 1 if the first n entries of x are finite.
static inline int gf_vec3_is_finite_n(const gf_vec3 *x, unsigned n)
{
    return gf_all_finite(x->v, n);
}

// A model callback's status, with anything that is not a known failure
// mapped to GF_ERR_MODEL; so is GF_ERR_GATED, which only the filter's own
// gate may report (the caller then expects the innovation to be written).
static inline gf_status gf_callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
               ? GF_ERR_MODEL
               : st;
}

// Entry (i, j), j <= i, of a lower triangle packed by rows:
// (0,0) (1,0) (1,1) (2,0) (2,1) (2,2).
#define GF_TRI(i, j) ((i) * ((i) + 1u) / 2u + (j))

// Cholesky factorisation in place: l holds the lower triangle (packed,
// GF_TRI) of the leading n x n block (n = 1..3) of a symmetric
// positive-definite matrix and receives its factor L (= L L^T) there. A
// pivot below GF_PD_RTOL times its diagonal entry, NaN or inf gives
// GF_ERR_SINGULAR, with l partly overwritten. gf_mat3_chol's arithmetic,
// for callers that cannot spare a 3x3 copy.
static inline gf_status gf_chol_packed(gf_real l[6], unsigned n)
{
    for (unsigned j = 0; j < n; j++) {
        const gf_real sjj = l[GF_TRI(j, j)];
        gf_real d = sjj;
        for (unsigned k = 0; k < j; k++) {
            d -= l[GF_TRI(j, k)] * l[GF_TRI(j, k)];
        }
        // Written so that NaN fails too.
        if (!(d > GF_PD_RTOL * sjj) || !GF_ISFINITE(d)) {
            return GF_ERR_SINGULAR;
        }
        const gf_real ljj = GF_SQRT(d);
        l[GF_TRI(j, j)] = ljj;
        for (unsigned i = j + 1; i < n; i++) {
            gf_real v = l[GF_TRI(i, j)];
            for (unsigned k = 0; k < j; k++) {
                v -= l[GF_TRI(i, k)] * l[GF_TRI(j, k)];
            }
            l[GF_TRI(i, j)] = v / ljj;
        }
    }
    return GF_OK;
}

// Square root of a symmetric positive SEMIdefinite matrix, packed: l
// (GF_TRI) receives the lower triangle of L, L L^T = the leading n x n
// block (n = 1..3) of s, which the caller has checked with
// gf_mat3_check_psd. A pivot within GF_PD_RTOL of zero gives a zero
// column. The one implementation: gf_mat3_sqrt_psd unpacks it; UKF3 and
// PF3 keep it packed (no 3x3 temporary). Entries of l beyond the block
// are zeroed.
static inline void gf_sqrt_psd_packed(const gf_mat3 *s, unsigned n,
                                      gf_real l[6])
{
    for (unsigned k = 0; k < 6u; k++) {
        l[k] = 0;
    }
    for (unsigned j = 0; j < n; j++) {
        gf_real d = s->m[j][j];
        for (unsigned k = 0; k < j; k++) {
            d -= l[GF_TRI(j, k)] * l[GF_TRI(j, k)];
        }
        if (!(d > GF_PD_RTOL * s->m[j][j])) {
            continue; // semidefinite direction: zero column
        }
        const gf_real ljj = GF_SQRT(d);
        l[GF_TRI(j, j)] = ljj;
        for (unsigned i = j + 1; i < n; i++) {
            gf_real v = GF_R(0.5) * s->m[i][j] + GF_R(0.5) * s->m[j][i];
            for (unsigned k = 0; k < j; k++) {
                v -= l[GF_TRI(i, k)] * l[GF_TRI(j, k)];
            }
            l[GF_TRI(i, j)] = v / ljj;
        }
    }
}

// Solves L L^T x = b in place on the leading n entries of x (b in, x
// out), L from gf_chol_packed.
static inline void gf_chol_solve_packed(const gf_real l[6], unsigned n,
                                        gf_real x[3])
{
    for (unsigned i = 0; i < n; i++) { // L y = b
        for (unsigned k = 0; k < i; k++) {
            x[i] -= l[GF_TRI(i, k)] * x[k];
        }
        x[i] /= l[GF_TRI(i, i)];
    }
    for (unsigned i = n; i-- > 0;) { // L^T x = y
        for (unsigned k = i + 1; k < n; k++) {
            x[i] -= l[GF_TRI(k, i)] * x[k];
        }
        x[i] /= l[GF_TRI(i, i)];
    }
}

// The upper triangle (j >= i) of a s a^T into o, its lower triangle left
// as it was: gf_mat3_sandwich's arithmetic (row i of t = a s, then row i of
// t a^T), with no 3x3 temporary. o may be a itself (row i of a is last read
// before row i of o is written), not s.
static inline void gf_sandwich_upper(const gf_mat3 *a, const gf_mat3 *s,
                                     gf_mat3 *o)
{
    for (unsigned i = 0; i < 3; i++) {
        gf_real t[3];
        for (unsigned k = 0; k < 3; k++) {
            t[k] = a->m[i][0] * s->m[0][k] + a->m[i][1] * s->m[1][k] +
                   a->m[i][2] * s->m[2][k];
        }
        for (unsigned j = i; j < 3; j++) {
            o->m[i][j] =
                t[0] * a->m[j][0] + t[1] * a->m[j][1] + t[2] * a->m[j][2];
        }
    }
}

#endif
