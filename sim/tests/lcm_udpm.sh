#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Multi-process LCM tests over udpm: simulator, filter node and checker run
# as separate processes and talk over real UDP multicast sockets.
#
#   lcm_udpm.sh SCENARIO PORT BIN_DIR LCM_BIN_DIR WORK_DIR
#
# As root the whole scenario runs in a private network namespace
# (unshare -n; lo up; 224.0.0.0/4 routed to lo), so nothing leaves it;
# otherwise on the host's loopback. Always ttl=0, always the test's own
# PORT, so tests cannot hear each other.
#
# Scenarios:
#   table11, table21, table42  the exercise, checked from the wire by gf_check
#   malformed  broken packets on the node's channels: counted exactly,
#              dropped, and the node still reproduces Table 4.2 afterwards
#   replay     gf_record records the simulators' 768 messages; the log is
#              played through the node twice with the file:// provider
#              (speed=0): the two belief logs are identical, and Table 2.1
#              is in them; and gf_sim gives the same bytes for the same
#              seed (and session)
#   config     node_test.conf: a car at 100 Hz (position and velocity), a
#              robot with odometry noise seeing (x, y), and one seeing the
#              range and bearing of a landmark; three nodes (one per model,
#              all with --config), M = 50 runs of each model streamed by
#              gf_sim over udpm, every input applied, and the NEES and NIS
#              of the beliefs consistent (gf_consist, 95% bounds per step)
#   linear     node_test.conf's linear models (gf_kf): a 2-D constant-
#              velocity target (n = 4), the same in constant acceleration
#              (n = 6), a 3-D drone with commanded accelerations (n = 6, B,
#              m = 3); one node each (--strict), 50 runs of 100 steps,
#              every input applied, NEES and NIS consistent (gf_consist),
#              and sim/tools/gf_nees.py finds the same means in the logs,
#              inside its 95% bounds, and draws them
#   strict     a configuration error names the file and the key's line;
#              a --strict node refuses exercise 1's unnamed track 1
#              (no_model, said once) and runs the configured car on 100; a
#              node without --strict runs exercise 2 on the preset book-car
#              and says so (gf_check: Table 2.1); without a multicast route
#              (as root: a namespace of its own) the node and gf_sim name
#              the group and the fix, and LCM's garbled "No route to"
#              never comes
#   peers      two nodes (--name a, --name b) on the same tracks: each
#              warns once that the other publishes beliefs of track 1,
#              and counts them (peer_beliefs)
#   quickstart docs/node.md's quick start, its commands as written (the
#              block between <!-- quickstart --> and <!-- /quickstart -->;
#              README.md's copy of its commands checked line by line, and
#              that it stops the node),
#              run by bash in a folder that holds build/sim/sim/bin, .venv
#              and examples/: every input applied, none lost before the
#              node was ready, beliefs.py's 201 beliefs and its plot
#   model      a node without a configuration; gf_setmodel gives track 150
#              the car100 model at run time; after it, every belief of the
#              track (gf_record records them from the wire) equals that of
#              a node configured with car100 from the start (gf_logcmp)
#   sensors    examples/node.conf's vehicle, one track fused from three
#              sensors at 100, 50 and 5 Hz: 50 runs of 5 s over udpm,
#              every input applied, NEES and NIS in their 95% bounds per
#              sensor and over all (gf_fusecheck), and sim/tools/gf_nees.py
#              (scripts/nees) finds the same means per sensor, inside its
#              bounds; the same inputs replayed
#              through a node give the live run's beliefs byte for byte;
#              3 runs with jittered sample times and the gnss silent for
#              2 s equal a filter written in the checker, dt by dt; that
#              node with --rate 20 also publishes beliefs predicted to
#              now, and its inputs' beliefs are a replay's without --rate;
#              a sensor 0.1 s late (late) and one 0.5 s late (too_old),
#              a status belief each, counted exactly
#   generated  the kinematic bicycle written by gaussfilt.codegen
#              (gen_bicycle.py), built into a shared object and loaded by
#              the node (type = generated): a missing library, one of the
#              other precision, without the export or of another
#              descriptor version, params, prior, sensor and Q of the
#              wrong size, a linear key: each refused naming the file and
#              the line; 50 runs of 10 s over udpm, every input applied,
#              the states named from the library (by the node, and by
#              scripts/plot's tool); NEES and NIS per sensor
#              (gf_nees.py) and over all updates inside their 95% bounds;
#              the inputs replayed through a node give the live beliefs
#              byte for byte, and so do they replayed into the package's
#              gaussfilt.float64.EKF on codegen.build's callables
#              (gen_bicycle.py same; not with a Q one ulp off)
#   silence    nothing wrong in silence: a simulator sends m = 2 to a
#              track whose model measures m = 3: every measurement
#              bad_field, each with its status belief on the wire, said
#              once with both sizes, no false gap; the node's socket
#              buffer as asked (capped by net.core.rmem_max) on its ready
#              line; its status (node_status_t) on the wire as its summary
#              says, printed by examples/beliefs.py --status; two nodes of
#              one --name each warn once and count the other's statuses;
#              a node stopped (SIGSTOP) while 400 inputs are sent
#              to its small socket buffer: the kernel's drops counted
#              (kernel_drops=), received + kernel_drops = sent exactly
#   java       a demo-like log (exercises 1, 2, 4 and a random robot through
#              an EKF and a PF node, a run-time model_t) by gf_record; the
#              Java types jar decodes every GF_ event of it the way lcm-spy
#              does, all six types (GfDecodeLog; GF_JAVA, GF_JAVA_CP); the
#              lcm-spy plugin, found as lcm-spy finds it, names every code
#              of that log and of messages made in the test (GfSpyCheck)
#   python     examples/beliefs.py (the venv's Python, the installed
#              gaussfilt_lcm types) listens while lcm-logplayer replays a
#              node's beliefs of exercise 2 and of a car at 100 Hz: it
#              prints Table 2.1's beliefs and draws the car's track
#   ex4three   exercise 4 through three nodes (--filter ekf, ukf, pf):
#              gf_ex4check sees the EKF at (0.15, 0), the UKF's predicted
#              mean inside the unit circle, the PF's two modes
#
# Nothing is sent before its receivers are ready (their ready lines), and
# no count depends on a fixed sleep: a test that counts messages on the
# wire records them with gf_record (sim/tests/gf_record.c: LCM's queue
# unbounded, a socket buffer that holds the whole test, kernel drops
# counted), not with lcm-logger, whose subscription keeps LCM's default
# queue of 30 messages and loses the rest whenever it falls behind. A
# node is stopped only once its last belief has been seen.
set -euo pipefail
scenario=$1 port=$2 bin=$3 lcmbin=$4 work=$5

if [ "$(id -u)" -eq 0 ] && [ -z "${GF_IN_NETNS:-}" ] &&
    unshare -n true 2>/dev/null; then
    exec env GF_IN_NETNS=1 unshare -n bash "$0" "$@"
fi
GF_PROC_DIR=$work GF_PROC_TAG=lcm_udpm
. "$(dirname "$0")/../tools/procs.sh"

# The datagrams the kernel dropped in this namespace because a socket's
# buffer was full (UDP RcvbufErrors), said at the end of every scenario.
udp_drops() { awk '/^Udp:/ { if (n++) print $6 }' /proc/net/snmp; }
on_exit() {
    local rc=$?
    [ -z "${GF_IN_NETNS:-}" ] ||
        echo "lcm_udpm: datagrams the kernel dropped in the namespace (socket buffers full): $(udp_drops)"
    gf_procs_cleanup
    exit "$rc"
}
trap on_exit EXIT
if [ -n "${GF_IN_NETNS:-}" ]; then
    gf_netns_lo
    where="a private network namespace"
else
    where="the host's loopback (not root: no namespace)"
fi
URL="udpm://239.255.76.67:$port?ttl=0"
rm -rf "$work"
mkdir -p "$work"
echo "lcm_udpm: $scenario on $URL in $where; files in $work"

