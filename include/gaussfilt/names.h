// SPDX-License-Identifier: MIT
// gaussfilt: every public function's link name carries the precision it was
// compiled for, so a program and a library built for different gf_real
// cannot link: a float library (GF_SINGLE_PRECISION) defines
// gf_kf2_update_f32, and a program built without GF_SINGLE_PRECISION calls
// gf_kf2_update_f64, which the linker reports as undefined. Source code
// uses the plain names; debuggers, nm and map files show the suffixed ones.
// Included by config.h once gf_real is chosen; not meant to be included on
// its own. gf_status_str keeps its name: it has no gf_real in it.
//
// Every function of the API is listed here; the library's internal
// functions are in src/gf_names.h (scripts/test compares both lists with
// nm of the built library, both precisions).
#ifndef GAUSSFILT_NAMES_H
#define GAUSSFILT_NAMES_H

#ifdef GF_SINGLE_PRECISION
#define GF_NAME(name) name##_f32
#else
#define GF_NAME(name) name##_f64
#endif

// mat.h
#define gf_angle_wrap GF_NAME(gf_angle_wrap)
#define gf_atan2 GF_NAME(gf_atan2)
#define gf_exp GF_NAME(gf_exp)
#define gf_log GF_NAME(gf_log)
#define gf_mat2_check_psd GF_NAME(gf_mat2_check_psd)
#define gf_mat2_eig_sym GF_NAME(gf_mat2_eig_sym)
#define gf_mat2_is_finite GF_NAME(gf_mat2_is_finite)
#define gf_mat2_mul GF_NAME(gf_mat2_mul)
#define gf_mat2_mulv GF_NAME(gf_mat2_mulv)
#define gf_mat2_sandwich GF_NAME(gf_mat2_sandwich)
#define gf_mat2_spd_inv GF_NAME(gf_mat2_spd_inv)
#define gf_mat2_symmetrize GF_NAME(gf_mat2_symmetrize)
#define gf_mat3_check_psd GF_NAME(gf_mat3_check_psd)
#define gf_mat3_chol GF_NAME(gf_mat3_chol)
#define gf_mat3_chol_solve GF_NAME(gf_mat3_chol_solve)
#define gf_mat3_is_finite GF_NAME(gf_mat3_is_finite)
#define gf_mat3_mul GF_NAME(gf_mat3_mul)
#define gf_mat3_mulv GF_NAME(gf_mat3_mulv)
#define gf_mat3_sandwich GF_NAME(gf_mat3_sandwich)
#define gf_mat3_sqrt_psd GF_NAME(gf_mat3_sqrt_psd)
#define gf_mat3_symmetrize GF_NAME(gf_mat3_symmetrize)
#define gf_sincos GF_NAME(gf_sincos)

// cov2.h
#define gf_cov2_correlation GF_NAME(gf_cov2_correlation)
#define gf_cov2_ellipse GF_NAME(gf_cov2_ellipse)
#define gf_cov2_marginal GF_NAME(gf_cov2_marginal)

// kf2.h
#define gf_kf2_cov GF_NAME(gf_kf2_cov)
#define gf_kf2_init GF_NAME(gf_kf2_init)
#define gf_kf2_predict GF_NAME(gf_kf2_predict)
#define gf_kf2_predict_prepared GF_NAME(gf_kf2_predict_prepared)
#define gf_kf2_prepare_meas GF_NAME(gf_kf2_prepare_meas)
#define gf_kf2_prepare_model GF_NAME(gf_kf2_prepare_model)
#define gf_kf2_update GF_NAME(gf_kf2_update)
#define gf_kf2_update_prepared GF_NAME(gf_kf2_update_prepared)

// ekf3.h
#define gf_ekf3_cov GF_NAME(gf_ekf3_cov)
#define gf_ekf3_init GF_NAME(gf_ekf3_init)
#define gf_ekf3_meas_x GF_NAME(gf_ekf3_meas_x)
#define gf_ekf3_meas_xy GF_NAME(gf_ekf3_meas_xy)
#define gf_ekf3_motion_forward_turn GF_NAME(gf_ekf3_motion_forward_turn)
#define gf_ekf3_predict GF_NAME(gf_ekf3_predict)
#define gf_ekf3_predict_prepared GF_NAME(gf_ekf3_predict_prepared)
#define gf_ekf3_prepare_meas GF_NAME(gf_ekf3_prepare_meas)
#define gf_ekf3_prepare_motion GF_NAME(gf_ekf3_prepare_motion)
#define gf_ekf3_update GF_NAME(gf_ekf3_update)
#define gf_ekf3_update_prepared GF_NAME(gf_ekf3_update_prepared)

// kf.h
#define gf_kf_cov GF_NAME(gf_kf_cov)
#define gf_kf_init GF_NAME(gf_kf_init)
#define gf_kf_predict GF_NAME(gf_kf_predict)
#define gf_kf_predict_prepared GF_NAME(gf_kf_predict_prepared)
#define gf_kf_prepare_meas GF_NAME(gf_kf_prepare_meas)
#define gf_kf_prepare_model GF_NAME(gf_kf_prepare_model)
#define gf_kf_update GF_NAME(gf_kf_update)
#define gf_kf_update_prepared GF_NAME(gf_kf_update_prepared)

// ekf.h
#define gf_ekf_check_model GF_NAME(gf_ekf_check_model)
#define gf_ekf_init GF_NAME(gf_ekf_init)
#define gf_ekf_predict GF_NAME(gf_ekf_predict)
#define gf_ekf_predict_prepared GF_NAME(gf_ekf_predict_prepared)
#define gf_ekf_prepare_meas GF_NAME(gf_ekf_prepare_meas)
#define gf_ekf_prepare_motion GF_NAME(gf_ekf_prepare_motion)
#define gf_ekf_update GF_NAME(gf_ekf_update)
#define gf_ekf_update_prepared GF_NAME(gf_ekf_update_prepared)

// rng.h
#define gf_rng_mvn3 GF_NAME(gf_rng_mvn3)
#define gf_rng_normal GF_NAME(gf_rng_normal)
#define gf_rng_seed GF_NAME(gf_rng_seed)
#define gf_rng_u32 GF_NAME(gf_rng_u32)
#define gf_rng_uniform GF_NAME(gf_rng_uniform)

// if2.h
#define gf_if2_from_moments GF_NAME(gf_if2_from_moments)
#define gf_if2_init GF_NAME(gf_if2_init)
#define gf_if2_predict GF_NAME(gf_if2_predict)
#define gf_if2_to_moments GF_NAME(gf_if2_to_moments)
#define gf_if2_update GF_NAME(gf_if2_update)

// ukf3.h
#define gf_ukf3_init GF_NAME(gf_ukf3_init)
#define gf_ukf3_predict GF_NAME(gf_ukf3_predict)
#define gf_ukf3_update GF_NAME(gf_ukf3_update)

// pf3.h
#define gf_pf3_estimate GF_NAME(gf_pf3_estimate)
#define gf_pf3_init GF_NAME(gf_pf3_init)
#define gf_pf3_neff GF_NAME(gf_pf3_neff)
#define gf_pf3_predict GF_NAME(gf_pf3_predict)
#define gf_pf3_resample GF_NAME(gf_pf3_resample)
#define gf_pf3_update GF_NAME(gf_pf3_update)

#endif
