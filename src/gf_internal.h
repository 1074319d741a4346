// gaussfilt: helpers shared by the filters' sources. Not installed, not
// part of the API; everything here is static inline.
#ifndef GAUSSFILT_SRC_INTERNAL_H
#define GAUSSFILT_SRC_INTERNAL_H

#include "gaussfilt/mat.h"

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
// mapped to GF_ERR_MODEL.
static inline gf_status gf_callback_status(gf_status st)
{
    return (st < GF_ERR_MODEL || st > GF_OK) ? GF_ERR_MODEL : st;
}

#endif
