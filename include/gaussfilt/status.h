// SPDX-License-Identifier: MIT
// gaussfilt: the one status enum every call returns.
#ifndef GAUSSFILT_STATUS_H
#define GAUSSFILT_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

// OK is 0; every failure is negative and names its cause. A call that
// returns anything but GF_OK has left the filter's belief bit-for-bit as it
// was.
typedef enum gf_status {
    GF_OK = 0,             // success
    GF_ERR_ARG = -1,       // NULL pointer or a size out of range
    GF_ERR_NONFINITE = -2, // an input (or a model's output) is NaN or inf
    GF_ERR_NOT_PSD = -3,   // a covariance or noise matrix is not symmetric
                           // positive semidefinite
    GF_ERR_SINGULAR = -4,  // innovation covariance S is not positive
                           // definite (singular relative to its scale)
    GF_ERR_GATED = -5,     // measurement rejected by the chi-square gate
    GF_ERR_UNDEFINED = -6, // quantity undefined for this input, e.g. the
                           // correlation of a zero variance
    GF_ERR_MODEL = -7,     // a caller-supplied model callback failed
} gf_status;

// Short, constant, English name of a status ("ok", "gated", ...), for logs.
// Never NULL; unknown codes give "unknown".
const char *gf_status_str(gf_status status);

#ifdef __cplusplus
}
#endif

#endif
