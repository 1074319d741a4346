#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage demo: scripts/demo with the exercises' numbers changed (exercise
# 2's measurement variance, exercise 4's heading variance) streams, checks,
# draws every figure, exits 0 and names each table that differs from the
# book with the option that made it differ; scripts/demo --core with
# another z and number of steps draws the same figures from the in-process
# run; scripts/plot draws from the demo's log (the figures, and the random
# robot's track), and scripts/nees reads it (the random car's and robot's
# NEES and NIS against their truth: the car inside, the robot OUTSIDE).
# Output in build/demo-test/.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"

export GF_DEMO_OUT=$GF_BUILD/demo-test
rm -rf "$GF_DEMO_OUT"
mkdir -p "$GF_DEMO_OUT"
passed=0 failed=0
check() { # check NAME COMMAND...: counts into the tally
    if "${@:2}"; then
        passed=$((passed + 1))
        echo "demo: $1 passed"
    else
        failed=$((failed + 1))
        echo "demo: $1 FAILED" >&2
    fi
}

streaming() {
    scripts/demo --meas-var 4 --heading-var 100 >"$GF_DEMO_OUT/demo.out" 2>&1 ||
        { tail -30 "$GF_DEMO_OUT/demo.out"; return 1; }
    grep -q 'Table 2.1 differs from the book because of --meas-var 4 (the book: 10)' \
        "$GF_DEMO_OUT/demo.out" &&
        grep -q 'Table 4.2 differs from the book because of --heading-var 100 (the book: 10000)' \
            "$GF_DEMO_OUT/demo.out" &&
        grep -q 'gf_check: Table 1.1 reproduced from the wire (0 mismatches)$' \
            "$GF_DEMO_OUT/demo.out" || { echo "the changed tables are not named" >&2; return 1; }
    local f
    for f in fig1_1_ellipses fig1_2_correlation fig2_1_measurement \
        fig4_1_prediction fig4_2_correction stream_car ex4_three_ways; do
        [ -s "$GF_DEMO_OUT/$f.png" ] || { echo "no $f.png" >&2; return 1; }
    done
}

core() {
    scripts/demo --core --z 3 --steps 8 >"$GF_DEMO_OUT/core.out" 2>&1 ||
        { tail -30 "$GF_DEMO_OUT/core.out"; return 1; }
    grep -q 'differs from the book because of --z 3 (the book: 5), --steps 8 (the book: 5)' \
        "$GF_DEMO_OUT/core.out" &&
        grep -q '^OK: 0 value(s) disagree with the worked solutions; not compared (changed by an option): Table 2.1$' \
            "$GF_DEMO_OUT/core.out" || { echo "the changed table is not named" >&2; return 1; }
    local f
    for f in fig1_1_ellipses fig1_2_correlation fig2_1_measurement \
        fig4_1_prediction fig4_2_correction; do
        [ -s "$GF_DEMO_OUT/core/$f.png" ] || { echo "no core/$f.png" >&2; return 1; }
    done
}

plot() {
    scripts/plot "$GF_DEMO_OUT/gaussfilt-demo.lcmlog" "$GF_DEMO_OUT/plot" >/dev/null &&
        [ -s "$GF_DEMO_OUT/plot/fig2_1_measurement.png" ] &&
        [ -s "$GF_DEMO_OUT/plot/ex4_three_ways.png" ] &&
        scripts/plot "$GF_DEMO_OUT/gaussfilt-demo.lcmlog" --track 11 --out "$GF_DEMO_OUT/plot/robot.png" |
        grep -qx "drew $GF_DEMO_OUT/plot/robot.png (track 11: 201 beliefs, 100 truths): x, y, theta (rad)"
}

# The random car (book-car) is consistent; the random robot is the book's
# exercise-4 robot, an EKF from a heading variance of 10000, and is not:
# scripts/nees says so and exits 1. Every update of both is there.
nees() {
    local rc=0
    scripts/nees "$GF_DEMO_OUT/gaussfilt-demo.lcmlog" --plot "$GF_DEMO_OUT/nees.png" \
        >"$GF_DEMO_OUT/nees.out" || rc=$?
    cat "$GF_DEMO_OUT/nees.out"
    [ "$rc" -eq 1 ] || { echo "scripts/nees: exit $rc, not 1 (the robot OUTSIDE)" >&2; return 1; }
    grep -Eq '^track 10 \(car, n=2, m=1\): 100 updates \(0 gated, 0 missing of 100 measurements\): NEES [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside.*; NIS [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, inside\)$' \
        "$GF_DEMO_OUT/nees.out" &&
        grep -Eq '^track 11 \(robot, n=3, m=1\): 100 updates \(0 gated, 0 missing of 100 measurements\): NEES [0-9.]+ \(95% bounds [0-9.]+\.\.[0-9.]+, OUTSIDE' "$GF_DEMO_OUT/nees.out" &&
        [ -s "$GF_DEMO_OUT/nees.png" ]
}

if [ "$(id -u)" -eq 0 ]; then
    gf_log "demo: streaming, exercise 2's variance 4 and exercise 4's heading variance 100"
    check demo_changed streaming
    gf_log "demo: scripts/plot on the demo's log"
    check plot_log plot
    gf_log "demo: scripts/nees on the demo's log"
    check nees_log nees
else
    echo "demo: the streaming demo, scripts/plot and scripts/nees on its log are skipped:" \
        "they need root (a private network namespace) here"
fi
gf_log "demo: --core, exercise 2's z = 3 after 8 steps"
check demo_core_changed core
mkdir -p "$(dirname "$GF_TALLY")"
echo "$passed $failed" >>"$GF_TALLY"
[ "$failed" -eq 0 ]
