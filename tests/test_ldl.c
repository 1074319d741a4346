// SPDX-License-Identifier: MIT
// The verdict on a covariance passed in (gf_cov_factor): its factors
// multiply back to the matrix, and gf_mat2_check_psd / gf_mat3_check_psd
// give its verdict. On seeded random matrices and edge
// cases: zero variances, rank-deficient, near-singular, indefinite, scaled
// by 2^-60 and 2^60, asymmetric beyond the tolerance, negative variances,
// signed zeros, infinities and NaNs in the triangle read. Also the
// factorisation of a prior (gf_udu_factor) against exact factors, and a
// swap of two indices of the factors (gf_udu_swap) keeping Sigma.
#include <float.h>
#include <math.h>

#include "gf_test.h"

#include "ldl.h"
#include "udu.h"

#define DRAWS 60000

// A sentinel byte pattern for the outputs, so that an entry one path
// writes and the other does not shows.
#define SENTINEL 0x5a

typedef struct {
    gf_real F[9], d[3];
    unsigned order[3];
} factors;

// A random n x n matrix (rows of stride) of one of several kinds.
static void draw(gf_rng *rng, unsigned n, unsigned stride, gf_real *s)
{
    const unsigned kind = gf_rng_u32(rng) % 8u;
    // W W^T of rank r <= n, rows of W zero at random (zero variances)
    double w[3][3] = {{0}};
    const unsigned r = gf_rng_u32(rng) % (n + 1u);
    for (unsigned i = 0; i < n; i++) {
        const int zero_row = gf_rng_u32(rng) % 4u == 0u;
        for (unsigned k = 0; k < r; k++) {
            w[i][k] = zero_row ? 0.0 : gf_test_uniform(rng, -1.0, 1.0);
        }
    }
    const double scale = ldexp(1.0, (int)(gf_rng_u32(rng) % 121u) - 60);
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < stride; j++) {
            double acc = 0.0;
            for (unsigned k = 0; k < n && j < n; k++) {
                acc += w[i][k] * w[j][k];
            }
            s[i * stride + j] = (gf_real)(acc * scale);
        }
    }
    const unsigned i = gf_rng_u32(rng) % n, j = gf_rng_u32(rng) % n;
    switch (kind) {
    case 0: // as it is: positive semidefinite, often singular
        break;
    case 1: { // near-singular: a perturbation at the tolerance's scale
        const gf_real e = (gf_real)(gf_test_uniform(rng, -1.0, 1.0) * 64.0 *
                                    (double)GF_REAL_EPSILON * scale);
        s[i * stride + j] += e;
        s[j * stride + i] = s[i * stride + j];
        break;
    }
    case 2: // a coupling removed: block-diagonal, often indefinite
        s[i * stride + j] = 0;
        s[j * stride + i] = 0;
        break;
    case 3: // a variance negative or zero
        s[i * stride + i] = (gf_rng_u32(rng) % 2u) ? -s[i * stride + i] : 0;
        break;
    case 4: // the lower triangle off from the upper
        if (i != j) {
            s[(i > j ? i : j) * stride + (i > j ? j : i)] *=
                (gf_real)gf_test_uniform(rng, 0.5, 1.5);
        }
        break;
    default: { // random entries, some of them extreme
        static const double special[] = {
            0.0, -0.0, 1.0, -1.0, 1e-7, 3e38, (double)INFINITY, (double)NAN};
        for (unsigned a = 0; a < n; a++) {
            for (unsigned b = 0; b < n; b++) {
                const unsigned c = gf_rng_u32(rng) % 12u;
                s[a * stride + b] =
                    (gf_real)((c < 8u)
                                  ? special[c]
                                  : gf_test_uniform(rng, -1.0, 1.0) * scale);
            }
        }
        if (kind == 5u) { // no negative variance, no NaN on the diagonal
            for (unsigned a = 0; a < n; a++) {
                const gf_real v = s[a * stride + a];
                s[a * stride + a] = (v == v) ? (gf_real)fabs((double)v) : 0;
            }
        }
        break;
    }
    }
}

