#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest lcm_tools: scripts/nees and scripts/plot on logs of a linear model,
# made without a network: gf_sim writes a stream into a file:// log and a
# gf_node replays it (file://...?speed=0) into a log of beliefs.
#
#   tools.sh BIN LCM_BIN WORK     (LCM_BIN: the venv's lcm package's bin/)
#
# nees   20 runs of examples/node.conf's target2d: every update there, 0
#        missing, exit 0, the figure written where the caller is (a
#        relative --plot path), not in the repository; the simulator's
#        log alone: every update missing, exit 1; the node's alone:
#        nothing to judge, exit 2. The same stream
#        with every 25th measurement taken out before the node: 80 of
#        2000 missing, said exactly, "NOT JUDGED" and exit 1 (and judged
#        with --max-missing 5); the per-time averages (--csv) aligned by
#        utime: 100 times, at each the tracks that have an update there,
#        one fewer where one was taken out. A target that moves 40 times
#        harder than the node's model: gated updates counted and in the
#        NIS mean (the mean of every update's NIS, gated or not, read from
#        the beliefs here), OUTSIDE, exit 1.
# plot   scripts/plot LOG --track 400 --config examples/node.conf: the
#        figure of a linear track, its states named from the model's
#        states and units, the truth drawn, into a path relative to the
#        caller; a track the log has no beliefs of, and a log with no
#        beliefs: a clear error and exit 2, before any install.
# spy    the JRE scripts/spy takes (gf_java_gui): the installed java when
#        its JRE can open windows, never a headless copy of it.
set -euo pipefail
bin=$1 lcmbin=$2 work=$3
root=$(cd "$(dirname "$0")/../.." && pwd)
venv=$(cd "$lcmbin/../../../.." && pwd)
py=$venv/bin/python
export GF_VENV=$venv
# the build sim/ is in (BUILD/sim/sim/bin), for the scripts' checks
export GF_BUILD=${GF_BUILD:-$(cd "$bin/../../.." && pwd)}
rm -rf "$work"
mkdir -p "$work/caller"
conf=$root/examples/node.conf
fail() {
    echo "lcm_tools: $*" >&2
    exit 1
}

# stream NAME ARGS...: gf_sim's stream into NAME.lcmlog
stream() {
    local name=$1
    shift
    "$bin/gf_sim" --url "file://$work/$name.lcmlog?mode=w" --session 1 "$@" >/dev/null
}
# node IN OUT: a node replays IN.lcmlog into OUT.lcmlog
node() {
    "$bin/gf_node" --config "$conf" --name tools \
        --url "file://$work/$1.lcmlog?speed=0" \
        --out-url "file://$work/$2.lcmlog?mode=w" >"$work/$2.node" 2>&1 ||
        { cat "$work/$2.node"; fail "gf_node on $1 failed"; }
}
# nees ARGS...: scripts/nees from the caller's folder; sets out and rc
nees() {
    rc=0
    out=$(cd "$work/caller" && "$root/scripts/nees" "$@" 2>&1) || rc=$?
    printf '%s\n' "$out" | grep -v '^track ' || true
}

echo "== scripts/nees: a consistent run, every update there"
stream sim --config "$conf" --model target2d --track 400 --runs 20 --steps 100 --seed 4
node sim beliefs
rm -f "$root/nees-rel.png"
nees "$work/sim.lcmlog" "$work/beliefs.lcmlog" --plot nees-rel.png
[ "$rc" -eq 0 ] || fail "exit $rc on a consistent run"
grep -Eq '^all 20 linear tracks \(n=4, m=2\): 2000 updates \([0-9]+ gated, 0 missing of 2000 measurements\): NEES [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside\); NIS [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside\)$' <<<"$out" ||
    fail "the consistent run's line"
[ -s "$work/caller/nees-rel.png" ] || fail "--plot nees-rel.png is not in the caller's folder"
[ ! -e "$root/nees-rel.png" ] || fail "--plot nees-rel.png was written into the repository"

# the simulator's log alone: every update missing, said; the node's alone:
# nothing to judge against
nees "$work/sim.lcmlog"
[ "$rc" -eq 1 ] && grep -qx 'all 20 linear tracks without beliefs: 0 updates (0 gated, 2000 missing of 2000 measurements): no update belief in the logs (the node'"'"'s log too?)' <<<"$out" ||
    fail "the simulator's log alone (exit $rc)"
nees "$work/beliefs.lcmlog"
[ "$rc" -eq 2 ] && grep -q "^gf_nees: no update belief with a truth before it in $work/beliefs.lcmlog (the truths are in gf_sim's log" <<<"$out" ||
    fail "the node's log alone (exit $rc)"

