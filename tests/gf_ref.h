// SPDX-License-Identifier: MIT
// The reference of every test and of bench/accuracy.c: a Joseph filter in
// long double for any n up to GR_N (the batch form; its perturbed copies,
// which measure a scenario's conditioning; and the sequential form, for
// comparison) and an independent positive-semidefiniteness test, used by
// tests/test_random.c, tests/test_kf.c and bench/accuracy.c; then seeded
// random scenarios for KF2 and EKF3 with the reference on them, and a
// textbook Joseph filter in gf_real for those. Test code: static inline
// helpers; no state outside the structs the caller owns but the steps'
// scratch matrices (gr_ws).
//
// The generator works in double, rounds every input to gf_real once, and
// the reference reads those rounded inputs: the reference and the filter
// under test see exactly the same numbers. The reference is long double
// (64-bit significand on x86-64; on targets where long double is double,
// such as the Cortex-M4F, the float build is still referenced in double,
// 2^29 times finer than float).
#ifndef GF_REF_H
#define GF_REF_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "gaussfilt/gaussfilt.h"

typedef long double gr_real;

// The unit roundoff of gf_real and of the reference.
#ifdef GF_SINGLE_PRECISION
#define GR_U (0.5 * (double)FLT_EPSILON)
#else
#define GR_U (0.5 * DBL_EPSILON)
#endif
#define GR_U_REF (0.5 * (double)LDBL_EPSILON)

// Ranges of the scenarios, per build (docs/accuracy.md): the
// largest ratio of prior to measurement-noise variance (in measurement
// space), and the largest condition number of the prior's correlation form.
#ifdef GF_SINGLE_PRECISION
#define GR_RATIO_MAX 1e12
#define GR_COND_MAX 1e6
#else
#define GR_RATIO_MAX 1e16
#define GR_COND_MAX 1e12
#endif
// Every unit is scaled by a factor in [1 / GR_UNIT, GR_UNIT].
#define GR_UNIT 1e3
// Measurement-noise correlation forms are drawn with a condition number up
// to GR_QCOND (the "correlated Q" of the scenarios; well-posed, see
// gr_scen.q_pd).
#define GR_QCOND 1e3

// ---- a small seeded PRNG of our own (splitmix64) -------------------------

typedef struct gr_rng {
    uint64_t s;
} gr_rng;

static inline uint64_t gr_next(gr_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Uniform in [0, 1).
static inline double gr_unif(gr_rng *r)
{
    return (double)(gr_next(r) >> 11) * 0x1.0p-53;
}

// exp, log, sin and cos of our own, from +, *, / and frexp/ldexp only
// (sqrt is correctly rounded everywhere): every machine draws the same
// scenarios bit for bit, whatever its libm. Accurate to a few ulps, which
// is all the generator and the reference's turn need.
static inline double gr_exp(double x)
{
    double k = floor(x / 0.6931471805599453 + 0.5);
    double r = x - k * 0.6931471805599453, t = 1.0, e = 1.0;
    for (int i = 1; i < 24; i++) {
        t *= r / i;
        e += t;
    }
    return ldexp(e, (int)k);
}

static inline double gr_log(double x)
{
    int k;
    double m = frexp(x, &k) * 2.0; // x = m 2^(k-1), m in [1, 2)
    double z = (m - 1.0) / (m + 1.0), z2 = z * z, t = z, s = 0;
    for (int i = 1; i < 60; i += 2) {
        s += t / i;
        t *= z2;
    }
    return 2.0 * s + (k - 1) * 0.6931471805599453;
}

// sin and cos of a reduced to [-pi, pi] by multiples of 2 pi.
static inline void gr_sincos(double a, double *s, double *c)
{
    const double two_pi = 6.283185307179586;
    double x = a - two_pi * floor(a / two_pi + 0.5);
    double x2 = x * x, ts = x, tc = 1.0, ss = x, cc = 1.0;
    for (int i = 1; i < 20; i++) {
        ts *= -x2 / ((2 * i) * (2 * i + 1));
        tc *= -x2 / ((2 * i - 1) * (2 * i));
        ss += ts;
        cc += tc;
    }
    *s = ss;
    *c = cc;
}

// Standard normal (Box-Muller).
static inline double gr_normal(gr_rng *r)
{
    double u1 = 1.0 - gr_unif(r), u2 = gr_unif(r), s, c;
    gr_sincos(6.283185307179586 * u2, &s, &c);
    return sqrt(-2.0 * gr_log(u1)) * c;
}

// Log-uniform in [lo, hi].
static inline double gr_logu(gr_rng *r, double lo, double hi)
{
    return gr_exp(gr_log(lo) + gr_unif(r) * (gr_log(hi) - gr_log(lo)));
}

static inline unsigned gr_below(gr_rng *r, unsigned n)
{
    return (unsigned)(gr_next(r) % n);
}

// ---- the reference filter (long double, any n up to GR_N) -----------------

// The largest n (and m) the reference takes.
#define GR_N 12
typedef gr_real gr_mat[GR_N][GR_N];

// Deliberate bugs of the reference, to show that a bound catches them.
enum gr_bug {
    GR_BUG_NONE,
    GR_BUG_NO_R,  // predictions without R
    GR_BUG_NO_KQK // Joseph forms without K Q K^T (and no second pass)
};

// The reference: the textbook steps in long double. With eps > 0 it is a
// perturbed copy: every input it reads (models, measurement), every
// intermediate of the batch Joseph update (P H^T, S, y, K, I - K H) and the
// belief it holds after each step are multiplied by 1 +- eps (signs drawn
// from its own rng), eps being gf_real's unit roundoff: a model of one
// rounding of each quantity a textbook Joseph filter in gf_real forms. The
// spread of such copies around the unperturbed reference is the error that
// the scenario's conditioning gives that filter at gf_real's precision,
// measured on the scenario rather than estimated from norms.
typedef struct gr_filt {
    int n;
    int angle_row; // the measurement row whose residual is an angle, or -1
    int bug;       // enum gr_bug
    gr_real mu[GR_N];
    gr_mat P;
    double eps;
    gr_rng rng;
} gr_filt;

// The steps' matrices: file-scope, as the emulated target's stack (16 KiB)
// is small. One step at a time.
static struct {
    gr_mat a, GP, P, H, Q, PH, S, L, Si, K, M, Pn, LQ, Qi, MP, ldl, psd, psdL;
    gr_filt seq;
} gr_ws;

// The reference at the prior (mu0, S0), S0 n x n with rows lds apart; a
// perturbed copy when eps != 0, its signs drawn from seed.
static inline void gr_ref_init(gr_filt *f, int n, const gf_real *mu0,
                               const gf_real *S0, int lds, double eps,
                               uint64_t seed)
{
    memset(f, 0, sizeof *f);
    f->n = n;
    f->angle_row = -1;
    f->eps = eps;
    f->rng.s = seed;
    for (int i = 0; i < n; i++) {
        f->mu[i] = (gr_real)mu0[i];
        for (int j = 0; j < n; j++) {
            f->P[i][j] = (gr_real)S0[i * lds + j];
        }
    }
}

// a wrapped to [-pi, pi], in long double.
static inline gr_real gr_wrap(gr_real a)
{
    const gr_real two_pi = 6.283185307179586476925L;
    return a - two_pi * (gr_real)floor((double)(a / two_pi) + 0.5);
}

static inline gr_real gr_pert(gr_filt *f, gr_real x)
{
    if (f->eps == 0) {
        return x;
    }
    double e = (gr_next(&f->rng) & 1) ? f->eps : -f->eps;
    return x * (1.0L + (gr_real)e);
}

// An input as this copy reads it.
static inline gr_real gr_in(gr_filt *f, gf_real x)
{
    return gr_pert(f, (gr_real)x);
}

// A covariance-like matrix as a copy stores it: its variances times 1 -
// eps and its covariances times 1 + eps in one copy (eps < 0 in the other):
// the direction in which rounding moves its correlation form most, towards
// or away from singular, which random signs can miss (a relative
// perturbation of all entries alike changes no correlation).
static inline void gr_pert_cov(gr_filt *f, int n, gr_mat P)
{
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            gr_real v = 0.5L * (P[i][j] + P[j][i]);
            gr_real e = (gr_real)f->eps;
            v *= i == j ? 1.0L - e : 1.0L + e;
            P[i][j] = P[j][i] = v;
        }
    }
}

