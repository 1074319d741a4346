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
//
// Linear, any n (gf_kf, 1 <= n <= GF_NODE_NMAX): the book's linear
// Gaussian system written out,
//   x_t = A x_{t-1} + B u_t + eps,  eps ~ N(0, R),
//   z_t = C x_t + delta,            delta ~ N(0, Q),
// with A, B, R, C and Q (gf_sim's noise; the node takes each message's q)
// given as numbers, or A and R built from dt per axis: a constant-velocity
// axis (position, velocity) has the car's A and R; a constant-acceleration
// axis (position, velocity, acceleration)
//   A = ((1, dt, dt^2/2), (0, 1, dt), (0, 0, 1)),
//   R = accel_var g g^T,  g = (dt^2/2, dt, 1)
// (the acceleration's change over a step has variance accel_var: Bar-Shalom
// 6.3.3's discrete Wiener process acceleration, FilterPy's
// Q_discrete_white_noise(3, dt, accel_var)). Axes stack in the order given,
// each axis's states together: "cv cv" is (x, vx, y, vy). There is no
// linear preset: a linear track runs only with a model its channels name.
#ifndef GF_NODE_MODEL_H
#define GF_NODE_MODEL_H

#include <regex.h>
#include <stddef.h>
#include <stdint.h>

#include "gaussfilt/codegen.h"
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
    GF_NODE_MEASURE_RANGE_BEARING = 5, // robot: landmark range and bearing
    // a robot's sensor only (not model_t's):
    GF_NODE_MEASURE_RANGE = 6,   // the landmark's range
    GF_NODE_MEASURE_BEARING = 7, // the landmark's bearing
    GF_NODE_MEASURE_HEADING = 8  // theta
} gf_node_measure;

// Kinds, as measurement_t.MODEL_CAR / MODEL_ROBOT / MODEL_LINEAR.
#define GF_NODE_KIND_CAR 1
#define GF_NODE_KIND_ROBOT 2
#define GF_NODE_KIND_LINEAR 3

#define GF_NODE_MODEL_NAME 32

// The most states (and controls, and measured quantities) of a linear
// model: gf_kf's.
#define GF_NODE_NMAX GF_KF_NMAX
#define GF_NODE_STR_(x) #x
#define GF_NODE_STR(x) GF_NODE_STR_(x)
#define GF_NODE_NMAX_STR GF_NODE_STR(GF_KF_NMAX)

// Axis kinds of a linear model's dt-built motion (the kind's states).
#define GF_NODE_AXIS_C 1  // a constant: a random walk of variance q per s
#define GF_NODE_AXIS_CV 2 // (position, velocity)
#define GF_NODE_AXIS_CA 3 // (position, velocity, acceleration)

// A model's named sensors: at most GF_NODE_SENSORS, names of
// [A-Za-z][A-Za-z0-9]* up to GF_NODE_SENSOR_NAME - 1 characters. A
// sensor's measurements come on GF_MEAS_<id>_<name>.
#define GF_NODE_SENSORS 8
#define GF_NODE_SENSOR_NAME 16

typedef struct gf_node_sensor {
    char name[GF_NODE_SENSOR_NAME];
    unsigned m;
    int8_t measure;      // robot: gf_node_measure; linear: 0 (C)
    unsigned angle_mask; // bit i: residual i is an angle, wrapped
    double gate;         // chi-square gate on the NIS, 0 for none
    double landmark[2];  // robot: range, bearing
    double rate;         // gf_sim: samples per second (0: every step)
    double C[GF_KF_NMAX * GF_KF_NMAX]; // linear: m rows of n
    double Q[GF_KF_NMAX * GF_KF_NMAX]; // its default noise, m x m; a
                                       // message's q overrides it
} gf_node_sensor;

typedef struct gf_node_sensors {
    unsigned count;
    gf_node_sensor s[GF_NODE_SENSORS];
} gf_node_sensors;