// gf_cov_factor on s: on GF_OK, factors in their pivot order (F unit lower triangular there,
// d >= 0) whose F diag(d) F^T is s, within GF_PD_RTOL (a pivot up to it
// is zero) times sqrt(s_ii s_jj).
static void check_factors(const gf_real *s, unsigned stride, unsigned n)
{
    factors f;
    memset(&f, SENTINEL, sizeof f);
    const gf_status st = gf_cov_factor(s, stride, n, f.F, f.d, f.order);
    if (st != GF_OK) {
        return;
    }
    unsigned at[3]; // the step of each state
    for (unsigned u = 0; u < n; u++) {
        assert_true(f.order[u] < n);
        at[f.order[u]] = u;
    }
    for (unsigned i = 0; i < n; i++) {
        assert_true(f.d[i] >= 0);
        for (unsigned j = 0; j < n; j++) {
            if (i == j) {
                assert_true(f.F[i * n + j] == GF_R(1.0));
            } else if (at[i] < at[j]) {
                assert_true(f.F[i * n + j] == GF_R(0.0));
            }
        }
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            long double acc = 0;
            for (unsigned k = 0; k < n; k++) {
                acc += (long double)f.F[i * n + k] * (long double)f.d[k] *
                       (long double)f.F[j * n + k];
            }
            const long double sij =
                (long double)s[(i < j ? i : j) * stride + (i < j ? j : i)];
            const long double tol = 4.0L * (long double)GF_PD_RTOL *
                                    sqrtl((long double)s[i * stride + i] *
                                          (long double)s[j * stride + j]);
            if (!(fabsl(acc - sij) <= tol)) {
                print_error("n = %u, (%u, %u): F diag(d) F^T %Lg, s %Lg\n", n,
                            i, j, acc, sij);
                fail();
            }
        }
    }
}

// gf_cov_factor's factors multiply back to the matrix.
static void factors_match(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 20261202u);
    unsigned ok = 0, not_psd = 0;
    for (unsigned t = 0; t < DRAWS; t++) {
        const unsigned n = 1u + t % 3u;
        const unsigned stride = (t / 3u) % 2u ? 3u : n;
        gf_real s[9];
        draw(&rng, n, stride, s);
        check_factors(s, stride, n);
        factors f;
        if (gf_cov_factor(s, stride, n, f.F, f.d, f.order) == GF_OK) {
            ok++;
        } else {
            not_psd++;
        }
    }
    // both verdicts well represented
    assert_true(ok > DRAWS / 5u);
    assert_true(not_psd > DRAWS / 5u);
}

// The edge cases by hand: zero, one or all variances zero, coupled or
// not; a coupling at the bound; the pivot's choice tied.
static void edge_cases(void **state)
{
    (void)state;
    const gf_real m = GF_REAL_MIN, big = GF_R(1e30);
    const gf_real cases[][9] = {
        {0, 0, 0, 0, 0, 0, 0, 0, 0},
        {0, 1, 0, 1, 0, 0, 0, 0, 0},
        {0, 0, 0, 0, 1, 1, 0, 1, 1},
        {0, 0, 0, 0, 0, 0, 0, 0, 1},
        {0, 0, 1, 0, 0, 0, 1, 0, 1},
        {1, 1, 1, 1, 1, 1, 1, 1, 1},
        {1, 1, 0, 1, 1, 0, 0, 0, 0},
        {4, 2, 2, 2, 1, 1, 2, 1, 1},
        {1, 0, 0, 0, 1, 0, 0, 0, 1},
        {1, 0, 0, 0, 0, 0, 0, 0, 1},
        {1, 0, 1, 0, 1, 0, 1, 0, 1},
        {1, 0, 1, 0, 1, 1, 1, 1, 1},
        {2, 1, 1, 1, 2, 1, 1, 1, 2},
        {1, 2, 0, 2, 1, 0, 0, 0, 1},
        {m, m, m, m, m, m, m, m, m},
        {big, big, 0, big, big, 0, 0, 0, big},
        {1, -0.0, -0.0, -0.0, 1, -0.0, -0.0, -0.0, 1},
        {-1, 0, 0, 0, 1, 0, 0, 0, 1},
        {1, 0, 0, 0, -1, 0, 0, 0, 1},
        {0, 0, 0, 0, 1, 0, 0, 0, -1},
    };
    for (unsigned c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        for (unsigned n = 1; n <= 3; n++) {
            check_factors(cases[c], 3, n);
        }
    }
}

