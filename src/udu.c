// SPDX-License-Identifier: MIT
// The factored covariance's steps (udu.h), written once for any n.
#include <stddef.h>

#include "udu.h"

#include "gf_internal.h"

// ---- init: the factors of a covariance ----------------------------------

// Veltkamp's splitting constant for gf_real's p-bit significand,
// 2^ceil(p / 2) + 1: a = ah + al with ah and al of at most p / 2 bits,
// whose products are exact.
#ifdef GF_SINGLE_PRECISION
#define UDU_SPLIT GF_R(4097.0) // 2^12 + 1
#else
#define UDU_SPLIT GF_R(134217729.0) // 2^27 + 1
#endif

// a b - p for p = fl(a b), exactly (Dekker's TwoProduct: + - * only, each
// rounded to nearest, none fused); 0 where a split leaves the range (|a|
// or |b| beyond the largest gf_real / UDU_SPLIT): no correction there.
static gf_real udu_prod_err(gf_real a, gf_real b, gf_real p)
{
    const gf_real ca = UDU_SPLIT * a, cb = UDU_SPLIT * b;
    const gf_real ah = ca - (ca - a), bh = cb - (cb - b);
    const gf_real al = a - ah, bl = b - bh;
    const gf_real e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    return GF_ISFINITE(e) ? e : GF_R(0.0);
}

// a + b - t for t = fl(a + b), exactly (Knuth's TwoSum).
static gf_real udu_sum_err(gf_real a, gf_real b, gf_real t)
{
    const gf_real bb = t - a;
    return (a - (t - bb)) + (b - bb);
}

// x - sum_(k>j) U_ik d_k U_jk in about twice gf_real's precision: the sum
// as a plain loop gives the return value, and *err collects its roundings
// (TwoSum, TwoProduct) and the low parts of the factors it reads (lo:
// U_ik + lo_ik, d_k + lo_kk) to first order, as Ogita, Rump and Oishi's
// compensated dot product does. *err is 0 where it is not finite.
static gf_real udu_schur(gf_real x, const gf_real *ud, const gf_real *lo,
                         unsigned n, unsigned i, unsigned j, gf_real *err)
{
    gf_real acc = x, e = 0;
    for (unsigned k = j + 1u; k < n; k++) {
        const gf_real a = ud[GF_UD(i, k)], d = ud[GF_UD(k, k)];
        const gf_real b = ud[GF_UD(j, k)];
        const gf_real t1 = a * d, t = t1 * b, next = acc - t;
        // a d b (with the low parts) - t
        const gf_real c = udu_prod_err(t1, b, t) + udu_prod_err(a, d, t1) * b +
                          t1 * lo[GF_UD(j, k)] +
                          (lo[GF_UD(i, k)] * d + a * lo[GF_UD(k, k)]) * b;
        e += udu_sum_err(acc, -t, next) - c;
        acc = next;
    }
    *err = GF_ISFINITE(e) ? e : GF_R(0.0);
    return acc;
}

