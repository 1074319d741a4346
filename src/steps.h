// SPDX-License-Identifier: MIT
// gaussfilt: the factored steps of src/udu.h compiled once for n = 2, 3
// (defined in steps.c) and 4 (steps4.c), their loops unrolled: KF2 and the
// gf_kf and gf_ekf filters of 2 states run the same machine code, as do
// EKF3 and those of 3 states; filters of 4 states (a 2-D constant-velocity
// target) run about 1.3x faster than on the loops for any n. Not
// installed, not part of the API.
#ifndef GAUSSFILT_SRC_STEPS_H
#define GAUSSFILT_SRC_STEPS_H

#include "gf_internal.h"

// gf_udu_factor for n <= 3, one copy for KF2 and EKF3 (a filter's init:
// its loops stay loops).
void gf_udu_factor3(const gf_real *s, unsigned stride, unsigned n, gf_real *ud,
                    unsigned char *perm);

// gf_udu_predict for n = 2 and n = 3, with scratch of their own.
void gf_udu_predict2(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr);
void gf_udu_predict3(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr);

// gf_udu_correct for n = 2 and n = 3, with scratch of their own.
gf_status gf_udu_correct2(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis);
gf_status gf_udu_correct3(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis);

// The same for n = 4.
void gf_udu_predict4(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr);
gf_status gf_udu_correct4(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis);

// Defines gf_udu_predictN and gf_udu_correctN for n = N, with W (N rows of
// 2N) and its weights on their own stack, in a source that has included
// udu.h.
#define GF_UDU_STEPS(N)                                                        \
    void gf_udu_predict##N(const gf_real *ud, gf_real *ud_new,                 \
                           const unsigned char *perm, const gf_real *a,        \
                           const gf_real *fr, const gf_real *dr)               \
    {                                                                          \
        gf_real w[2u * (N##u) * (N##u)], wd[2u * (N##u)];                      \
        gf_udu_predict((N##u), ud, ud_new, perm, a, fr, dr, w, wd);            \
    }                                                                          \
    gf_status gf_udu_correct##N(gf_real *ud, unsigned char *perm, unsigned m,  \
                                const gf_real *hw, const gf_real *e,           \
                                const gf_real *yw, gf_real *dx, gf_real *nis)  \
    {                                                                          \
        gf_real w[(N##u) * (N##u)], wd[N##u];                                  \
        return gf_udu_correct((N##u), ud, perm, m, hw, e, yw, dx, nis, w, wd); \
    }

#endif
