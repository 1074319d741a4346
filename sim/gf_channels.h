// SPDX-License-Identifier: MIT
// gaussfilt sim: every LCM channel name, in one place. (sim/tools/*.py
// repeat the prefixes; keep them in step.)
//
// One channel per track and kind: the track id follows the prefix in its
// one decimal spelling (no sign for 0 and positive ids, no leading zero),
// e.g. GF_MEAS_2, GF_BELIEF_-3; the node takes GF_MEAS_0002 or GF_MEAS_-0
// for no track (unknown_channel). Per-track channels let several
// nodes share the tracks by channel pattern (gf_node --channels REGEX).
#ifndef GF_CHANNELS_H
#define GF_CHANNELS_H

// gaussfilt_lcm_measurement_t, simulator -> node; a configured sensor's
// on GF_MEAS_<id>_<sensor name>
#define GF_CHANNEL_MEAS "GF_MEAS_"
// gaussfilt_lcm_control_t, simulator -> node: one prediction step each
#define GF_CHANNEL_CTRL "GF_CTRL_"
// gaussfilt_lcm_model_t, anyone -> node: sets one track's model at run time
#define GF_CHANNEL_MODEL "GF_MODEL_"
// gaussfilt_lcm_belief_t, node -> anyone: after every applied input
#define GF_CHANNEL_BELIEF "GF_BELIEF_"
// gaussfilt_lcm_particles_t, node -> anyone: after every belief of a
// particle-filter track (gf_node --filter pf)
#define GF_CHANNEL_PARTICLES "GF_PARTICLES_"
// gaussfilt_lcm_node_status_t, node -> anyone: its diagnostics, once a
// second (one channel for all nodes: each status names its node)
#define GF_CHANNEL_STATUS "GF_NODE_STATUS"
// gaussfilt_lcm_groundtruth_t, simulator -> tools (never read by the node)
#define GF_CHANNEL_TRUTH "GF_TRUTH_"

// scripts/demo's multicast self-test (sim/tools/lcm_selftest.py)
#define GF_CHANNEL_SELFTEST "GF_SELFTEST"

// What a node subscribes to unless told otherwise (LCM anchors the regex at
// both ends): the controls, measurements and models of every track, and
// its sensors' measurements.
#define GF_CHANNEL_NODE_DEFAULT "GF_(MEAS|CTRL|MODEL)_-?[0-9]+(_[A-Za-z0-9]+)?"

// Longest channel name we build: prefix + "-2147483648" + "_" + a sensor's
// name (15) + NUL.
#define GF_CHANNEL_MAX 48

#endif