void gf_udu_factor(const gf_real *s, unsigned stride, unsigned n, gf_real *ud,
                   unsigned char *perm, gf_real *work)
{
    gf_real *lo = work; // the factors' low parts
    for (unsigned k = 0; k < n; k++) {
        perm[k] = (unsigned char)(n - 1u - k);
    }
    for (unsigned k = n; k < (unsigned)sizeof(gf_real); k++) {
        perm[k] = 0; // a belief's unused bytes, set
    }
    for (unsigned j = n; j-- > 0u;) {
        const unsigned sj = perm[j];
        gf_real dl;
        const gf_real d0 = udu_schur(s[sj * stride + sj], ud, lo, n, j, j, &dl);
        // d_j = dj + dl, dj rounded to nearest
        gf_real dj = d0 + dl;
        dl = udu_sum_err(d0, dl, dj);
        if (!GF_ISFINITE(dl)) {
            dl = 0;
        }
        const int pos = !(dj < GF_REAL_MIN);
        for (unsigned i = 0; i < j; i++) {
            const unsigned si = perm[i];
            gf_real rl;
            const gf_real r =
                udu_schur(s[(si < sj ? si : sj) * stride + (si < sj ? sj : si)],
                          ud, lo, n, i, j, &rl);
            // U_ij = (r + rl) / (dj + dl) = q + ql
            gf_real q = 0, ql = 0;
            if (pos) {
                q = r / dj;
                const gf_real p = q * dj;
                ql = (((r - p) - udu_prod_err(q, dj, p)) + rl - q * dl) / dj;
                if (!GF_ISFINITE(ql)) {
                    ql = 0;
                }
                const gf_real u = q + ql;
                ql = udu_sum_err(q, ql, u);
                q = u;
                if (!GF_ISFINITE(ql)) {
                    ql = 0;
                }
            }
            ud[GF_UD(i, j)] = q;
            lo[GF_UD(i, j)] = ql;
        }
        ud[GF_UD(j, j)] = pos ? dj : GF_R(0.0);
        lo[GF_UD(j, j)] = pos ? dl : GF_R(0.0);
    }
}

// ---- the accessor -------------------------------------------------------

void gf_udu_to_cov(const gf_real *ud, const unsigned char *perm, unsigned n,
                   gf_real *s, unsigned stride)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real acc = 0;
            for (unsigned k = j; k < n; k++) {
                const gf_real uik = (k == i) ? GF_R(1.0) : ud[GF_UD(i, k)];
                const gf_real ujk = (k == j) ? GF_R(1.0) : ud[GF_UD(j, k)];
                acc += uik * ud[GF_UD(k, k)] * ujk;
            }
            s[perm[i] * stride + perm[j]] = acc;
            s[perm[j] * stride + perm[i]] = acc;
        }
    }
    for (unsigned i = 0; i < n; i++) {
        if (s[i * stride + i] < GF_REAL_MIN) {
            for (unsigned j = 0; j < n; j++) {
                s[i * stride + j] = 0;
                s[j * stride + i] = 0;
            }
        }
    }
}

int gf_belief_finite(const gf_real *mu, const gf_real *ud, unsigned n)
{
    // mu, and each variance sum_(k >= i) U_ik d_k U_ik as gf_udu_to_cov
    // computes it: every factor is a term of one of them, so a factor that
    // is not finite makes its variance NaN or infinite, as does a variance
    // beyond the largest gf_real
    gf_real acc = gf_nan_sum(GF_R(0.0), mu, n);
    for (unsigned i = 0; i < n; i++) {
        gf_real v = ud[GF_UD(i, i)];
        for (unsigned k = i + 1u; k < n; k++) {
            v += ud[GF_UD(i, k)] * ud[GF_UD(k, k)] * ud[GF_UD(i, k)];
        }
        acc += v * GF_R(0.0);
    }
    return gf_sum_finite(acc);
}

// ---- prediction: Thornton's time update ---------------------------------

// The modified weighted Gram-Schmidt: the factors U D U^T (into ud) of
// W diag(wd) W^T, W n rows of cols, from the last row up:
//   c = diag(wd) w_j,  d_j = w_j . c,
//   U_ij = (w_i . c) / d_j,  w_i -= U_ij w_j   (i < j).
// Each d_j is a weighted sum of squares: never negative. A d_j below
// GF_REAL_MIN is zero, with a zero column of U: that state is known
// exactly once the later ones are; a NaN (from a NaN or an infinity in W)
// is kept, for the filter's test of the result to refuse (at n = 1 it is
// the only trace). w is overwritten; c: scratch of cols.
static void udu_mwgs(unsigned n, unsigned cols, gf_real *w, const gf_real *wd,
                     gf_real *ud, gf_real *c)
{
    for (unsigned j = n; j-- > 0u;) {
        const gf_real *wj = &w[(size_t)j * cols];
        gf_real dj = 0;
        for (unsigned k = 0; k < cols; k++) {
            c[k] = wd[k] * wj[k];
            dj += wj[k] * c[k];
        }
        if (dj < GF_REAL_MIN) {
            dj = 0;
        }
        const gf_real inv = (dj > 0) ? GF_R(1.0) / dj : GF_R(0.0);
        ud[GF_UD(j, j)] = dj;
        for (unsigned i = j; i-- > 0u;) { // (each row on its own)
            gf_real *wi = &w[(size_t)i * cols];
            gf_real acc = 0;
            for (unsigned k = 0; k < cols; k++) {
                acc += wi[k] * c[k];
            }
            const gf_real uij = acc * inv;
            for (unsigned k = 0; k < cols; k++) {
                wi[k] -= uij * wj[k];
            }
            ud[GF_UD(i, j)] = uij;
        }
    }
}