n=0

# stop_node: SIGTERM, wait, print its summary line into $summary.
stop_node() {
    kill -0 "$node_pid" || { echo "lcm_udpm: the node died" >&2; exit 1; }
    kill -TERM "$node_pid"
    wait "$node_pid" || { echo "lcm_udpm: node exit status $?" >&2; exit 1; }
    summary=$(grep 'gf_node: summary' "$work/node.out") ||
        { echo "lcm_udpm: no summary from the node" >&2; exit 1; }
    echo "$summary"
}

# recorded NAME: waits for gf_record NAME to end; fails unless it recorded
# exactly the events it was told to expect, with no kernel drop.
recorded() {
    local pid_var=${1}_pid rc=0
    wait "${!pid_var}" || rc=$?
    cat "$work/$1.out"
    [ "$rc" -eq 0 ] || { echo "lcm_udpm: $1 did not record what was sent" >&2; exit 1; }
}

# expect KEY VALUE: the node's summary says KEY=VALUE.
expect() {
    grep -qw "$1=$2" <<<"$summary" ||
        { echo "lcm_udpm: expected $1=$2 in the summary" >&2; exit 1; }
}

# stream MODEL K: gf_sim's $runs runs of $steps steps of MODEL on track K00,
# the same stream twice: over udpm to the node, and into a file for its
# truths (truth-MODEL.lcmlog)
stream() {
    local out
    for out in "$URL" "file://$work/truth-$1.lcmlog?mode=w"; do
        "$bin/gf_sim" --url "$out" --config "$conf" --model "$1" \
            --track "${2}00" --runs "$runs" --steps "$steps" --seed "$2" \
            --session 1 --rate 100
    done
}

# node_done K: stops node K and reads its summary line into $summary: it
# received and applied every input of $runs runs of $steps steps (a
# control and a measurement each), with no gap, no drop, a track per run
node_done() {
    local node_pid
    node_pid=$(eval echo "\$node${1}_pid")
    kill -TERM "$node_pid"
    wait "$node_pid" || { echo "lcm_udpm: node $1 exit status $?" >&2; exit 1; }
    summary=$(grep 'gf_node: summary' "$work/node$1.out")
    echo "node $1: $summary"
    expect received $((2 * runs * steps))
    expect applied $((2 * runs * steps))
    expect gaps 0
    expect dropped 0
    expect tracks "$runs"
}

# exercise TABLE EXERCISE TRACK APPLIED
exercise() {
    start check "$bin/gf_check" --url "$URL" --table "$1" --track "$3"
    ready check
    start node "$bin/gf_node" --url "$URL"
    ready node
    "$bin/gf_sim" --url "$URL" --exercise "$2" --track "$3"
    local rc=0
    wait "$check_pid" || rc=$?
    cat "$work/check.out"
    [ "$rc" -eq 0 ] || { echo "lcm_udpm: gf_check failed" >&2; exit 1; }
    stop_node
    expect applied "$4"
    expect received "$4"
}

case $scenario in
table11) exercise 1.1 1 1 10 ;;
table21) exercise 2.1 2 2 6 ;;
table42) exercise 4.2 4 4 2 ;;
malformed)
    rounds=25
    start check "$bin/gf_check" --url "$URL" --table 4.2 --track 4
    ready check
    start node "$bin/gf_node" --url "$URL"
    ready node
    "$bin/gf_inject" --url "$URL" --track 4 --rounds $rounds --seed 7
    sleep 0.2
    "$bin/gf_sim" --url "$URL" --exercise 4 --track 4
    rc=0
    wait "$check_pid" || rc=$?
    cat "$work/check.out"
    [ "$rc" -eq 0 ] || { echo "lcm_udpm: no Table 4.2 after the junk" >&2; exit 1; }
    stop_node
    expect malformed $((3 * rounds))
    expect type_mismatch $rounds
    expect applied 2
    expect received $((4 * rounds + 2))
    ;;
replay)
    # inputs: 10 + 6 + 2 + 400 + 100; truths: 200 + 50
    start recorder "$bin/gf_record" --url "$URL" --channels 'GF_.*' \
        --count 768 "$work/in.lcmlog"
    ready recorder
    "$bin/gf_sim" --url "$URL" --exercise 1 --track 1
    "$bin/gf_sim" --url "$URL" --exercise 2 --track 2
    "$bin/gf_sim" --url "$URL" --exercise 4 --track 4
    "$bin/gf_sim" --url "$URL" --model car --track 10 --steps 200 --seed 7 --rate 2000
    "$bin/gf_sim" --url "$URL" --model robot --track 11 --steps 50 --seed 8 --rate 2000
    recorded recorder
    "$bin/gf_logcmp" --prefix GF_ --expect 768 "$work/in.lcmlog"
    for run in a b; do
        "$bin/gf_node" --url "file://$work/in.lcmlog?speed=0" --name replay \
            --out-url "file://$work/out-$run.lcmlog?mode=w" | tee "$work/node-$run.out"
        grep -q 'received=518 applied=518 published=523 ' "$work/node-$run.out" ||
            { echo "lcm_udpm: replay $run did not apply all 518 inputs" >&2; exit 1; }
    done
    # 5 initial beliefs + one per input
    "$bin/gf_logcmp" --prefix GF_BELIEF_ --expect 523 \
        "$work/out-a.lcmlog" "$work/out-b.lcmlog"
    "$bin/gf_check" --url "file://$work/out-a.lcmlog?speed=0" --table 2.1 \
        --track 2 --timeout-ms 5000
    # The simulator is deterministic: same seed, same bytes; another seed,
    # other bytes.
    for s in 7 7 8; do
        "$bin/gf_sim" --url "file://$work/sim-$s-$((++n)).lcmlog?mode=w" \
            --model car --track 10 --steps 200 --seed $s --session 1
    done
    "$bin/gf_logcmp" --expect 600 "$work/sim-7-1.lcmlog" "$work/sim-7-2.lcmlog"
    if "$bin/gf_logcmp" "$work/sim-7-1.lcmlog" "$work/sim-8-3.lcmlog" 2>/dev/null; then
        echo "lcm_udpm: seeds 7 and 8 gave the same stream" >&2
        exit 1
    fi
    ;;
ex4three)
    # Three nodes, one filter each, on tracks 41 (EKF), 42 (UKF), 43 (PF);
    # the simulator replays exercise 4 on each; gf_ex4check asserts what
    # each filter must show, from the beliefs and the particle cloud.
    start check "$bin/gf_ex4check" --url "$URL" --ekf 41 --ukf 42 --pf 43
    ready check
    for f in ekf:41 ukf:42 pf:43; do
        start "node_${f%:*}" "$bin/gf_node" --url "$URL" --filter "${f%:*}" \
            --channels "GF_(MEAS|CTRL)_${f#*:}"
        ready "node_${f%:*}"
    done
    for t in 41 42 43; do
        "$bin/gf_sim" --url "$URL" --exercise 4 --track $t
    done
    rc=0
    wait "$check_pid" || rc=$?
    cat "$work/check.out"
    [ "$rc" -eq 0 ] || { echo "lcm_udpm: exercise 4 three ways failed" >&2; exit 1; }
    for f in ekf ukf pf; do
        v=node_${f}_pid
        kill -TERM "${!v}"
        wait "${!v}" || { echo "lcm_udpm: node $f exit status $?" >&2; exit 1; }
        summary=$(grep 'gf_node: summary' "$work/node_$f.out") ||
            { echo "lcm_udpm: no summary from node $f" >&2; exit 1; }
        echo "$f: $summary"
        expect applied 2
        expect received 2
        grep -q "filter=$f" "$work/node_$f.out" ||
            { echo "lcm_udpm: node $f did not run filter=$f" >&2; exit 1; }
    done
    # 3 beliefs from each node, and 3 clouds from the PF node
    grep -q 'published=6 ' "$work/node_pf.out" ||
        { echo "lcm_udpm: the PF node did not publish 3 beliefs + 3 clouds" >&2; exit 1; }
    ;;
