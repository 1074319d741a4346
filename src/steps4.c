// SPDX-License-Identifier: MIT
// udu.h's steps for n = 4 (steps.h), in a source of their own: their O(n)
// locals sized for 4 states, where steps.c's stay sized for 3.
#include "steps.h"

#define GF_UDU_NMAX 4u
#include "udu.h"

void gf_udu_predict4(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr)
{
    gf_real w[4 * 8], wd[8];
    gf_udu_predict(4u, ud, ud_new, perm, a, fr, dr, w, wd);
}

gf_status gf_udu_correct4(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis)
{
    gf_real w[4 * 8], wd[8];
    return gf_udu_correct(4u, ud, perm, m, hw, e, yw, dx, nis, w, wd);
}
