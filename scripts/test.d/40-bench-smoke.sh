# Smoke stage for the benchmarks (issue 5): builds bench/gf_bench in double
# and float and runs every workload and part for a few steps, and runs the
# LCM pipeline benchmark for half a second, so they cannot rot. No timing
# is asserted: figures come from scripts/bench and scripts/bench-lcm.
# gf_bench exits non-zero if any filter call fails.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt cmake make gcc libc6-dev

for prec in double float; do
    single=OFF
    [ "$prec" = float ] && single=ON
    dir=$GF_BUILD/bench-smoke-$prec
    cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DGAUSSFILT_BUILD_BENCH=ON \
        -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF \
        -DGAUSSFILT_SINGLE_PRECISION=$single >/dev/null
    cmake --build "$dir" --parallel 2 >/dev/null
    for wl in w1 w1p w2 w2c; do
        for part in step predict update ref; do
            "$dir/bench/gf_bench" count "$wl" "$part" 2500
            "$dir/bench/gf_bench" time "$wl" "$part" 100 3 >/dev/null
            "$dir/bench/gf_bench" floor "$wl" "$part" >/dev/null
        done
    done
done
echo "bench smoke: gf_bench runs in double and float"

# The LCM pipeline benchmark, briefly: it must build, run against a real
# gf_node and get beliefs back (no rate or latency is asserted).
out=$(GF_LCM_RATES=2000 GF_LCM_SECONDS=0.5 "$GF_ROOT/scripts/bench-lcm")
echo "$out" | tail -4
row=$(grep -E '^\|[ ]+2000 ' <<<"$out") || gf_die "bench-lcm printed no row"
beliefs=$(awk -F'|' '{gsub(/ /, "", $6); print $6}' <<<"$row")
[ "${beliefs:-0}" -gt 0 ] || gf_die "bench-lcm: no beliefs came back ($row)"
echo "bench smoke: gf_lcmbench got $beliefs beliefs back from gf_node"