// The belief stored after a step.
static inline void gr_store(gr_filt *f, const gr_real *mu, gr_mat P)
{
    for (int i = 0; i < f->n; i++) {
        f->mu[i] = gr_pert(f, mu[i]);
        for (int j = 0; j < f->n; j++) {
            f->P[i][j] = P[i][j];
        }
    }
    gr_pert_cov(f, f->n, f->P);
}

// P = G P G^T + R (R n x n, rows ld apart), then the belief (mu, P) stored.
static inline void gr_predict_cov(gr_filt *f, gr_mat G, const gr_real *mu,
                                  const gf_real *R, int ld)
{
    const int n = f->n;
    gr_real(*GP)[GR_N] = gr_ws.GP, (*P)[GR_N] = gr_ws.P;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            GP[i][j] = 0;
            for (int k = 0; k < n; k++) {
                GP[i][j] += G[i][k] * f->P[k][j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            P[i][j] = f->bug == GR_BUG_NO_R ? 0.0L : gr_in(f, R[i * ld + j]);
            for (int k = 0; k < n; k++) {
                P[i][j] += GP[i][k] * G[j][k];
            }
            P[j][i] = P[i][j];
        }
    }
    gr_store(f, mu, P);
}

// Prediction with a linear model: mu = A mu + B u + c, P = A P A^T + R (A
// and R n x n, rows ld apart; B n x nu, u nu, both unread when nu = 0).
static inline void gr_predict(gr_filt *f, const gf_real *A, const gf_real *B,
                              const gf_real *u, int nu, const gf_real *c,
                              const gf_real *R, int ld)
{
    const int n = f->n;
    gr_real(*a)[GR_N] = gr_ws.a, mu[GR_N];
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            a[i][j] = gr_in(f, A[i * ld + j]);
        }
    }
    for (int i = 0; i < n; i++) {
        mu[i] = gr_in(f, c[i]);
        for (int k = 0; k < nu; k++) {
            mu[i] += gr_in(f, B[i * nu + k]) * (gr_real)u[k];
        }
        for (int j = 0; j < n; j++) {
            mu[i] += a[i][j] * f->mu[j];
        }
    }
    gr_predict_cov(f, a, mu, R, ld);
}

// LDL^T of the leading m x m block of a symmetric s, no pivoting, in long
// double: s = L D L^T, L unit lower triangular. A pivot that is not
// positive stops it (returns 0) unless allow_zero, where a zero pivot
// with a zero column below it is kept as d_k = 0 (semidefinite s).
static inline int gr_ldl(int m, gr_mat s, gr_mat L, gr_real *D, int allow_zero)
{
    gr_real(*a)[GR_N] = gr_ws.ldl;
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < m; j++) {
            a[i][j] = s[i][j];
            L[i][j] = i == j ? 1.0L : 0.0L;
        }
    }
    for (int k = 0; k < m; k++) {
        D[k] = a[k][k];
        if (!(D[k] > 0)) {
            if (!allow_zero || D[k] < 0) {
                return 0;
            }
            for (int i = k + 1; i < m; i++) {
                if (a[i][k] != 0) {
                    return 0;
                }
            }
            D[k] = 0;
            continue;
        }
        for (int i = k + 1; i < m; i++) {
            L[i][k] = a[i][k] / D[k];
        }
        for (int i = k + 1; i < m; i++) {
            for (int j = k + 1; j <= i; j++) {
                a[i][j] -= L[i][k] * D[k] * L[j][k];
                a[j][i] = a[i][j];
            }
        }
    }
    return 1;
}

// inv = (L D L^T)^-1, column by column, D > 0.
static inline void gr_ldl_inverse(int m, gr_mat L, const gr_real *D, gr_mat inv)
{
    for (int j = 0; j < m; j++) {
        gr_real x[GR_N];
        for (int i = 0; i < m; i++) {
            x[i] = i == j ? 1.0L : 0.0L;
            for (int k = 0; k < i; k++) {
                x[i] -= L[i][k] * x[k];
            }
        }
        for (int i = 0; i < m; i++) {
            x[i] /= D[i];
        }
        for (int i = m - 1; i >= 0; i--) {
            for (int k = i + 1; k < m; k++) {
                x[i] -= L[k][i] * x[k];
            }
        }
        for (int i = 0; i < m; i++) {
            inv[i][j] = x[i];
        }
    }
}

