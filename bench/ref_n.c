// SPDX-License-Identifier: MIT
// The conventional (unsafe) floor for n states (ref_n.h): the textbook
// step, as a careful firmware engineer would write it without a library,
//   predict: mu = A mu;  P = A P A^T + R
//   update:  S = C P C^T + Q;  K = P C^T S^-1;  mu += K (z - C mu);
//            P -= K C P
// for a generic n and m, in plain loops, no checks, no symmetrisation
// beyond forming the upper triangle of each symmetric product and copying
// it down (what the hand-unrolled floor of ref.c does too). S^-1 by a
// square-root-free Cholesky (S = L D L^T: no sqrt, m divisions), the gain
// by forward and back substitution. Nothing guards against a negative
// pivot or a covariance that loses its positive definiteness.
#include "ref_n.h"

void ref_n_from(ref_n *r, unsigned n, const gf_real *mu, const gf_real *sigma)
{
    r->n = n;
    for (unsigned i = 0; i < n; i++) {
        r->mu[i] = mu[i];
        for (unsigned j = 0; j < n; j++) {
            r->P[i * n + j] = sigma[i * n + j];
        }
    }
}

// P = A P A^T + R (A n x n).
static void predict_cov(ref_n *r, const gf_real *A, const gf_real *R)
{
    const unsigned n = r->n;
    gf_real *P = r->P, *T = r->T;
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < n; j++) {
            gf_real s = 0;
            for (unsigned k = 0; k < n; k++) {
                s += A[i * n + k] * P[k * n + j];
            }
            T[i * n + j] = s;
        }
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real s = R[i * n + j];
            for (unsigned k = 0; k < n; k++) {
                s += T[i * n + k] * A[j * n + k];
            }
            P[i * n + j] = s;
            P[j * n + i] = s;
        }
    }
}

// With r->y = the innovation: K = P C^T S^-1, mu += K y, P -= K (P C^T)^T
// (C m x n).
static void update_core(ref_n *r, const gf_real *C, const gf_real *Q,
                        unsigned m)
{
    const unsigned n = r->n;
    gf_real *P = r->P, *T = r->T, *S = r->S, *K = r->K;
    // T = P C^T (n x m).
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = 0; j < m; j++) {
            gf_real s = 0;
            for (unsigned k = 0; k < n; k++) {
                s += P[i * n + k] * C[j * n + k];
            }
            T[i * m + j] = s;
        }
    }
    // S = C T + Q, the lower triangle.
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j <= i; j++) {
            gf_real s = Q[i * m + j];
            for (unsigned k = 0; k < n; k++) {
                s += C[i * n + k] * T[k * m + j];
            }
            S[i * m + j] = s;
        }
    }
    // S = L D L^T in place: L below the diagonal, 1/D on it, L_ij D_j
    // (i > j) in the upper triangle at (j, i).
    for (unsigned j = 0; j < m; j++) {
        gf_real d = S[j * m + j];
        for (unsigned k = 0; k < j; k++) {
            d -= S[j * m + k] * S[k * m + j];
        }
        const gf_real id = 1 / d;
        S[j * m + j] = id;
        for (unsigned i = j + 1; i < m; i++) {
            gf_real w = S[i * m + j];
            for (unsigned k = 0; k < j; k++) {
                w -= S[i * m + k] * S[k * m + j];
            }
            S[j * m + i] = w;      // L_ij D_j
            S[i * m + j] = w * id; // L_ij
        }
    }
    // K's rows: S k = T's row, by L, 1/D, L^T.
    for (unsigned r0 = 0; r0 < n; r0++) {
        gf_real *k = &K[r0 * m];
        const gf_real *t = &T[r0 * m];
        for (unsigned i = 0; i < m; i++) {
            gf_real s = t[i];
            for (unsigned j = 0; j < i; j++) {
                s -= S[i * m + j] * k[j];
            }
            k[i] = s;
        }
        for (unsigned i = 0; i < m; i++) {
            k[i] *= S[i * m + i];
        }
        for (unsigned i = m; i-- > 0;) {
            gf_real s = k[i];
            for (unsigned j = i + 1; j < m; j++) {
                s -= S[j * m + i] * k[j];
            }
            k[i] = s;
        }
    }
    // mu += K y; P -= K T^T (upper triangle, copied down).
    for (unsigned i = 0; i < n; i++) {
        gf_real s = r->mu[i];
        for (unsigned j = 0; j < m; j++) {
            s += K[i * m + j] * r->y[j];
        }
        r->mu[i] = s;
    }
    for (unsigned i = 0; i < n; i++) {
        for (unsigned j = i; j < n; j++) {
            gf_real s = P[i * n + j];
            for (unsigned k = 0; k < m; k++) {
                s -= K[i * m + k] * T[j * m + k];
            }
            P[i * n + j] = s;
            P[j * n + i] = s;
        }
    }
}

void ref_kf_predict(ref_n *r, const gf_kf_model *model)
{
    const unsigned n = r->n;
    const gf_real *A = model->A;
    for (unsigned i = 0; i < n; i++) {
        gf_real s = 0;
        for (unsigned k = 0; k < n; k++) {
            s += A[i * n + k] * r->mu[k];
        }
        r->v[i] = s;
    }
    for (unsigned i = 0; i < n; i++) {
        r->mu[i] = r->v[i];
    }
    predict_cov(r, A, model->R);
}

void ref_kf_update(ref_n *r, const gf_kf_meas *meas, const gf_real *z)
{
    const unsigned n = r->n, m = meas->m;
    const gf_real *C = meas->C;
    for (unsigned i = 0; i < m; i++) {
        gf_real s = z[i];
        for (unsigned k = 0; k < n; k++) {
            s -= C[i * n + k] * r->mu[k];
        }
        r->y[i] = s;
    }
    update_core(r, C, meas->Q, m);
}

void ref_ekf_predict(ref_n *r, const gf_ekf_motion *motion, const gf_real *u)
{
    const unsigned n = r->n;
    for (unsigned i = 0; i < n; i++) {
        r->v[i] = r->mu[i];
        for (unsigned j = 0; j < n; j++) {
            r->J[i * n + j] = (gf_real)(i == j);
        }
    }
    (void)motion->g(motion->ctx, n, r->mu, u, r->v, r->J);
    for (unsigned i = 0; i < n; i++) {
        r->mu[i] = r->v[i];
    }
    predict_cov(r, r->J, motion->R);
}

void ref_ekf_update(ref_n *r, const gf_ekf_meas *meas, const gf_real *z)
{
    const unsigned n = r->n, m = meas->m;
    for (unsigned i = 0; i < m; i++) {
        r->v[i] = 0;
        for (unsigned j = 0; j < n; j++) {
            r->J[i * n + j] = 0;
        }
    }
    (void)meas->h(meas->ctx, n, m, r->mu, r->v, r->J);
    for (unsigned i = 0; i < m; i++) {
        r->y[i] = z[i] - r->v[i];
    }
    update_core(r, r->J, meas->Q, m);
}
