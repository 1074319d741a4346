// SPDX-License-Identifier: MIT
// gaussfilt sim: a track's model as data, and the configuration file that
// maps channel patterns to models (gf_node --config, gf_sim --config).
//
// A model says everything the node needs to run one track without any
// constant in C: for the car (KF2) the time step, the process noise and
// the prior; for the robot (EKF3, UKF3 or PF3) the odometry noise and the
// prior; for both the gate and which quantities are measured. The
// measurement noise Q comes with every measurement (measurement_t.q); a
// model's meas_cov is what gf_sim draws its noise from and sends.
//
// Car, x = (position, velocity), one step of dt seconds:
//   A = ((1, dt), (0, 1)),  B = I,
//   R = accel_var * ((dt^4/4, dt^3/2), (dt^3/2, dt^2))
// (a white acceleration of variance accel_var held over each step: the
// discrete form of Bar-Shalom, Li and Kirubarajan 6.3.3, FilterPy's
// Q_discrete_white_noise(2, dt, accel_var)).
//
// Robot, x = (x, y, theta), control u = (d, phi) "move d forward, then turn
// phi". The odometry's errors grow with the distance and the turn:
//   var(d) = a1 d^2 + a2 phi^2,  var(phi) = a3 d^2 + a4 phi^2
// (independent), carried to the state at the mean's heading:
//   R = V diag(var(d), var(phi)) V^T,  V = dg/du = ((cos, 0), (sin, 0), (0, 1))
// (Probabilistic Robotics Table 7.2, lines 5-6, for this motion).
//
// Measurements: car position, velocity or both; robot x, (x, y), or the
// range and bearing of a landmark at a known place (lx, ly):
//   r = sqrt((lx - x)^2 + (ly - y)^2),  b = atan2(ly - y, lx - x) - theta,
// the bearing's residual wrapped to (-pi, pi].
//
// The book's exercises are two presets, the defaults of every track no
// configuration names: "book-car" (exercises 1-2: dt = 1, accel_var = 1,
// prior N(0, 0)) and "book-robot" (exercise 4: no odometry noise, prior
// N(0, diag(0.01, 0.01, 10000))), both measuring what each measurement's m
// says (GF_NODE_MEASURE_AUTO).
#ifndef GF_NODE_MODEL_H
#define GF_NODE_MODEL_H

#include <regex.h>
#include <stddef.h>
#include <stdint.h>

#include "gaussfilt/gaussfilt.h"

