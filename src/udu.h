// gaussfilt: the covariance arithmetic of KF2 and EKF3, one implementation
// for n = 2 or 3 states (docs/numerics.md says why it is this one).
//
// The belief keeps Sigma itself (mu and Sigma stay readable, and no larger
// than n + n^2 numbers), but every step works on its factors
// Sigma = U D U^T (U unit upper triangular, D >= 0 diagonal):
//   prediction  Sigma_bar = (A U) D (A U)^T + R, a sum of squares with
//               weights d_k >= 0, so no variance can come out negative;
//   correction  Bierman's scalar update of U and D, one measured quantity
//               at a time (the measurement noise decorrelated first), in
//               which every new d_j is d_j times a ratio in [0, 1]: the
//               posterior is positive semidefinite by construction, and
//               the gain never comes from a difference of large numbers.
// Matrices are row-major with rows of `stride` entries (n for the belief
// and the models: KF2's 2x2 and EKF3's 3x3 read in place); the factors are
// locals of at most 3x3.
//
// Everything here is static inline, included by kf2.c, ekf3.c and mat.c:
// each filter's copy is compiled for its own n, so that an optimising
// build unrolls the loops (sizes 2 and 3 known), while a build for size
// keeps them as loops. One implementation either way.
#ifndef GAUSSFILT_SRC_UDU_H
#define GAUSSFILT_SRC_UDU_H

#include "gf_internal.h"

// Before each loop over states or measured quantities (at most 3 trips):
// unrolled when the compiler optimises for speed, kept as a loop when it
// optimises for size (-Os, -Oz: flash first).
#if defined(__GNUC__) && !defined(__clang__) && !defined(__OPTIMIZE_SIZE__)
#define GF_UNROLL _Pragma("GCC unroll 3")
#elif defined(__clang__) && !defined(__OPTIMIZE_SIZE__)
#define GF_UNROLL _Pragma("unroll")
#else
#define GF_UNROLL
#endif

// 1 if the n entries of x are all finite: one test of their sum (a NaN or
// inf cannot vanish in a sum), entry by entry only if the sum is not
// finite (finite entries whose sum overflows).
static inline int gf_all_finite(const gf_real *x, unsigned n)
{
    gf_real sum = 0;
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        sum += x[i];
    }
    if (GF_ISFINITE(sum)) {
        return 1;
    }
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        if (!GF_ISFINITE(x[i])) {
            return 0;
        }
    }
    return 1;
}

// s = U D U^T for the leading n x n block of a symmetric s (upper triangle
// read): u unit upper triangular (upper triangle and diagonal written), d
// >= 0. A pivot below its diagonal entry times GF_PD_RTOL (check != 0), or
// not above zero (check == 0: the filter's own covariance), is zero, with a
// zero column. check != 0 also judges: GF_ERR_NOT_PSD for a pivot below
// -GF_PD_RTOL times its diagonal entry or an entry coupled to a zero pivot
// (correlation form); else GF_OK.
static inline gf_status gf_udu_factor(const gf_real *s, unsigned stride, unsigned n,
                        int check, gf_real u[3][3], gf_real d[3])
{
    // A pivot is a variance left once the later states are known; relative
    // to the state's own variance (the pivot of the correlation form
    // D^-1/2 S D^-1/2) it is in [0, 1]. A verdict (check) takes one below
    // GF_PD_RTOL as zero. The filter's own covariance (no check) keeps
    // every positive pivot, however small: calling a direction exactly
    // known because its variance is at the rounding level of the others
    // would make the filter overconfident there, the collapse this
    // arithmetic exists to prevent; only a pivot <= 0 (rounding of a
    // semidefinite covariance) is zero.
    const gf_real rtol = check ? GF_PD_RTOL : GF_R(0.0);
    gf_real a[3][3]; // the Schur complements, upper triangle
    if (n > 3u) {
        return GF_ERR_ARG;
    }
    d[0] = d[1] = d[2] = 0;
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            a[i][j] = s[i * stride + j];
        }
    }
    // s = U D U^T from the last column back: d_j = a_jj, u_ij = a_ij / d_j,
    // then a_ik -= u_ij a_kj for i <= k < j.
    GF_UNROLL
    for (unsigned t = 0; t < n; t++) {
        const unsigned j = n - 1u - t;
        const gf_real sjj = s[j * stride + j];
        const gf_real p = a[j][j];
        u[j][j] = 1;
        if (p > rtol * sjj) { // (NaN fails)
            d[j] = p;
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                u[i][j] = a[i][j] / p;
            }
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                GF_UNROLL
                for (unsigned k = i; k < j; k++) {
                    a[i][k] -= u[i][j] * a[k][j];
                }
            }
            continue;
        }
        if (check) {
            // Semidefinite in this direction only if the pivot is zero
            // within the tolerance and nothing is coupled to it: |a_ij| <=
            // rtol sqrt(s_ii s_jj), the correlation form's entry (by
            // Cauchy-Schwarz it is at most sqrt(pivot) there).
            if (!(p >= -rtol * sjj)) {
                return GF_ERR_NOT_PSD;
            }
            GF_UNROLL
            for (unsigned i = 0; i < j; i++) {
                const gf_real lim =
                    rtol * GF_SQRT(s[i * stride + i]) * GF_SQRT(sjj);
                if (!(GF_FABS(a[i][j]) <= lim)) {
                    return GF_ERR_NOT_PSD;
                }
            }
        }
        d[j] = 0;
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            u[i][j] = 0;
        }
    }
    return GF_OK;
}

