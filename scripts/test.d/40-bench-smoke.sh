# SPDX-License-Identifier: MIT
# Smoke stage for the benchmarks: builds bench/gf_bench in double and float
# and runs every workload and part for a few steps (the filters of n states,
# cv2 ... cv12 and gps, their step and their floor's), runs the Cortex-M4F
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
    # The filters of n states (bench/workloads_n.h): set-up runs the filter
    # over the whole table, then a few hundred steps of each loop.
    for wl in cv2 cv3 cv4 cv6 cv8 cv12 gps; do
        for part in step ref; do
            "$dir/bench/gf_bench" count "$wl" "$part" 300
            "$dir/bench/gf_bench" time "$wl" "$part" 50 3 >/dev/null
        done
    done
done
echo "bench smoke: gf_bench runs in double and float"

# The Cortex-M4F image under the plugin (-Os). The plugin's figures must be
# counts of what ran: an empty region is exactly the one `bl` to the stop
# marker, every workload counts more than the floor's W1 step and fewer
# than 200000 instructions per call, the filters of n states report their
# 14 rows (step and floor of cv2 ... cv12 and gps), each step dearer than
# the one before it in n (cv2 < cv3 < ... < cv12), and the run as a whole
# counts at least as many as all the regions. The loop floors of W1 and W2
# (bench/floor.h) count fewer than the library's steps.
gf_log "bench smoke: the Cortex-M4F image under qemu and insncount (-Os)"
plugin=$(gf_m4f_plugin)
elf=$(gf_m4f_image Os)
counts=$(gf_m4f_count "$elf" "$plugin")
echo "$counts"
awk '$1 == "empty" {if ($8 != $3) bad = bad " empty region counted " $8 / $3 " instructions, not 1"}
     $1 == "w1" && $2 == "ref" {floor = $4}
     $1 ~ /^w[12]$/ && $2 == "floor" {loop[$1] = $4}
     $1 ~ /^w[12]$/ && $2 == "step" {lib[$1] = $4}
     $1 != "empty" && $1 != "total" {rows++; n[rows] = $1 " " $2; v[rows] = $4; sum += $8}
     $1 == "total" {total = $2}
     END {if (floor < 20) bad = bad " W1 floor " floor
          for (i = 1; i <= rows; i++)
              if (v[i] < floor || v[i] > 200000) bad = bad " " n[i] " " v[i]
          if (rows < 24) bad = bad " only " rows " rows"
          for (w in lib) if (!(loop[w] > 0 && loop[w] < lib[w])) bad = bad " " w " loop floor " loop[w] " (step " lib[w] ")"
          split("cv2 cv3 cv4 cv6 cv8 cv12 gps", nr, " ")
          for (i = 1; i <= 7; i++) for (j = 1; j <= rows; j++)
              if (n[j] == nr[i] " step") { step[i] = v[j]; found[i]++ }
              else if (n[j] == nr[i] " ref") found[i]++
          for (i = 1; i <= 7; i++) if (found[i] != 2) bad = bad " " nr[i] ": " found[i] + 0 " of 2 rows"
          for (i = 2; i <= 6; i++) if (step[i] <= step[i - 1]) bad = bad " " nr[i] " step not above " nr[i - 1]
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