// Thornton's W = [P^T A P U | P^T F_R] (n rows of 2n) and its weights
// wd = [D | d_R] into work, as gf_udu_predict lays them out; work's last
// 2n entries are not written. Kept out of line: its frame does not sit
// under the Gram-Schmidt's.
GF_NOINLINE void udu_thornton_w(unsigned n, const gf_real *ud,
                                const unsigned char *perm, const gf_real *A,
                                const gf_real *Rf, const gf_real *Rd,
                                gf_real *work)
{
    const unsigned cols = 2u * n;
    gf_real *w = work, *wd = &work[(size_t)n * cols];
    for (unsigned j = 0; j < n; j++) {
        wd[j] = ud[GF_UD(j, j)];
        wd[n + j] = Rd[j];
    }
    // (P^T A P U)_ij = A_(pi)(pj) + sum_(l<j) A_(pi)(pl) U_lj, and P^T F_R
    for (unsigned i = 0; i < n; i++) {
        const gf_real *ai = &A[(size_t)perm[i] * n];
        gf_real *wi = &w[(size_t)i * cols];
        for (unsigned l = 0; l < n; l++) {
            wi[n + l] = Rf[perm[i] * n + l];
        }
        for (unsigned j = 0; j < n; j++) {
            gf_real acc = ai[perm[j]];
            for (unsigned l = 0; l < j; l++) {
                acc += ai[perm[l]] * ud[GF_UD(l, j)];
            }
            wi[j] = acc;
        }
    }
}

void gf_udu_predict(unsigned n, const gf_real *ud, gf_real *ud_new,
                    const unsigned char *perm, const gf_real *A,
                    const gf_real *Rf, const gf_real *Rd, gf_real *work)
{
    const unsigned cols = 2u * n;
    gf_real *w = work;                           // W, n rows of 2n
    gf_real *wd = &work[(size_t)n * cols];       // its weights, 2n
    gf_real *c = &work[((size_t)n + 1u) * cols]; // mwgs's scratch, 2n
    udu_thornton_w(n, ud, perm, A, Rf, Rd, work);
    udu_mwgs(n, cols, w, wd, ud_new, c);
}

// ---- correction: Bierman's scalar update --------------------------------

// A correction makes the state its quantity measures most the root of the
// factors when the quantity tells more than this (sum_s h_s^2 Sigma_ss /
// e_i: by how much it can shrink a variance); below, Bierman's update
// loses fewer digits than this ratio, and the factors keep their order.
#define UDU_ROOT_TELL GF_R(16.0)

void gf_udu_whiten(const gf_real *F, const unsigned *order, unsigned m,
                   gf_real *x, unsigned cols)
{
    for (unsigned t = 1; t < m; t++) {
        gf_real *xi = &x[(size_t)order[t] * cols];
        for (unsigned u = 0; u < t; u++) {
            const unsigned k = order[u];
            const gf_real fik = F[order[t] * m + k];
            if (!(GF_FABS(fik) > 0)) {
                continue; // (x finite: subtracting 0 x changes nothing)
            }
            for (unsigned c = 0; c < cols; c++) {
                xi[c] -= fik * x[k * cols + c];
            }
        }
    }
}

