// SPDX-License-Identifier: MIT
// gaussfilt: the steps gf_kf and gf_ekf share (defined in kf.c), on the
// factored core of src/udu.h, for n states up to GF_KF_NMAX, the scratch
// in the caller's gf_kf_work. Not installed, not part of the API.
#ifndef GAUSSFILT_SRC_KF_CORE_H
#define GAUSSFILT_SRC_KF_CORE_H

#include "gaussfilt/kf.h"

#include "gf_internal.h"

// The verdict on an n x n covariance s passed in (gf_cov_factor) and, where
// fac is not NULL, its factors in work->noise (*fac points there on
// GF_OK).
gf_status gf_kfc_noise(const gf_real *s, unsigned n, gf_kf_work *work,
                       const gf_kf_factors **fac);

// Checks n and mu, judges sigma, and sets *kf to N(mu, sigma) factored,
// with kf->angles = angles (gf_ekf wraps those states once a step
// succeeds); kf untouched on failure.
gf_status gf_kfc_init(gf_kf *kf, unsigned n, const gf_real *mu,
                      const gf_real *sigma, unsigned angles, gf_kf_work *work);

// The prediction once the model is checked: mu_bar (n), Sigma_bar =
// G Sigma G^T + R with R's factors (Rf, Rd); the belief written only if
// all of it is finite.
gf_status gf_kfc_predict(gf_kf *kf, const gf_real *mu_bar, const gf_real *G,
                         const gf_real *Rf, const gf_real *Rd,
                         gf_kf_work *work);

// The checks of m, Q, the gate and z (if not NULL), in the order of the
// update's statuses; on GF_OK, *fac holds Q's factors (gf_kfc_noise).
gf_status gf_kfc_meas_check(unsigned n, unsigned m, const gf_real *Q,
                            gf_real gate, const gf_real *z, gf_kf_work *work,
                            const gf_kf_factors **fac);

// The correction once the measurement is checked, with the innovation y
// (m entries) in work->in.y and in work->yw, and the whitened rows hw (m x
// n, F_Q^-1 H): y_w = F_Q^-1 y in work->yw (Q's factors Qf, Qorder), one
// scalar update per quantity with the noises Qe (gf_udu_correct), the gate
// on the total NIS; the belief and info written only if every quantity
// passed and the result is finite.
gf_status gf_kfc_correct(gf_kf *kf, unsigned m, const gf_real *hw,
                         const gf_real *Qf, const gf_real *Qe,
                         const unsigned *Qorder, gf_real gate,
                         gf_kf_innovation *info, gf_kf_work *work);

// Copies a noise's factors (m x m) into a prepared model's arrays (order
// may be NULL).
void gf_kfc_keep(const gf_kf_factors *fac, unsigned m, gf_real *F, gf_real *d,
                 unsigned *order);

#endif
