// SPDX-License-Identifier: MIT
// The benchmarks' workloads, shared by the host program (bench.c) and the
// Cortex-M4F image (m4f.c): the models, and the inputs and beliefs of a
// simulated truth of WL_TAB steps, computed before anything is measured.
//
//   W1, KF2:  the car of exercises 1 and 2: A = ((1,1),(0,1)), no control,
//             R = ((0.25,0.5),(0.5,1)); one step = predict + update with a
//             scalar position measurement, C = (1,0), Q = 10.
//   W2, EKF3: the robot of exercise 4: predict with "move 1 forward, then
//             turn phi" (gf_ekf3_motion_forward_turn), then an update with
//             m = 1: x (gf_ekf3_meas_x), Q = 0.01;
//             m = 2: x and y (gf_ekf3_meas_xy), Q = 0.01 I;
//             m = 3: x, y and the heading (wl_meas_xyt, this file's own
//             callback; the heading's residual wrapped), Q = diag(0.01,
//             0.01, 0.0025).
//             The turn phi is drawn in [-0.6, 0.6] each step, so the
//             heading wanders over the whole circle (theta = 0 would let
//             sin/cos take a fast path).
#ifndef GF_BENCH_WORKLOADS_H
#define GF_BENCH_WORKLOADS_H

#include "gaussfilt/gaussfilt.h"

#define WL_TAB 1024u // steps of simulated truth; a power of two

extern const gf_kf2_model wl_w1_model;
extern const gf_kf2_meas wl_w1_meas;
extern gf_kf2_pmodel wl_w1_pmodel; // wl_w1_model and wl_w1_meas, prepared
extern gf_kf2_pmeas wl_w1_pmeas;
extern gf_kf2 wl_w1_init;          // belief at the start of each replay
extern gf_vec2 wl_w1_z[WL_TAB];    // measurement of step i
extern gf_kf2 wl_w1_post[WL_TAB];  // belief before step i's predict
extern gf_kf2 wl_w1_prior[WL_TAB]; // belief before step i's update

extern gf_ekf3_motion wl_w2_motion;
extern gf_ekf3_meas wl_w2_meas;
extern gf_ekf3_pmotion wl_w2_pmotion; // wl_w2_motion and wl_w2_meas, prepared
extern gf_ekf3_pmeas wl_w2_pmeas;
extern gf_ekf3 wl_w2_init;
extern gf_real wl_w2_u[WL_TAB][2]; // control of step i: (1, phi_i)
extern gf_vec3 wl_w2_z[WL_TAB];    // x, y, heading of step i
extern gf_ekf3 wl_w2_post[WL_TAB];
extern gf_ekf3 wl_w2_prior[WL_TAB];

// Fills the W1 tables and the prepared models.
void wl_setup_w1(void);

// Fills the W2 tables for an update of m = 1, 2 or 3 measured quantities.
// user (m = 1 only): the caller's own copies of the two built-in models
// (wl_forward_turn, wl_meas_x), which the core cannot recognise.
void wl_setup_w2(unsigned m, int user);

// W2's models as a caller would write them.
gf_status wl_forward_turn(void *ctx, const gf_vec3 *mu, const gf_real *u,
                          gf_vec3 *mu_bar, gf_mat3 *G);
gf_status wl_meas_x(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                    gf_mat3 *H);
gf_status wl_meas_xyt(void *ctx, const gf_vec3 *mu_bar, gf_vec3 *z_hat,
                      gf_mat3 *H);

// The simulated truth's generator: xorshift64* on *state, uniform in
// (0, 1), and Box-Muller normals (double; bench only).
double wl_uniform(unsigned long long *state);
double wl_normal(unsigned long long *state);

// Prints what failed and exits with 1.
void wl_die(const char *what, int i, gf_status st);

#endif