// The state measured by the row h (by state) with the largest share of
// h Sigma h^T, h_s^2 Sigma_ss (Sigma_ss = sum_(k >= i) U_ik^2 d_k for the
// state s = perm[i]); *total the sum of the shares.
static unsigned udu_main_state(unsigned n, const gf_real *ud,
                               const unsigned char *perm, const gf_real *h,
                               gf_real *total)
{
    unsigned best = 0;
    gf_real most = -1, acc = 0;
    for (unsigned i = 0; i < n; i++) {
        gf_real v = ud[GF_UD(i, i)];
        for (unsigned k = i + 1u; k < n; k++) {
            v += ud[GF_UD(i, k)] * ud[GF_UD(i, k)] * ud[GF_UD(k, k)];
        }
        const unsigned s = perm[i];
        const gf_real part = h[s] * h[s] * v;
        acc += part;
        if (part > most) {
            most = part;
            best = s;
        }
    }
    *total = acc;
    return best;
}

void gf_udu_swap(unsigned n, unsigned k, gf_real *ud, unsigned char *perm)
{
    const unsigned ok = GF_UD(0u, k), ol = GF_UD(0u, k + 1u);
    const gf_real a = ud[ol + k], dk = ud[ok + k], dl = ud[ol + k + 1u];
    const gf_real dq = dk + a * a * dl;
    gf_real r = 0, sk = 0, dp = dl;
    if (dq >= GF_REAL_MIN) {
        const gf_real inv = GF_R(1.0) / dq;
        r = dl * inv;
        sk = dk * inv;
        dp = dk * r;
    }
    const gf_real beta = a * r;
    const int zk = dp < GF_REAL_MIN;
    for (unsigned i = 0; i < k; i++) {
        const gf_real uk = ud[ok + i], ul = ud[ol + i];
        ud[ok + i] = zk ? GF_R(0.0) : ul - a * uk;
        ud[ol + i] = sk * uk + beta * ul;
    }
    ud[ok + k] = zk ? GF_R(0.0) : dp;
    ud[ol + k] = beta;
    ud[ol + k + 1u] = (dq < GF_REAL_MIN) ? GF_R(0.0) : dq;
    for (unsigned j = k + 2u; j < n; j++) {
        const unsigned oj = GF_UD(0u, j);
        const gf_real t = ud[oj + k];
        ud[oj + k] = ud[oj + k + 1u];
        ud[oj + k + 1u] = t;
    }
    const unsigned char t = perm[k];
    perm[k] = perm[k + 1u];
    perm[k + 1u] = t;
}