// Pn = M P M^T + K Q K^T (K Q K^T left out by GR_BUG_NO_KQK).
static inline void gr_joseph(const gr_filt *f, int m, gr_mat M, gr_mat K,
                             gr_mat Q, gr_mat Pn)
{
    const int n = f->n;
    gr_real(*MP)[GR_N] = gr_ws.MP;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            MP[i][j] = 0;
            for (int k = 0; k < n; k++) {
                MP[i][j] += M[i][k] * f->P[k][j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            Pn[i][j] = 0;
            for (int k = 0; k < n; k++) {
                Pn[i][j] += MP[i][k] * M[j][k];
            }
            for (int a = 0; a < m && f->bug != GR_BUG_NO_KQK; a++) {
                for (int b = 0; b < m; b++) {
                    Pn[i][j] += K[i][a] * Q[a][b] * K[j][b];
                }
            }
        }
    }
}

// Row i of M = I - K H.
static inline void gr_i_minus_kh(gr_filt *f, int m, int i, gr_mat K, gr_mat H,
                                 gr_mat M)
{
    for (int j = 0; j < f->n; j++) {
        M[i][j] = i == j ? 1.0L : 0.0L;
        for (int k = 0; k < m; k++) {
            M[i][j] -= K[i][k] * H[k][j];
        }
        M[i][j] = gr_pert(f, M[i][j]);
    }
}

// Whether gr_update takes its second pass (the gain from Q^-1): Q = LQ
// DQ LQ^T succeeds (written into LQ, DQ), and Q's least pivot relative to
// its diagonal entry is 1e-12 or more, or no smaller than S's (DS: S's
// pivots). A Q singular but for its rounding (a least pivot of about 1e-17
// relative) has a Q^-1 of that condition number, and Sigma H^T Q^-1 loses
// every digit, in long double and in 128 bits alike (docs/accuracy.md);
// the first pass, K = Sigma H^T S^-1, loses u kappa(S) only.
static inline int gr_second_pass(int m, gr_mat Q, gr_mat LQ, gr_real *DQ,
                                 gr_mat S, const gr_real *DS)
{
    if (!gr_ldl(m, Q, LQ, DQ, 0)) {
        return 0;
    }
    gr_real q = 1, s = 1;
    for (int k = 0; k < m; k++) {
        q = DQ[k] / Q[k][k] < q ? DQ[k] / Q[k][k] : q;
        s = DS[k] / S[k][k] < s ? DS[k] / S[k][k] : s;
    }
    return q >= 1e-12L || q >= s;
}

// The batch update (Table 3.1 with the Joseph form), m = 1..n, H m x n with
// rows ldh apart, Q m x m with rows ldq apart, d (a constant term of the
// measurement) NULL or m:
//   y = z - d - H mu,  S = H P H^T + Q,  K = P H^T S^-1,  mu = mu + K y,
//   P = (I - K H) P (I - K H)^T + K Q K^T,  NIS = y^T S^-1 y.
// Returns 0 (and leaves f alone) when S is not positive definite.
static inline int gr_update(gr_filt *f, int m, const gf_real *Hin, int ldh,
                            const gf_real *Qin, int ldq, const gf_real *zin,
                            const gf_real *din, gr_real *nis_out)
{
    const int n = f->n;
    gr_real(*H)[GR_N] = gr_ws.H, (*Q)[GR_N] = gr_ws.Q, (*PH)[GR_N] = gr_ws.PH;
    gr_real(*S)[GR_N] = gr_ws.S, (*L)[GR_N] = gr_ws.L, (*Si)[GR_N] = gr_ws.Si;
    gr_real(*K)[GR_N] = gr_ws.K, (*M)[GR_N] = gr_ws.M, (*Pn)[GR_N] = gr_ws.Pn;
    gr_real z[GR_N], D[GR_N], y[GR_N];
    for (int i = 0; i < m; i++) {
        z[i] = gr_in(f, zin[i]);
        if (din) {
            z[i] -= gr_in(f, din[i]);
        }
        for (int j = 0; j < n; j++) {
            H[i][j] = gr_in(f, Hin[i * ldh + j]);
        }
        for (int j = 0; j <= i; j++) {
            Q[i][j] = Q[j][i] = (gr_real)Qin[i * ldq + j];
        }
    }
    gr_pert_cov(f, m, Q);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < m; j++) {
            PH[i][j] = 0;
            for (int k = 0; k < n; k++) {
                PH[i][j] += f->P[i][k] * H[j][k];
            }
            PH[i][j] = gr_pert(f, PH[i][j]);
        }
    }
    for (int i = 0; i < m; i++) {
        for (int j = 0; j <= i; j++) {
            S[i][j] = Q[i][j];
            for (int k = 0; k < n; k++) {
                S[i][j] += H[i][k] * PH[k][j];
            }
            S[j][i] = S[i][j];
        }
    }
    gr_pert_cov(f, m, S);
    if (!gr_ldl(m, S, L, D, 0)) {
        return 0;
    }
    gr_ldl_inverse(m, L, D, Si);
    for (int i = 0; i < m; i++) {
        y[i] = z[i];
        for (int k = 0; k < n; k++) {
            y[i] -= H[i][k] * f->mu[k];
        }
        if (i == f->angle_row) {
            y[i] = gr_wrap(y[i]);
        }
        y[i] = gr_pert(f, y[i]);
    }
    gr_real nis = 0;
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < m; j++) {
            nis += y[i] * Si[i][j] * y[j];
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < m; j++) {
            K[i][j] = 0;
            for (int k = 0; k < m; k++) {
                K[i][j] += PH[i][k] * Si[k][j];
            }
            K[i][j] = gr_pert(f, K[i][j]);
        }
    }
    for (int i = 0; i < n; i++) {
        gr_i_minus_kh(f, m, i, K, H, M);
    }
    gr_joseph(f, m, M, K, Q, Pn);
    // A second pass with the gain in its information form, K = Sigma H^T
    // Q^-1 (Sigma the posterior just found; Q's LDL^T, Q being far better
    // conditioned than S when the prior/noise ratio is large): the first
    // pass's Sigma is only second-order sensitive to the error of K (the
    // Joseph form), so this K is accurate where S^-1 y was not, and the
    // mean and the NIS follow from it: mu = mu + K y, NIS = y^T Q^-1 (y - H
    // K y) (= y^T S^-1 y). Without a positive definite Q, or with a Q
    // singular but for its rounding (gr_second_pass), the first pass.
    gr_real(*LQ)[GR_N] = gr_ws.LQ, (*Qi)[GR_N] = gr_ws.Qi, DQ[GR_N];
    if (f->bug == GR_BUG_NONE && gr_second_pass(m, Q, LQ, DQ, S, D)) {
        gr_ldl_inverse(m, LQ, DQ, Qi);
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < m; j++) {
                K[i][j] = 0;
                for (int a = 0; a < n; a++) {
                    for (int b = 0; b < m; b++) {
                        K[i][j] += Pn[i][a] * H[b][a] * Qi[b][j];
                    }
                }
                K[i][j] = gr_pert(f, K[i][j]);
            }
            gr_i_minus_kh(f, m, i, K, H, M);
        }
        gr_joseph(f, m, M, K, Q, Pn);
        gr_real dm[GR_N], r[GR_N];
        for (int i = 0; i < n; i++) {
            dm[i] = 0;
            for (int k = 0; k < m; k++) {
                dm[i] += K[i][k] * y[k];
            }
        }
        for (int i = 0; i < m; i++) {
            r[i] = y[i];
            for (int k = 0; k < n; k++) {
                r[i] -= H[i][k] * dm[k];
            }
        }
        nis = 0;
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++) {
                nis += y[i] * Qi[i][j] * r[j];
            }
        }
    }
    gr_real mu[GR_N];
    for (int i = 0; i < n; i++) {
        mu[i] = f->mu[i];
        for (int k = 0; k < m; k++) {
            mu[i] += K[i][k] * y[k];
        }
    }
    gr_store(f, mu, Pn);
    *nis_out = nis;
    return 1;
}