// The verdict of gf_cov_factor (the symmetry and variance
// checks, then gf_ldl's loop), after gf_mat3_check_psd's finiteness check.
static gf_status reference_verdict(const gf_real *s, unsigned stride,
                                   unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            if (!isfinite((double)s[i * stride + j])) {
                return GF_ERR_NONFINITE;
            }
        }
    }
    factors f;
    return gf_cov_factor(s, stride, n, f.F, f.d, f.order);
}

// s (n x n, rows of 3) times 2^e into z.
static void scale_by(const gf_mat3 *s, int e, gf_mat3 *z)
{
    for (unsigned i = 0; i < 3; i++) {
        for (unsigned j = 0; j < 3; j++) {
            z->m[i][j] = (gf_real)ldexp((double)s->m[i][j], e);
        }
    }
}

// gf_mat2_check_psd and gf_mat3_check_psd give the reference's verdict;
// and the same one for a matrix of moderate spread (its nonzero entries
// within 2^14 of the largest, so that no product the verdict forms
// underflows or overflows in either precision) scaled by 2^-60 and 2^60.
static void check_psd_matches_reference(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 7u);
    unsigned scaled = 0;
    for (unsigned t = 0; t < DRAWS; t++) {
        const unsigned n = 1u + t % 3u;
        gf_mat3 s3 = {{{0}}};
        draw(&rng, n, 3, s3.m[0]);
        if (t % 5u == 0u && n > 1u) { // asymmetric near the tolerance
            const double x = (double)s3.m[0][1];
            const double e = gf_test_uniform(&rng, -4.0, 4.0) * 1024.0 *
                             (double)GF_REAL_EPSILON;
            s3.m[1][0] = (gf_real)(x * (1.0 + e));
        }
        const gf_status want = reference_verdict(s3.m[0], 3, n);
        assert_int_equal(gf_mat3_check_psd(&s3, n), want);
        if (n == 2u) {
            const gf_mat2 s2 = {
                {{s3.m[0][0], s3.m[0][1]}, {s3.m[1][0], s3.m[1][1]}}};
            assert_int_equal(gf_mat2_check_psd(&s2),
                             reference_verdict(s2.m[0], 2, 2));
        }
        // the scale: the largest entry brought to [1, 2), then the spread
        double top = 0.0, low = (double)INFINITY;
        for (unsigned i = 0; i < n; i++) {
            for (unsigned j = 0; j < n; j++) {
                const double x = fabs((double)s3.m[i][j]);
                top = (x > top) ? x : top;
                low = (x > 0.0 && x < low) ? x : low;
            }
        }
        if (want == GF_ERR_NONFINITE || !(top > 0.0) ||
            !(low >= ldexp(top, -14))) {
            continue;
        }
        gf_mat3 base, z;
        scale_by(&s3, -ilogb(top), &base);
        const gf_status verdict = gf_mat3_check_psd(&base, n);
        assert_int_equal(verdict, want);
        for (int e = -60; e <= 60; e += 120) {
            scale_by(&base, e, &z);
            assert_int_equal(gf_mat3_check_psd(&z, n), verdict);
        }
        scaled++;
    }
    assert_true(scaled > DRAWS / 4u);
}