// One scalar correction (Bierman's update), in place on ud, for the
// measured quantity z = h x + v, v ~ N(0, r), r >= 0, whose innovation at
// the current mean is y; hp = P^T h and dx in the factors' order. With
// f = U^T hp, g = D f and alpha_(-1) = r,
//   alpha_j = alpha_(j-1) + f_j g_j,
//   d_j    <- d_j alpha_(j-1) / alpha_j,
//   U_ij   <- U_ij - b_i f_j / alpha_(j-1),  b_i <- b_i + U_ij g_j (i < j),
//   b_j    =  g_j,
// then K = b / alpha_(n-1), alpha_(n-1) = h Sigma h^T + r = s:
//   dx += K y,  *nis += y^2 / s.
// A zero alpha (an exact quantity, r = 0, on the states taken so far; or
// one below GF_REAL_MIN) leaves U as it is (b is zero there) and d_j as
// it is while alpha stays zero; the first d_j to make it positive becomes
// zero: that direction is now known exactly. A d_j below GF_REAL_MIN
// becomes zero, with its column of U. GF_ERR_NONFINITE if s overflows
// (for r = 0, udu_update_exact has judged s before). b: scratch of n.
static gf_status udu_update(unsigned n, gf_real *ud, const gf_real *hp,
                            gf_real r, gf_real y, gf_real *dx, gf_real *nis,
                            gf_real *b)
{
    gf_real alpha = r, inv_prev = 0;
    gf_real *uj = ud; // column j: uj[i] = U_ij, uj[j] = d_j
    for (unsigned j = 0; j < n; j++) {
        // f_j = (U^T hp)_j
        gf_real fj = hp[j];
        for (unsigned i = 0; i < j; i++) {
            fj += uj[i] * hp[i];
        }
        const gf_real d = uj[j];
        const gf_real gj = d * fj;
        const gf_real a1 = alpha + fj * gj;
        gf_real inv = 0, dj = d;
        if (a1 >= GF_REAL_MIN) { // (a smaller one is zero: 1 / a1 overflows)
            inv = GF_R(1.0) / a1;
            dj = d * (alpha * inv);
        }
        // a d_j below GF_REAL_MIN is zero, with its column of U
        const int zero = dj < GF_REAL_MIN;
        uj[j] = zero ? GF_R(0.0) : dj;
        const gf_real p = -fj * inv_prev;
        for (unsigned i = 0; i < j; i++) {
            const gf_real uij = uj[i];
            uj[i] = zero ? GF_R(0.0) : uij + b[i] * p;
            b[i] += uij * gj;
        }
        b[j] = gj;
        alpha = a1;
        inv_prev = inv;
        uj = &uj[j + 1u]; // column j + 1
    }
    if (!GF_ISFINITE(alpha)) {
        return GF_ERR_NONFINITE;
    }
    const gf_real k = y * inv_prev; // y / s
    *nis += y * k;
    for (unsigned j = 0; j < n; j++) {
        dx[j] += b[j] * k;
    }
    return GF_OK;
}

// The singular verdict's scale of an exact quantity (r = 0) hp, in the
// factors' order, with f = U^T hp (h Sigma h^T = sum_j d_j f_j^2) and
// t_j = |hp_j| + sum_(i<j) |U_ij hp_i|, f_j's terms without their
// cancellations (the same in any units; f into f[0..n), *hsh = h Sigma
// h^T):
//   (n / 8) sum_j d_j t_j^2                      (terms)
//   n sum_j d_j t_j (2 |f_j| + GF_PD_RTOL t_j)   (cancelled)
// The sum is rounded by about 2 n u times sum_j d_j t_j^2 (u the unit
// roundoff); GF_PD_RTOL (64 u) times the first is four times that: a sum
// below it is a rounding residue, or has less than a digit (a direction
// known exactly, or one whose variance the rounding of h or Sigma made).
// The second bounds the sum's rounding to first order (each f_j off by
// about u t_j): for a whitened quantity met after noisy ones of its
// update, which subtracts a large multiple of one of them (a
// rank-deficient Q in units far apart) and so cancels far more than it
// loses; what it measures was judged by the first on the update's prior.
static gf_real udu_exact_scale(unsigned n, const gf_real *ud, const gf_real *hp,
                               int cancelled, gf_real *f, gf_real *hsh)
{
    gf_real scale = 0, acc = 0;
    for (unsigned j = 0; j < n; j++) {
        gf_real fj = hp[j], t = GF_FABS(hp[j]);
        for (unsigned i = 0; i < j; i++) {
            fj += ud[GF_UD(i, j)] * hp[i];
            t += GF_FABS(ud[GF_UD(i, j)] * hp[i]);
        }
        const gf_real w = cancelled ? GF_R(2.0) * GF_FABS(fj) + GF_PD_RTOL * t
                                    : GF_R(0.125) * t;
        scale += ud[GF_UD(j, j)] * t * w;
        acc += ud[GF_UD(j, j)] * fj * fj;
        f[j] = fj;
    }
    *hsh = acc;
    return (gf_real)n * scale;
}

// Below this share of s = h Sigma h^T, the first state an exact quantity
// touches (in the factors' order) leaves Bierman's update too few digits
// (udu_update_exact).
#define UDU_EXACT_SHARE GF_R(0.1)