// The sequential form the library uses, in long double, to check the
// reference's batch form against (H and Q as gr_update's): Q = L D L^T,
// z - H mu and H transformed by L^-1, then one scalar Joseph update per
// row. Returns 0 when a row's s is not positive.
static inline int gr_update_seq(gr_filt *f, int m, const gf_real *H, int ldh,
                                const gf_real *Q, int ldq, const gf_real *z,
                                gr_real *nis_out)
{
    const int n = f->n;
    gr_real(*Qs)[GR_N] = gr_ws.Q, (*L)[GR_N] = gr_ws.L, (*h)[GR_N] = gr_ws.H;
    gr_real(*M)[GR_N] = gr_ws.M, (*MP)[GR_N] = gr_ws.MP, D[GR_N], y[GR_N];
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < m; j++) {
            Qs[i][j] = (gr_real)Q[i * ldq + j];
        }
    }
    if (!gr_ldl(m, Qs, L, D, 1)) {
        return 0;
    }
    for (int i = 0; i < m; i++) { // L h = H, L y = z - H mu
        y[i] = (gr_real)z[i];
        for (int k = 0; k < n; k++) {
            y[i] -= (gr_real)H[i * ldh + k] * f->mu[k];
        }
        if (i == f->angle_row) {
            y[i] = gr_wrap(y[i]);
        }
        for (int j = 0; j < n; j++) {
            h[i][j] = (gr_real)H[i * ldh + j];
        }
        for (int k = 0; k < i; k++) {
            y[i] -= L[i][k] * y[k];
            for (int j = 0; j < n; j++) {
                h[i][j] -= L[i][k] * h[k][j];
            }
        }
    }
    gr_filt *g = &gr_ws.seq;
    *g = *f;
    gr_real nis = 0;
    for (int r = 0; r < m; r++) {
        // The row's innovation against the current mean: y_r less what the
        // earlier rows moved, h_r (mu - mu_0).
        gr_real yr = y[r];
        for (int k = 0; k < n; k++) {
            yr -= h[r][k] * (g->mu[k] - f->mu[k]);
        }
        gr_real p[GR_N], k[GR_N], s = D[r];
        for (int i = 0; i < n; i++) {
            p[i] = 0;
            for (int j = 0; j < n; j++) {
                p[i] += g->P[i][j] * h[r][j];
            }
        }
        for (int i = 0; i < n; i++) {
            s += h[r][i] * p[i];
        }
        if (!(s > 0)) {
            return 0;
        }
        for (int i = 0; i < n; i++) {
            k[i] = p[i] / s;
            g->mu[i] += k[i] * yr;
        }
        nis += yr * yr / s;
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++) {
                M[i][j] = (i == j ? 1.0L : 0.0L) - k[i] * h[r][j];
            }
        }
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++) {
                MP[i][j] = 0;
                for (int a = 0; a < n; a++) {
                    MP[i][j] += M[i][a] * g->P[a][j];
                }
            }
        }
        for (int i = 0; i < n; i++) {
            for (int j = 0; j <= i; j++) {
                gr_real v = D[r] * k[i] * k[j];
                for (int a = 0; a < n; a++) {
                    v += MP[i][a] * M[j][a];
                }
                g->P[i][j] = g->P[j][i] = v;
            }
        }
    }
    *f = *g;
    *nis_out = nis;
    return 1;
}

// ---- comparisons -----------------------------------------------------------

// The heading difference a - b taken on the circle (EKF3's mean heading is
// wrapped, the reference's is not).
static inline gr_real gr_angle_diff(gr_real a, gr_real b)
{
    return gr_wrap(a - b);
}

// Relative errors of (mu, P) against the reference f in its correlation
// form: Sigma max_ij |P_ij - ref_ij| / sqrt(v_i v_j), mu max_i |mu_i -
// ref_i| / sqrt(v_i), v the reference's variances, the heading (state 2)
// taken on the circle when `angle` (EKF3). With dg, v is dg instead (an
// update with zero-noise quantities: its exact directions' posterior
// variances are zero, and what is left of them in any filter a rounding
// residue; measured against the prior's variances, an error is what it
// costs of the prior's information). A zero v with any difference: +inf.
static inline void gr_errors(const gr_filt *f, const gr_real *dg,
                             const gr_real *mu, gr_mat P, int angle, double *es,
                             double *em)
{
    double s = 0, m = 0;
    for (int i = 0; i < f->n; i++) {
        const gr_real vi = dg ? dg[i] : f->P[i][i];
        for (int j = 0; j < f->n; j++) {
            gr_real dd = P[i][j] - f->P[i][j];
            gr_real den = vi * (dg ? dg[j] : f->P[j][j]);
            double e = dd == 0   ? 0.0
                       : den > 0 ? sqrt((double)(dd * dd / den))
                                 : (double)INFINITY;
            s = e > s ? e : s;
        }
        gr_real dm = (angle && i == 2) ? gr_angle_diff(mu[i], f->mu[i])
                                       : mu[i] - f->mu[i];
        double e = dm == 0  ? 0.0
                   : vi > 0 ? sqrt((double)(dm * dm / vi))
                            : (double)INFINITY;
        m = e > m ? e : m;
    }
    *es = s;
    *em = m;
}