config)
    conf=$(dirname "$0")/node_test.conf
    runs=50 steps=100
    # every node's socket sees every model's stream: room for the bursts
    # of 100 messages each step brings
    for spec in car100:1 rover-xy:2 rover-landmark:3; do
        m=${spec%:*} k=${spec#*:}
        start "node$k" "$bin/gf_node" --config "$conf" \
            --url "$URL&recv_buf_size=4194304" \
            --channels "GF_(MEAS|CTRL|MODEL)_${k}[0-9][0-9]" \
            --out-url "file://$work/beliefs-$m.lcmlog?mode=w"
        ready "node$k"
    done
    grep -q 'models=6 config=' "$work/node1.out" ||
        { echo "lcm_udpm: the ready line does not name the models" >&2; exit 1; }
    for spec in car100:1 rover-xy:2 rover-landmark:3; do
        stream "${spec%:*}" "${spec#*:}"
    done
    for k in 1 2 3; do
        node_done "$k"
    done
    for spec in car100:1 rover-xy:2 rover-landmark:3; do
        m=${spec%:*} k=${spec#*:}
        "$bin/gf_consist" --url "file://$work/truth-$m.lcmlog?speed=0" \
            --url "file://$work/beliefs-$m.lcmlog?speed=0" --first "${k}00" \
            --runs $runs --steps $steps --label "$m" ||
            { echo "lcm_udpm: $m is not consistent through the node" >&2; exit 1; }
    done
    ;;
linear)
    conf=$(dirname "$0")/node_test.conf
    runs=50 steps=100
    models="target2d:4 target2d-ca:5 drone3d:6"
    for spec in $models; do
        m=${spec%:*} k=${spec#*:}
        start "node$k" "$bin/gf_node" --config "$conf" --strict \
            --url "$URL&recv_buf_size=4194304" \
            --channels "GF_(MEAS|CTRL|MODEL)_${k}[0-9][0-9]" \
            --out-url "file://$work/beliefs-$m.lcmlog?mode=w"
        ready "node$k"
    done
    for spec in $models; do
        stream "${spec%:*}" "${spec#*:}"
    done
    for spec in $models; do
        m=${spec%:*} k=${spec#*:}
        node_done "$k"
        expect no_model 0
        grep -q "^gf_node: track ${k}00 (linear, gf_kf): model $m, its channels" \
            "$work/node$k.out" ||
            { echo "lcm_udpm: node $k did not say track ${k}00's model" >&2; exit 1; }
    done
    py=$(cd "$lcmbin/../../../.." && pwd)/bin/python
    tools=$(cd "$(dirname "$0")/../tools" && pwd)
    for spec in $models; do
        m=${spec%:*} k=${spec#*:}
        cons=$("$bin/gf_consist" --url "file://$work/truth-$m.lcmlog?speed=0" \
            --url "file://$work/beliefs-$m.lcmlog?speed=0" --first "${k}00" \
            --runs $runs --steps $steps --label "$m") ||
            { echo "$cons"; echo "lcm_udpm: $m is not consistent through the node" >&2; exit 1; }
        echo "$cons"
        # the log tool finds the same means, inside its 95% bounds
        nees=$(sed -n 's/.* NEES dof=.* mean=\([0-9.]*\) .*/\1/p' <<<"$cons")
        nis=$(sed -n 's/.* NIS dof=.* mean=\([0-9.]*\) .*/\1/p' <<<"$cons")
        MPLCONFIGDIR=$work/mpl "$py" "$tools/gf_nees.py" "$work/truth-$m.lcmlog" \
            "$work/beliefs-$m.lcmlog" --plot "$work/nees-$m.png" >"$work/nees-$m.out"
        grep '^all ' "$work/nees-$m.out"
        grep -Eq "^all $runs linear tracks .*: NEES $nees \(95% bounds [0-9.]+\.\.[0-9.]+, inside\); NIS $nis \(95% bounds [0-9.]+\.\.[0-9.]+, inside\)$" \
            "$work/nees-$m.out" && [ -s "$work/nees-$m.png" ] ||
            { echo "lcm_udpm: gf_nees.py does not agree with gf_consist on $m" >&2; exit 1; }
    done
    ;;
strict)
    conf=$(dirname "$0")/node_test.conf
    printf '[model a]\ntype = linear\nmotion = cv cv\nC = 1 0 0 0\n\nQ = -1\n' \
        >"$work/bad.conf"
    if "$bin/gf_node" --config "$work/bad.conf" --url "$URL" 2>"$work/bad.err"; then
        echo "lcm_udpm: the node started with a bad configuration" >&2
        exit 1
    fi
    cat "$work/bad.err"
    grep -qxF "gf_node: $work/bad.conf: line 6: model a: Q must be symmetric positive semidefinite (and C finite)" \
        "$work/bad.err" || { echo "lcm_udpm: the error does not name Q's line" >&2; exit 1; }
    # Without a multicast route (a namespace of its own, lo up, no route):
    # the node names the group and the fix, and LCM's own route message,
    # which prints an address from freed memory, never comes.
    if [ -n "${GF_IN_NETNS:-}" ]; then
        if unshare -n sh -c 'ip link set lo up && exec "$0" --url "$1"' \
            "$bin/gf_node" "$URL" >"$work/noroute.out" 2>"$work/noroute.err"; then
            echo "lcm_udpm: the node started without a multicast route" >&2
            exit 1
        fi
        cat "$work/noroute.err"
        group=$(sed -E 's|^udpm://([0-9.]+).*|\1|' <<<"$URL")
        grep -qF "gf_node: no route to the multicast group $group of $URL (Network is unreachable): udpm needs one; on one machine, as root: ip route add 224.0.0.0/4 dev lo" \
            "$work/noroute.err" || { echo "lcm_udpm: no clear word without a route" >&2; exit 1; }
        ! grep -q '^No route to\|^connect:' "$work/noroute.err" ||
            { echo "lcm_udpm: LCM's own route message came" >&2; exit 1; }
        # gf_sim opens LCM the same way.
        if unshare -n sh -c 'ip link set lo up && exec "$0" --url "$1" --exercise 1 --track 1' \
            "$bin/gf_sim" "$URL" >"$work/noroute-sim.out" 2>"$work/noroute-sim.err"; then
            echo "lcm_udpm: gf_sim ran without a multicast route" >&2
            exit 1
        fi
        cat "$work/noroute-sim.err"
        grep -qF "gf_sim: no route to the multicast group $group of $URL (Network is unreachable): udpm needs one; on one machine, as root: ip route add 224.0.0.0/4 dev lo" \
            "$work/noroute-sim.err" || { echo "lcm_udpm: gf_sim has no clear word without a route" >&2; exit 1; }
        ! grep -q '^No route to\|^connect:' "$work/noroute-sim.err" ||
            { echo "lcm_udpm: LCM's own route message came from gf_sim" >&2; exit 1; }
    fi
    # 1 initial belief + 10 of the car100 track; Table 2.1 of the preset
    start check100 "$bin/gf_check" --url "$URL" --count 11 --track 100
    start check2 "$bin/gf_check" --url "$URL" --table 2.1 --track 2
    ready check100
    ready check2
    start node "$bin/gf_node" --config "$conf" --strict --name strict \
        --url "$URL" --channels 'GF_(MEAS|CTRL|MODEL)_(1|100)'
    start lax "$bin/gf_node" --config "$conf" --name lax --url "$URL" \
        --channels 'GF_(MEAS|CTRL|MODEL)_2'
    ready node
    ready lax
    "$bin/gf_sim" --url "$URL" --exercise 1 --track 1
    "$bin/gf_sim" --url "$URL" --exercise 2 --track 2
    "$bin/gf_sim" --url "$URL" --config "$conf" --model car100 --track 100 \
        --steps 5 --seed 3 --session 1
    for c in check100 check2; do
        v=${c}_pid
        wait "${!v}" || { cat "$work/$c.out"; echo "lcm_udpm: $c failed" >&2; exit 1; }
    done
    for n in node lax; do
        v=${n}_pid
        kill -TERM "${!v}"
        wait "${!v}" || { echo "lcm_udpm: $n exit status $?" >&2; exit 1; }
    done
    summary=$(grep 'gf_node: summary' "$work/node.out")
    echo "strict: $summary"
    expect received 20
    expect applied 10
    expect no_model 10
    [ "$(grep -c 'refused' "$work/node.out")" -eq 1 ] &&
        grep -qxF 'gf_node: track 1 (car) refused (strict): no configured model'"'"'s channels name GF_MEAS_1 or GF_CTRL_1' \
            "$work/node.out" &&
        grep -qxF 'gf_node: track 100 (car): model car100, its channels GF_(MEAS|CTRL|MODEL)_1[0-9][0-9] name it' \
            "$work/node.out" || { cat "$work/node.out"; echo "lcm_udpm: the strict node's track lines" >&2; exit 1; }
    summary=$(grep 'gf_node: summary' "$work/lax.out")
    echo "lax: $summary"
    expect applied 6
    grep -qxF 'gf_node: track 2 (car): the preset book-car: no configured model'"'"'s channels name GF_MEAS_2 or GF_CTRL_2 (strict refuses such a track)' \
        "$work/lax.out" || { cat "$work/lax.out"; echo "lcm_udpm: no preset line" >&2; exit 1; }
    ;;
peers)
    # 11 beliefs of exercise 1's track from each node
    start recorder "$bin/gf_record" --url "$URL" --channels GF_BELIEF_1 \
        --count 22 "$work/beliefs.lcmlog"
    ready recorder
    for n in a b; do
        start "node_$n" "$bin/gf_node" --name "$n" --url "$URL"
        ready "node_$n"
    done
    "$bin/gf_sim" --url "$URL" --exercise 1 --track 1
    recorded recorder
    wait_line node_a 'warning: node "b" also publishes beliefs of track 1 '
    wait_line node_b 'warning: node "a" also publishes beliefs of track 1 '
    for n in a b; do
        v=node_${n}_pid
        kill -TERM "${!v}"
        wait "${!v}" || { echo "lcm_udpm: node $n exit status $?" >&2; exit 1; }
        summary=$(grep 'gf_node: summary' "$work/node_$n.out")
        echo "node $n: $summary"
        expect applied 10
        grep -Eq ' peer_beliefs=([1-9]|1[01]) ' <<<"$summary" ||
            { echo "lcm_udpm: node $n counted no peer belief" >&2; exit 1; }
        [ "$(grep -c 'warning: node' "$work/node_$n.out")" -eq 1 ] ||
            { echo "lcm_udpm: node $n did not warn exactly once" >&2; exit 1; }
    done
    ;;
sensors)
    # examples/node.conf's vehicle: one track fused from three sensors at
    # 100 Hz (gyro), 50 Hz (wheel) and 5 Hz (gnss), each on its own
    # channel, every measurement predicting the track to its utime
    conf=$(dirname "$0")/../../examples/node.conf
    chans='GF_(MEAS|CTRL|MODEL)_7[0-9][0-9](_[A-Za-z0-9]+)?'
    runs=50 steps=500 # 5 s of each run: 775 measurements
    start node "$bin/gf_node" --config "$conf" --strict --name fuse \
        --url "$URL&recv_buf_size=4194304" --channels "$chans" \
        --out-url "file://$work/beliefs-live.lcmlog?mode=w"
    ready node
    for out in "$URL" "file://$work/inputs.lcmlog?mode=w"; do
        "$bin/gf_sim" --url "$out" --config "$conf" --model vehicle \
            --track 700 --runs $runs --steps $steps --seed 7 --session 1 \
            --rate 200
    done
    stop_node
    expect received $((runs * 775))
    expect applied $((runs * 775))
    expect gaps 0
    expect dropped 0
    expect tracks $runs
    expect late 0
    expect too_old 0
    # NEES and NIS per sensor and over all updates, against the truths
    "$bin/gf_fusecheck" --truth "file://$work/inputs.lcmlog?speed=0" \
        --beliefs "file://$work/beliefs-live.lcmlog?speed=0" --first 700 \
        --runs $runs --label vehicle | tee "$work/fuse.out" ||
        { echo "lcm_udpm: the fused vehicle is not consistent" >&2; exit 1; }
    # scripts/nees's tool judges each sensor apart, with the same means
    py=$(cd "$lcmbin/../../../.." && pwd)/bin/python
    tools=$(cd "$(dirname "$0")/../tools" && pwd)
    "$py" "$tools/gf_nees.py" "$work/inputs.lcmlog" \
        "$work/beliefs-live.lcmlog" >"$work/nees.out" ||
        { tail -n 5 "$work/nees.out"; echo "lcm_udpm: gf_nees.py calls the vehicle inconsistent" >&2; exit 1; }
    for spec in gyro:1:500 wheel:1:250 gnss:2:25; do
        s=${spec%%:*} m=${spec#*:} k=${spec##*:} m=${m%:*}
        nees=$(sed -n "s/.* vehicle $s NEES .* mean=\([0-9.]*\) .*/\1/p" "$work/fuse.out")
        nis=$(sed -n "s/.* vehicle $s NIS .* mean=\([0-9.]*\) .*/\1/p" "$work/fuse.out")
        grep -E "^all $runs linear tracks \(n=4, m=$m, sensor $s\): $((runs * k)) updates \(0 gated, 0 missing of $((runs * k)) measurements\): NEES $nees \(95% bounds [0-9.]+\.\.[0-9.]+, inside\); NIS $nis \(95% bounds [0-9.]+\.\.[0-9.]+, inside\)$" \
            "$work/nees.out" ||
            { echo "lcm_udpm: gf_nees.py does not agree with gf_fusecheck on $s" >&2; exit 1; }
    done
    # the same by replay: the same beliefs, byte for byte
    "$bin/gf_node" --config "$conf" --strict --name fuse --channels "$chans" \
        --url "file://$work/inputs.lcmlog?speed=0" \
        --out-url "file://$work/beliefs-replay.lcmlog?mode=w" >"$work/replay.out"
    tail -n 1 "$work/replay.out"
    "$bin/gf_logcmp" --prefix GF_BELIEF_ --expect $((runs * 776)) \
        "$work/beliefs-live.lcmlog" "$work/beliefs-replay.lcmlog"
    # irregular timestamps: each sample jittered by up to +-25% of its
    # sensor's period, the gnss silent from 1 s to 3 s; every corrected
    # belief equals the checker's own filter stepped with the same dts
    # (this node also publishes each track's belief predicted to now at
    # 20 Hz: --rate)
    start node "$bin/gf_node" --config "$conf" --strict --name jitter \
        --url "$URL&recv_buf_size=4194304" --channels "$chans" --rate 20 \
        --out-url "file://$work/beliefs-jitter.lcmlog?mode=w"
    ready node
    for out in "$URL" "file://$work/jitter.lcmlog?mode=w"; do
        "$bin/gf_sim" --url "$out" --config "$conf" --model vehicle \
            --track 750 --runs 3 --steps $steps --seed 9 --session 1 \
            --rate 200 --jitter 0.5 --drop gnss:1:3
    done
    stop_node
    expect gaps 0
    expect dropped 0
    expect late 0
    "$bin/gf_fusecheck" --reference "$conf" vehicle \
        --inputs "file://$work/jitter.lcmlog?speed=0" \
        --beliefs "file://$work/beliefs-jitter.lcmlog?speed=0" ||
        { echo "lcm_udpm: the jittered vehicle's beliefs are not the reference's" >&2; exit 1; }
    # --rate: beliefs predicted to now beside the inputs' (trigger 1,
    # STAGE_PREDICT, status 0, never before the track's last input), and
    # the inputs' beliefs the numbers of a replay without --rate
    "$bin/gf_node" --config "$conf" --strict --name jitter --channels "$chans" \
        --url "file://$work/jitter.lcmlog?speed=0" \
        --out-url "file://$work/beliefs-norate.lcmlog?mode=w" >/dev/null
    "$py" - "$work/beliefs-jitter.lcmlog" "$work/beliefs-norate.lcmlog" <<'PY'
import sys
import lcm
from gaussfilt_lcm import belief_t


def beliefs(path):
    return [belief_t.decode(e.data) for e in lcm.EventLog(path, "r")
            if e.channel.startswith("GF_BELIEF_")]


live, plain = beliefs(sys.argv[1]), beliefs(sys.argv[2])
rate = [b for b in live if b.trigger == belief_t.TRIGGER_RATE]
last = {}
for b in live:
    if b.trigger == belief_t.TRIGGER_RATE:
        assert b.stage == belief_t.STAGE_PREDICT and b.status == 0, b.seq
        assert b.utime >= last[b.track], (b.track, b.utime, last[b.track])
    else:
        last[b.track] = b.utime
key = lambda b: (b.track, b.input_seq, b.sensor, b.stage, b.status,
                 list(b.mean), [list(r) for r in b.cov], b.nis)
inputs = [key(b) for b in live if b.trigger == belief_t.TRIGGER_INPUT]
assert inputs == [key(b) for b in plain], "--rate changed the beliefs"
assert all(b.trigger == belief_t.TRIGGER_INPUT for b in plain)
assert len(rate) >= 60, len(rate)
print("lcm_udpm: --rate 20: %d beliefs predicted to now beside %d for "
      "inputs, those the same numbers as without --rate" % (len(rate),
                                                          len(inputs)))
PY
    # late and too old: each gnss fix sent 0.1 s late (within the model's
    # late_window of 0.2 s: late), each wheel speed 0.5 s late (too_old;
    # those of the last 0.2 s late), each a status belief; the last sample
    # of each at 5 s is no older than the track: applied (the node is
    # stopped once its last belief has been seen)
    start late "$bin/gf_record" --url "$URL" --channels 'GF_BELIEF_7[67][0-9]' \
        --count $((2 * 3 * 775 + 6)) "$work/late.lcmlog"
    ready late
    start node "$bin/gf_node" --config "$conf" --strict --name late \
        --url "$URL&recv_buf_size=4194304" --channels "$chans"
    ready node
    "$bin/gf_sim" --url "$URL" --config "$conf" --model vehicle --track 760 \
        --runs 3 --steps $steps --seed 5 --session 1 --rate 200 --delay gnss:0.1
    "$bin/gf_sim" --url "$URL" --config "$conf" --model vehicle --track 770 \
        --runs 3 --steps $steps --seed 5 --session 1 --rate 200 --delay wheel:0.5
    recorded late
    stop_node
    expect received $((2 * 3 * 775))
    expect late $((3 * 24 + 3 * 10))
    expect too_old $((3 * (250 - 11)))
    expect applied $((2 * 3 * 775 - 3 * 24 - 3 * 10 - 3 * 239))
    expect published $((2 * 3 * 775 + 6))
    expect gaps 0
    ;;
generated)
    # The kinematic bicycle of docs/codegen.md, written by gaussfilt.codegen
    # (gen_bicycle.py, SymPy from the venv) and built as docs/codegen.md
    # says: a shared object with -DGF_CODEGEN_EXPORT, in double as the node
    py=$(cd "$lcmbin/../../../.." && pwd)/bin/python
    root=$(cd "$(dirname "$0")/../.." && pwd)
    gen=$work/gen
    "$py" "$(dirname "$0")/gen_bicycle.py" write "$root" "$gen" >/dev/null
    build_lib() { # OUT [FLAGS...]
        local out=$1
        shift
        cc -std=c99 -O2 -ffp-contract=off -fPIC -shared -Wall -Wextra \
            -Werror "$@" -I "$root/include" "$gen/bicycle_model.c" \
            "$root/src/angle.c" -o "$gen/$out"
    }
    build_lib libbicycle.so -DGF_CODEGEN_EXPORT
    build_lib libbicycle-f32.so -DGF_CODEGEN_EXPORT -DGF_SINGLE_PRECISION
    build_lib libbicycle-hidden.so
    sed 's/^    1u, "bicycle"/    2u, "bicycle"/' "$gen/bicycle_model.c" \
        >"$gen/v2.c"
    grep -q '^    2u, "bicycle"' "$gen/v2.c"
    cc -std=c99 -fPIC -shared -DGF_CODEGEN_EXPORT -I "$root/include" \
        -I "$gen" "$gen/v2.c" "$root/src/angle.c" -o "$gen/libbicycle-v2.so"
    # bicycle.conf: its library named relative to the file's folder, the
    # sensors' Q the library's (the messages carry q of zeros)
    conf_with() { # EXTRA-LINES [LIBRARY]
        printf '[model bicycle]\ntype = generated\n'
        printf 'channels = GF_(MEAS|CTRL|MODEL)_8[0-9][0-9]\n'
        printf 'library = %s\nparams = 2.5\ndt = 0.1\n' "${2:-libbicycle.so}"
        printf 'prior_mean = 0 0 0 2 0\nprior_cov = 1 1 0.01 0.25 0.0004\n'
        printf '%s\n' "$1"
    }
    conf_with '[sensor gps]
gate = 0' >"$gen/bicycle.conf"
    # configuration errors: the file, the line, what is wrong
    refused() { # WHAT MESSAGE-REGEX
        local rc=0
        "$bin/gf_node" --config "$gen/bad.conf" --url "$URL" \
            >"$work/bad.out" 2>&1 || rc=$?
        [ "$rc" -eq 2 ] && grep -Eq "^gf_node: $gen/bad.conf: $2" "$work/bad.out" ||
            { cat "$work/bad.out"; echo "lcm_udpm: $1 not refused as expected (exit $rc)" >&2; exit 1; }
        echo "lcm_udpm: $1: $(cat "$work/bad.out")"
    }
    conf_with '' nowhere.so >"$gen/bad.conf"
    refused "a missing library" "line 4: model bicycle: library does not load: $gen/nowhere.so: .*No such file"
    conf_with '' libbicycle-f32.so >"$gen/bad.conf"
    refused "a float library" "line 4: model bicycle: library $gen/libbicycle-f32.so is built with gf_real of 4 bytes, this node with 8 \(build it without -DGF_SINGLE_PRECISION\)"
    conf_with '' libbicycle-hidden.so >"$gen/bad.conf"
    refused "a library without the export" "line 4: model bicycle: library $gen/libbicycle-hidden.so has no gf_codegen_exported \(build gaussfilt.codegen's C with -DGF_CODEGEN_EXPORT\)"
    conf_with '' libbicycle-v2.so >"$gen/bad.conf"
    refused "another descriptor version" "line 4: model bicycle: library $gen/libbicycle-v2.so: descriptor version 2 \(export 1\), this node reads 1 \(export 1\)"
    conf_with 'params = 2.5 1' >"$gen/bad.conf"
    refused "params of the wrong count" "line 9: model bicycle: params takes 1 number, its library's parameters \(L\) in order"
    conf_with 'prior_mean = 0 0 0 2' >"$gen/bad.conf"
    refused "a prior of n = 4" "line 9: prior_mean takes 5 numbers"
    conf_with '[sensor lidar]' >"$gen/bad.conf"
    refused "a sensor the library has not" "line 9: model bicycle: its library has no sensor lidar \(it has: gps compass wheel\)"
    conf_with '[sensor gps]
Q = 1 2 3' >"$gen/bad.conf"
    refused "a Q of m = 3 for the GPS" "line 10: Q takes 2 or 4 numbers \(m = 2\)"
    conf_with 'A = 1 0 0 0 0' >"$gen/bad.conf"
    refused "a linear key" "line 9: a generated model has no A \(its library gives the states, the motion and the sensors\)"
    printf '[model b]\ntype = generated\nchannels = GF_MEAS_1\nprior_cov = 1\n' >"$gen/bad.conf"
    refused "a key before the library" "line 4: model b: library before prior_cov"
    # 50 runs of 10 s streamed over udpm to the node (and into a log, the
    # same bytes): a control, the truth, the compass and the wheel speed
    # every 0.1 s, the GPS every second
    chans='GF_(MEAS|CTRL|MODEL)_8[0-9][0-9](_[A-Za-z0-9]+)?'
    runs=50
    start node "$bin/gf_node" --config "$gen/bicycle.conf" --strict \
        --name bike --url "$URL&recv_buf_size=4194304" --channels "$chans" \
        --out-url "file://$work/beliefs-live.lcmlog?mode=w"
    ready node
    "$py" "$(dirname "$0")/gen_bicycle.py" sim "$gen/libbicycle.so" "$URL" \
        "$work/inputs.lcmlog" --first 800 --runs $runs --steps 100 --seed 7
    stop_node
    expect received $((runs * 310))
    expect applied $((runs * 310))
    expect gaps 0
    expect dropped 0
    expect tracks $runs
    expect gated 0
    grep -q "track 800 (generated, gf_ekf: x (m), y (m), theta (rad), v (m/s), delta (rad) from libbicycle.so): model bicycle" "$work/node.out" ||
        { echo "lcm_udpm: the node did not name the bicycle's states" >&2; exit 1; }
    # NEES and NIS per sensor (scripts/nees's tool), inside their 95% bounds
    tools=$(cd "$(dirname "$0")/../tools" && pwd)
    "$py" "$tools/gf_nees.py" "$work/inputs.lcmlog" \
        "$work/beliefs-live.lcmlog" >"$work/nees.out" ||
        { tail -n 5 "$work/nees.out"; echo "lcm_udpm: gf_nees.py calls the bicycle inconsistent" >&2; exit 1; }
    for spec in compass:1:100 wheel:1:100 gps:2:10; do
        s=${spec%%:*} m=${spec#*:} k=${spec##*:} m=${m%:*}
        grep -E "^all $runs linear tracks \(n=5, m=$m, sensor $s\): $((runs * k)) updates \(0 gated, 0 missing of $((runs * k)) measurements\): NEES [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside\); NIS [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside\)$" \
            "$work/nees.out" ||
            { grep "^all" "$work/nees.out"; echo "lcm_udpm: the bicycle's $s is not judged consistent" >&2; exit 1; }
    done
    # and over all updates: the NIS summed over every update against
    # chi-square of the summed m, the NEES of every update against n
    "$py" - "$work/inputs.lcmlog" "$work/beliefs-live.lcmlog" <<'PY'
import math
import sys

import lcm
import numpy as np
from gaussfilt_lcm import belief_t, groundtruth_t

truth = {}
for e in lcm.EventLog(sys.argv[1], "r"):
    if e.channel.startswith("GF_TRUTH_"):
        g = groundtruth_t.decode(e.data)
        truth[(g.track, g.utime)] = np.array(g.state)
nis, dof, nees, n_upd = 0.0, 0, {}, 0
for e in lcm.EventLog(sys.argv[2], "r"):
    if not e.channel.startswith("GF_BELIEF_"):
        continue
    b = belief_t.decode(e.data)
    if b.stage != belief_t.STAGE_UPDATE:
        continue
    assert b.status == 0, (b.track, b.seq, b.status)
    m = {"gps": 2}.get(b.sensor, 1)
    nis += b.nis
    dof += m
    n_upd += 1
    err = truth[(b.track, b.utime)] - np.array(b.mean)
    P = np.array([list(r) for r in b.cov])
    nees.setdefault(b.track, []).append(err @ np.linalg.solve(P, err))


def bounds(k, N):  # the 95% interval of the mean of N chi2(k) samples
    def q(z):
        a = 2.0 / (9.0 * k * N)
        return k * N * (1.0 - a + z * math.sqrt(a)) ** 3 / N
    return q(-1.959964), q(1.959964)


lo, hi = bounds(dof / n_upd, n_upd)
m_nis = nis / n_upd
runs = len(nees)
m_nees = float(np.mean([np.mean(v) for v in nees.values()]))
lo_e, hi_e = bounds(5, runs)
print("lcm_udpm: the bicycle over all %d updates of %d runs: NIS %.3f per "
      "update (95%% bounds %.3f..%.3f), NEES %.3f (95%% bounds %.3f..%.3f)"
      % (n_upd, runs, m_nis, lo, hi, m_nees, lo_e, hi_e))
assert n_upd == 50 * 210 and runs == 50
assert lo <= m_nis <= hi and lo_e <= m_nees <= hi_e
PY
    # scripts/plot's tool names the states from the library
    "$py" "$tools/gf_track.py" "$work/inputs.lcmlog" \
        "$work/beliefs-live.lcmlog" --track 807 --config "$gen/bicycle.conf" \
        --out "$work/track_807.png" | tee "$work/plot.out"
    grep -qx "drew $work/track_807.png (track 807: 311 beliefs, 100 truths): x (m), y (m), theta (rad), v (m/s), delta (rad)" "$work/plot.out" ||
        { echo "lcm_udpm: the plot does not name the bicycle's states" >&2; exit 1; }
    # the same inputs replayed through a node: the live beliefs, byte for
    # byte (a belief per input and each track's first)
    "$bin/gf_node" --config "$gen/bicycle.conf" --strict --name bike \
        --channels "$chans" --url "file://$work/inputs.lcmlog?speed=0" \
        --out-url "file://$work/beliefs-replay.lcmlog?mode=w" >"$work/replay.out"
    tail -n 1 "$work/replay.out"
    "$bin/gf_logcmp" --prefix GF_BELIEF_ --expect $((runs * 311)) \
        "$work/beliefs-live.lcmlog" "$work/beliefs-replay.lcmlog"
    # and the same inputs in a notebook: gaussfilt.float64.EKF on
    # codegen.build's callables, stepped as the node steps, gives every
    # live belief's mean and covariance byte for byte; with the wheel's Q
    # one ulp up it must not
    "$py" "$(dirname "$0")/gen_bicycle.py" same "$root" "$work/nb" \
        "$work/inputs.lcmlog" "$work/beliefs-live.lcmlog" | tee "$work/same.out"
    grep -qx "gen_bicycle: $((runs * 311)) beliefs of $runs tracks: the node's means and covariances are gaussfilt.float64.EKF's, byte for byte" "$work/same.out" ||
        { echo "lcm_udpm: the node's beliefs are not the notebook's" >&2; exit 1; }
    rc=0
    "$py" "$(dirname "$0")/gen_bicycle.py" same "$root" "$work/nb" \
        "$work/inputs.lcmlog" "$work/beliefs-live.lcmlog" --q-ulp wheel \
        >"$work/ulp.out" || rc=$?
    cat "$work/ulp.out"
    [ "$rc" -eq 1 ] && grep -Eq "^gen_bicycle: track 800, belief [0-9]+ \(utime [0-9]+, wheel\): the (mean|covariance) differs" "$work/ulp.out" ||
        { echo "lcm_udpm: a Q one ulp off is not told from the node's (exit $rc)" >&2; exit 1; }
    ;;
silence)
    py=$(cd "$lcmbin/../../../.." && pwd)/bin/python
    # the node's model measures (x, y, vx); the simulator's sends (x, y)
    model() {
        printf '[model t]\ntype = linear\nchannels = GF_(MEAS|CTRL|MODEL)_4[0-9][0-9]\n'
        printf 'motion = cv cv\ndt = 0.1\naccel_var = 0.5\nprior_cov = 1 1 1 1\n%s\n' "$1"
    }
    model 'C = 1 0 0 0 ; 0 0 1 0 ; 0 1 0 0
Q = 0.09 0.09 0.01' >"$work/node.conf"
    model 'C = 1 0 0 0 ; 0 0 1 0
Q = 0.09 0.09' >"$work/sim.conf"
    start beliefs "$bin/gf_record" --url "$URL" --channels 'GF_BELIEF_400' \
        --count 41 "$work/beliefs.lcmlog"
    ready beliefs
    start statuses "$bin/gf_record" --url "$URL" --channels GF_NODE_STATUS \
        "$work/status.lcmlog"
    ready statuses
    start node "$bin/gf_node" --config "$work/node.conf" --url "$URL" --name s
    ready node
    rmem=$(cat /proc/sys/net/core/rmem_max)
    want=$((rmem < 4194304 ? rmem : 4194304))
    grep -q " rcvbuf=$want rcvbuf_asked=4194304 " "$work/node.out" ||
        { echo "lcm_udpm: the ready line does not say rcvbuf=$want" >&2; exit 1; }
    "$bin/gf_sim" --url "$URL" --config "$work/sim.conf" --model t --track 400 \
        --steps 20 --seed 3 --session 1 --rate 1000
    recorded beliefs
    sleep 1.1 # a status between the first and the last
    stop_node
    sleep 0.2
    kill -TERM "$statuses_pid"
    recorded statuses
    cat "$work/node.out"
    expect received 40
    expect applied 20
    expect bad_field 20
    expect gaps 0
    expect published 41
    [ "$(grep -c 'bad_field' "$work/node.out")" -eq 2 ] &&
        grep -qxF 'gf_node: track 400: a measurement has m = 2, its model t measures m = 3 (C'"'"'s rows) (bad_field)' \
            "$work/node.out" ||
        { echo "lcm_udpm: the refusal was not said once, with both sizes" >&2; exit 1; }
    "$py" - "$work/beliefs.lcmlog" <<'PY'
import sys
import lcm
from gaussfilt_lcm import belief_t
log = lcm.EventLog(sys.argv[1], "r")
b = [belief_t.decode(e.data) for e in log]
refused = [x for x in b if x.status == belief_t.STATUS_BAD_FIELD]
assert len(refused) == 20, len(refused)
assert all(x.stage == belief_t.STAGE_UPDATE for x in refused)
assert sorted(x.input_seq for x in refused) == list(range(2, 41, 2))
# each the belief as it was: the prediction before it
prev = {x.seq: x for x in b}
assert all(list(prev[x.seq - 1].mean) == list(x.mean) for x in refused)
print("lcm_udpm: 20 status beliefs STATUS_BAD_FIELD on the wire, each the "
      "prediction before it")
PY
    # its status on the wire, as examples/beliefs.py --status prints it:
    # the first (seq 0), one a second later, and its last, whose track
    # 400 took 20 inputs and refused 20 (bad_field)
    root=$(cd "$(dirname "$0")/../.." && pwd)
    "$py" "$root/examples/beliefs.py" --status --url "file://$work/status.lcmlog?speed=0" \
        >"$work/status.out"
    cat "$work/status.out"
    grep -q '^status s seq 0 ' "$work/status.out" &&
        grep -q '^status s seq 1 ' "$work/status.out" &&
        grep -q '^status s seq [0-9]* STOPPING .* received 40, applied 20, gated 0, refused bad_field 20; gaps 0, dropped 0, kernel_drops 0, lost_before_first 0, name_clashes 0; .* 1 tracks$' "$work/status.out" &&
        grep -q '^  track 400 (linear, t): inputs 40, applied 20, gated 0 (0 in a row), refused bad_field 20; no update yet; last input seq 39, ' "$work/status.out" ||
        { echo "lcm_udpm: the node's status is not as its summary" >&2; exit 1; }
    # two nodes of one name: each warns once (the other's status), counts
    for k in 1 2; do
        start "twin$k" "$bin/gf_node" --url "$URL" --name twin --channels 'GF_MEAS_9'
        ready "twin$k"
    done
    for k in 1 2; do
        wait_line "twin$k" 'warning: another node is named "twin" \(host [^,]+, pid [0-9]+, started [0-9.]+ s (after|before) this one\)' 5
    done
    for k in 1 2; do
        v=twin${k}_pid
        kill -TERM "${!v}"
        wait "${!v}"
        [ "$(grep -c 'another node is named' "$work/twin$k.out")" -eq 1 ] &&
            grep -Eq 'name_clashes=[1-9]' "$work/twin$k.out" ||
            { cat "$work/twin$k.out"; echo "lcm_udpm: twin $k did not warn once and count" >&2; exit 1; }
        grep -o 'warning: another node.*' "$work/twin$k.out"
    done
    # the kernel's drops: a small socket buffer, the node stopped while a
    # burst is sent (its beliefs elsewhere: only inputs reach its socket)
    start node "$bin/gf_node" --config "$work/node.conf" \
        --url "$URL&recv_buf_size=65536" --out-url "udpm://239.255.76.67:$((port + 100))?ttl=0"
    ready node
    kill -STOP "$node_pid"
    # (gf_load: controls and measurements only, no truths)
    "$bin/gf_load" --url "$URL" --first 1 --tracks 1 --rate 2000 --seconds 0.1 \
        >"$work/load.out"
    kill -CONT "$node_pid"
    sleep 0.5
    stop_node
    sent=$(sed -nE 's/.*sent=([0-9]+).*/\1/p' "$work/load.out")
    drops=$(sed -nE 's/.* kernel_drops=([0-9]+).*/\1/p' <<<"$summary")
    received=$(sed -nE 's/.* received=([0-9]+) .*/\1/p' <<<"$summary")
    echo "lcm_udpm: $sent sent to a stopped node: received $received, dropped by the kernel $drops"
    [ -n "$drops" ] && [ "$drops" -gt 0 ] && [ $((received + drops)) -eq "$sent" ] ||
        { echo "lcm_udpm: received + kernel_drops is not the $sent sent" >&2; exit 1; }
    ;;
quickstart)
    root=$(cd "$(dirname "$0")/../.." && pwd)
    venv=$(cd "$lcmbin/../../../.." && pwd)
    here=$work/clone
    mkdir -p "$here/build/sim/sim"
    ln -s "$bin" "$here/build/sim/sim/bin"
    ln -s "$venv" "$here/.venv"
    ln -s "$root/examples" "$here/examples"
    sed -n '/^<!-- quickstart -->$/,/^<!-- \/quickstart -->$/p' "$root/docs/node.md" |
        sed -n '/^```/,/^```/p' | sed '1d;$d' >"$work/quickstart.sh"
    [ -s "$work/quickstart.sh" ] || { echo "lcm_udpm: no quick start in docs/node.md" >&2; exit 1; }
    cat "$work/quickstart.sh"
    # README.md shows the quick start's commands: each line as here
    sed -n '/^    B=build\/sim\/sim\/bin$/,/^$/p' "$root/README.md" | sed 's/^    //; /^$/d' >"$work/readme.sh"
    [ "$(wc -l <"$work/readme.sh")" -ge 3 ] || { echo "lcm_udpm: no quick start in README.md" >&2; exit 1; }
    while IFS= read -r line; do
        grep -qxF -- "$line" "$work/quickstart.sh" ||
            { echo "lcm_udpm: README.md's '$line' is not docs/node.md's quick start" >&2; exit 1; }
    done <"$work/readme.sh"
    grep -q '^kill %1 ' "$work/readme.sh" ||
        { echo "lcm_udpm: README.md's quick start leaves the node running (no kill %1)" >&2; exit 1; }
    # outside a namespace, the test's own port instead of LCM's default
    [ -n "${GF_IN_NETNS:-}" ] || export LCM_DEFAULT_URL=$URL
    (cd "$here" && MPLCONFIGDIR=$work/mpl timeout 120 bash -e "$work/quickstart.sh") \
        >"$work/quickstart.out" 2>&1 || { cat "$work/quickstart.out"; echo "lcm_udpm: the quick start failed" >&2; exit 1; }
    cat "$work/quickstart.out"
    summary=$(grep 'gf_node: summary' "$here/node.out") ||
        { echo "lcm_udpm: no node summary in node.out" >&2; exit 1; }
    expect received 200
    expect applied 200
    expect lost_before_first 0
    grep -q '^201 beliefs$' "$here/beliefs.out" ||
        { echo "lcm_udpm: beliefs.py did not get 201 beliefs" >&2; exit 1; }
    grep -qx 'drew target.png (201 beliefs, 100 truths): x (m), vx (m/s), y (m), vy (m/s)' "$here/beliefs.out" &&
        [ -s "$here/target.png" ] || { echo "lcm_udpm: no plot with the truth" >&2; exit 1; }
    ;;
