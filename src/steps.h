// SPDX-License-Identifier: MIT
// gaussfilt: the factored steps of src/udu.h compiled once for n = 2, 3
// (defined in steps.c) and 4 (steps4.c), their loops unrolled, for the
// gf_kf and gf_ekf filters of those sizes (filters of 4 states, a 2-D
// constant-velocity target, run about 1.3x faster than on the loops for
// any n; KF2 and EKF3 inline the steps for their own size); and the
// prior's factorisation for KF2 and EKF3. Not installed, not part of the
// API.
#ifndef GAUSSFILT_SRC_STEPS_H
#define GAUSSFILT_SRC_STEPS_H

#include <stddef.h>

#include "gaussfilt/kf.h"

#include "gf_internal.h"

// gf_udu_factor for n <= 3, one copy for KF2 and EKF3 (a filter's init:
// its loops stay loops).
void gf_udu_factor3(const gf_real *s, unsigned stride, unsigned n, gf_real *ud,
                    unsigned char *perm);

// The caller's scratch of the steps for n states (gf_real): W, n rows of
// 2n, at 0; its weights, 2n, at GF_UDU_WD(n); the steps' vectors at
// GF_UDU_SV(n), 4n (gf_udu_correct_s's sv; gf_udu_predict_s's v takes
// 2n of them): 2 n^2 + 6 n in all.
#define GF_UDU_WD(n) ((size_t)(n)*2u * (size_t)(n))
#define GF_UDU_SV(n) ((size_t)(n)*2u * ((size_t)(n) + 1u))

// gf_udu_predict_s for n = 2 and n = 3, on the caller's scratch w (2 n^2
// + 6 n entries); gf_udu_correct_s for n = 2 and 3 on
// work->b, with the whitened innovations in work->s (the step added to
// work->b's mean), the NIS into work->in.nis, the scratch in
// work->w (few arguments: no stack arguments on Arm, so that
// kf.c reaches them by tail calls).
void gf_udu_predict2(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr, gf_real *w);
void gf_udu_predict3(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr, gf_real *w);
gf_status gf_udu_correct2(unsigned m, const gf_real *hw, const gf_real *e,
                          gf_kf_work *work);
gf_status gf_udu_correct3(unsigned m, const gf_real *hw, const gf_real *e,
                          gf_kf_work *work);

// The same for n = 4.
void gf_udu_predict4(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr, gf_real *w);
gf_status gf_udu_correct4(unsigned m, const gf_real *hw, const gf_real *e,
                          gf_kf_work *work);

// Defines gf_udu_predictN and gf_udu_correctN for n = N, in a source that
// has included udu.h.
#define GF_UDU_STEPS(N)                                                        \
    void gf_udu_predict##N(const gf_real *ud, gf_real *ud_new,                 \
                           const unsigned char *perm, const gf_real *a,        \
                           const gf_real *fr, const gf_real *dr, gf_real *w)   \
    {                                                                          \
        gf_udu_predict_s((N##u), ud, ud_new, perm, a, fr, dr, w,               \
                         &w[GF_UDU_WD(N##u)], &w[GF_UDU_SV(N##u)]);            \
    }                                                                          \
    gf_status gf_udu_correct##N(unsigned m, const gf_real *hw,                 \
                                const gf_real *e, gf_kf_work *work)            \
    {                                                                          \
        return gf_udu_correct_s((N##u), work->b.ud, work->b.perm, m, hw, e,    \
                                work->s, work->b.mu, &work->in.nis,            \
                                &work->w[GF_UDU_SV(N##u)]);                    \
    }

#endif
