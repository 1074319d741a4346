#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The live part of scripts/demo: node, simulators, checkers and lcm-logger
# as separate processes over LCM udpm (ttl=0). scripts/demo runs it inside
# a private network namespace when root (GF_IN_NETNS=1: lo up, multicast
# routed to lo), else on the host's loopback.
#
#   demo_live.sh BIN_DIR VENV_DIR LCM_BIN_DIR OUT_DIR URL [EXERCISE OPTIONS]
#
# EXERCISE OPTIONS (scripts/demo --help) go to gf_sim --exercise 2 and the
# checkers; --heading-var V becomes the prior of track 4 in a node
# configuration (OUT_DIR/book.conf).
set -euo pipefail
bin=$1 venv=$2 lcmbin=$3 out=$4 url=$5
shift 5
book=("$@") ex2=() node_conf=()
while [ $# -gt 0 ]; do
    case $1 in
    --meas-var | --z | --steps) ex2+=("$1" "$2") ;;
    --heading-var)
        cat >"$out/book.conf" <<CONF
# exercise 4 with another initial heading variance (scripts/demo --heading-var)
[model exercise4]
base = book-robot
channels = GF_(MEAS|CTRL|MODEL)_4
prior_cov = 0.01 0.01 $2
CONF
        node_conf=(--config "$out/book.conf")
        ;;
    esac
    shift 2
done
tools=$(cd "$(dirname "$0")" && pwd)
log=$out/gaussfilt-demo.lcmlog

GF_PROC_DIR=$out GF_PROC_TAG=error
. "$tools/procs.sh"
[ -z "${GF_IN_NETNS:-}" ] || gf_netns_lo

# Multicast self-test, before anything else.
if ! "$venv/bin/python" "$tools/lcm_selftest.py" "$url"; then
    cat >&2 <<MSG

error: LCM's multicast self-test failed on $url: no multicast route.
  fix: route multicast to loopback, then run scripts/demo again:
         sudo ip route add 224.0.0.0/4 dev lo
       (or run scripts/demo as root: it then uses a private network
        namespace with that route and touches nothing on the host)
MSG
    exit 3
fi
echo "LCM multicast self-test passed on $url"


rm -f "$log"
start logger "$lcmbin/lcm-logger" --lcm-url="$url" -f "$log"
start check11 "$bin/gf_check" --url "$url" --table 1.1 --track 1
start check21 "$bin/gf_check" --url "$url" --table 2.1 --track 2 "${book[@]}"
start check42 "$bin/gf_check" --url "$url" --table 4.2 --track 4 "${book[@]}"
start check4x "$bin/gf_ex4check" --url "$url" --ekf 41 --ukf 42 --pf 43
for c in check11 check21 check42 check4x; do ready $c; done
# The main node takes tracks 0..39; exercise 4 three ways runs on 41, 42
# and 43, one node per filter.
start node "$bin/gf_node" --url "$url" --channels 'GF_(MEAS|CTRL|MODEL)_([0-9]|[1-3][0-9])' \
    "${node_conf[@]}"
ready node
for f in ekf:41 ukf:42 pf:43; do
    start "node_${f%:*}" "$bin/gf_node" --url "$url" --filter "${f%:*}" \
        --channels "GF_(MEAS|CTRL)_${f#*:}"
    ready "node_${f%:*}"
done
sleep 0.3 # lcm-logger has no ready line

echo "gf_node is up ($(sed -n 's/.*ready //p' "$out/node.out"))"
echo "and three more for exercise 4 three ways: $(sed -n 's/.*ready.* filter=\([a-z]*\).*/--filter \1/p' \
    "$out/node_ekf.out" "$out/node_ukf.out" "$out/node_pf.out" | paste -sd, - | sed 's/,/, /g') on tracks 41, 42, 43"
echo "simulators: the exercises (as fast as possible), then a random car and"
echo "a random robot streaming in real time at 50 Hz for 2 s"
"$bin/gf_sim" --url "$url" --exercise 1 --track 1
"$bin/gf_sim" --url "$url" --exercise 2 --track 2 "${ex2[@]}"
"$bin/gf_sim" --url "$url" --exercise 4 --track 4
for t in 41 42 43; do "$bin/gf_sim" --url "$url" --exercise 4 --track $t; done
start car "$bin/gf_sim" --url "$url" --model car --track 10 --steps 100 --seed 1 --rate 50
start robot "$bin/gf_sim" --url "$url" --model robot --track 11 --steps 100 --seed 2 --rate 50

fails=0
for c in check11 check21 check42 check4x; do
    echo
    rc=0
    pid_var=${c}_pid
    wait "${!pid_var}" || rc=$?
    sed '/: ready/d' "$out/$c.out"
    [ "$rc" -eq 0 ] || fails=$((fails + 1))
done
wait "$car_pid" "$robot_pid"
echo
cat "$out/car.out" "$out/robot.out"
sleep 0.3
kill -TERM "$node_pid" "$node_ekf_pid" "$node_ukf_pid" "$node_pf_pid"
wait "$node_pid" "$node_ekf_pid" "$node_ukf_pid" "$node_pf_pid" || true
sed -n 's/^gf_node: summary /gf_node summary: /p' "$out/node.out"
for f in ekf ukf pf; do
    sed -n "s/^gf_node: summary /gf_node --filter $f summary: /p" "$out/node_$f.out"
done
# lcm-logger writes behind (every 100 ms): stop it once the log has stopped
# growing (up to 5 s).
last=-1
for i in $(seq 25); do
    n=$("$bin/gf_logcmp" "$log" 2>/dev/null | awk '{print $2}')
    [ "$n" = "$last" ] && break
    last=$n
    sleep 0.2
done
kill -INT "$logger_pid"
for i in $(seq 30); do kill -0 "$logger_pid" 2>/dev/null || break; sleep 0.1; done
kill -TERM "$logger_pid" 2>/dev/null || true
wait "$logger_pid" || true
[ "$fails" -eq 0 ] || { echo "error: $fails table(s) not reproduced" >&2; exit 1; }