// Positive semidefinite within `tol` in the correlation form: the
// correlation form's smallest eigenvalue >= -tol, tested without square
// roots as: a negative variance fails; a zero variance needs its row and
// column exactly zero; on the other indices, M + tol diag(M) (congruent to
// C + tol I, C = D^-1/2 M D^-1/2) must have an LDL^T with positive pivots,
// and M be symmetric within tol. Long double, independent of the library.
static inline int gr_psd(int n, gr_mat M, double tol)
{
    gr_real(*a)[GR_N] = gr_ws.psd, D[GR_N];
    int idx[GR_N], k = 0;
    for (int i = 0; i < n; i++) {
        if (M[i][i] < 0 || M[i][i] != M[i][i]) {
            return 0;
        }
        if (M[i][i] == 0) {
            for (int j = 0; j < n; j++) {
                if (M[i][j] != 0 || M[j][i] != 0) {
                    return 0;
                }
            }
            continue;
        }
        idx[k++] = i;
    }
    for (int i = 0; i < k; i++) {
        for (int j = 0; j < k; j++) {
            gr_real mij = M[idx[i]][idx[j]], mji = M[idx[j]][idx[i]];
            if ((mij - mji) * (mij - mji) >
                (gr_real)(tol * tol) * M[idx[i]][idx[i]] * M[idx[j]][idx[j]]) {
                return 0;
            }
            a[i][j] = 0.5L * (mij + mji);
        }
        a[i][i] *= 1.0L + (gr_real)tol;
    }
    return k == 0 || gr_ldl(k, a, gr_ws.psdL, D, 0);
}

// ---- small dense helpers in double (generation only) ---------------------

typedef double gr_m3[3][3];

static inline void gr_mmul(int n, int k, int p, double a[3][3], double b[3][3],
                           double out[3][3])
{
    double r[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < p; j++) {
            for (int l = 0; l < k; l++) {
                r[i][j] += a[i][l] * b[l][j];
            }
        }
    }
    memcpy(out, r, sizeof r);
}

// A random orthogonal n x n matrix (Gram-Schmidt on Gaussian columns),
// n <= GR_N, into q with rows ld apart.
static inline void gr_orth(gr_rng *r, int n, double *q, int ld)
{
    for (int j = 0; j < n; j++) {
        for (;;) {
            double v[GR_N];
            for (int i = 0; i < n; i++) {
                v[i] = gr_normal(r);
            }
            for (int k = 0; k < j; k++) {
                double d = 0;
                for (int i = 0; i < n; i++) {
                    d += v[i] * q[i * ld + k];
                }
                for (int i = 0; i < n; i++) {
                    v[i] -= d * q[i * ld + k];
                }
            }
            double nn = 0;
            for (int i = 0; i < n; i++) {
                nn += v[i] * v[i];
            }
            if (nn > 1e-6) {
                for (int i = 0; i < n; i++) {
                    q[i * ld + j] = v[i] / sqrt(nn);
                }
                break;
            }
        }
    }
}

// f (n x n) with f f^T a random correlation-like matrix whose eigenvalues
// are spread log-uniformly over [1 / cond, 1] (rank-deficient: the last
// n - rank eigenvalues are 0), rows normalised so that (f f^T)_ii = 1.
static inline void gr_corr_factor(gr_rng *r, int n, double cond, int rank,
                                  double f[3][3])
{
    double q[3][3];
    gr_orth(r, n, &q[0][0], 3);
    double lam[3];
    for (int i = 0; i < n; i++) {
        double t = n > 1 ? (double)i / (double)(n - 1) : 0.0;
        lam[i] = i < rank ? gr_exp(-t * gr_log(cond)) : 0.0;
    }
    if (rank >= 2 && n == 3 && rank == 3) {
        lam[1] = gr_exp(-gr_unif(r) * gr_log(cond)); // middle one anywhere
    }
    for (int i = 0; i < n; i++) {
        double nn = 0;
        for (int j = 0; j < n; j++) {
            f[i][j] = q[i][j] * sqrt(lam[j]);
            nn += f[i][j] * f[i][j];
        }
        for (int j = 0; j < n && nn > 0; j++) {
            f[i][j] /= sqrt(nn);
        }
    }
}

// ---- scenarios ------------------------------------------------------------

enum gr_kind {
    GR_KF2,      // KF2, linear motion, m = 1 or 2
    GR_EKF3_LIN, // EKF3 with the test's linear motion and measurement
    GR_EKF3_TURN // EKF3 with gf_ekf3_motion_forward_turn, linear measurement
};

// One scenario: a prior, a motion and a measurement model, fixed for the
// run, and a simulated truth that produces the measurements. Every gf_real
// field is an input as the filters see it.
typedef struct gr_scen {
    int kind, n, m;
    int pre;     // predictions without a measurement before the first update
    int steps;   // then this many predict + update steps
    int compare; // 1: the errors against the reference are asserted
    int q_pd;    // 1: Q positive definite, correlation form's eigenvalues
                 // >= 1 / GR_QCOND (a well-posed update, see below)
    gf_real mu0[3], S0[3][3];
    gf_real A[3][3], c[3], R[3][3]; // linear motion (KF2, EKF3_LIN)
    gf_real u[2];                   // forward_turn: distance and turn
    gf_real H[3][3], Q[3][3];       // measurement, m x n and m x m
    // The truth and the factors that draw its noise (double).
    double x[3], fr[3][3], fq[3][3];
    gr_rng rng;
} gr_scen;

// mu_bar = g(u, x) of forward_turn, in double, for the truth.
static inline void gr_turn_d(const double x[3], const gf_real u[2],
                             double out[3])
{
    double d = (double)u[0], s, c;
    gr_sincos(x[2], &s, &c);
    out[0] = x[0] + d * c;
    out[1] = x[1] + d * s;
    out[2] = x[2] + (double)u[1];
}