model)
    conf=$(dirname "$0")/node_test.conf
    # 1 initial belief (the model message's) + 100
    start recorder "$bin/gf_record" --url "$URL" --channels GF_BELIEF_150 \
        --count 101 "$work/beliefs-set.lcmlog"
    ready recorder
    start node "$bin/gf_node" --url "$URL" --name n150
    ready node
    # the node's socket keeps the order of sending: the model first
    "$bin/gf_setmodel" --url "$URL" --config "$conf" --model car100 \
        --track 150 --reset --utime 10000
    "$bin/gf_sim" --url "$URL" --config "$conf" --model car100 --track 150 \
        --steps 50 --seed 5 --session 1 --rate 500
    recorded recorder
    stop_node
    expect models 1
    expect received 101
    expect applied 101
    # the same inputs through a node configured with car100 from the start
    "$bin/gf_sim" --url "file://$work/in.lcmlog?mode=w" --config "$conf" \
        --model car100 --track 150 --steps 50 --seed 5 --session 1
    "$bin/gf_node" --config "$conf" --url "file://$work/in.lcmlog?speed=0" \
        --name n150 --out-url "file://$work/beliefs-conf.lcmlog?mode=w" >"$work/node-conf.out"
    cat "$work/node-conf.out"
    # 1 initial belief (the model message's) + 100
    "$bin/gf_logcmp" --prefix GF_BELIEF_ --expect 101 \
        "$work/beliefs-set.lcmlog" "$work/beliefs-conf.lcmlog"
    ;;
