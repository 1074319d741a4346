// SPDX-License-Identifier: MIT
// gaussfilt: the checks of an EKF3 measurement model, which EKF3, UKF3 and
// PF3 share. Not installed, not part of the API.
#ifndef GAUSSFILT_SRC_MEAS3_H
#define GAUSSFILT_SRC_MEAS3_H

#include "gaussfilt/ekf3.h"

#include "gf_internal.h"

// The checks every update with an EKF3 measurement model starts with, in
// the order of the status rules: GF_ERR_ARG (meas or h NULL, m not 1..3),
// GF_ERR_NONFINITE (z if not NULL, gate), GF_ERR_ARG (gate < 0), then Q's
// verdict (gf_cov_factor); on GF_OK, q holds Q's factors: Q = F diag(Qe)
// F^T, F in Qf (m x m, rows of m) unit lower triangular in the order
// Qorder (q is written on failure too).
gf_status gf_meas3_check(const gf_ekf3_meas *meas, const gf_vec3 *z,
                         gf_ekf3_qfactors *q);

// gf_meas3_check's status alone, Q's factors kept in its own frame, not
// its caller's (defined in meas3.c).
gf_status gf_meas3_verdict(const gf_ekf3_meas *meas, const gf_vec3 *z);

#endif