// A covariance of n states, each coupled to at most one other (random
// pairs, random units per pair): each pair positive definite, exactly
// singular (powers of two), zero, indefinite, or of a zero and a positive
// variance coupled (not PSD).
#define PAIRS_NMAX 12u
static void draw_pairs(gf_rng *rng, unsigned n, gf_real *s)
{
    unsigned perm[PAIRS_NMAX];
    for (unsigned i = 0; i < n; i++) {
        perm[i] = i;
    }
    for (unsigned i = n; i-- > 1u;) {
        const unsigned k = gf_rng_u32(rng) % (i + 1u), t = perm[i];
        perm[i] = perm[k];
        perm[k] = t;
    }
    for (unsigned k = 0; k < n * n; k++) {
        s[k] = 0;
    }
    for (unsigned i = 0; i < n; i += 2u) {
        const double u = ldexp(1.0, (int)(gf_rng_u32(rng) % 81u) - 40);
        const unsigned a = perm[i];
        const int single = i + 1u == n || gf_rng_u32(rng) % 4u == 0u;
        if (single) {
            s[a * n + a] = (gf_real)(gf_rng_u32(rng) % 5u == 0u
                                         ? 0.0
                                         : u * gf_test_uniform(rng, 0.1, 2.0));
            i--; // (the next state starts the next pair)
            continue;
        }
        const unsigned b = perm[i + 1u];
        double saa = 0, sbb = 0, sab = 0;
        switch (gf_rng_u32(rng) % 5u) {
        case 0:
        case 1: { // positive definite, correlation up to 0.99
            const double r = gf_test_uniform(rng, -0.99, 0.99);
            saa = u * gf_test_uniform(rng, 0.5, 2.0);
            sbb = u * 0x1p-10 * gf_test_uniform(rng, 0.5, 2.0);
            sab = r * sqrt(saa * sbb);
            break;
        }
        case 2: // exactly singular: (2, 1) (2, 1)^T u
            saa = 4.0 * u;
            sbb = u;
            sab = 2.0 * u;
            break;
        case 3: // indefinite: correlation 1.5
            saa = u;
            sbb = 4.0 * u;
            sab = 3.0 * u;
            break;
        default: // a zero variance coupled to a positive one
            saa = 0;
            sbb = u;
            sab = 0.5 * u;
            break;
        }
        s[a * n + a] = (gf_real)saa;
        s[b * n + b] = (gf_real)sbb;
        s[a * n + b] = (gf_real)sab;
        s[b * n + a] = (gf_real)sab;
    }
}

// gf_cov_factor on covariances of more than 3 states, each coupled to at
// most one other: on GF_OK, factors in their pivot order (F unit lower
// triangular there, d >= 0) whose F diag(d) F^T is the matrix.
static void pairs_match_ldl(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 20261203u);
    unsigned ok = 0, not_psd = 0;
    for (unsigned t = 0; t < DRAWS / 10u; t++) {
        const unsigned n = 4u + t % (PAIRS_NMAX - 3u);
        gf_real s[PAIRS_NMAX * PAIRS_NMAX], F[PAIRS_NMAX * PAIRS_NMAX];
        gf_real d[PAIRS_NMAX];
        unsigned order[PAIRS_NMAX];
        draw_pairs(&rng, n, s);
        const gf_status got = gf_cov_factor(s, n, n, F, d, order);
        if (got != GF_OK) {
            not_psd++;
            continue;
        }
        ok++;
        unsigned at[PAIRS_NMAX]; // the step of each state
        for (unsigned u = 0; u < n; u++) {
            assert_true(order[u] < n);
            at[order[u]] = u;
        }
        for (unsigned i = 0; i < n; i++) {
            assert_true(d[i] >= 0);
            for (unsigned j = 0; j < n; j++) {
                if (i == j) {
                    assert_true(F[i * n + j] == GF_R(1.0));
                } else if (at[i] < at[j]) {
                    assert_true(F[i * n + j] == GF_R(0.0));
                }
            }
        }
        for (unsigned i = 0; i < n; i++) {
            for (unsigned j = 0; j < n; j++) {
                long double acc = 0;
                for (unsigned k = 0; k < n; k++) {
                    acc += (long double)F[i * n + k] * (long double)d[k] *
                           (long double)F[j * n + k];
                }
                const double tol =
                    8.0 * (double)GF_REAL_EPSILON *
                    sqrt((double)s[i * n + i] * (double)s[j * n + j]);
                if (!(fabsl(acc - (long double)s[i * n + j]) <=
                      (long double)tol)) {
                    print_error("n = %u, (%u, %u): F diag(d) F^T %Lg, s %g\n",
                                n, i, j, acc, (double)s[i * n + j]);
                    fail();
                }
            }
        }
    }
    assert_true(ok > DRAWS / 100u);
    assert_true(not_psd > DRAWS / 100u);
}