java)
    # inputs 10 + 6 + 2 + 2 + 40 and 1 model_t; truths 20; beliefs (the
    # initial one and one per input) 11 + 7 + 3 + 3 + 41; clouds 3 (PF node)
    # (the nodes' statuses, once a second, recorded apart)
    want=$((10 + 6 + 2 + 2 + 40 + 1 + 20 + 11 + 7 + 3 + 3 + 41 + 3))
    start recorder "$bin/gf_record" --url "$URL" --channels 'GF_[A-Z]+_[0-9]+' \
        --count $want "$work/demo.lcmlog"
    ready recorder
    start statuses "$bin/gf_record" --url "$URL" --channels GF_NODE_STATUS \
        "$work/status.lcmlog"
    ready statuses
    start node "$bin/gf_node" --url "$URL" --channels 'GF_(MEAS|CTRL|MODEL)_[0-9]'
    start pfnode "$bin/gf_node" --url "$URL" --filter pf \
        --channels 'GF_(MEAS|CTRL|MODEL)_43'
    ready node
    ready pfnode
    "$bin/gf_sim" --url "$URL" --exercise 1 --track 1
    "$bin/gf_sim" --url "$URL" --exercise 2 --track 2
    "$bin/gf_sim" --url "$URL" --exercise 4 --track 4
    "$bin/gf_sim" --url "$URL" --exercise 4 --track 43
    "$bin/gf_setmodel" --url "$URL" --model book-robot --track 5 --reset
    "$bin/gf_sim" --url "$URL" --model robot --track 5 --steps 20 --seed 3 --rate 500
    recorded recorder # the inputs, and every belief and cloud of both nodes
    stop_node
    kill -TERM "$pfnode_pid"
    wait "$pfnode_pid" || true
    sleep 0.2 # (their last statuses)
    kill -TERM "$statuses_pid"
    recorded statuses
    "$bin/gf_logcmp" --prefix GF_ --expect $want "$work/demo.lcmlog"
    "$GF_JAVA" -cp "$GF_JAVA_CP" GfDecodeLog "$work/demo.lcmlog" $want \
        2>"$work/java.err" | tee "$work/java.out"
    n=$(grep -c '^GfDecodeLog: gaussfilt_lcm\.' "$work/java.out")
    [ "$n" -eq 6 ] ||
        { echo "lcm_udpm: $n of the 6 types decoded" >&2; exit 1; }
    # the nodes' statuses: at least the first and the last of each
    "$GF_JAVA" -cp "$GF_JAVA_CP" GfDecodeLog "$work/status.lcmlog" \
        2>>"$work/java.err" | tee "$work/java-status.out"
    k=$(sed -nE 's/^GfDecodeLog: gaussfilt_lcm\.node_status_t ([0-9]+)$/\1/p' "$work/java-status.out")
    [ -n "$k" ] && [ "$k" -ge 4 ] ||
        { echo "lcm_udpm: ${k:-no} node_status_t decoded, 4 at least wanted" >&2; exit 1; }
    # lcm-spy's plugin: found as lcm-spy finds plugins, codes named
    for log in demo status; do
        "$GF_JAVA" -Djava.awt.headless=true -cp "$GF_JAVA_CP" GfSpyCheck "$work/$log.lcmlog" ||
            { echo "lcm_udpm: the lcm-spy plugin failed on $log.lcmlog" >&2; exit 1; }
    done
    ;;