echo "== scripts/nees: every 25th measurement lost before the node"
"$py" - "$work/sim.lcmlog" "$work/lossy.lcmlog" <<'PY' 2>/dev/null ||
import sys, lcm
src, dst = lcm.EventLog(sys.argv[1], "r"), lcm.EventLog(sys.argv[2], "w", overwrite=True)
k = 0
for ev in src:
    if ev.channel.startswith("GF_MEAS_"):
        k += 1
        if k % 25 == 0:
            continue
    dst.write_event(ev.timestamp, ev.channel, ev.data)
PY
    true
[ -s "$work/lossy.lcmlog" ] || fail "no lossy log (python)"
node lossy lossy-beliefs
nees "$work/sim.lcmlog" "$work/lossy-beliefs.lcmlog" --csv lossy.csv
[ "$rc" -eq 1 ] || fail "exit $rc with 80 of 2000 updates missing"
grep -Eq '^all 20 linear tracks \(n=4, m=2\): 1920 updates \([0-9]+ gated, 80 missing of 2000 measurements\): ' <<<"$out" ||
    fail "the missing updates are not counted"
grep -qx 'NOT JUDGED: linear tracks (n=4, m=2): 80 of 2000 updates missing (4.0% > 1%): their means cannot say the filter is consistent' <<<"$out" ||
    fail "no NOT JUDGED line"
# aligned by time: 100 step times, 20 tracks at each but where one lost
# its measurement (80 of them in all)
awk -F, 'NR > 1 { rows++; short += 20 - $2; if ($2 > 20 || $2 < 18) bad++ }
    END { exit !(rows == 100 && short == 80 && !bad) }' "$work/caller/lossy.csv" ||
    { head -5 "$work/caller/lossy.csv"; fail "the per-time averages are not aligned by utime"; }
nees "$work/sim.lcmlog" "$work/lossy-beliefs.lcmlog" --max-missing 5
[ "$rc" -eq 0 ] || fail "exit $rc with --max-missing 5"

echo "== scripts/nees: a target 40 times wilder than the model: gated updates"
sed 's/^accel_var = 0.5 .*/accel_var = 20/' "$conf" >"$work/wild.conf"
stream wild --config "$work/wild.conf" --model target2d --track 400 --runs 5 --steps 100 --seed 7
node wild wild-beliefs
nees "$work/wild.lcmlog" "$work/wild-beliefs.lcmlog"
[ "$rc" -eq 1 ] || fail "exit $rc on a mis-tuned model"
want=$("$py" - "$work/wild-beliefs.lcmlog" <<'PY'
import sys, lcm
from gaussfilt_lcm import belief_t
nis, gated = [], 0
for ev in lcm.EventLog(sys.argv[1], "r"):
    if ev.channel.startswith("GF_BELIEF_"):
        b = belief_t.decode(ev.data)
        if b.stage == 2 and b.status in (0, -5):
            nis.append(b.nis)
            gated += b.status == -5
print("%d updates \\(%d gated, 0 missing of %d measurements\\): NEES [0-9.]+ \\(95%% bounds [0-9.]+\\.\\.[0-9.]+, [A-Z]+\\); NIS %.3f \\(95%% bounds [0-9.]+\\.\\.[0-9.]+, OUTSIDE\\)" % (len(nis), gated, len(nis), sum(nis) / len(nis)))
print(gated)
PY
)
gated=$(tail -1 <<<"$want")
[ "$gated" -gt 10 ] || fail "only $gated gated updates: the scenario does not gate"
grep -Eq "^all 5 linear tracks \(n=4, m=2\): $(head -1 <<<"$want")$" <<<"$out" ||
    fail "the gated updates are not in the NIS mean ($(head -1 <<<"$want"))"


echo "== scripts/plot: a linear track of any model, from a node's and gf_sim's logs"
plot() { # plot ARGS...: scripts/plot from the caller's folder; sets out and rc
    rc=0
    out=$(cd "$work/caller" && "$root/scripts/plot" "$@" 2>&1) || rc=$?
    printf '%s\n' "$out"
}
rm -f "$root/track-rel.png"
plot "$work/sim.lcmlog" "$work/beliefs.lcmlog" --track 400 --config "$conf" --out track-rel.png
[ "$rc" -eq 0 ] || fail "scripts/plot: exit $rc"
grep -qx 'drew track-rel.png (track 400: 201 beliefs, 100 truths): x (m), vx (m/s), y (m), vy (m/s)' <<<"$out" ||
    fail "scripts/plot: not the track's beliefs, truths and named states"
[ -s "$work/caller/track-rel.png" ] && [ ! -e "$root/track-rel.png" ] ||
    fail "scripts/plot: --out track-rel.png is not in the caller's folder"
