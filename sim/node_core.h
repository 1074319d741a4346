// gaussfilt sim: the filter node's message handling, with no sockets.
//
// gf_node_handle() takes one LCM message (channel + bytes, exactly as LCM
// delivered it), checks it, runs the core filter of its track (KF2 for the
// car, EKF3 for the robot; no filter math here) and hands every belief to a
// publish callback as encoded gaussfilt_lcm_belief_t bytes. gf_node.c wires
// it to LCM; tests, fuzzers and benchmarks call it directly.
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
// GF_NODE_MAX_TRACKS per node; each starts from its model's exercise prior
// (car: mu = 0, Sigma = 0; robot: mu = 0, Sigma = diag(0.01, 0.01, 10000))
// and publishes that initial belief first. Nothing is allocated: a gf_node
// is one plain struct the caller owns.
#ifndef GF_NODE_CORE_H
#define GF_NODE_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "gaussfilt/gaussfilt.h"
#include "gf_channels.h"

#ifdef __cplusplus
extern "C" {
#endif

// The most tracks one node holds. A message for a new track beyond this is
// rejected with GF_NODE_TRACK_LIMIT. Split more tracks over several nodes
// by channel pattern.
#define GF_NODE_MAX_TRACKS 64

// What became of one message. Everything but GF_NODE_APPLIED is a
// rejection: the belief of the track is unchanged.
typedef enum gf_node_result {
    GF_NODE_APPLIED = 0,   // filter step ran, belief published
    GF_NODE_DUPLICATE,     // seq equal to the last one seen on its track
    GF_NODE_OUT_OF_ORDER,  // seq or utime older than the last one seen
    GF_NODE_MALFORMED,     // truncated, trailing bytes, unknown fingerprint
    GF_NODE_TYPE_MISMATCH, // another gaussfilt_lcm type on this channel
    GF_NODE_BAD_FIELD,     // decodes, but track/model/size makes no sense
    GF_NODE_UNKNOWN_CHANNEL, // not GF_MEAS_<n> or GF_CTRL_<n>
    GF_NODE_TRACK_LIMIT,   // a new track with GF_NODE_MAX_TRACKS in use
    GF_NODE_NONFINITE,     // the core said GF_ERR_NONFINITE: published with
                           // that status, belief unchanged
    GF_NODE_FILTER_ERROR,  // any other core failure (gated, not PSD,
                           // singular): published with its status
    GF_NODE_STALE_SESSION, // from a simulator run older than the track's
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
    uint64_t published; // beliefs handed to the publish callback
    uint64_t publish_failed; // of those, the callback returned non-zero
    uint64_t gaps;
    uint64_t tracks_created;
    uint64_t resyncs; // tracks re-initialised by a newer simulator session
} gf_node_counts;

// One track: its filter and where its input sequence stands.
typedef struct gf_node_track {
    int32_t id;
    int8_t model; // gaussfilt_lcm MODEL_CAR or MODEL_ROBOT
    int has_input;
    int64_t session;    // of the last input consumed
    int64_t last_seq;   // of the last input consumed (applied or failed)
    int64_t last_utime;
    int64_t belief_seq; // of the last belief published
    int64_t last_rx;    // `now` of the last input consumed
    union {
        gf_kf2 kf2;
        gf_ekf3 ekf3;
    } f;
} gf_node_track;

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
    uint8_t buf[256]; // one encoded belief (belief_t is 169 bytes)
} gf_node;

// Sets up an empty node; publish may be NULL (beliefs are then only
// counted). Returns 0, or -1 on a NULL node.
int gf_node_init(gf_node *node, gf_node_publish_fn publish, void *ctx);

// Handles one message received on `channel` (data: len bytes; NULL with
// len 0 is allowed). now: the receive time in microseconds, kept per track
// (never put in a belief, so replays are bit-identical). Never fails
// loudly: every outcome is a gf_node_result and a counter.
gf_node_result gf_node_handle(gf_node *node, const char *channel,
                              const void *data, size_t len, int64_t now);

// The track with this id, or NULL.
const gf_node_track *gf_node_find(const gf_node *node, int32_t id);

// Prints the counters as one line of "key=value" pairs into out (always
// NUL-terminated). Returns what snprintf returns.
int gf_node_summary(const gf_node *node, char *out, size_t size);

#ifdef __cplusplus
}
#endif

#endif
