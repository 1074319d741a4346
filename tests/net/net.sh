#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Network tests of the LCM node: faults, scale-out, load.
#
#   net.sh SCENARIO PORT BIN_DIR PYTHON LCM_PYTHONPATH WORK_DIR [SECONDS]
#
# Every scenario runs in a private network namespace (unshare -n; needs
# root): nothing leaves it. udpm with ttl=0 on lo, ports PORT and PORT+1,
# except veth, whose ttl=1 traffic crosses only a veth pair between this
# namespace and a second one the test makes.
#
#   faults  sims -> gf_relay.py (seeded drop/dup/reorder/delay) -> gf_node;
#           the simulator of track 1 and then the node are restarted
#           mid-stream; gf_netcheck.py reconciles every message exactly
#   veth    two nodes in two namespaces over a veth pair, each taking half
#           the tracks by --channels; stopping one stops only its tracks
#   load    gf_load drives many tracks at a high rate for SECONDS (default
#           3; scripts/soak: 60+): the node's RSS does not grow, and it
#           handles every message its socket received (drops counted from
#           /proc/net/udp and LCM's own counters)
#   burst   three gf_load publishers (9 tracks at 1 kHz each: 54 000
#           messages/s) for 0.7 s into one node:
#           with the default queue nothing is dropped in the node; with
#           --queue 4 some are, counted as dropped; both times what was sent
#           = received + dropped in the node + dropped by the socket buffer
set -euo pipefail
scenario=$1 port=$2 bin=$3 py=$4 pypath=$5 work=$6 seconds=${7:-3}
here=$(cd "$(dirname "$0")" && pwd)

if [ -z "${GF_IN_NETNS:-}" ]; then
    if [ "$(id -u)" -ne 0 ] || ! unshare -n true 2>/dev/null; then
        echo "net: needs root and unshare -n (a private network namespace)" >&2
        exit 1
    fi
    exec env GF_IN_NETNS=1 unshare -n bash "$0" "$@"
fi
GF_PROC_DIR=$work GF_PROC_TAG=net
. "$here/../../sim/tools/procs.sh"
gf_netns_lo
export PYTHONPATH=$pypath
RCVBUF=4194304
URL_A="udpm://239.255.76.67:$port?ttl=0&recv_buf_size=$RCVBUF"
URL_B="udpm://239.255.76.67:$((port + 1))?ttl=0&recv_buf_size=$RCVBUF"
rm -rf "$work"
mkdir -p "$work"
echo "net: $scenario in a private network namespace; files in $work"

die() { echo "net: $*" >&2; exit 1; }
# stop NAME: SIGTERM, and it must exit 0.
stop() {
    local p="${1}_pid"
    kill -0 "${!p}" 2>/dev/null || die "$1 died early: $(tail -3 "$work/$1.out")"
    kill -TERM "${!p}"
    wait "${!p}" || die "$1 exit status $?: $(tail -3 "$work/$1.out")"
}
event() { echo "$1 $(date +%s.%N)" >>"$work/events"; }
# The receive-buffer drops of every UDP socket in this namespace.
udp_drops() { awk 'NR > 1 { d += $NF } END { print d + 0 }' /proc/net/udp; }

case $scenario in
faults)
    start listen "$py" "$here/gf_netcheck.py" listen "$URL_B" "$work/beliefs"
    ready listen
    start node1 "$bin/gf_node" --url "$URL_B"
    ready node1
    start relay "$py" "$here/gf_relay.py" --in "$URL_A" --out "$URL_B" \
        --log "$work/relay.log" --seed 11 --drop 0.05 --dup 0.05 \
        --reorder 0.05 --delay 0.05 --delay-ms 40
    ready relay
    sim="$bin/gf_sim --url $URL_A --rate 300 --steps 100000"
    start sim1a $sim --model car --track 1 --seed 1
    start sim2 $sim --model car --track 2 --seed 2
    start sim3 $sim --model robot --track 3 --seed 3 --meas-var 0.01
    sleep 1
    stop sim1a
    event sim_restarted # (before: its first beliefs may beat `date`)
    start sim1b $sim --model car --track 1 --seed 4
    sleep 1
    # The node restart: the relay holds the wire (it keeps reading) while
    # the old node drains and stops and the new one starts.
    kill -USR1 "$relay_pid"
    sleep 0.3
    event node_restarted
    stop node1
    start node2 "$bin/gf_node" --url "$URL_B"
    ready node2
    kill -USR2 "$relay_pid"
    event node_resumed
    sleep 1.5
    stop sim1b
    stop sim2
    stop sim3
    sleep 0.2
    stop relay
    sleep 0.5
    stop node2
    stop listen
    cat "$work"/sim*.out "$work/relay.out" "$work"/node*.out | grep -v ready
    drops=$(udp_drops)
    [ "$drops" -eq 0 ] || die "$drops packets dropped by socket buffers"
    "$py" "$here/gf_netcheck.py" faults "$work"
    ;;
