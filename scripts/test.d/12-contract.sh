# SPDX-License-Identifier: MIT
# Bit-identity that survives vendoring: the core and tests/contract/contract.c
# (a fixed run of KF2, EKF3 and gf_kf, every number printed exactly): the
# core built from the sources alone, the way a firmware project compiles them, once
# as the reference (gcc -O2 -ffp-contract=off) and again with the
# compilers free to fuse products and sums into FMAs: gcc with
# -ffp-contract=fast -march=x86-64-v3, and clang with its default
# contraction and -march=x86-64-v3 (where the host has FMA). The core's
# own pragma (src/gf_internal.h) must keep every output the same, byte for
# byte, in double and in float. clang's -ffp-contract=fast overrides any
# pragma; that build is shown, counted, not required to match
# (docs/firmware.md says not to pass it).
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt gcc clang binutils
out="$GF_BUILD/contract"
mkdir -p "$out"
fma=0
grep -qw fma /proc/cpuinfo && fma=1

# build NAME CC FLAGS...: the core with FLAGS, the driver as the reference
# is built (its own arithmetic, the inputs, is not what is tested)
build() {
    local name=$1 cc=$2
    shift 2
    local dir="$out/$name"
    rm -rf "$dir"
    mkdir -p "$dir"
    local f
    for f in src/*.c; do
        "$cc" -std=c99 -Iinclude "$@" -c "$f" -o "$dir/$(basename "$f" .c).o"
    done
    local def=
    case " $* " in *" -DGF_SINGLE_PRECISION "*) def=-DGF_SINGLE_PRECISION ;; esac
    gcc -std=c99 -O2 -ffp-contract=off -Iinclude $def tests/contract/contract.c \
        "$dir"/*.o -lm -o "$dir/contract"
}

# fmas NAME: the FMA instructions in the build's core objects
fmas() {
    objdump -d "$out/$1"/*.o | grep -cE 'vfn?m(add|sub)[0-9]' || true
}

fail=0
for prec in double float; do
    def=
    [ "$prec" = float ] && def=-DGF_SINGLE_PRECISION
    build ref-$prec gcc -O2 -ffp-contract=off $def
    "$out/ref-$prec/contract" >"$out/ref-$prec.txt"
    echo "$prec: reference (gcc -O2 -ffp-contract=off): $(wc -l <"$out/ref-$prec.txt") lines"
    if [ $fma = 0 ]; then
        gf_skip "contract ($prec): the host has no FMA, so -march=x86-64-v3 builds cannot run here"
        continue
    fi
    for v in "gcc-fast gcc -ffp-contract=fast" "clang-default clang" \
        "clang-fast clang -ffp-contract=fast"; do
        # shellcheck disable=SC2086
        set -- $v
        name=$1-$prec cc=$2
        shift 2
        build "$name" "$cc" -O2 -march=x86-64-v3 "$@" $def
        "$out/$name/contract" >"$out/$name.txt"
        n=$(fmas "$name")
        if cmp -s "$out/ref-$prec.txt" "$out/$name.txt"; then
            echo "$prec: $cc -O2 -march=x86-64-v3 $*: $n FMA instructions in the core, outputs identical"
        elif [ "$1" = -ffp-contract=fast ] && [ "$cc" = clang ]; then
            echo "$prec: $cc -O2 -march=x86-64-v3 $*: $n FMA instructions, outputs differ (clang's fast contraction overrides the pragma; not supported)"
        else
            echo "error: $prec: $cc -O2 -march=x86-64-v3 $*: $n FMA instructions, outputs differ from the reference:"
            diff "$out/ref-$prec.txt" "$out/$name.txt" | head -4 || true
            fail=1
        fi
    done
done
exit $fail