// The kinds of quantity an update has taken so far (udu_update_exact's
// seen).
#define UDU_SEEN_NOISY 1u
#define UDU_SEEN_EXACT 2u

// One exact quantity (r = 0), in place on ud. Bierman's update gives the
// exact direction to the first state the quantity touches, j0, and then
// loses about log10(s / alpha_j0) digits, alpha_j0 = f_j0^2 d_j0 that
// state's share of s: all of them when the share is a rounding residue an
// earlier exact quantity left. So where alpha_j0 < UDU_EXACT_SHARE s, the
// Joseph form on the factors, triangularised again as a prediction is:
// with f = U^T hp, b = U D f (Sigma h^T in the factors' order),
//   Sigma+ = (I - K h) Sigma (I - K h)^T = W D W^T,  W = U - (b / s) f^T,
// then the modified weighted Gram-Schmidt (each d_j a weighted sum of
// squares; the exact direction's d a rounding residue, not zero), and
//   dx += K y,  *nis += y^2 / s;
// else Bierman's update (udu_update). es: the quantity's S_ii on the
// update's prior (gf_udu_correct), read only after an exact quantity;
// seen: UDU_SEEN_* of the quantities taken before. GF_ERR_NONFINITE if s
// overflows; GF_ERR_SINGULAR if s <= GF_PD_RTOL scale, scale
// udu_exact_scale's (its cancelled form after noisy quantities alone), or
// S_ii if larger after an exact one; nothing written then. The Joseph form
// keeps D in hp, read no more then. b: scratch of n (f, then the modified
// weighted Gram-Schmidt's); w: scratch of n^2.
static gf_status udu_update_exact(unsigned n, gf_real *ud, gf_real *hp,
                                  gf_real es, unsigned seen, gf_real y,
                                  gf_real *dx, gf_real *nis, gf_real *b,
                                  gf_real *w)
{
    // singular when s is zero relative to its own terms, or, after noisy
    // quantities alone, to its rounding; and after exact ones, also when
    // it is zero relative to S_ii
    // f = U^T hp in b's scratch (the vector b below is computed an entry
    // at a time)
    gf_real *f = b, hsh;
    gf_real scale = udu_exact_scale(n, ud, hp, seen == UDU_SEEN_NOISY, f, &hsh);
    scale = ((seen & UDU_SEEN_EXACT) && es > scale) ? es : scale;
    // s in Bierman's order, alpha_j0 = the first alpha_j of at least
    // GF_REAL_MIN (Bierman's test)
    gf_real s = 0, first = 0;
    for (unsigned j = 0; j < n; j++) {
        s += f[j] * (ud[GF_UD(j, j)] * f[j]);
        if (!(first > 0) && s >= GF_REAL_MIN) {
            first = s;
        }
    }
    if (!GF_ISFINITE(s)) {
        return GF_ERR_NONFINITE;
    }
    if (!(s > GF_PD_RTOL * scale)) {
        return GF_ERR_SINGULAR;
    }
    if (!(first < UDU_EXACT_SHARE * s)) {
        // (Bierman's alpha_(n-1) is s: the same sum in the same order)
        return udu_update(n, ud, hp, GF_R(0.0), y, dx, nis, b);
    }
    // D, then b = U D f, W = U - (b / s) f^T
    gf_real *wd = hp;
    for (unsigned j = 0; j < n; j++) {
        wd[j] = ud[GF_UD(j, j)];
    }
    const gf_real inv = GF_R(1.0) / s, k = y * inv; // y / s
    *nis += y * k;
    for (unsigned i = 0; i < n; i++) {
        gf_real acc = wd[i] * f[i];
        for (unsigned j = i + 1u; j < n; j++) {
            acc += ud[GF_UD(i, j)] * (wd[j] * f[j]);
        }
        dx[i] += acc * k;
        const gf_real bi = acc * inv;
        for (unsigned j = 0; j < n; j++) {
            const gf_real uij = (j > i)    ? ud[GF_UD(i, j)]
                                : (j == i) ? GF_R(1.0)
                                           : GF_R(0.0);
            w[(size_t)i * n + j] = uij - bi * f[j];
        }
    }
    udu_mwgs(n, n, w, wd, ud, b);
    return GF_OK;
}