// A prior's factors as every init takes them (gf_udu_factor) against
// the exact factors of the matrix given, on seeded random nearly singular
// priors of 2 to 4 states (rows alike to 1e-3, so correlations to within
// about 1e-6 of 1; units 2^-30 to 2^30). The exact factors are computed
// here in long double by the same recurrences (state n - 1 first): for a
// float build that has precision to spare on every target (53 bits or
// more against 24), and every d_j and U_ij must be within 64 u of it,
// relative (u = GF_REAL_EPSILON; measured: 38 u at worst, 34 of 60,000
// beyond 2 u; a d_j is the difference of nearly equal numbers here, and
// the plain recurrences miss by up to 2e8 u). A double build has no such
// reference on most targets; there the factors multiplied out must give
// the matrix within the recurrences' backward bound.
#define FAC_NMAX 4u
static void prior_factors_match_exact(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 20261204u);
    const int exact_ref =
        LDBL_MANT_DIG >= 2 * (int)(sizeof(gf_real) == 4 ? 24 : 53) + 4;
    const long double u = (long double)GF_REAL_EPSILON;
    unsigned checked = 0;
    for (unsigned t = 0; t < DRAWS / 3u; t++) {
        const unsigned n = 2u + t % (FAC_NMAX - 1u);
        double w[FAC_NMAX][FAC_NMAX], base[FAC_NMAX];
        for (unsigned k = 0; k < n; k++) {
            base[k] = gf_test_uniform(&rng, -1.0, 1.0);
        }
        for (unsigned i = 0; i < n; i++) {
            const double e = pow(10.0, gf_test_uniform(&rng, -3.0, 0.0));
            for (unsigned k = 0; k < n; k++) {
                w[i][k] = base[k] + e * gf_test_uniform(&rng, -1.0, 1.0);
            }
        }
        const double scale = ldexp(1.0, (int)(gf_rng_u32(&rng) % 61u) - 30);
        gf_real s[FAC_NMAX * FAC_NMAX];
        for (unsigned i = 0; i < n; i++) {
            for (unsigned j = 0; j < n; j++) {
                double acc = 0.0;
                for (unsigned k = 0; k < n; k++) {
                    acc += w[i][k] * w[j][k];
                }
                s[i * n + j] = (gf_real)(acc * scale);
            }
        }
        for (unsigned i = 0; i < n; i++) { // exactly symmetric
            for (unsigned j = 0; j < i; j++) {
                s[i * n + j] = s[j * n + i];
            }
        }
        // The exact factors of s, index k holding state n - 1 - k
        long double U[FAC_NMAX][FAC_NMAX] = {{0}}, D[FAC_NMAX];
        int pd = 1;
        for (unsigned j = n; j-- > 0u;) {
            const unsigned sj = n - 1u - j;
            long double dj = (long double)s[sj * n + sj];
            for (unsigned k = j + 1u; k < n; k++) {
                dj -= U[j][k] * U[j][k] * D[k];
            }
            D[j] = dj;
            if (!(dj > (long double)s[sj * n + sj] * 1e-9L)) {
                pd = 0; // (too near singular for the reference to tell)
                break;
            }
            for (unsigned i = 0; i < j; i++) {
                const unsigned si = n - 1u - i;
                long double r = (long double)s[si * n + sj];
                for (unsigned k = j + 1u; k < n; k++) {
                    r -= U[i][k] * U[j][k] * D[k];
                }
                U[i][j] = r / dj;
            }
        }
        if (!pd) {
            continue;
        }
        gf_real ud[GF_UD_SIZE(FAC_NMAX)], lo[GF_UD_SIZE(FAC_NMAX)];
        unsigned char perm[sizeof(gf_real)];
        gf_udu_factor(s, n, n, ud, perm, lo);
        checked++;
        for (unsigned j = 0; j < n; j++) {
            assert_int_equal(perm[j], n - 1u - j);
            if (exact_ref) {
                const long double dj = (long double)ud[GF_UD(j, j)];
                if (!(fabsl(dj - D[j]) <= 64 * u * D[j])) {
                    print_error("n = %u, d_%u %.9Lg, exact %.12Lg\n", n, j, dj,
                                D[j]);
                    fail();
                }
                for (unsigned i = 0; i < j; i++) {
                    const long double uij = (long double)ud[GF_UD(i, j)];
                    // (an entry that cancels to near zero: to u^2 of the
                    // terms it came from)
                    const long double tol =
                        64 * u * fabsl(U[i][j]) +
                        64 * u * u *
                            sqrtl((long double)s[(n - 1u - i) * (n + 1u)] /
                                  D[j]);
                    if (!(fabsl(uij - U[i][j]) <= tol)) {
                        print_error("n = %u, U_%u%u %.9Lg, exact %.12Lg\n", n,
                                    i, j, uij, U[i][j]);
                        fail();
                    }
                }
            }
        }
        if (!exact_ref) {
            for (unsigned i = 0; i < n; i++) {
                for (unsigned j = 0; j < n; j++) {
                    long double acc = 0;
                    for (unsigned k = (i > j ? i : j); k < n; k++) {
                        const long double uik =
                            (k == i) ? 1.0L : (long double)ud[GF_UD(i, k)];
                        const long double ujk =
                            (k == j) ? 1.0L : (long double)ud[GF_UD(j, k)];
                        acc += uik * (long double)ud[GF_UD(k, k)] * ujk;
                    }
                    const unsigned si = n - 1u - i, sj = n - 1u - j;
                    const long double tol = 8 * u *
                                            sqrtl((long double)s[si * n + si] *
                                                  (long double)s[sj * n + sj]);
                    assert_true(fabsl(acc - (long double)s[si * n + sj]) <=
                                tol);
                }
            }
        }
    }
    print_message(
        "prior factors: %u nearly singular priors checked (%s)\n", checked,
        exact_ref ? "to 64 u of the exact factors" : "multiplied out");
    assert_true(checked > DRAWS / 6u);
}