#ifdef __cplusplus
extern "C" {
#endif

// What a measurement carries (model_t.MEASURE_* on the wire, same values).
typedef enum gf_node_measure {
    GF_NODE_MEASURE_AUTO = 0, // as measurement_t.m says: 1 position (car)
                              // or x (robot), 2 both (car) or (x, y)
    GF_NODE_MEASURE_X = 1,    // car: position; robot: x
    GF_NODE_MEASURE_V = 2,    // car: velocity
    GF_NODE_MEASURE_XV = 3,   // car: (position, velocity)
    GF_NODE_MEASURE_XY = 4,   // robot: (x, y)
    GF_NODE_MEASURE_RANGE_BEARING = 5 // robot: landmark range and bearing
} gf_node_measure;

// Kinds, as measurement_t.MODEL_CAR / MODEL_ROBOT.
#define GF_NODE_KIND_CAR 1
#define GF_NODE_KIND_ROBOT 2

#define GF_NODE_MODEL_NAME 32

typedef struct gf_node_model {
    char name[GF_NODE_MODEL_NAME];
    int8_t kind;          // GF_NODE_KIND_CAR or GF_NODE_KIND_ROBOT
    int8_t measure;       // gf_node_measure, valid for the kind
    double dt;            // car: seconds per step, > 0
    double accel_var;     // car: variance of the acceleration, >= 0
    double odometry[4];   // robot: a1..a4, >= 0
    double landmark[2];   // robot, range-bearing: (lx, ly)
    double gate;          // chi-square gate on the NIS, 0 for none
    double prior_mean[3]; // first n entries (n = 2 car, 3 robot)
    double prior_cov[3][3];
    double meas_cov[3][3]; // the sensor's noise, m x m (gf_sim draws it)
} gf_node_model;

// The presets (never NULL).
const gf_node_model *gf_node_model_book_car(void);
const gf_node_model *gf_node_model_book_robot(void);

// Measured quantities of a measure (1..2) for a kind, 0 if the measure is
// not valid for the kind (GF_NODE_MEASURE_AUTO: 0).
unsigned gf_node_measure_m(int8_t kind, int8_t measure);

// The measure a measurement of m quantities gets under this model: the
// model's own, or for GF_NODE_MEASURE_AUTO the one m says. -1 when m does
// not fit the model.
int gf_node_model_measure(const gf_node_model *mdl, unsigned m);

// Checks a model: kind and measure agree, every number finite, dt > 0,
// variances and gate >= 0, prior and meas_cov symmetric PSD, and the prior
// one the filter's init takes (gf_kf2_init or gf_ekf3_init, in gf_real).
// Returns 0, or -1 and a reason in why (may be NULL).
int gf_node_model_check(const gf_node_model *mdl, const char **why);

// ---- the core's model structs, built from a model ------------------------

// The car's motion model (A, B, R of the comment at the top).
void gf_node_model_car(const gf_node_model *mdl, gf_kf2_model *out);

// The car's measurement model for a measure (gf_node_model_measure) with
// noise q (m x m, row stride 3).
void gf_node_model_car_meas(const gf_node_model *mdl, int measure,
                            const double q[3][3], gf_kf2_meas *out);

// The robot's motion (forward-turn) with R from the odometry noise at
// heading theta for the control u.
void gf_node_model_robot(const gf_node_model *mdl, gf_real theta,
                         const gf_real u[2], gf_ekf3_motion *out);

// The robot's measurement model with noise q; its callback's ctx points
// at mdl, which must outlive the update.
void gf_node_model_robot_meas(const gf_node_model *mdl, int measure,
                              const double q[3][3], gf_ekf3_meas *out);

// The range-bearing measurement callback (ctx: a gf_node_model): z_hat =
// (r, b) and H. GF_ERR_MODEL when the robot stands on the landmark.
gf_status gf_node_meas_range_bearing(void *ctx, const gf_vec3 *mu_bar,
                                     gf_vec3 *z_hat, gf_mat3 *H);

// ---- the configuration file ----------------------------------------------
//
//   # a comment, to the end of the line
//   [model NAME]          one section per model
//   base = book-car       start from a preset or an earlier model
//   type = car|robot
//   channels = REGEX      the tracks that use it (POSIX extended regex,
//                         anchored, matched against GF_MEAS_<id> and
//                         GF_CTRL_<id>; the first model that matches wins)
//   dt = 0.01             accel_var = 4        (car)
//   odometry = a1 a2 a3 a4                     (robot)
//   measure = position | velocity | position velocity   (car)
//   measure = x | x y | range bearing                   (robot)
//   measure = auto        (as measurement_t.m says, the presets' way)
//   landmark = LX LY      gate = G (0: none)
//   prior_mean = n numbers
//   prior_cov = n numbers (the diagonal) or n*n (row by row)
//   meas_cov = m numbers (the diagonal) or m*m
//
// Every key is optional but type (or base); numbers are C's strtod.

#define GF_NODE_CONFIG_MODELS 16

typedef struct gf_node_config {
    unsigned count;
    gf_node_model model[GF_NODE_CONFIG_MODELS];
    int has_regex[GF_NODE_CONFIG_MODELS];
    regex_t regex[GF_NODE_CONFIG_MODELS];
    char channels[GF_NODE_CONFIG_MODELS][128];
} gf_node_config;

// Reads a configuration from text (NUL-terminated). Returns 0, or -1 with
// "line N: what is wrong" in err.
int gf_node_config_parse(gf_node_config *cfg, const char *text, char *err,
                         size_t err_size);

// Reads a configuration file (at most 64 kB). As gf_node_config_parse.
int gf_node_config_load(gf_node_config *cfg, const char *path, char *err,
                        size_t err_size);

// Frees the compiled patterns.
void gf_node_config_free(gf_node_config *cfg);

// The model for a new track id of this kind: the first whose channels
// match GF_MEAS_<id> or GF_CTRL_<id> and whose kind agrees, else the
// kind's preset. cfg may be NULL (presets only). Never NULL.
const gf_node_model *gf_node_config_lookup(const gf_node_config *cfg,
                                           int32_t id, int8_t kind);

// The model named name (presets included), or NULL.
const gf_node_model *gf_node_config_find(const gf_node_config *cfg,
                                         const char *name);

#ifdef __cplusplus
}
#endif

#endif
