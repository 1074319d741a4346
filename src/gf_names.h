// SPDX-License-Identifier: MIT
// gaussfilt: the link names of the library's internal functions, which
// carry their precision as the public ones do (include/gaussfilt/names.h):
// gf_ldl_f32 in the float build, gf_ldl_f64 in the double build. Included
// by gf_internal.h, so by every source before it declares one of them.
//
// Every function a library source defines outside the API is listed here
// (scripts/test compares this list and names.h with nm of the built
// library, both precisions).
#ifndef GAUSSFILT_SRC_NAMES_H
#define GAUSSFILT_SRC_NAMES_H

#include "gaussfilt/config.h"

// ldl.h: defined in ldl.c
#define gf_cov_factor GF_NAME(gf_cov_factor)

// gf_meas3.h: defined in meas3.c
#define gf_meas3_check GF_NAME(gf_meas3_check)
#define gf_meas3_verdict GF_NAME(gf_meas3_verdict)

// udu.h: defined in udu.c
#define gf_belief_finite GF_NAME(gf_belief_finite)
#define gf_udu_correct GF_NAME(gf_udu_correct)
#define gf_udu_factor GF_NAME(gf_udu_factor)
#define gf_udu_predict GF_NAME(gf_udu_predict)
#define gf_udu_swap GF_NAME(gf_udu_swap)
#define gf_udu_to_cov GF_NAME(gf_udu_to_cov)
#define gf_udu_whiten GF_NAME(gf_udu_whiten)

// kf_core.h: defined in kf.c
#define gf_kfc_correct GF_NAME(gf_kfc_correct)
#define gf_kfc_init GF_NAME(gf_kfc_init)
#define gf_kfc_keep GF_NAME(gf_kfc_keep)
#define gf_kfc_meas_check GF_NAME(gf_kfc_meas_check)
#define gf_kfc_noise GF_NAME(gf_kfc_noise)
#define gf_kfc_predict GF_NAME(gf_kfc_predict)

#endif