// Sigma = P U D U^T P^T of packed factors, in long double: entry (perm[i],
// perm[j]) = sum_(k >= max(i, j)) U_ik d_k U_jk; abs gets the same sum of
// absolute terms (the scale of its rounding).
static void factors_to_sigma(unsigned n, const gf_real *ud,
                             const unsigned char *perm, long double *sig,
                             long double *abs)
{
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            long double acc = 0, mag = 0;
            for (unsigned k = (i > j ? i : j); k < n; k++) {
                const long double uik =
                    (k == i) ? 1.0L : (long double)ud[GF_UD(i, k)];
                const long double ujk =
                    (k == j) ? 1.0L : (long double)ud[GF_UD(j, k)];
                const long double t = uik * (long double)ud[GF_UD(k, k)] * ujk;
                acc += t;
                mag += fabsl(t);
            }
            sig[perm[i] * n + perm[j]] = acc;
            abs[perm[i] * n + perm[j]] = mag;
        }
    }
}

// gf_udu_swap, which moves a measured state to the root of the factors:
// on seeded random factors of 2 to 5 states (d_j over 2^-40 to 2^40, some
// zero with their column, U_ij up to 10^3, some zero), every swap keeps
// Sigma to a few u of its terms, before and after; the two states trade
// places in perm; every d stays >= 0, and a d below GF_REAL_MIN is zero
// with its column of U.
#define SWAP_NMAX 5u
static void swap_keeps_sigma(void **state)
{
    (void)state;
    gf_rng rng;
    gf_rng_seed(&rng, 20261202u);
    const long double u = (long double)GF_REAL_EPSILON;
    unsigned swaps = 0, zero_d = 0;
    long double worst = 0;
    for (unsigned t = 0; t < DRAWS / 2u; t++) {
        const unsigned n = 2u + t % (SWAP_NMAX - 1u);
        gf_real ud[GF_UD_SIZE(SWAP_NMAX)];
        unsigned char perm[SWAP_NMAX];
        for (unsigned j = 0; j < n; j++) {
            perm[j] = (unsigned char)(n - 1u - j);
            const int zero = gf_rng_u32(&rng) % 5u == 0u;
            ud[GF_UD(j, j)] =
                zero ? GF_R(0.0)
                     : (gf_real)ldexp(gf_test_uniform(&rng, 0.5, 1.0),
                                      (int)(gf_rng_u32(&rng) % 81u) - 40);
            for (unsigned i = 0; i < j; i++) {
                const int zu = zero || gf_rng_u32(&rng) % 4u == 0u;
                ud[GF_UD(i, j)] =
                    zu ? GF_R(0.0)
                       : (gf_real)(gf_test_uniform(&rng, -1.0, 1.0) *
                                   pow(10.0, gf_test_uniform(&rng, -3.0, 3.0)));
            }
        }
        long double before[SWAP_NMAX * SWAP_NMAX], after[SWAP_NMAX * SWAP_NMAX];
        long double mb[SWAP_NMAX * SWAP_NMAX], ma[SWAP_NMAX * SWAP_NMAX];
        factors_to_sigma(n, ud, perm, before, mb);
        const unsigned k = gf_rng_u32(&rng) % (n - 1u);
        const unsigned char pk = perm[k], pl = perm[k + 1u];
        gf_udu_swap(n, k, ud, perm);
        swaps++;
        assert_int_equal(perm[k], pl);
        assert_int_equal(perm[k + 1u], pk);
        for (unsigned j = 0; j < n; j++) {
            const gf_real dj = ud[GF_UD(j, j)];
            assert_true(dj >= 0);
            if (!(dj >= GF_REAL_MIN)) {
                assert_true(dj == 0);
                zero_d++;
                for (unsigned i = 0; i < j; i++) {
                    assert_true(ud[GF_UD(i, j)] == 0);
                }
            }
        }
        factors_to_sigma(n, ud, perm, after, ma);
        for (unsigned e = 0; e < n * n; e++) {
            const long double err = fabsl(after[e] - before[e]);
            const long double scale = mb[e] + ma[e];
            if (!(err <= 8 * u * scale + (long double)GF_REAL_MIN)) {
                print_error("n = %u, swap %u, entry %u: %.12Lg, was %.12Lg "
                            "(terms %.3Lg)\n",
                            n, k, e, after[e], before[e], scale);
                fail();
            }
            if (scale > 0 && err / scale > worst) {
                worst = err / scale;
            }
        }
    }
    print_message("factor swaps: %u checked (%u zero variances), worst "
                  "error %.2Lg u of Sigma's terms\n",
                  swaps, zero_d, worst / u);
    assert_true(zero_d > DRAWS / 20u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(factors_match),
        cmocka_unit_test(edge_cases),
        cmocka_unit_test(check_psd_matches_reference),
        cmocka_unit_test(pairs_match_ldl),
        cmocka_unit_test(prior_factors_match_exact),
        cmocka_unit_test(swap_keeps_sigma),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