// The verdict on a covariance passed in (n x n block, rows of stride):
// GF_ERR_NONFINITE, GF_ERR_NOT_PSD (not symmetric within GF_SYM_RTOL, a
// negative variance, or gf_udu_factor's verdict), else GF_OK with its
// factors in u and d.
static inline gf_status gf_psd_check(const gf_real *s, unsigned stride,
                                     unsigned n, gf_real u[3][3],
                                     gf_real d[3])
{
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        if (!gf_all_finite(&s[i * stride], n)) {
            return GF_ERR_NONFINITE;
        }
    }
    // Symmetric: |a_ij - a_ji| <= GF_SYM_RTOL (|a_ij| + |a_ji|), exact for
    // equal entries (zeros included) and the same for any scale.
    gf_real off = 0; // the sum of |off-diagonal entries|
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i + 1u; j < n; j++) {
            const gf_real x = s[i * stride + j], y = s[j * stride + i];
            if (!(GF_FABS(x - y) <= GF_SYM_RTOL * (GF_FABS(x) + GF_FABS(y)))) {
                return GF_ERR_NOT_PSD;
            }
            off += GF_FABS(x) + GF_FABS(y);
        }
        if (s[i * stride + i] < 0) {
            return GF_ERR_NOT_PSD;
        }
    }
    if (!(off > 0)) {
        // Diagonal (the usual noise): its own factors, d = the variances.
        GF_UNROLL
        for (unsigned i = 0; i < 3u; i++) {
            GF_UNROLL
            for (unsigned j = 0; j < 3u; j++) {
                u[i][j] = (i == j) ? GF_R(1.0) : GF_R(0.0);
            }
            d[i] = (i < n) ? s[i * stride + i] : GF_R(0.0);
        }
        return GF_OK;
    }
    return gf_udu_factor(s, stride, n, 1, u, d);
}

// sigma = U D U^T (rows of n), exactly symmetric: entry (i, j), j >= i,
// is the sum over k >= j of u_ik d_k u_jk, so every variance is a sum of
// non-negative terms.
static inline void gf_udu_recompose(gf_real u[3][3], const gf_real d[3], unsigned n,
                      gf_real *sigma)
{
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned k = j; k < n; k++) {
                acc += u[i][k] * d[k] * u[j][k];
            }
            sigma[i * n + j] = acc;
            sigma[j * n + i] = acc;
        }
    }
}

// out = G Sigma G^T + R as (G U) D (G U)^T + R (Sigma = U D U^T), upper
// triangle of R, result exactly symmetric; out may be sigma.
static inline void gf_cov_predict(const gf_real *sigma, unsigned n, const gf_real *g,
                    const gf_real *r, gf_real *out)
{
    gf_real u[3][3], d[3];
    (void)gf_udu_factor(sigma, n, n, 0, u, d);
    // W = G U
    gf_real w[3][3];
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned k = 0; k < n; k++) {
            gf_real acc = 0;
            GF_UNROLL
            for (unsigned l = 0; l <= k; l++) {
                acc += g[i * n + l] * u[l][k];
            }
            w[i][k] = acc;
        }
    }
    // Sigma_bar = W D W^T + R (R's upper triangle, mirrored)
    GF_UNROLL
    for (unsigned i = 0; i < n; i++) {
        GF_UNROLL
        for (unsigned j = i; j < n; j++) {
            gf_real acc = r[i * n + j];
            GF_UNROLL
            for (unsigned k = 0; k < n; k++) {
                acc += w[i][k] * d[k] * w[j][k];
            }
            out[i * n + j] = acc;
            out[j * n + i] = acc;
        }
    }
}