// The most parameters of a generated model.
#define GF_NODE_PARAMS 32

// A generated model (type = generated): its descriptor
// (gaussfilt/codegen.h), read from a shared object built from the
// generated C with -DGF_CODEGEN_EXPORT, which defines gf_codegen_exported.
typedef struct gf_node_generated {
    void *handle;                 // dlopen's (NULL in a model based on it)
    const gf_codegen_model *desc; // the library's descriptor
    char path[256];               // the library, as the configuration names it
    gf_real params[GF_NODE_PARAMS]; // its callbacks' ctx (params = ...)
    int has_params;                 // params given
} gf_node_generated;

// A linear model's numbers, row-major (rows of n; B rows of nu, C and Q
// rows of n and m). axes > 0: A and R are built from dt and accel_var per
// axis (gf_node_linear_build) when the configuration's section ends.
typedef struct gf_node_linear {
    unsigned n, nu, m;
    double A[GF_NODE_NMAX * GF_NODE_NMAX];
    double B[GF_NODE_NMAX * GF_NODE_NMAX];
    double R[GF_NODE_NMAX * GF_NODE_NMAX];
    double C[GF_NODE_NMAX * GF_NODE_NMAX];
    double Q[GF_NODE_NMAX * GF_NODE_NMAX]; // the sensor's (gf_sim draws it)
    double prior_mean[GF_NODE_NMAX];
    double prior_cov[GF_NODE_NMAX * GF_NODE_NMAX];
    unsigned axes;                    // dt-built axes, 0: A and R as given
    unsigned char axis[GF_NODE_NMAX]; // GF_NODE_AXIS_CV or _CA
    double accel_var[GF_NODE_NMAX];   // per axis
    // type = generated: its library (non-NULL once library = is read); g
    // and R(dt) from it in place of A, B and R, its sensors' h in place of
    // C, and the states' names and units from its descriptor
    int generated;
    const gf_node_generated *gen;
} gf_node_linear;

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
    // linear: its numbers (prior and noise there, not above); they belong
    // to the configuration, which outlives every track made from it
    const gf_node_linear *lin;
    // the configuration's channels pattern that names this model, or NULL
    const char *channels;
    // its named sensors (in the configuration, as lin), or NULL for none
    const gf_node_sensors *sensors;
    // seconds an input may be older than the track's time and still be
    // answered with a late status belief (a model whose motion is built
    // from dt); older ones are too_old
    double late_window;
} gf_node_model;

// The default late_window, seconds.
#define GF_NODE_LATE_WINDOW 1.0

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
// one the filter's init takes (gf_kf2_init, gf_ekf3_init or gf_kf_init, in
// gf_real); a linear model's sizes in range and A, B, R, C, Q as
// gf_kf_prepare_model and gf_kf_prepare_meas take them. Returns 0, or -1
// and a reason in why (may be NULL) that starts with the key at fault.
int gf_node_model_check(const gf_node_model *mdl, const char **why);

// Builds a linear model's A and R from dt and its axes (see the top).
void gf_node_linear_build(gf_node_linear *lin, double dt);

// A and R (n x n, rows of n) of a linear model's dt-built axes for a step
// of dt seconds (dt >= 0; dt = 0: A = I, R = 0), as gf_node_linear_build.
void gf_node_linear_motion(const gf_node_linear *lin, double dt, double *A,
                           double *R);

// The sensor of this name, or NULL.
const gf_node_sensor *gf_node_model_sensor(const gf_node_model *mdl,
                                           const char *name);

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

