# SPDX-License-Identifier: MIT
# Counting on the Cortex-M4F: building the insncount plugin and the
# benchmark image (bench/m4f.c), and running the image under QEMU with the
# plugin. Shared by scripts/bench and scripts/test.d/40-bench-smoke.sh;
# sourced after scripts/lib.sh and scripts/firmware.sh, not run.

# gf_m4f_plugin: builds bench/qemu/insncount.c into
# $GF_BUILD/insncount/libinsncount.so (host gcc; no QEMU header needed).
# Prints the path.
gf_m4f_plugin() {
    gf_apt gcc libc6-dev qemu-system-arm >&2
    local out=$GF_BUILD/insncount src=$GF_ROOT/bench/qemu/insncount.c
    mkdir -p "$out"
    if [ ! -f "$out/libinsncount.so" ] || [ "$src" -nt "$out/libinsncount.so" ]; then
        ${CC:-gcc} -std=c99 -O2 -Wall -Wextra -Werror -shared -fPIC \
            -fvisibility=hidden -o "$out/libinsncount.so" "$src" ||
            gf_die "building the insncount plugin failed"
    fi
    echo "$out/libinsncount.so"
}

# gf_m4f_image Os|O2: builds the float benchmark image for Cortex-M4F at
# that optimisation level (library and bench alike); the build's output goes
# to $GF_BUILD/insncount/image-Os.log (or -O2), shown if it fails. Prints
# the ELF's path.
gf_m4f_image() {
    local dir log=$GF_BUILD/insncount/image-$1.log
    mkdir -p "$GF_BUILD/insncount"
    dir=$(GF_FW_OPT=$1 GF_FW_VARIANT=bench-$1 gf_fw_build cortex-m4f float \
        -DGF_FW_BENCH=ON 2>"$log" | tail -1)
    if [ ! -f "$dir/gf_fw_bench.elf" ] || grep -q '^error:' "$log"; then
        tail -30 "$log" >&2
        gf_die "building the Cortex-M4F bench image (-$1) failed"
    fi
    echo "$dir/gf_fw_bench.elf"
}

# gf_m4f_count ELF PLUGIN [PROFILE]: runs the image once under the plugin and prints
# one line per report:
#   WL PART N INSNS_PER_REGION VDIV_PER_REGION VSQRT_PER_REGION CALLS TOTAL
# per region = the total over the N regions / N, minus the empty region's
# count (the markers' own instructions), for instructions; vdiv, vsqrt and
# calls (entries of soft-double helpers and double libm functions) are not
# corrected (the markers have none). The last line is "total T": every
# instruction the run executed, set-up included. With PROFILE, a file name,
# the run is profiled (profile=on) and bench/qemu/profile.py's breakdown by
# function of every report is written there.
gf_m4f_count() {
    local elf=$1 plugin=$2 prof=${3:-} nm=arm-none-eabi-nm addr args log out
    addr() {
        # (awk reads to the end: nm must not die of SIGPIPE under pipefail)
        "$nm" "$elf" | awk -v s="$1" '$3 == s && !f {print "0x" $1; f = 1}'
    }
    args="start=$(addr bench_mark_start),stop=$(addr bench_mark_stop)"
    args="$args,report=$(addr bench_mark_report)"
    case $args in *=,* | *=) gf_die "$elf: a marker symbol is missing" ;; esac
    # Soft double: libgcc's helpers and newlib's double functions.
    local f
    for f in $("$nm" "$elf" | awk '$2 ~ /^[Tt]$/ && $3 ~ /^(__aeabi_d[a-z0-9]+|__(add|sub|mul|div|extendsf|truncdf|fix|float)[a-z]*df[0-9a-z]*|sqrt|sin|cos|atan2|log|exp|floor|ceil|fabs)$/ {print "0x" $1}' | sort -u); do
        args="$args,call=$f"
    done
    [ -z "$prof" ] || args="$args,profile=on"
    log=$(mktemp) out=$(mktemp)
    timeout 600 qemu-system-arm -M mps2-an386 -nographic -monitor none \
        -serial none -semihosting-config enable=on,target=native \
        -plugin "$plugin,$args" -d plugin -D "$log" -kernel "$elf" >"$out" ||
        { cat "$out" "$log" >&2; rm -f "$log" "$out"; gf_die "$elf failed under qemu"; }
    grep -qx 'bench done' "$out" || { cat "$out" >&2; gf_die "$elf did not finish"; }
    paste -d' ' <(grep '^bench ' "$out" | grep -v '^bench done') \
        <(grep '^insncount: regions' "$log") |
        awk '{ wl = $2; part = $3; n = $4; r = $7; ins = $9; dv = $11; sq = $13; ca = $15
               if (r != n) { print "error: " wl " " part ": " r " regions for " n " steps" > "/dev/stderr"; exit 1 }
               if (wl == "empty") { e = ins / r }
               printf "%s %s %d %.1f %.4g %.4g %d %d\n", wl, part, n, ins / r - e, dv / r, sq / r, ca, ins }' ||
        gf_die "the plugin's reports do not match the image's"
    awk '/^insncount: total/ {print "total " $3}' "$log"
    if [ -n "$prof" ]; then
        python3 "$GF_ROOT/bench/qemu/profile.py" "$elf" "$out" "$log" >"$prof" ||
            gf_die "bench/qemu/profile.py failed"
    fi
    rm -f "$log" "$out"
}
