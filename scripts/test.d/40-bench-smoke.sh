# SPDX-License-Identifier: MIT
# Smoke stage for the benchmarks: builds bench/gf_bench in double and float
# and runs every workload and part for a few steps, runs the Cortex-M4F
# benchmark image once under QEMU and the insncount plugin, and runs the
# LCM pipeline benchmark for half a second, so they cannot rot. No timing
# is asserted: figures come from scripts/bench and scripts/bench-lcm.
# gf_bench and the image exit non-zero if any filter call fails.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
. "$GF_ROOT/scripts/firmware.sh"
. "$GF_ROOT/bench/qemu/m4f.sh"
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
    for wl in w1 w1p w2 w2p w2c w2m2 w2m3; do
        for part in step predict update ref; do
            "$dir/bench/gf_bench" count "$wl" "$part" 2500
            "$dir/bench/gf_bench" time "$wl" "$part" 100 3 >/dev/null
            "$dir/bench/gf_bench" floor "$wl" "$part" >/dev/null
        done
    done
done
echo "bench smoke: gf_bench runs in double and float"

# The Cortex-M4F image under the plugin (-Os). The plugin's figures must be
# counts of what ran: an empty region is exactly the one `bl` to the stop
# marker, every workload counts more than the floor's W1 step and fewer
# than 100000 instructions per call, and the run as a whole counts at least
# as many as all the regions.
gf_log "bench smoke: the Cortex-M4F image under qemu and insncount (-Os)"
plugin=$(gf_m4f_plugin)
elf=$(gf_m4f_image Os)
counts=$(gf_m4f_count "$elf" "$plugin")
echo "$counts"
awk '$1 == "empty" {if ($8 != $3) bad = bad " empty region counted " $8 / $3 " instructions, not 1"}
     $1 == "w1" && $2 == "ref" {floor = $4}
     $1 != "empty" && $1 != "total" {rows++; n[rows] = $1 " " $2; v[rows] = $4; sum += $8}
     $1 == "total" {total = $2}
     END {if (floor < 20) bad = bad " W1 floor " floor
          for (i = 1; i <= rows; i++)
              if (v[i] < floor || v[i] > 100000) bad = bad " " n[i] " " v[i]
          if (rows < 8) bad = bad " only " rows " rows"
          if (total < sum) bad = bad " run total " total " < regions " sum
          if (bad != "") {print "implausible counts:" bad; exit 1}}' <<<"$counts" ||
    gf_die "bench smoke: the plugin's counts are implausible"
echo "bench smoke: the M4F image ran and insncount counted it"

# The LCM pipeline benchmark, briefly: it must build, run against a real
# gf_node and get beliefs back (no rate or latency is asserted).
out=$(GF_LCM_RATES=2000 GF_LCM_SECONDS=0.5 "$GF_ROOT/scripts/bench-lcm")
echo "$out" | tail -4
row=$(grep -E '^\|[ ]+2000 ' <<<"$out") || gf_die "bench-lcm printed no row"
beliefs=$(awk -F'|' '{gsub(/ /, "", $6); print $6}' <<<"$row")
[ "${beliefs:-0}" -gt 0 ] || gf_die "bench-lcm: no beliefs came back ($row)"
echo "bench smoke: gf_lcmbench got $beliefs beliefs back from gf_node"
