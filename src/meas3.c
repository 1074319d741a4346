// SPDX-License-Identifier: MIT
#include <stddef.h>

#include "gf_meas3.h"

#include "gf_internal.h"
#include "ldl.h"

gf_status gf_meas3_check(const gf_ekf3_meas *meas, const gf_vec3 *z,
                         gf_ekf3_qfactors *q)
{
    if (!meas || !meas->h || meas->m < 1u || meas->m > 3u) {
        return GF_ERR_ARG;
    }
    const unsigned m = meas->m;
    gf_real f = meas->gate * GF_R(0.0);
    if (z) {
        f = gf_nan_sum(f, z->v, m);
    }
    if (!gf_sum_finite(f)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    return gf_cov_factor(meas->Q.m[0], 3, m, q->Qf, q->Qe, q->Qorder);
}

gf_status gf_meas3_verdict(const gf_ekf3_meas *meas, const gf_vec3 *z)
{
    gf_ekf3_qfactors own;
    return gf_meas3_check(meas, z, &own);
}