// Draws scenario number `index` of family `kind` from `seed`. The rounding
// to gf_real happens here, once.
static inline void gr_scen_make(gr_scen *sc, int kind, uint64_t seed,
                                unsigned index, int long_runs)
{
    memset(sc, 0, sizeof *sc);
    gr_rng *r = &sc->rng;
    r->s = seed ^ (0x100000001B3ull * (uint64_t)(index + 1)) ^
           ((uint64_t)kind << 56);
    (void)gr_next(r);
    const int n = kind == GR_KF2 ? 2 : 3;
    sc->kind = kind;
    sc->n = n;
    sc->m = 1 + (int)gr_below(r, kind == GR_KF2 ? 2u : 3u);
    const int m = sc->m;
    sc->compare = 1;
    // One run in eight is a long run without measurements.
    sc->pre = (long_runs && gr_below(r, 8) == 0) ? long_runs : 0;
    sc->steps = sc->pre ? 3 : 12;

    // Units: state i in units of unit[i]; EKF3's x and y share theirs (a
    // turn mixes them) and its heading stays in radians (it is wrapped).
    double unit[3], zunit[3];
    for (int i = 0; i < 3; i++) {
        unit[i] = gr_logu(r, 1.0 / GR_UNIT, GR_UNIT);
        zunit[i] = gr_logu(r, 1.0 / GR_UNIT, GR_UNIT);
    }
    if (kind != GR_KF2) {
        unit[1] = unit[0];
        unit[2] = 1.0;
    }
    if (kind == GR_EKF3_TURN) {
        zunit[2] = 1.0; // a measured heading is an angle, in radians
    }

    // Prior: std devs (in units) spread over 1e-2..1e2, correlation form
    // with condition number log-uniform in [1, GR_COND_MAX].
    double sd[3], f[3][3], s0[3][3];
    for (int i = 0; i < n; i++) {
        sd[i] = unit[i] * gr_logu(r, 1e-2, 1e2);
    }
    int turn = kind == GR_EKF3_TURN;
    double cond = gr_logu(r, 1.0, GR_COND_MAX);
    if (turn) {
        // The heading's variance small enough that one step's
        // linearisation (d^2 sigma_theta^2 against sigma_x^2) does not
        // dominate; a separate set of diffuse headings is not compared.
        double sxy = sd[0] < sd[1] ? sd[0] : sd[1];
        sd[2] = gr_logu(r, 1e-4, 1.0);
        double d = unit[0] * gr_logu(r, 1e-2, 10.0);
        if (d * sd[2] > sxy) {
            d = sxy / sd[2];
        }
        sc->u[0] = (gf_real)(gr_unif(r) < 0.5 ? -d : d);
        sc->u[1] = (gf_real)(0.3 * gr_normal(r));
        if (gr_below(r, 6) ==
            0) { // diffuse heading: a prior that refused float updates
            sd[0] = sd[1] = unit[0] * gr_logu(r, 1e-2, 1.0);
            sd[2] = gr_logu(r, 1.0, 316.0);
            sc->u[0] = (gf_real)(unit[0] * gr_logu(r, 0.1, 10.0));
            cond = 1.0;
            sc->compare = 0;
        }
    }
    gr_corr_factor(r, n, cond, n, f);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            f[i][j] *= sd[i];
        }
    }
    double ft[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            ft[i][j] = f[j][i];
        }
    }
    gr_mmul(n, n, n, f, ft, s0);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j <= i; j++) {
            gf_real v = (gf_real)(0.5 * (s0[i][j] + s0[j][i]));
            sc->S0[i][j] = sc->S0[j][i] = v;
        }
    }
    // mean and truth: truth = mu0 + f w
    for (int i = 0; i < n; i++) {
        sc->mu0[i] = (gf_real)(sd[i] * gr_normal(r));
    }
    for (int i = 0; i < n; i++) {
        double w = 0;
        for (int j = 0; j < n; j++) {
            w += f[i][j] * gr_normal(r);
        }
        sc->x[i] = (double)sc->mu0[i] + w;
    }

    // Motion A = D A0 D^-1, A0 = V T V^T, T upper triangular with
    // eigenvalues in [0.5, 1.3] (unstable up to 1.3; [0.9, 1.02] for long
    // runs) and off-diagonals N(0, 0.3^2); c = D N(0, 0.1^2).
    double v[3][3], t[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, a0[3][3];
    gr_orth(r, n, &v[0][0], 3);
    double lmax = sc->pre ? 1.02 : 1.3;
    for (int i = 0; i < n; i++) {
        // Long runs: no eigenvalue below 0.9, so that 100 predictions
        // keep every variance a normal number.
        double lmin = sc->pre ? 0.9 : 0.5;
        t[i][i] = lmin + (lmax - lmin) * gr_unif(r);
        if (gr_unif(r) < 0.2) {
            t[i][i] = -t[i][i];
        }
        for (int j = i + 1; j < n; j++) {
            t[i][j] = (sc->pre ? 0.03 : 0.3) * gr_normal(r);
        }
    }
    double vt[3][3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            vt[i][j] = v[j][i];
        }
    }
    gr_mmul(n, n, n, v, t, a0);
    gr_mmul(n, n, n, a0, vt, a0);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            sc->A[i][j] = (gf_real)(unit[i] * a0[i][j] / unit[j]);
        }
        sc->c[i] = (gf_real)(0.1 * unit[i] * gr_normal(r));
    }
    // Process noise: rank 0..n, variances 1e-8..1 of the prior's.
    {
        int rank = (int)gr_below(r, (unsigned)n + 1);
        double fr[3][3], rr[3][3];
        gr_corr_factor(r, n, gr_logu(r, 1.0, 1e3), rank, fr);
        double rs = gr_logu(r, 1e-8, 1.0);
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++) {
                fr[i][j] *= sd[i] * sqrt(rs);
            }
        }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                ft[i][j] = fr[j][i];
            }
        }
        gr_mmul(n, n, n, fr, ft, rr);
        for (int i = 0; i < n; i++) {
            for (int j = 0; j <= i; j++) {
                gf_real e = (gf_real)(0.5 * (rr[i][j] + rr[j][i]));
                sc->R[i][j] = sc->R[j][i] = e;
            }
        }
        memcpy(sc->fr, fr, sizeof fr);
    }
    // Measurement H = E H0 D^-1, H0 rows N(0, 1) (for EKF3_TURN and one
    // scenario in four the identity rows: a position fix).
    double h0[3][3];
    int ident = turn || gr_below(r, 4) == 0;
    int perm = (int)gr_below(r, 3);
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < n; j++) {
            h0[i][j] = ident ? (j == (i + perm) % n ? 1.0 : 0.0) : gr_normal(r);
        }
    }
    if (turn) { // x, y and the heading
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < n; j++) {
                h0[i][j] = i == j ? 1.0 : 0.0;
            }
        }
    }
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < n; j++) {
            sc->H[i][j] = (gf_real)(zunit[i] * h0[i][j] / unit[j]);
        }
    }
    // Q: correlated, its scale set by the prior/noise ratio in measurement
    // space: Q_ii = (H S0 H^T)_ii / ratio, ratio log-uniform in [1e-2,
    // GR_RATIO_MAX]. One in five is rank-deficient (rank m - 1, or 0 when
    // m is 1: a noiseless measurement).
    {
        int rank = m;
        sc->q_pd = 1;
        if (gr_below(r, 5) == 0) {
            rank = m - 1;
            sc->q_pd = 0;
        }
        double fq[3][3], hs[3][3], hsh[3][3], ht[3][3], qq[3][3];
        double hd[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < n; j++) {
                hd[i][j] = (double)sc->H[i][j];
            }
        }
        gr_mmul(m, n, n, hd, s0, hs);
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                ht[i][j] = hd[j][i];
            }
        }
        gr_mmul(m, n, m, hs, ht, hsh);
        gr_corr_factor(r, m, gr_logu(r, 1.0, GR_QCOND), rank, fq);
        for (int i = 0; i < m; i++) {
            double ratio = gr_logu(r, 1e-2, GR_RATIO_MAX);
            double qs = sqrt(hsh[i][i] / ratio);
            for (int j = 0; j < m; j++) {
                fq[i][j] *= qs;
            }
        }
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) {
                ft[i][j] = fq[j][i];
            }
        }
        gr_mmul(m, m, m, fq, ft, qq);
        for (int i = 0; i < m; i++) {
            for (int j = 0; j <= i; j++) {
                gf_real e = (gf_real)(0.5 * (qq[i][j] + qq[j][i]));
                sc->Q[i][j] = sc->Q[j][i] = e;
            }
        }
        memcpy(sc->fq, fq, sizeof fq);
    }
}

