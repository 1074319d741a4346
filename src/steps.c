// SPDX-License-Identifier: MIT
#include "steps.h"

#include "udu.h"

void gf_udu_factor3(const gf_real *s, unsigned stride, unsigned n, gf_real *ud,
                    unsigned char *perm)
{
    gf_udu_factor(s, stride, n, ud, perm);
}

GF_UDU_STEPS(2)
GF_UDU_STEPS(3)