// Bierman's update of Sigma = U D U^T by one measured quantity z = h x +
// noise of variance r >= 0. Returns alpha = h Sigma h^T + r (the
// innovation's variance) and b = Sigma h^T (the gain is b / alpha); U and D
// become the posterior's factors. With f = U^T h and v_j = d_j f_j:
//   alpha_j = alpha_{j-1} + v_j f_j,  d_j *= alpha_{j-1} / alpha_j,
//   u_ij -= b_i f_j / alpha_{j-1},  b_i += u_ij v_j  (old u_ij), b_j = v_j.
// alpha only grows (every term is d_j f_j^2 >= 0). alpha_{j-1} = 0 happens
// only with r = 0 and every earlier v zero, and then b is zero too: no u
// changes. (Bierman, Factorization Methods for Discrete Sequential
// Estimation, 1977, section V.3.)
static inline gf_real gf_bierman(gf_real u[3][3], gf_real d[3], unsigned n,
                       const gf_real *h, gf_real r, gf_real b[3])
{
    gf_real f[3], v[3];
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        gf_real acc = h[j];
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            acc += u[i][j] * h[i];
        }
        f[j] = acc;
        v[j] = d[j] * acc;
    }
    gf_real alpha = r;
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        const gf_real prev = alpha;
        alpha = prev + v[j] * f[j];
        if (alpha > 0) {
            d[j] *= prev / alpha;
        }
        const gf_real p = (prev > 0) ? f[j] / prev : GF_R(0.0);
        GF_UNROLL
        for (unsigned i = 0; i < j; i++) {
            const gf_real uij = u[i][j];
            u[i][j] = uij - b[i] * p;
            b[i] += uij * v[j];
        }
        b[j] = v[j];
    }
    return alpha;
}

// The correction with m = 1..n measured quantities, in place on the
// caller's copies: mu (mu_bar in, mu out), sigma (Sigma_bar in, Sigma
// out), y (z - h(mu_bar), angles wrapped; overwritten). h: the m x n
// Jacobian (rows of n); v, e: the factors Q = V E V^T of the noise, from
// gf_psd_check. The quantities V^-1 z have independent noises e_i, so they
// are m scalar measurements: one Bierman update each, *nis = the sum of
// their y_i^2 / alpha_i, which is y^T S^-1 y. GF_ERR_NONFINITE (an
// innovation variance overflowed), GF_ERR_SINGULAR (an exact quantity,
// e_i = 0, with h Sigma h^T zero in the correlation form); the outputs are
// partly written then.
static inline gf_status gf_cov_correct(unsigned n, gf_real *mu,
                                       gf_real *sigma, unsigned m,
                                       const gf_real *h, gf_real *y,
                                       gf_real v[3][3], const gf_real e[3],
                                       gf_real *nis)
{
    if (n > 3u || m > n) {
        return GF_ERR_ARG;
    }
    // V^-1 by back substitution, into y and a copy of H
    gf_real hw[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    GF_UNROLL
    for (unsigned t = 0; t < m; t++) {
        const unsigned i = m - 1u - t;
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            gf_real acc = h[i * n + j];
            GF_UNROLL
            for (unsigned k = i + 1u; k < m; k++) {
                acc -= v[i][k] * hw[k][j];
            }
            hw[i][j] = acc;
        }
        GF_UNROLL
        for (unsigned k = i + 1u; k < m; k++) {
            y[i] -= v[i][k] * y[k];
        }
    }

    gf_real u[3][3], d[3];
    (void)gf_udu_factor(sigma, n, n, 0, u, d);
    gf_real dx[3] = {0, 0, 0}; // mu - mu_bar so far
    gf_real total = 0;
    GF_UNROLL
    for (unsigned i = 0; i < m; i++) {
        // this quantity's innovation, at the mean of the rows before it
        gf_real yi = y[i];
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            yi -= hw[i][j] * dx[j];
        }
        gf_real b[3] = {0, 0, 0};
        const gf_real alpha = gf_bierman(u, d, n, hw[i], e[i], b);
        if (!GF_ISFINITE(alpha)) {
            return GF_ERR_NONFINITE;
        }
        // S >= Q > 0 is never singular. An exact quantity (e_i = 0) needs
        // h Sigma_bar h^T > 0 relative to its scale: at most n sum
        // h_j^2 Sigma_jj (Cauchy-Schwarz), the same for any units.
        if (!(e[i] > 0)) {
            gf_real scale = 0;
            GF_UNROLL
            for (unsigned j = 0; j < n; j++) {
                scale += hw[i][j] * hw[i][j] * sigma[j * n + j];
            }
            if (!(alpha > GF_PD_RTOL * (gf_real)n * scale)) {
                return GF_ERR_SINGULAR;
            }
        }
        // mu += K y_i with K = b / alpha; NIS += y_i^2 / alpha
        const gf_real g = yi / alpha;
        GF_UNROLL
        for (unsigned j = 0; j < n; j++) {
            dx[j] += b[j] * g;
        }
        total += yi * g;
    }
    gf_udu_recompose(u, d, n, sigma);
    GF_UNROLL
    for (unsigned j = 0; j < n; j++) {
        mu[j] += dx[j];
    }
    *nis = total;
    return GF_OK;
}

#endif
