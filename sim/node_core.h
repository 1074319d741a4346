// SPDX-License-Identifier: MIT
// gaussfilt sim: the filter node's message handling, with no sockets.
//
// gf_node_handle() takes one LCM message (channel + bytes, exactly as LCM
// delivered it), checks it, runs the core filter of its track (KF2 for the
// car; EKF3, UKF3 or PF3 for the robot, see gf_node_set_filter; gf_kf for
// a linear model of any size; no filter math here) and hands every belief
// to a publish callback as encoded gaussfilt_lcm_belief_t bytes (a PF3
// track also a particles_t cloud). gf_node.c wires it to LCM; tests,
// fuzzers and benchmarks call it directly.
//
// Restarts. A node keeps no state across its own restarts: a restarted node
// re-initialises each track from the prior on the track's first message
// (whatever its seq) and says so with a STAGE_INIT belief of seq 0. A
// restarted simulator starts seq at 1 again under a larger `session`: the
// first input of a larger session re-initialises the track the same way (a
// STAGE_INIT belief, counted in resyncs) and the seq rules start afresh;
// an input of a smaller session is rejected as GF_NODE_STALE_SESSION.
//
// Tracks are created by their first valid message, up to
// GF_NODE_MAX_TRACKS per node; each takes its model (node_model.h) from
// the node's model lookup (gf_node_set_models: gf_node --config; a model
// gf_node_model_check refuses counts as none), else the
// book's preset of its kind (car: exercises 1-2, mu = 0, Sigma = 0; robot:
// exercise 4, mu = 0, Sigma = diag(0.01, 0.01, 10000)), starts from the
// model's prior and publishes that initial belief first. A linear track
// has no preset: with no model named it is refused (no_model), and so is
// every track no model names once gf_node_set_strict is on. A model_t on
// GF_MODEL_<id> sets a car's or robot's model at run time, or resets any
// track (a linear one to its configured prior). The node says
// which model each new track got and why, a track whose first input comes
// after others it never saw, and another node's beliefs of its own tracks,
// through the log callback (gf_node_set_log).
//
// Sensors: a model's named sensors (node_model.h) take their
// measurements on GF_MEAS_<id>_<name>, each channel its own seq (stream
// 1 + k; the controls and GF_MEAS_<id> share stream 0), all updating the
// one belief in arrival order; a message of a sensor its model lacks is
// bad_field (said once per track). Every belief a sensor made names it
// (belief_t.sensor).
//
// Time: a track whose linear model has dt-built axes (motion = cv|ca|c)
// or is generated (type = generated: gf_ekf with its library's g, R(dt)
// and sensors' h) is in time: every input first predicts it to its utime,
// A and R (g and R) built for the dt since the track's last input (the
// model's dt before its first), a control with its B u (its inputs; a
// measurement's prediction takes them as zero); an input the core
// refuses leaves the track's belief and time as they were, a gated
// measurement the prediction to its utime. An input older than the track's time is
// late (within the model's late_window: refused, a STATUS_LATE belief) or
// too_old (refused, no belief); both keep their stream's seq. Other tracks
// step once per control, and an input whose utime falls is out_of_order.
//
// Refusals: every control or measurement of a track the node holds that
// decodes gets a belief, a refused one too: the track's belief as it is,
// with the input's utime, seq, stage and sensor and a status that says
// why (GF_NODE_STATUS_* below, the core's gf_status for a failed step); a
// refused input's seq counts as received (no gap; before the track is
// made, none lost before its first). A refused model_t is said and gets a
// GF_NODE_STATUS_BAD_FIELD belief (STAGE_INIT). The first refusal of each
// kind on each track id is said through the log callback, naming the
// field and both sizes where a size is wrong; a track's first
// GF_NODE_GATED_WARN updates all gated, or as many in a row later, too.
//
// Edges, with their rules:
// - Sequence resync: GF_NODE_RESYNC_AFTER inputs in a row rejected as
//   out_of_order on a track (e.g. after one packet with seq or utime at
//   INT64_MAX) make the next input the track's new reference: it is taken
//   whatever its seq and utime, the belief kept, counted in seq_resyncs
//   (no gaps counted for the jump).
// - PF summary: a PF step whose particles moved but whose weighted mean or
//   covariance overflows (or has no heading direction) is the result
//   no_summary; the belief carries status STATUS_NO_SUMMARY with mean and
//   cov NaN, exactly what the track holds until a step's summary can be
//   computed again; particles beyond float's range are sent as +-FLT_MAX.
// Nothing is allocated: a gf_node is one plain struct the caller owns.
#ifndef GF_NODE_CORE_H
#define GF_NODE_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "gaussfilt/gaussfilt.h"
#include "gf_channels.h"
#include "node_model.h"