veth)
    # A second namespace (a sleeping process holds it) and a veth pair to
    # it; multicast routed over the pair on both sides, ttl=1 so it crosses.
    start ns2 unshare -n sleep 600
    sleep 0.1
    ip link add gfv1 type veth peer name gfv2 netns "$ns2_pid"
    ip addr add 10.213.0.1/24 dev gfv1
    ip link set gfv1 up
    ip route replace 224.0.0.0/4 dev gfv1
    nsenter -t "$ns2_pid" -n sh -ec 'ip link set lo up
        ip addr add 10.213.0.2/24 dev gfv2; ip link set gfv2 up
        ip route add 224.0.0.0/4 dev gfv2'
    URL="udpm://239.255.76.67:$port?ttl=1&recv_buf_size=$RCVBUF"
    start listen "$py" "$here/gf_netcheck.py" listen "$URL" "$work/beliefs"
    ready listen
    start nodeA "$bin/gf_node" --url "$URL" --channels 'GF_(MEAS|CTRL)_[12]'
    start nodeB nsenter -t "$ns2_pid" -n "$bin/gf_node" --url "$URL" \
        --channels 'GF_(MEAS|CTRL)_[34]'
    ready nodeA
    ready nodeB
    for k in 1 2 3 4; do
        start sim$k "$bin/gf_sim" --url "$URL" --rate 200 --steps 100000 \
            --model car --track $k --seed $k
    done
    sleep 1.5
    t_stop=$(date +%s.%N)
    stop nodeB
    sleep 1.5
    for k in 1 2 3 4; do stop sim$k; done
    sleep 0.2
    stop nodeA
    stop listen
    grep -h summary "$work"/node*.out
    "$py" "$here/gf_netcheck.py" split "$work/beliefs" "$t_stop" 1,2 3,4
    ;;
