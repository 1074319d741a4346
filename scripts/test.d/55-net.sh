#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage net: the LCM node under network faults (a seeded drop/dup/reorder/
# delay relay, node and simulator restarts, every message reconciled), two
# nodes over a veth pair sharing the tracks, and a few seconds of load
# (RSS, socket-buffer vs node drops). tests/net/net.sh, in private network
# namespaces: needs root. The long load run is scripts/soak.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
. "$(dirname "$0")/../lcm.sh"
cd "$GF_ROOT"

[ "$(id -u)" -eq 0 ] || gf_skip "stage net needs root (private network namespaces)"
gf_apt iproute2 util-linux bc
gf_lcm_setup
gf_log "net: configure and build sim/ with tests/net"
gf_lcm_build "$GF_BUILD/sim"
gf_log "net: ctest (faults, veth, load)"
gf_ctest "$GF_BUILD/sim" -R '^net_'
