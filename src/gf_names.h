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
#define gf_ldl_core GF_NAME(gf_ldl_core)
#define gf_ldl_small GF_NAME(gf_ldl_small)

// steps.h: defined in steps.c and steps4.c
#define gf_udu_correct2 GF_NAME(gf_udu_correct2)
#define gf_udu_factor3 GF_NAME(gf_udu_factor3)
#define gf_udu_correct3 GF_NAME(gf_udu_correct3)
#define gf_udu_correct4 GF_NAME(gf_udu_correct4)
#define gf_udu_predict2 GF_NAME(gf_udu_predict2)
#define gf_udu_predict3 GF_NAME(gf_udu_predict3)
#define gf_udu_predict4 GF_NAME(gf_udu_predict4)

// kf_core.h: defined in kf.c
#define gf_kfc_init GF_NAME(gf_kfc_init)
#define gf_kfc_keep GF_NAME(gf_kfc_keep)
#define gf_kfc_meas_check GF_NAME(gf_kfc_meas_check)
#define gf_kfc_noise GF_NAME(gf_kfc_noise)
#define gf_kfc_predict GF_NAME(gf_kfc_predict)
#define gf_kfc_update GF_NAME(gf_kfc_update)
#define gf_kfc_update_begin GF_NAME(gf_kfc_update_begin)

#endif
