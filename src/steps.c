// SPDX-License-Identifier: MIT
#include "steps.h"

#include "udu.h"

void gf_udu_predict2(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr)
{
    gf_real w[2 * 4], wd[4];
    gf_udu_predict(2u, ud, ud_new, perm, a, fr, dr, w, wd);
}

void gf_udu_predict3(const gf_real *ud, gf_real *ud_new,
                     const unsigned char *perm, const gf_real *a,
                     const gf_real *fr, const gf_real *dr)
{
    gf_real w[3 * 6], wd[6];
    gf_udu_predict(3u, ud, ud_new, perm, a, fr, dr, w, wd);
}

gf_status gf_udu_correct2(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis)
{
    gf_real w[2 * 4], wd[4];
    return gf_udu_correct(2u, ud, perm, m, hw, e, yw, dx, nis, w, wd);
}

gf_status gf_udu_correct3(gf_real *ud, unsigned char *perm, unsigned m,
                          const gf_real *hw, const gf_real *e,
                          const gf_real *yw, gf_real *dx, gf_real *nis)
{
    gf_real w[3 * 6], wd[6];
    return gf_udu_correct(3u, ud, perm, m, hw, e, yw, dx, nis, w, wd);
}
