# SPDX-License-Identifier: MIT
# Background processes for the multi-process scripts (sim/tests/lcm_udpm.sh,
# tests/net/net.sh, sim/tools/demo_live.sh). Sourced, not run:
#
#   GF_PROC_DIR=DIR GF_PROC_TAG=NAME; . sim/tools/procs.sh
#
# start NAME CMD...   CMD in the background, output in DIR/NAME.out, its
#                     pid in the variable NAME_pid; killed when the script
#                     exits
# ready NAME [SECS]   waits (default 20 s) for NAME's ": ready" line; if it
#                     never comes (or NAME ends first), prints NAME's
#                     output and exits 1
# wait_line NAME REGEX [SECS]
#                     the same for the first line of NAME's output that
#                     matches REGEX (grep -E)
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
    # emptied here, before the job starts: a ready line left by an earlier
    # process of the same name must not pass for this one's
    : >"$GF_PROC_DIR/$name.out"
    "$@" >>"$GF_PROC_DIR/$name.out" 2>&1 &
    gf_pids+=($!)
    printf -v "${name}_pid" '%s' $!
}

ready() {
    wait_line "$1" ': ready' "${2:-20}"
}

wait_line() {
    local i tries=$((${3:-20} * 20)) pid_var=${1}_pid alive=1
    for ((i = 0; i < tries && alive; i++)); do
        kill -0 "${!pid_var}" 2>/dev/null || alive=0 # one last look below
        grep -Eq "$2" "$GF_PROC_DIR/$1.out" 2>/dev/null && return 0
        [ "$alive" -eq 0 ] || sleep 0.05
    done
    cat "$GF_PROC_DIR/$1.out" >&2
    if [ "$alive" -eq 0 ]; then
        echo "$GF_PROC_TAG: $1 ended before a line matching '$2'" >&2
    else
        echo "$GF_PROC_TAG: $1 never got ready (no line matching '$2' in ${3:-20} s)" >&2
    fi
    exit 1
}

gf_netns_lo() {
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo
}
