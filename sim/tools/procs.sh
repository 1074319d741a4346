# SPDX-License-Identifier: MIT
# Background processes for the multi-process scripts (sim/tests/lcm_udpm.sh,
# tests/net/net.sh, sim/tools/demo_live.sh). Sourced, not run:
#
#   GF_PROC_DIR=DIR GF_PROC_TAG=NAME; . sim/tools/procs.sh
#
# start NAME CMD...   CMD in the background, output in DIR/NAME.out, its
#                     pid in the variable NAME_pid; killed when the script
#                     exits
# ready NAME [SECS]   waits (default 5 s) for NAME's ": ready" line; if it
#                     never comes, prints NAME's output and exits 1
# gf_netns_lo         in a private network namespace: lo up, multicast
#                     (224.0.0.0/4) routed to lo

gf_pids=()
gf_procs_cleanup() {
    local p
    for p in "${gf_pids[@]}"; do kill "$p" 2>/dev/null || true; done
}
trap gf_procs_cleanup EXIT

start() {
    local name=$1
    shift
    "$@" >"$GF_PROC_DIR/$name.out" 2>&1 &
    gf_pids+=($!)
    printf -v "${name}_pid" '%s' $!
}

ready() {
    local i tries=$((${2:-5} * 20))
    for ((i = 0; i < tries; i++)); do
        grep -q ': ready' "$GF_PROC_DIR/$1.out" 2>/dev/null && return 0
        sleep 0.05
    done
    cat "$GF_PROC_DIR/$1.out" >&2
    echo "$GF_PROC_TAG: $1 never got ready" >&2
    exit 1
}

gf_netns_lo() {
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo
}