// A robot sensor's measurement model with noise q (m x m, row stride 3);
// its callback's ctx points into sen, which must outlive the update.
void gf_node_sensor_robot_meas(const gf_node_sensor *sen, const double q[3][3],
                               gf_ekf3_meas *out);

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
//   type = linear         a linear model of any n (see the top):
//   motion = cv cv        dt-built axes (cv, ca), giving n; or n = N and
//   A = n*n numbers       row by row (a ';' may end each row)
//   accel_var = q | q1 q2 ...   one per axis (with motion); or
//   R = n or n*n numbers
//   B = n*nu numbers      (nu controls; none without it)
//   C = m*n numbers       the measured quantities, one row each
//   Q = m or m*m numbers  (the same as meas_cov)
//   prior_mean, prior_cov, gate as above
//   late_window = S       seconds an input may be older than its track's
//                         time and still get a late status belief (1)
//
//   type = generated      a model gaussfilt.codegen wrote (docs/codegen.md):
//   library = PATH        its shared object (relative to the file's folder),
//                         built with -DGF_CODEGEN_EXPORT in this node's
//                         precision; n, the inputs (a control's u), the
//                         states' names and units and the sensors are its
//   params = P ...        its parameters, in its order
//   prior_mean, prior_cov, gate, late_window as above; it runs in time
//   dt = S                the step before a track's first input (1)
//   [sensor NAME]         one of its sensors: Q, gate, angles, rate (Q's
//                         default: the library's)
//
//   [sensor NAME]         a named sensor of the model above it (linear or
//                         robot; at most GF_NODE_SENSORS), measured on
//                         GF_MEAS_<id>_<NAME>:
//   C = m*n numbers       linear: its measured quantities
//   measure = x | x y | range bearing | range | bearing | heading (robot)
//   landmark = LX LY      robot: range, bearing
//   Q = m or m*m numbers  its default noise (a message's q overrides it;
//                         a q of zeros takes it)
//   gate = G              angles = ROW ...   (rows from 0, wrapped)
//   rate = HZ             what gf_sim sends at (0: every dt)
//
// Every key is optional but type (or base); numbers are C's strtod. An
// error names the line of the key at fault.

#define GF_NODE_CONFIG_MODELS 16

typedef struct gf_node_config {
    unsigned count;
    gf_node_model model[GF_NODE_CONFIG_MODELS];
    gf_node_linear linear[GF_NODE_CONFIG_MODELS]; // model[i].lin, if linear
    int has_regex[GF_NODE_CONFIG_MODELS];
    regex_t regex[GF_NODE_CONFIG_MODELS];
    char channels[GF_NODE_CONFIG_MODELS][128];
    gf_node_sensors sensors[GF_NODE_CONFIG_MODELS];     // model[i].sensors
    gf_node_generated generated[GF_NODE_CONFIG_MODELS]; // linear[i].gen
} gf_node_config;

// Reads a configuration from text (NUL-terminated). Returns 0, or -1 with
// "line N: what is wrong" in err.
int gf_node_config_parse(gf_node_config *cfg, const char *text, char *err,
                         size_t err_size);

// Reads a configuration file (at most 64 kB). As gf_node_config_parse.
int gf_node_config_load(gf_node_config *cfg, const char *path, char *err,
                        size_t err_size);

// Frees the compiled patterns and closes the generated models' libraries
// (after a failed parse too). A configuration's models point into it:
// it must not move while they are used.
void gf_node_config_free(gf_node_config *cfg);

// The model a configuration names for a new track id of this kind: the
// first whose channels match GF_MEAS_<id> or GF_CTRL_<id> and whose kind
// agrees; NULL when none does (cfg may be NULL).
const gf_node_model *gf_node_config_named(const gf_node_config *cfg, int32_t id,
                                          int8_t kind);

// As gf_node_config_named, else the kind's preset (NULL for a linear
// track: there is no linear preset).
const gf_node_model *gf_node_config_lookup(const gf_node_config *cfg,
                                           int32_t id, int8_t kind);

// The model named name (presets included), or NULL.
const gf_node_model *gf_node_config_find(const gf_node_config *cfg,
                                         const char *name);

#ifdef __cplusplus
}
#endif

#endif
