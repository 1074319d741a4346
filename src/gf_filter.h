// SPDX-License-Identifier: MIT
// gaussfilt: what the filters of 2 and 3 states share (kf2.c, ekf3.c,
// if2.c, ukf3.c, pf3.c): a prior's checks and the innovation's storing.
// Not installed, not part of the API; everything here is static inline.
#ifndef GAUSSFILT_SRC_FILTER_H
#define GAUSSFILT_SRC_FILTER_H

#include "gaussfilt/kf2.h"

#include "gf_internal.h"

// The checks every init makes of the prior it is given, in the order of
// the status rules: GF_ERR_NONFINITE (mu, then sigma), then sigma's
// verdict (GF_ERR_NOT_PSD), else GF_OK.
static inline gf_status gf_prior2_check(const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!gf_all_finite(mu->v, 2)) {
        return GF_ERR_NONFINITE; // (sigma's: gf_cov_factor's first test)
    }
    return gf_mat2_check_psd(sigma);
}

static inline gf_status gf_prior3_check(const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!gf_all_finite(mu->v, 3)) {
        return GF_ERR_NONFINITE;
    }
    return gf_mat3_check_psd(sigma, 3);
}

// *info = *in where info is not NULL and st is GF_OK or GF_ERR_GATED (an
// update's caller gets the innovation then), field by field: a struct copy
// may carry the padding bytes of the local (after m, in double), which
// callers comparing the whole struct would see change from call to call.
// Returns st.
static inline gf_status
gf_innovation_keep(gf_status st, const gf_innovation *in, gf_innovation *info)
{
    if (info && (st == GF_OK || st == GF_ERR_GATED)) {
        info->m = in->m;
        info->y[0] = in->y[0];
        info->y[1] = in->y[1];
        info->y[2] = in->y[2];
        info->nis = in->nis;
    }
    return st;
}

#endif