python)
    py=$(cd "$lcmbin/../../../.." && pwd)/bin/python
    example=$(cd "$(dirname "$0")/../../examples" && pwd)/beliefs.py
    conf=$(cd "$(dirname "$0")/../../examples" && pwd)/node.conf
    "$bin/gf_sim" --url "file://$work/in-2.lcmlog?mode=w" --exercise 2 --track 2 --session 1
    "$bin/gf_sim" --url "file://$work/in-150.lcmlog?mode=w" --config "$conf" \
        --model car100 --track 150 --steps 100 --seed 4 --session 1
    for k in 2 150; do
        "$bin/gf_node" --config "$conf" --url "file://$work/in-$k.lcmlog?speed=0" \
            --out-url "file://$work/out-$k.lcmlog?mode=w" >/dev/null
    done
    # offline: the log read to its end
    "$py" "$example" --url "file://$work/out-2.lcmlog?speed=0" | tee "$work/table.out"
    grep -Eq '^ +2 +6 update +0 \| +4\.0244 +1\.2195 \|' "$work/table.out" ||
        { echo "lcm_udpm: beliefs.py did not print Table 2.1's corrected belief" >&2; exit 1; }
    grep -q '^7 beliefs' "$work/table.out" ||
        { echo "lcm_udpm: beliefs.py did not print the 7 beliefs of Table 2.1" >&2; exit 1; }
    # live: lcm-logplayer replays the car's beliefs on udpm, as fast as the
    # node wrote them: a socket buffer that holds all 201 (up to 400 at
    # the kernel's usual net.core.rmem_max), and the listener's header
    # line (printed once it has subscribed) before the first is sent
    start example "$py" "$example" --url "$URL&recv_buf_size=2097152" \
        --track 150 --count 201 --seconds 10 --plot "$work/car100.png"
    wait_line example '^ +track +seq ' 60
    "$lcmbin/lcm-logplayer" --lcm-url="$URL" -s 4 "$work/out-150.lcmlog"
    wait "$example_pid" || { cat "$work/example.out"; echo "lcm_udpm: beliefs.py failed" >&2; exit 1; }
    tail -3 "$work/example.out"
    grep -q '^201 beliefs' "$work/example.out" ||
        { echo "lcm_udpm: beliefs.py missed beliefs of the replay" >&2; exit 1; }
    [ -s "$work/car100.png" ] || { echo "lcm_udpm: no plot" >&2; exit 1; }
    ;;
*)
    echo "lcm_udpm: no scenario $scenario" >&2
    exit 2
    ;;
esac
echo "lcm_udpm: $scenario passed"
