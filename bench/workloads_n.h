// SPDX-License-Identifier: MIT
// The benchmarks' workloads for the filters of n states (gf_kf, gf_ekf),
// shared by the host program (bench.c) and the Cortex-M4F image (m4f.c):
// the models, and the measurements of a simulated truth of WL_TAB steps,
// computed before anything is measured and replayed from a table.
//
//   cvN (N = 2, 4, 6, 8, 12), gf_kf: N/2 independent constant-velocity
//        axes, state (p0, v0, p1, v1, ...), A block-diagonal ((1, dt), (0,
//        1)) with dt = 0.1 s, per axis the white-acceleration process noise
//        of Bar-Shalom 6.3.3, R = q ((dt^3/3, dt^2/2), (dt^2/2, dt)), q =
//        0.5 + 0.1 axis; m = N/2 positions measured (C picks them), Q
//        diagonal, 1 m^2 (+ 0.25 per axis).
//   cv3, gf_kf: N/2 is not an integer: one constant-velocity axis (p, v)
//        plus one random-walk state b (b += w, w ~ N(0, 0.01 dt)), m = 2:
//        the position and b measured (C = ((1,0,0), (0,0,1)); b alone
//        would be unobservable through p + b), Q = diag(1, 0.25).
//   gps, gf_ekf: 8 states (x, y, z, vx, vy, vz, b, d): position and
//        velocity on three Earth-centred axes (m, m/s), each axis the
//        white-acceleration model of cvN with dt = 1 s, q = 0.1, and the
//        receiver clock's bias and drift (b, d in m, m/s: b += d dt, the
//        clock's noise R_bb = 0.1 dt + 0.01 dt^3/3, R_bd = 0.01 dt^2/2,
//        R_dd = 0.01 dt); m = 4 pseudoranges rho_i = |s_i - p| + b from 4
//        satellites at 26,560 km from the Earth's centre, fixed over the
//        run (a simplification: their motion would only change the
//        table), Q = 25 I (5 m). The receiver: on the surface (6,371 km)
//        at 45 N 10 E, driving at about 15 m/s. The motion and the
//        measurement are the callbacks wl_gps_motion and wl_gps_meas,
//        whose cost is in every figure ("model included").
#ifndef GF_BENCH_WORKLOADS_N_H
#define GF_BENCH_WORKLOADS_N_H

#include "gaussfilt/ekf.h"
#include "gaussfilt/kf.h"
#include "workloads.h"

// The rows, in the order the bench prints them.
#define WL_N_ROWS 7
extern const char *const wl_n_names[WL_N_ROWS]; // "cv2" ... "cv12", "gps"

// The workload set up by wl_setup_n: its sizes, models, initial belief
// (mu, Sigma as given to init, for the floor) and measurements.
typedef struct wl_n {
    const char *name;
    unsigned n, m;
    int ekf;           // 1: gps (gf_ekf), 0: gf_kf
    gf_kf_model model; // gf_kf rows
    gf_kf_meas meas;
    gf_ekf_motion motion; // the gps row
    gf_ekf_meas emeas;
    gf_kf init;              // the belief at the start of each replay
    gf_real mu0[GF_KF_NMAX]; // the same, as mu and Sigma
    gf_real sigma0[GF_KF_NMAX * GF_KF_NMAX];
} wl_n;

extern wl_n wl_nw;
extern gf_kf_work wl_n_work;
extern gf_real wl_n_z[WL_TAB][GF_KF_NMAX]; // step i's measurements

// Sets up row `name` (one of wl_n_names) in wl_nw and wl_n_z, and runs the
// filter over the table once (a failing step ends the program).
// Returns 0, or -1 for an unknown name.
int wl_setup_n(const char *name);

// The gps models (ctx: unused; the satellites are this file's).
gf_status wl_gps_motion(void *ctx, unsigned n, const gf_real *mu,
                        const gf_real *u, gf_real *mu_bar, gf_real *G);
gf_status wl_gps_meas(void *ctx, unsigned n, unsigned m, const gf_real *mu_bar,
                      gf_real *z_hat, gf_real *H);

#endif