#ifdef __cplusplus
extern "C" {
#endif

// The most tracks one node holds (gf_node prints track_bytes, all inside
// gf_node). A
// message for a new track beyond this is rejected with GF_NODE_TRACK_LIMIT.
// Split more tracks over several nodes by channel pattern, or build with
// another limit: CMake's GAUSSFILT_NODE_MAX_TRACKS (a PUBLIC definition of
// gaussfilt_node_core, so every user of this header sees the same value).
#ifndef GF_NODE_MAX_TRACKS
#define GF_NODE_MAX_TRACKS 64
#endif
#if GF_NODE_MAX_TRACKS < 1
#error "GF_NODE_MAX_TRACKS must be at least 1"
#endif

// The longest message the node reads (gf_node's input queue keeps as
// many bytes). Every size an int8 field can hold fits: a whole control
// or measurement with n or m beyond GF_NODE_NMAX is bad_field however
// long (a measurement with m = 127 is 130 086 bytes); a longer message
// is malformed. The largest input the node takes, a measurement with
// m = GF_NODE_NMAX = 12, is 1 286 bytes (one UDP datagram).
#define GF_NODE_MAX_LEN 131072

// The robot's filter (gf_node_set_filter; gf_node --filter ekf|ukf|pf).
// The car is always KF2.
typedef enum gf_node_filter {
    GF_NODE_FILTER_EKF = 0, // EKF3 (the default): Table 4.2
    GF_NODE_FILTER_UKF,     // UKF3, alpha = 1, beta = 2, kappa = 0
    GF_NODE_FILTER_PF       // PF3 from the node's particle pool
} gf_node_filter;

// Particle-filter tracks take their particles from a pool the caller owns
// (gf_node_pf_pool, handed to gf_node_set_filter), so that a node that runs
// EKF or UKF stays small. Fixed sizes, chosen here:
//   GF_NODE_PF_PARTICLES particles per PF track (32 B each in double, 16 B
//     in float: 128 kB / 64 kB per track). Exercise 4 needs them: after
//     z = -0.7 about 700 are effective, and with 2000 the place of a
//     mode wanders up to 0.16 from the truth over seeds 1..20 (0.07 with
//     4000: sim/tests/test_node_filters.c);
//   GF_NODE_PF_TRACKS PF tracks per node (a new one beyond this is
//     GF_NODE_TRACK_LIMIT; EKF/UKF tracks still go up to GF_NODE_MAX_TRACKS);
//   GF_NODE_PF_CLOUD particles at most in each particles_t message (every
//     GF_NODE_PF_PARTICLES / GF_NODE_PF_CLOUD-th particle: 8 kB a message).
// sizeof(gf_node_pf_pool): 4 x 128 kB + 16 kB in double (gf_node prints
// it as pool_bytes); a gf_node_track grows by the union's PF member only.
#define GF_NODE_PF_PARTICLES 4000
#define GF_NODE_PF_TRACKS 4
#define GF_NODE_PF_CLOUD 500
// A PF step resamples (low variance) when the effective sample size falls
// below this fraction of the particles.
#define GF_NODE_PF_RESAMPLE_FRACTION 0.5

typedef struct gf_node_pf_pool {
    gf_pf3_particle p[GF_NODE_PF_TRACKS][GF_NODE_PF_PARTICLES];
    unsigned used; // slots handed out, in track creation order
    // scratch for one particles_t message
    float x[GF_NODE_PF_CLOUD], y[GF_NODE_PF_CLOUD], theta[GF_NODE_PF_CLOUD],
        w[GF_NODE_PF_CLOUD];
    uint8_t buf[GF_NODE_PF_CLOUD * 16 + 128];
} gf_node_pf_pool;

// What became of one message. Everything but GF_NODE_APPLIED is a
// rejection: the belief of the track is unchanged.
typedef enum gf_node_result {
    GF_NODE_APPLIED = 0,     // filter step ran, belief published
    GF_NODE_DUPLICATE,       // seq equal to the last one seen on its track
    GF_NODE_OUT_OF_ORDER,    // seq or utime older than the last one seen
    GF_NODE_MALFORMED,       // truncated, trailing bytes, unknown fingerprint
    GF_NODE_TYPE_MISMATCH,   // another gaussfilt_lcm type on this channel
    GF_NODE_BAD_FIELD,       // decodes, but track/model/size makes no sense
    GF_NODE_UNKNOWN_CHANNEL, // not GF_MEAS_<n>, GF_CTRL_<n>, GF_MODEL_<n>
                             // with n in its one decimal spelling
    GF_NODE_TRACK_LIMIT,     // a new track with GF_NODE_MAX_TRACKS in use
    GF_NODE_NONFINITE,       // the core said GF_ERR_NONFINITE: published with
                             // that status, belief unchanged
    GF_NODE_FILTER_ERROR,    // any other core failure (not PSD, singular,
                             // a model callback): published with its status
    GF_NODE_STALE_SESSION,   // from a simulator run older than the track's
    GF_NODE_NO_SUMMARY,      // PF step done, its summary overflowed: published
                             // as STATUS_NO_SUMMARY (see the top)
    GF_NODE_GATED,           // the core said GF_ERR_GATED: the measurement's
                             // NIS beyond the model's gate, published with
                             // that status (and its NIS), belief unchanged
                             // (a track in time: predicted to its utime)
    GF_NODE_NO_MODEL,        // a new track no configured model names, where
                             // no preset may stand in: a linear track, or
                             // any track under gf_node_set_strict
    GF_NODE_LATE,            // a track in time (see the top): utime older
                             // than the track's time by at most its model's
                             // late_window: refused, published with status
                             // GF_NODE_STATUS_LATE
    GF_NODE_TOO_OLD,         // the same, older than late_window: refused,
                             // no belief
    GF_NODE_RESULT_COUNT
} gf_node_result;

// Short name of a result ("applied", "duplicate", ...), never NULL.
const char *gf_node_result_str(gf_node_result r);

// Counters since gf_node_init. Every handled message adds 1 to received
// and 1 to exactly one by_result entry, so
//   received == sum(by_result)  and  applied == by_result[GF_NODE_APPLIED].
// gaps counts seq numbers skipped on a track (messages lost upstream).
typedef struct gf_node_counts {
    uint64_t received;
    uint64_t by_result[GF_NODE_RESULT_COUNT];
    uint64_t published;      // beliefs handed to the publish callback
    uint64_t publish_failed; // of those, the callback returned non-zero
    uint64_t gaps;
    uint64_t tracks_created;
    uint64_t resyncs;     // tracks re-initialised by a newer simulator session
    uint64_t seq_resyncs; // sequence references reset (see the top)
    uint64_t models;      // model_t messages applied
    // messages that reached the process and were dropped before
    // gf_node_handle saw them (set by the caller: gf_node_add_dropped)
    uint64_t dropped;
    // inputs a track's first input says were sent before it and never
    // arrived: its seq - 1 (a session's seq starts at 1), e.g. sent before
    // the node was ready
    uint64_t lost_before_first;
    // beliefs of this node's tracks published by another node
    // (gf_node_peer_belief)
    uint64_t peer_beliefs;
    // status messages of another process that has this node's id
    // (gf_node_peer_status)
    uint64_t name_clashes;
} gf_node_counts;

// Inputs rejected as out_of_order in a row before a track's sequence
// reference is reset (see the top): far more than the reordering a network
// does to one track (tests/net's fault relay holds a message up to 40 ms
// and pauses the wire around a node restart, which makes runs of 16 and
// more), about 1.3 s of a 100 Hz track's controls and measurements.
#define GF_NODE_RESYNC_AFTER 256

// The PF summary's status in belief_t.status (belief_t.STATUS_NO_SUMMARY,
// not a gf_status).
#define GF_NODE_STATUS_NO_SUMMARY (-64)
// The status beliefs of refused inputs (belief_t.STATUS_*): the track's
// belief as it was, with the input's utime, seq and stage.
#define GF_NODE_STATUS_LATE (-65)
#define GF_NODE_STATUS_TOO_OLD (-66)
#define GF_NODE_STATUS_DUPLICATE (-67)
#define GF_NODE_STATUS_OUT_OF_ORDER (-68)
#define GF_NODE_STATUS_STALE_SESSION (-69)
#define GF_NODE_STATUS_BAD_FIELD (-70)

// A track's first updates all gated, this many in a row (or, later, this
// many gated in a row): said once per track (the prior too tight or
// wrong, or the track lost).
#define GF_NODE_GATED_WARN 5

// A track's input streams, each with its own seq: 0 its controls and
// GF_MEAS_<id>, 1 + k its model's sensor k (GF_MEAS_<id>_<name>).
#define GF_NODE_STREAMS (1 + GF_NODE_SENSORS)

// A new track's model: the lookup's answer for its id and kind
// (GF_NODE_KIND_*); NULL when nothing names the track (the node then takes
// the kind's preset, or refuses it: see the top). gf_node_config_named
// fits.
typedef const gf_node_model *(*gf_node_model_fn)(const void *ctx, int32_t id,
                                                 int8_t kind);

// One track: its filter and where its input sequence stands.
typedef struct gf_node_track {
    int32_t id;
    int8_t model;    // gaussfilt_lcm MODEL_CAR or MODEL_ROBOT
    int has_input;   // an input consumed since the track or session began
    int64_t session; // of the last input consumed
    int64_t seq[GF_NODE_STREAMS]; // per stream, of the last input consumed
                                  // (applied or failed)
    unsigned has_seq;             // bit k: stream k has one
    unsigned counting;  // bit k: stream k's next input is a session's first
    int64_t time;       // the track's time: the utime of its last input
    int has_time;       // time holds one (since the track or session began)
    int64_t input_seq;  // seq of the last input consumed
    int64_t belief_seq; // of the last belief published
    int64_t last_rx;    // `now` of the last input consumed
    unsigned rejected;  // out_of_order, late, too_old inputs in a row
    gf_node_model mdl;  // its model, a copy (a linear one's numbers stay
                        // in the configuration)
    int peer_warned;    // another node's beliefs of it were reported
    // what became of the messages on its channels (as gf_node_counts'
    // by_result, from the track's first)
    uint64_t by_result[GF_NODE_RESULT_COUNT];
    unsigned updates;   // measurements that ran an update (applied, gated)
    unsigned gated_run; // of those, gated in a row up to the last
    // NIS of its updates (gated ones too): the last, and sums since
    // gf_node_nis_take
    double nis_last;
    unsigned m_last; // the last update's measured quantities
    double nis_sum;
    unsigned nis_dof, nis_n; // sums of m and updates since then
    union {
        gf_kf kf; // linear
        gf_kf2 kf2;
        gf_ekf3 ekf3;
        gf_ukf3 ukf3;
        struct {
            gf_pf3 pf;     // pf.p re-pointed into the pool before each call
            gf_vec3 mu;    // the last weighted mean and covariance,
            gf_mat3 sigma; // what the belief carries
            unsigned slot; // in gf_node_pf_pool.p
            gf_real neff;
            int resampled;  // the last step resampled
            int no_summary; // mu, sigma are NaN: no summary (see the top)
        } pf3;
    } f;
    int8_t filter; // gaussfilt_lcm belief_t FILTER_KF2/EKF3/UKF3/PF3/KF
} gf_node_track;

// The longest node id (gf_node_set_id) carried in belief_t.node.
#define GF_NODE_ID_MAX 64
// The longest host name a node's status carries (node_status_t.host).
#define GF_NODE_HOST_MAX 64
// Bytes that hold any node_status_t of a node (gf_node_status).
#define GF_NODE_STATUS_BYTES (1024 + 320 * GF_NODE_MAX_TRACKS)
// Track ids the node keeps what it said about (see gf_node.said).
#define GF_NODE_SAID_IDS (2 * GF_NODE_MAX_TRACKS)
#define GF_NODE_PEER_EARLY 16

// Log callback: one line of what the node did with a track (no newline).
typedef void (*gf_node_log_fn)(void *ctx, const char *line);

// Publish callback: channel (NUL-terminated) and the encoded message.
// Returns 0 on success (anything else is counted in publish_failed).
typedef int (*gf_node_publish_fn)(void *ctx, const char *channel,
                                  const void *data, size_t len);

typedef struct gf_node {
    gf_node_publish_fn publish;
    void *ctx;
    unsigned ntracks;
    gf_node_track tracks[GF_NODE_MAX_TRACKS];
    gf_node_counts counts;
    // one encoded belief: its header, the id, n + n^2 + m numbers
    uint8_t buf[64 + GF_NODE_ID_MAX + GF_NODE_SENSOR_NAME +
                8 * (2 * GF_NODE_NMAX + GF_NODE_NMAX * GF_NODE_NMAX + 1)];
    gf_node_filter robot_filter; // for new robot tracks (default EKF)
    gf_node_pf_pool *pf_pool;    // the particles of PF tracks, or NULL
    uint32_t pf_seed;            // a PF track's generator: pf_seed + id
    gf_node_model_fn models;     // NULL: the presets
    const void *models_ctx;
    char id[GF_NODE_ID_MAX]; // belief_t.node ("" until gf_node_set_id)
    // the process behind it (gf_node_set_process), and its statuses
    char host[GF_NODE_HOST_MAX];
    int32_t pid;
    int64_t start_utime;
    int clash_warned;     // another process of its id was reported
    int64_t status_seq;   // of the next status
    int64_t status_utime; // when the last was published
    // other nodes' beliefs of tracks this node has not made yet (the
    // latest GF_NODE_PEER_EARLY, oldest overwritten): a track made later
    // is warned about then (gf_node_peer_belief)
    struct {
        int32_t track;
        uint32_t count;
        char id[GF_NODE_ID_MAX];
    } peer_early[GF_NODE_PEER_EARLY];
    unsigned npeer_early;
    int strict; // refuse tracks no model names
    gf_node_log_fn log;
    void *log_ctx;
    // What the node said about each track id (the first
    // GF_NODE_SAID_IDS ids, tracks it never made too), each topic once,
    // and per input stream the inputs it refused before it made the track
    // (its first input's lost_before_first does not count them).
    unsigned nsaid;
    struct {
        int32_t id;
        uint32_t topics; // bit k: topic k was said
        uint32_t refused[GF_NODE_STREAMS];
    } said[GF_NODE_SAID_IDS];
    int said_channel; // a message on a channel no track names was said
    // scratch of one step: gf_kf's workspace, a linear model's numbers in
    // gf_real, a belief's numbers as belief_t carries them
    gf_kf_work work;
    gf_real lin[5][GF_NODE_NMAX * GF_NODE_NMAX]; // A, B, R, C, Q
    gf_real vec[3][GF_NODE_NMAX];                // u, z, mu
    double dA[GF_NODE_NMAX * GF_NODE_NMAX], dR[GF_NODE_NMAX * GF_NODE_NMAX];
    union { // a belief predicted to now (gf_node_tick)
        gf_kf kf;
        gf_kf2 kf2;
    } ahead;
    double mean[GF_NODE_NMAX], cov[GF_NODE_NMAX * GF_NODE_NMAX],
        innovation[GF_NODE_NMAX];
    double *cov_rows[GF_NODE_NMAX];
} gf_node;

// Sets up an empty node; publish may be NULL (beliefs are then only
// counted). Returns 0, or -1 on a NULL node.
int gf_node_init(gf_node *node, gf_node_publish_fn publish, void *ctx);

// Chooses the filter of the robot tracks this node creates from now on
// (tracks already made keep theirs). GF_NODE_FILTER_PF needs a pool (its
// `used` is reset here) and seeds each PF track's generator with
// seed + (uint32_t)track id, so a run is reproducible; the pool must
// outlive the node and not move. Returns 0, or -1 on a NULL node, an
// unknown filter, or PF without a pool.
int gf_node_set_filter(gf_node *node, gf_node_filter filter,
                       gf_node_pf_pool *pool, uint32_t seed);

// Sets the model lookup for tracks created from now on (NULL: presets
// only). ctx is handed to fn, e.g. a gf_node_config. Returns 0, or -1 on a
// NULL node.
int gf_node_set_models(gf_node *node, gf_node_model_fn fn, const void *ctx);

// Adds n to counts.dropped: messages lost inside the process before
// gf_node_handle (the caller's queue was full).
void gf_node_add_dropped(gf_node *node, uint64_t n);

// Sets the id every belief carries (belief_t.node), cut to
// GF_NODE_ID_MAX - 1 characters. Returns 0, or -1 on NULL.
int gf_node_set_id(gf_node *node, const char *id);

// The process behind the node, which its status carries (node_status_t
// host, pid, start_utime): two processes with one id differ in these
// (gf_node_peer_status). host is cut to GF_NODE_HOST_MAX - 1 characters.
// Returns 0, or -1 on NULL.
int gf_node_set_process(gf_node *node, const char *host, int32_t pid,
                        int64_t start_utime);

// strict = 1: a new track no model names is refused (no_model) instead
// of running its kind's preset; model_t still creates tracks. Returns 0,
// or -1 on NULL.
int gf_node_set_strict(gf_node *node, int strict);

// Where the node says what it did with a track (NULL: nowhere): the model
// each new track got and why, a refused track, a first input after inputs
// that never arrived, another node's beliefs of its tracks. Returns 0, or
// -1 on NULL.
int gf_node_set_log(gf_node *node, gf_node_log_fn fn, void *ctx);

// Reads the track and node id of an encoded belief_t without decoding the
// rest: 0 (id NUL-terminated, cut to size - 1), or -1 if it is no
// belief_t.
int gf_node_belief_origin(const void *data, size_t len, int32_t *track,
                          char *id, size_t size);

// A belief seen on GF_BELIEF_<id> (the node's own come back over udpm):
// one of another node (another id) for a track this node holds is counted
// in peer_beliefs and said once per track through the log callback: two
// nodes filter the same track. One for a track this node has not made yet
// is kept (peer_early) and counted and said when it makes the track.
// Returns 1 for a belief of a track this node holds, else 0.
int gf_node_peer_belief(gf_node *node, const void *data, size_t len);

// "ekf", "ukf" or "pf" -> the filter; returns 0, or -1 if unknown.
int gf_node_filter_parse(const char *name, gf_node_filter *out);

// Handles one message received on `channel` (data: len bytes; NULL with
// len 0 is allowed). now: the receive time in microseconds, kept per track
// (never put in a belief, so replays are bit-identical). Never fails
// loudly: every outcome is a gf_node_result and a counter.
gf_node_result gf_node_handle(gf_node *node, const char *channel,
                              const void *data, size_t len, int64_t now);

// Publishes, for every track that has taken an input, its belief
// predicted to now (belief_t.trigger TRIGGER_RATE, stage STAGE_PREDICT):
// now is in the clock of gf_node_handle's `now`, and the track's time
// goes on from its last input's utime by the time passed since that input
// was received. A track in time (see the top) and a car are predicted
// with their motion over that time; a robot (its motion is its odometry)
// and a linear model whose A is given are published as they are. The
// tracks themselves do not change. Returns the beliefs published.
unsigned gf_node_tick(gf_node *node, int64_t now);

// What the caller knows of the node beside its messages, for its status.
typedef struct gf_node_status_info {
    int64_t utime;        // wall clock now, microseconds
    int64_t rx_now;       // now in gf_node_handle's `now` clock, or -1
                          // (a replay: no track's age is known)
    int64_t kernel_drops; // -1: unknown
    int32_t queue_depth, queue_peak;
    int stopping; // 1: the node's last status
} gf_node_status_info;

// Publishes the node's status (node_status_t: its identity, counters, and
// per track its results, updates and NIS) on GF_NODE_STATUS through the
// publish callback, encoded into buf (size bytes; GF_NODE_STATUS_BYTES
// hold any), and starts each track's NIS sums afresh. Returns 0, or -1
// (NULL, or buf too small: counted in publish_failed).
int gf_node_status(gf_node *node, const gf_node_status_info *info, uint8_t *buf,
                   size_t size);

// A node_status_t seen on GF_NODE_STATUS (its own come back over udpm):
// one of another process (host, pid or start) with this node's id is
// counted in name_clashes and warned about once through the log
// callback. Returns 1 for such a one, else 0.
int gf_node_peer_status(gf_node *node, const void *data, size_t len);

// The track with this id, or NULL.
const gf_node_track *gf_node_find(const gf_node *node, int32_t id);

// Prints the counters as one line of "key=value" pairs into out (always
// NUL-terminated). Returns what snprintf returns.
int gf_node_summary(const gf_node *node, char *out, size_t size);

#ifdef __cplusplus
}
#endif

#endif