load)
    # Beliefs go to the other port: the node's socket carries inputs only.
    tracks=${GF_LOAD_TRACKS:-48} rate=${GF_LOAD_RATE:-200}
    start node "$bin/gf_node" --url "$URL_A" --out-url "$URL_B"
    ready node
    start load "$bin/gf_load" --url "$URL_A" --tracks "$tracks" \
        --rate "$rate" --seconds "$seconds"
    rss() { awk '/^VmRSS/ { print $2 }' "/proc/$node_pid/status"; }
    : >"$work/rss"
    t=0
    while kill -0 "$load_pid" 2>/dev/null; do
        echo "$t $(rss)" >>"$work/rss"
        if [ $((t % 20)) -eq 0 ]; then
            echo "load: t=$((t / 2)) s rss=$(rss) kB"
        fi
        sleep 0.5
        t=$((t + 1))
    done
    wait "$load_pid" || die "gf_load failed: $(cat "$work/load.out")"
    sleep 0.5
    echo "$t $(rss)" >>"$work/rss"
    # The node's input socket: the one bound to $port, in this namespace.
    hexport=$(printf '%04X' "$port")
    sockdrops=$(awk -v p=":$hexport" 'NR > 1 && substr($2, length($2) - 4) == p { d += $NF }
        END { print d + 0 }' /proc/net/udp)
    stop node
    sent=$(sed -nE 's/.*sent=([0-9]+).*/\1/p' "$work/load.out")
    got=$(sed -nE 's/.*summary received=([0-9]+) applied=([0-9]+).*/\1/p' "$work/node.out")
    applied=$(sed -nE 's/.*summary received=([0-9]+) applied=([0-9]+).*/\2/p' "$work/node.out")
    cat "$work/load.out" "$work/node.out" | grep -v ready
    # RSS: after the first quarter (LCM's buffers filled), no growth.
    n=$(wc -l <"$work/rss")
    read -r rss0 rssmax rssend < <(awk -v q=$((n / 4 + 1)) '
        NR == q { a = $2 } NR >= q && $2 > m { m = $2 } { e = $2 }
        END { print a, m, e }' "$work/rss")
    printf 'load figures: %s s, %s tracks, %s messages (%.0f/s), node received %s, applied %s, socket-buffer drops %s, node drops %s, RSS %s kB after the first quarter, %s kB max, %s kB at the end\n' \
        "$seconds" "$tracks" "$sent" "$(echo "$sent / $seconds" | bc -l)" \
        "$got" "$applied" "$sockdrops" "$((sent - sockdrops - got))" \
        "$rss0" "$rssmax" "$rssend" | tee "$work/figures"
    [ "$got" -eq $((sent - sockdrops)) ] ||
        die "the node lost $((sent - sockdrops - got)) messages its socket received"
    [ "$applied" -eq "$got" ] || die "not every message applied"
    # A leak per message is at least one malloc chunk (32 bytes): 2.4 MB
    # over the 77 000 messages of the short run, 70 MB over a minute's soak.
    # LCM's udpm receive ring (200 KiB) is allocated up front and touched
    # page by page, which shows as a few steps of RSS: allow 512 kB.
    echo "load: RSS growth $((rssmax - rss0)) kB = $(echo "($rssmax - $rss0) * 1024 / $sent" | bc -l | cut -c1-6) bytes per message"
    [ "$rssmax" -le $((rss0 + 512)) ] || die "RSS grew from $rss0 to $rssmax kB"
    ;;
burst)
    hexport=$(printf '%04X' "$port")
    sockdrops() {
        awk -v p=":$hexport" 'NR > 1 && substr($2, length($2) - 4) == p {
            d += $NF } END { print d + 0 }' /proc/net/udp
    }
    key() { sed -nE "s/.* $1=([0-9]+).*/\1/p" "$2" | head -1; }
    for queue in default 4; do
        opt=()
        [ "$queue" = default ] || opt=(--queue "$queue")
        start node "$bin/gf_node" --url "$URL_A" --out-url "$URL_B" "${opt[@]}"
        ready node
        grep -o 'queue=[0-9]* queue_bytes=[0-9]* rcvbuf=[0-9a-z]*' "$work/node.out"
        before=$(sockdrops)
        for p in 0 1 2; do
            start "load$p" "$bin/gf_load" --url "$URL_A" --first $((100 * p)) \
                --tracks 9 --rate 1000 --seconds 0.7 --seed $p
        done
        for p in 0 1 2; do
            v=load${p}_pid
            wait "${!v}" || die "gf_load $p failed"
        done
        sleep 0.5
        lost_socket=$(($(sockdrops) - before))
        stop node
        cp "$work/node.out" "$work/node-$queue.out"
        sent=0
        for p in 0 1 2; do
            sent=$((sent + $(sed -nE 's/.*sent=([0-9]+).*/\1/p' "$work/load$p.out")))
        done
        f=$work/node.out
        received=$(key received "$f") dropped=$(key dropped "$f")
        gaps=$(key gaps "$f") peak=$(key queue_peak "$f")
        printf 'burst figures (queue %s): sent %s, received %s, dropped in the node %s, dropped by the socket buffer %s, gaps %s, queue peak %s\n' \
            "$queue" "$sent" "$received" "$dropped" "$lost_socket" "$gaps" \
            "$peak" | tee -a "$work/figures"
        [ "$sent" -eq $((received + dropped + lost_socket)) ] ||
            die "sent $sent != received $received + dropped $dropped + socket $lost_socket"
        # the node counts the socket's drops itself (SO_MEMINFO)
        [ "$(key kernel_drops "$f")" = "$lost_socket" ] ||
            die "the node says kernel_drops=$(key kernel_drops "$f"), /proc/net/udp $lost_socket"
        [ "$gaps" -le $((dropped + lost_socket)) ] ||
            die "more gaps ($gaps) than messages lost ($((dropped + lost_socket)))"
        if [ "$queue" = default ]; then
            [ "$dropped" -eq 0 ] || die "the default queue dropped $dropped"
        else
            [ "$dropped" -gt 0 ] || die "a queue of $queue dropped nothing"
        fi
    done
    ;;
*)
    die "no scenario $scenario"
    ;;
esac
echo "net: $scenario passed"
