# Smoke stage for the benchmark (issue 5): builds bench/gf_bench in double
# and float and runs every workload and part for a few steps, so the
# benchmark cannot rot. No timing is asserted: figures come from
# scripts/bench. gf_bench exits non-zero if any filter call fails.
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
    for wl in w1 w2 w2c; do
        for part in step predict update ref; do
            "$dir/bench/gf_bench" count "$wl" "$part" 2500
            "$dir/bench/gf_bench" time "$wl" "$part" 100 3 >/dev/null
            "$dir/bench/gf_bench" floor "$wl" "$part" >/dev/null
        done
    done
done
echo "bench smoke: gf_bench runs in double and float"
