// gaussfilt: helpers shared by the filters' sources. Not installed, not
// part of the API; everything here is static inline.
#ifndef GAUSSFILT_SRC_INTERNAL_H
#define GAUSSFILT_SRC_INTERNAL_H

#include "gaussfilt/ekf3.h"

// 1 if both entries of x are finite.
static inline int gf_vec2_is_finite(const gf_vec2 *x)
{
    return GF_ISFINITE(x->v[0]) && GF_ISFINITE(x->v[1]);
}

// 1 if the first n entries of x are finite.
static inline int gf_vec3_is_finite_n(const gf_vec3 *x, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        if (!GF_ISFINITE(x->v[i])) {
            return 0;
        }
    }
    return 1;
}

// A model callback's status, with anything that is not a known failure
// mapped to GF_ERR_MODEL; so is GF_ERR_GATED, which only the filter's own
// gate may report (the caller then expects the innovation to be written).
static inline gf_status gf_callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK || st == GF_ERR_GATED)
               ? GF_ERR_MODEL : st;
}

// The gate every update applies once it has the innovation: a NIS above a
// set gate (gate > 0) rejects the measurement, and the caller still gets
// the innovation. 1 if gated (info written), else 0 (info untouched).
static inline int gf_gated(const gf_innovation *in, gf_real gate,
                           gf_innovation *info)
{
    if (!(gate > 0 && in->nis > gate)) {
        return 0;
    }
    if (info) {
        *info = *in;
    }
    return 1;
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

#endif
