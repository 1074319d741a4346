// SPDX-License-Identifier: MIT
#include "gaussfilt/status.h"

#include "gf_internal.h"

const char *gf_status_str(gf_status status)
{
    switch (status) {
    case GF_OK:
        return "ok";
    case GF_ERR_ARG:
        return "bad argument";
    case GF_ERR_NONFINITE:
        return "non-finite value";
    case GF_ERR_NOT_PSD:
        return "covariance not positive semidefinite";
    case GF_ERR_SINGULAR:
        return "singular innovation covariance";
    case GF_ERR_GATED:
        return "gated";
    case GF_ERR_UNDEFINED:
        return "undefined";
    case GF_ERR_MODEL:
        return "model callback failed";
    }
    return "unknown";
}