// Advances the truth by one prediction (with its noise).
static inline void gr_scen_move(gr_scen *sc)
{
    const int n = sc->n;
    double x[3] = {0, 0, 0};
    if (sc->kind == GR_EKF3_TURN) {
        gr_turn_d(sc->x, sc->u, x);
    } else {
        for (int i = 0; i < n; i++) {
            x[i] = (double)sc->c[i];
            for (int j = 0; j < n; j++) {
                x[i] += (double)sc->A[i][j] * sc->x[j];
            }
        }
    }
    double w[3];
    for (int j = 0; j < n; j++) {
        w[j] = gr_normal(&sc->rng);
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            x[i] += sc->fr[i][j] * w[j];
        }
    }
    memcpy(sc->x, x, sizeof x);
}

// A measurement of the truth: z = H x + fq v, rounded to gf_real.
static inline void gr_scen_measure(gr_scen *sc, gf_real z[3])
{
    double v[3];
    for (int j = 0; j < sc->m; j++) {
        v[j] = gr_normal(&sc->rng);
    }
    for (int i = 0; i < 3; i++) {
        double zi = 0;
        if (i < sc->m) {
            for (int j = 0; j < sc->n; j++) {
                zi += (double)sc->H[i][j] * sc->x[j];
            }
            for (int j = 0; j < sc->m; j++) {
                zi += sc->fq[i][j] * v[j];
            }
        }
        z[i] = (gf_real)zi;
    }
}

// ---- the reference on a scenario -------------------------------------------

// The residual row that is a heading: forward_turn's third measured
// quantity (EKF3 measures it with angle_mask bit 2 set), else -1.
static inline int gr_angle_row(const gr_scen *sc)
{
    return (sc->kind == GR_EKF3_TURN && sc->m == 3) ? 2 : -1;
}

// The reference (eps = 0) or a perturbed copy at the scenario's prior.
static inline void gr_filt_init(gr_filt *f, const gr_scen *sc, double eps,
                                uint64_t seed)
{
    gr_ref_init(f, sc->n, sc->mu0, (const gf_real *)sc->S0, 3, eps, seed);
    f->angle_row = gr_angle_row(sc);
}

// The scenario's prediction: its linear model's, or forward_turn's, mu =
// g(u, mu), G = dg/dx at mu, P = G P G^T + R, at the reference's own
// heading (gr_sincos, in double: its error of a few ulps of double is far
// below float's, and below the double build's perturbations).
static inline void gr_predict_scen(gr_filt *f, const gr_scen *sc)
{
    if (sc->kind != GR_EKF3_TURN) {
        gr_predict(f, (const gf_real *)sc->A, NULL, NULL, 0, sc->c,
                   (const gf_real *)sc->R, 3);
        return;
    }
    gr_real dist = gr_in(f, sc->u[0]), phi = gr_in(f, sc->u[1]);
    double sd, cd;
    gr_sincos((double)f->mu[2], &sd, &cd);
    gr_real s = (gr_real)sd, co = (gr_real)cd;
    gr_real(*g)[GR_N] = gr_ws.a;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            g[i][j] = i == j ? 1.0L : 0.0L;
        }
    }
    g[0][2] = -dist * s;
    g[1][2] = dist * co;
    gr_real mu[3] = {f->mu[0] + dist * co, f->mu[1] + dist * s, f->mu[2] + phi};
    gr_predict_cov(f, g, mu, (const gf_real *)sc->R, 3);
}

// The scenario's update with the measurement z (gr_update).
static inline int gr_update_scen(gr_filt *f, const gr_scen *sc,
                                 const gf_real z[3], gr_real *nis)
{
    return gr_update(f, sc->m, (const gf_real *)sc->H, 3,
                     (const gf_real *)sc->Q, 3, z, NULL, nis);
}

// ---- a textbook Joseph filter in gf_real ----------------------------------
//
// What a careful engineer writes from the book: the batch update with S
// inverted (through its Cholesky factor), K = Sigma H^T S^-1, the Joseph
// sandwich (I - K H) Sigma (I - K H)^T + K Q K^T, symmetrized; predictions
// as products. Its heading is never wrapped. It refuses an update when a
// pivot of S is not positive or a result is not finite. Used to calibrate
// the bound (a textbook filter must meet it) and by bench/accuracy.c.
typedef struct gr_tb {
    int n, angle_row;
    gf_real mu[3], P[3][3];
} gr_tb;