gf_status gf_udu_correct(unsigned n, gf_real *ud, unsigned char *perm,
                         unsigned m, const gf_real *hw, const gf_real *e,
                         const gf_real *yw, gf_real *x, gf_real *nis,
                         gf_real *work)
{
    gf_real *dp = work;                  // P^T dx
    gf_real *hp = &work[n];              // P^T h_i
    gf_real *b = &work[(size_t)2u * n];  // Bierman's b
    gf_real *es = &work[(size_t)3u * n]; // exact quantities' S_ii on the prior
    gf_real *wx = &work[(size_t)4u * n]; // an exact quantity's W
    *nis = 0;
    for (unsigned j = 0; j < n; j++) {
        dp[j] = 0;
    }
    // Of m > 1 quantities, each exact one's h Sigma h^T on the update's
    // prior, sum_j d_j f_j^2 (f = U^T hp): S's diagonal entry, for the
    // verdict in S's correlation form. (One judged only on the factors an
    // earlier exact quantity had left would be judged on residues of its
    // own size when it measures a direction already known exactly.) -1
    // where that entry is zero relative to its terms: S is singular; 0
    // for the exact quantity of m = 1.
    for (unsigned i = 0; i < m; i++) {
        if (!(e[i] > 0)) {
            gf_real acc = 0;
            if (m > 1u) {
                for (unsigned j = 0; j < n; j++) {
                    hp[j] = hw[(size_t)i * n + perm[j]];
                }
                const gf_real sc = udu_exact_scale(n, ud, hp, 0, b, &acc);
                acc = (acc > GF_PD_RTOL * sc || !GF_ISFINITE(acc)) ? acc
                                                                   : GF_R(-1.0);
            }
            es[i] = acc;
        }
    }
    unsigned seen = 0;
    for (unsigned i = 0; i < m; i++) {
        const gf_real *h = &hw[(size_t)i * n];
        // Bierman's update changes no entry of U for the state at the root
        // (the last index), and loses digits in the entries of a state it
        // measures far more precisely than it was known: a quantity that
        // tells more than UDU_ROOT_TELL (sum_s h_s^2 Sigma_ss / e_i: by how
        // much it can shrink a variance) first makes the state it measures
        // most the root, one swap of adjacent indices at a time (dp's
        // entries move with their states).
        gf_real v;
        const unsigned main = udu_main_state(n, ud, perm, h, &v);
        const int to_root = v > UDU_ROOT_TELL * e[i];
        for (unsigned k = 0; to_root && k + 1u < n; k++) {
            if (perm[k] == main) {
                const gf_real dk = dp[k];
                dp[k] = dp[k + 1u];
                dp[k + 1u] = dk;
                gf_udu_swap(n, k, ud, perm);
            }
        }
        // in the factors' order: hp = P^T h_i, y_i = yw_i - h_i . dx
        gf_real yi = yw[i];
        for (unsigned j = 0; j < n; j++) {
            hp[j] = h[perm[j]];
            yi -= hp[j] * dp[j];
        }
        // an exact quantity is singular when its S_ii on the prior is zero
        // (es_i), else as udu_update_exact judges it
        gf_status st;
        if (e[i] > 0) {
            st = udu_update(n, ud, hp, e[i], yi, dp, nis, b);
            seen |= UDU_SEEN_NOISY;
        } else if (es[i] < 0) {
            return GF_ERR_SINGULAR;
        } else {
            st = udu_update_exact(n, ud, hp, es[i], seen, yi, dp, nis, b, wx);
            seen |= UDU_SEEN_EXACT;
        }
        if (st != GF_OK) {
            return st;
        }
    }
    for (unsigned j = 0; j < n; j++) {
        x[perm[j]] += dp[j];
    }
    return GF_OK;
}