# without --track, every track of the log; DIR relative to the caller
plot "$work/wild-beliefs.lcmlog" figs
[ "$rc" -eq 0 ] && [ "$(ls "$work/caller/figs" | wc -l)" -eq 5 ] &&
    grep -qx 'drew figs/track_404.png (track 404: 201 beliefs): x0, x1, x2, x3' <<<"$out" ||
    fail "scripts/plot: not a figure per track in figs/"

echo "== scripts/plot: what a log lacks, said before anything is installed"
# GF_VENV where nothing is: scripts/plot would make it, were it to install
GF_VENV=$work/no-venv plot "$work/beliefs.lcmlog" --track 7
[ "$rc" -eq 2 ] && grep -qx "error: $work/beliefs.lcmlog: no beliefs of track 7; beliefs of track(s) $(seq -s ' ' 400 419)" <<<"$out" ||
    fail "scripts/plot: a track the log has no beliefs of (exit $rc)"
GF_VENV=$work/no-venv plot "$work/sim.lcmlog"
[ "$rc" -eq 2 ] && grep -q "^error: $work/sim.lcmlog hold(s) no beliefs (no GF_BELIEF_<track> channel); truths of track(s) 400 401 " <<<"$out" ||
    fail "scripts/plot: a log with no beliefs (exit $rc)"
[ ! -e "$work/no-venv" ] || fail "scripts/plot made a venv before it found the log lacking"

echo "== examples/beliefs.py: the states named from the configuration"
"$py" - "$work/sim.lcmlog" "$work/beliefs.lcmlog" "$work/both.lcmlog" <<'PY'
import sys, lcm
out = lcm.EventLog(sys.argv[3], "w", overwrite=True)
for p in sys.argv[1:3]:
    for ev in lcm.EventLog(p, "r"):
        out.write_event(ev.timestamp, ev.channel, ev.data)
PY
(cd "$work/caller" && MPLCONFIGDIR=$work/mpl "$py" "$root/examples/beliefs.py" \
    --url "file://$work/both.lcmlog?speed=0" --track 500 --plot none.png >/dev/null 2>&1) &&
    fail "beliefs.py drew a track the log does not have"
(cd "$work/caller" && MPLCONFIGDIR=$work/mpl "$py" "$root/examples/beliefs.py" \
    --url "file://$work/both.lcmlog?speed=0" --track 401 --config "$conf" \
    --plot beliefs.png) >"$work/beliefs.out" 2>&1 || { cat "$work/beliefs.out"; fail "beliefs.py failed"; }
tail -1 "$work/beliefs.out"
grep -qx 'drew beliefs.png (201 beliefs, 100 truths): x (m), vx (m/s), y (m), vy (m/s)' "$work/beliefs.out" &&
    [ -s "$work/caller/beliefs.png" ] || fail "beliefs.py: the states are not named"

echo "== gf_node: states and units are checked against n"
sed 's/^states = x vx y vy$/states = x vx y/' "$conf" >"$work/short.conf"
line=$(grep -n '^states = x vx y$' "$work/short.conf" | cut -d: -f1)
if "$bin/gf_node" --config "$work/short.conf" --url "file://$work/sim.lcmlog?speed=0" \
    --out-url "file://$work/none.lcmlog?mode=w" 2>"$work/short.err"; then
    fail "gf_node took 3 state names for 4 states"
fi
grep -qx "gf_node: $work/short.conf: line $line: model target2d: states takes 4 words, one per state" "$work/short.err" ||
    { cat "$work/short.err"; fail "gf_node: no error at the states line"; }
echo "== scripts/spy's JRE: the installed java when it can open windows"
# (scripts/spy runs apt-get only when gf_java_gui says no)
if command -v java >/dev/null; then
    real=$(readlink -f "$(command -v java)")
    gui=no
    [ -e "$(dirname "$real")/../lib/libawt_xawt.so" ] && gui=yes
    got=$(bash -c '. "$1/scripts/lib.sh" && . "$1/scripts/lcm.sh" && gf_java_gui && echo yes || echo no' _ "$root")
    [ "$got" = "$gui" ] || fail "gf_java_gui says $got for $real (libawt_xawt.so: $gui)"
    # a headless JRE: the same java without AWT's X11 library beside it
    mkdir -p "$work/headless/bin" "$work/headless/lib"
    cp "$real" "$work/headless/bin/java"
    got=$(PATH=$work/headless/bin:$PATH bash -c '. "$1/scripts/lib.sh" && . "$1/scripts/lcm.sh" && gf_java_gui && echo yes || echo no' _ "$root")
    [ "$got" = no ] || fail "gf_java_gui takes a headless JRE"
    echo "gf_java_gui: $real: $gui; a headless copy: no"
fi
echo "lcm_tools: passed"