static inline void gr_tb_init(gr_tb *t, const gr_scen *sc)
{
    memset(t, 0, sizeof *t);
    t->n = sc->n;
    t->angle_row = gr_angle_row(sc);
    memcpy(t->mu, sc->mu0, sizeof t->mu);
    memcpy(t->P, sc->S0, sizeof t->P);
}

static inline void gr_tb_predict(gr_tb *t, const gr_scen *sc)
{
    const int n = t->n;
    gf_real G[3][3], mu[3], GP[3][3];
    if (sc->kind == GR_EKF3_TURN) {
        gf_real s, c;
        gf_sincos(t->mu[2], &s, &c);
        gf_real g[3][3] = {
            {1, 0, -sc->u[0] * s}, {0, 1, sc->u[0] * c}, {0, 0, 1}};
        memcpy(G, g, sizeof G);
        mu[0] = t->mu[0] + sc->u[0] * c;
        mu[1] = t->mu[1] + sc->u[0] * s;
        mu[2] = t->mu[2] + sc->u[1];
    } else {
        memcpy(G, sc->A, sizeof G);
        for (int i = 0; i < n; i++) {
            mu[i] = sc->c[i];
            for (int j = 0; j < n; j++) {
                mu[i] += G[i][j] * t->mu[j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            GP[i][j] = 0;
            for (int k = 0; k < n; k++) {
                GP[i][j] += G[i][k] * t->P[k][j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        t->mu[i] = mu[i];
        for (int j = 0; j <= i; j++) {
            gf_real v = sc->R[i][j];
            for (int k = 0; k < n; k++) {
                v += GP[i][k] * G[j][k];
            }
            t->P[i][j] = t->P[j][i] = v;
        }
    }
}

// Returns 1 if accepted. With gate > 0, an update whose NIS y^T S^-1 y
// (in gf_real) exceeds it is refused too (*gated set to 1).
static inline int gr_tb_update_gated(gr_tb *t, const gr_scen *sc,
                                     const gf_real z[3], gf_real gate,
                                     int *gated)
{
    const int n = t->n, m = sc->m;
    gf_real PH[3][3], S[3][3], L[3][3], Si[3][3], K[3][3], M[3][3], y[3];
    memset(L, 0, sizeof L);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < m; j++) {
            PH[i][j] = 0;
            for (int k = 0; k < n; k++) {
                PH[i][j] += t->P[i][k] * sc->H[j][k];
            }
        }
    }
    for (int i = 0; i < m; i++) {
        for (int j = 0; j < m; j++) {
            S[i][j] = sc->Q[i][j];
            for (int k = 0; k < n; k++) {
                S[i][j] += sc->H[i][k] * PH[k][j];
            }
        }
    }
    for (int j = 0; j < m; j++) { // Cholesky S = L L^T
        for (int i = j; i < m; i++) {
            gf_real v = GF_R(0.5) * (S[i][j] + S[j][i]);
            for (int k = 0; k < j; k++) {
                v -= L[i][k] * L[j][k];
            }
            if (i == j) {
                if (!(v > 0) || !GF_ISFINITE(v)) {
                    return 0;
                }
                L[j][j] = GF_SQRT(v);
            } else {
                L[i][j] = v / L[j][j];
            }
        }
    }
    for (int j = 0; j < m; j++) { // S^-1 column by column
        gf_real x[3];
        for (int i = 0; i < m; i++) {
            x[i] = i == j ? GF_R(1.0) : GF_R(0.0);
            for (int k = 0; k < i; k++) {
                x[i] -= L[i][k] * x[k];
            }
            x[i] /= L[i][i];
        }
        for (int i = m - 1; i >= 0; i--) {
            for (int k = i + 1; k < m; k++) {
                x[i] -= L[k][i] * x[k];
            }
            x[i] /= L[i][i];
        }
        for (int i = 0; i < m; i++) {
            Si[i][j] = x[i];
        }
    }
    for (int i = 0; i < m; i++) {
        y[i] = z[i];
        for (int k = 0; k < n; k++) {
            y[i] -= sc->H[i][k] * t->mu[k];
        }
        if (i == t->angle_row) {
            y[i] = gf_angle_wrap(y[i]);
        }
    }
    *gated = 0;
    if (gate > 0) {
        gf_real nis = 0;
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++) {
                nis += y[i] * Si[i][j] * y[j];
            }
        }
        if (!(nis <= gate)) {
            *gated = 1;
            return 0;
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < m; j++) {
            K[i][j] = 0;
            for (int k = 0; k < m; k++) {
                K[i][j] += PH[i][k] * Si[k][j];
            }
        }
        for (int j = 0; j < n; j++) {
            M[i][j] = i == j ? GF_R(1.0) : GF_R(0.0);
            for (int k = 0; k < m; k++) {
                M[i][j] -= K[i][k] * sc->H[k][j];
            }
        }
    }
    gf_real mu[3], MP[3][3], P[3][3];
    for (int i = 0; i < n; i++) {
        mu[i] = t->mu[i];
        for (int k = 0; k < m; k++) {
            mu[i] += K[i][k] * y[k];
        }
        for (int j = 0; j < n; j++) {
            MP[i][j] = 0;
            for (int k = 0; k < n; k++) {
                MP[i][j] += M[i][k] * t->P[k][j];
            }
        }
    }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            gf_real v = 0;
            for (int k = 0; k < n; k++) {
                v += MP[i][k] * M[j][k];
            }
            for (int a = 0; a < m; a++) {
                for (int b = 0; b < m; b++) {
                    v += K[i][a] * sc->Q[a][b] * K[j][b];
                }
            }
            P[i][j] = v;
            if (!GF_ISFINITE(v) || !GF_ISFINITE(mu[i])) {
                return 0;
            }
        }
    }
    for (int i = 0; i < n; i++) {
        t->mu[i] = mu[i];
        for (int j = 0; j < n; j++) {
            t->P[i][j] = GF_R(0.5) * (P[i][j] + P[j][i]);
        }
    }
    return 1;
}

static inline int gr_tb_update(gr_tb *t, const gr_scen *sc, const gf_real z[3])
{
    int gated;
    return gr_tb_update_gated(t, sc, z, 0, &gated);
}

#endif
