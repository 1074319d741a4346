// SPDX-License-Identifier: MIT
// The interface between the endurance driver and the filter steps, which
// are compiled twice: once with gf_real = double (names ending in _d) and
// once with gf_real = float (names ending in _f, every gf_ symbol of that
// copy renamed gff_ so both link into one program). Everything crossing it
// is double, so the driver never sees gf_real.
#ifndef GF_ENDURANCE_H
#define GF_ENDURANCE_H

// One filter's belief after a step, widened to double, and the statuses of
// its predict and update calls (update: 1 when there was no measurement).
typedef struct endurance_belief {
    double mu[3];
    double sigma[3][3];
    int predict_status;
    int update_status;
} endurance_belief;

// KF2 on the controlled car: x' = A x + B u + eps, B = ((0.5, 0), (1, 0)),
// R = ((0.25, 0.5), (0.5, 1)); position measured with variance 10.
#define ENDURANCE_KF2_Q 10.0
// EKF3 "move d forward, then turn phi", R = diag(0.005, 0.005, 0.001);
// (x, y) measured with variances 0.01.
#define ENDURANCE_EKF3_R_XY 0.005
#define ENDURANCE_EKF3_R_TH 0.001
#define ENDURANCE_EKF3_Q 0.01

// (Re)starts the filter of that copy: KF2 at N(0, diag(100, 100)), EKF3 at
// N((20, 0, pi/2), diag(1, 1, 0.1)). Returns the init status.
int endurance_kf2_start_d(void);
int endurance_kf2_start_f(void);
int endurance_ekf3_start_d(void);
int endurance_ekf3_start_f(void);

// One step: predict with the control u (acceleration for KF2; d, phi for
// EKF3), then update with z when z is not NULL (position for KF2; x, y for
// EKF3), and report the belief.
void endurance_kf2_step_d(double u, const double *z, endurance_belief *out);
void endurance_kf2_step_f(double u, const double *z, endurance_belief *out);
void endurance_ekf3_step_d(const double u[2], const double *z,
                           endurance_belief *out);
void endurance_ekf3_step_f(const double u[2], const double *z,
                           endurance_belief *out);

#endif
