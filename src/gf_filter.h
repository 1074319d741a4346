// SPDX-License-Identifier: MIT
// gaussfilt: the checks and the end of a step that the fixed-size filters
// share (kf2.c, ekf3.c, if2.c, ukf3.c, pf3.c): a prior's checks, an EKF3
// measurement model's checks, and the tail of every update (the NIS
// finite, the gate, the result finite, the innovation stored). Not
// installed, not part of the API; everything here is static inline.
#ifndef GAUSSFILT_SRC_FILTER_H
#define GAUSSFILT_SRC_FILTER_H

#include "gaussfilt/ekf3.h"

#include "udu.h"

// The checks every init makes of the prior it is given, in the order of
// the status rules: GF_ERR_NONFINITE (mu, then sigma), then sigma's
// verdict (GF_ERR_NOT_PSD), else GF_OK; one helper in the two sizes of
// mat.h. 2 x 2: the verdict in closed form (gf_cov_factor for n = 2: no
// gf_ldl call, so no stack beyond the caller's frame); 3 x 3: mat.c's
// (gf_mat3_check_psd), one copy for every filter.
static inline gf_status gf_prior2_check(const gf_vec2 *mu, const gf_mat2 *sigma)
{
    if (!gf_all_finite(mu->v, 2)) {
        return GF_ERR_NONFINITE; // (sigma's: gf_cov_factor's first test)
    }
    return gf_cov_factor(sigma->m[0], 2, 2, NULL, NULL, NULL);
}

static inline gf_status gf_prior3_check(const gf_vec3 *mu, const gf_mat3 *sigma)
{
    if (!gf_vec3_is_finite_n(mu, 3)) {
        return GF_ERR_NONFINITE;
    }
    return gf_mat3_check_psd(sigma, 3);
}

// The checks every update with an EKF3 measurement model starts with, in
// the order of the status rules: GF_ERR_ARG (NULL model, h, z; m not 1..3),
// GF_ERR_NONFINITE (z, gate), GF_ERR_ARG (gate < 0), then Q's
// gf_mat3_check_psd verdict.
static inline gf_status gf_meas3_check(const gf_ekf3_meas *meas,
                                       const gf_vec3 *z)
{
    if (!meas || !meas->h || !z || meas->m < 1 || meas->m > 3) {
        return GF_ERR_ARG;
    }
    if (!gf_vec3_is_finite_n(z, meas->m) || !GF_ISFINITE(meas->gate)) {
        return GF_ERR_NONFINITE;
    }
    if (meas->gate < 0) {
        return GF_ERR_ARG;
    }
    return gf_mat3_check_psd(&meas->Q, meas->m);
}

// The verdict on one measured quantity's noise q (a 1 x 1 Q): finite
// (GF_ERR_NONFINITE), then >= 0 (GF_ERR_NOT_PSD); on GF_OK, where qf is
// not NULL, its factors as gf_cov_factor's: F = 1, e = q, order 0.
static inline gf_status gf_noise1_check(gf_real q, gf_real *qf, gf_real *qe,
                                        unsigned *qorder)
{
    if (!gf_sum_finite(q * GF_R(0.0))) {
        return GF_ERR_NONFINITE;
    }
    if (q < 0) {
        return GF_ERR_NOT_PSD;
    }
    if (qf) {
        qf[0] = 1;
        qe[0] = q;
        qorder[0] = 0;
    }
    return GF_OK;
}

// *info = *in field by field: a struct copy may carry the padding bytes
// of the local (after m, in double), which callers comparing the whole
// struct would see change from call to call.
static inline void gf_info_store(gf_innovation *info, const gf_innovation *in)
{
    info->m = in->m;
    info->y[0] = in->y[0];
    info->y[1] = in->y[1];
    info->y[2] = in->y[2];
    info->nis = in->nis;
}

// The gate every update applies once it has the innovation: a NIS above a
// set gate (gate > 0) rejects the measurement, and the caller still gets
// the innovation. 1 if gated (info written, if not NULL), else 0 (info
// untouched).
static inline int gf_gated(const gf_innovation *in, gf_real gate,
                           gf_innovation *info)
{
    if (!(gate > 0 && in->nis > gate)) {
        return 0;
    }
    if (info) {
        gf_info_store(info, in);
    }
    return 1;
}

// The first half of every update's tail, once it has the innovation:
// GF_ERR_NONFINITE for a NIS that is not finite, GF_ERR_GATED as gf_gated,
// else GF_OK.
static inline gf_status gf_innovation_verdict(const gf_innovation *in,
                                              gf_real gate, gf_innovation *info)
{
    if (!GF_ISFINITE(in->nis)) {
        return GF_ERR_NONFINITE;
    }
    return gf_gated(in, gate, info) ? GF_ERR_GATED : GF_OK;
}

// The end of every update, once it has the new belief (finite: 1 if all
// of it is finite): GF_ERR_NONFINITE, the caller keeping the last good
// belief; else the innovation stored in info (if not NULL) and GF_OK, the
// caller then storing the new belief.
static inline gf_status gf_update_done(int finite, const gf_innovation *in,
                                       gf_innovation *info)
{
    if (!finite) {
        return GF_ERR_NONFINITE;
    }
    if (info) {
        gf_info_store(info, in);
    }
    return GF_OK;
}

#endif
