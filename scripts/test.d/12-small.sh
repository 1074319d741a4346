# GF_SMALL (the compact KF2/EKF3 predict/update of src/small.c instead of
# the fast paths): config.h's default, then the core and its tests forced
# to it (-DGAUSSFILT_SMALL=ON), gcc, warnings as errors, double and float:
# the same tests must pass. The default host builds (scripts/test core,
# -O2) test the fast paths.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt gcc clang cmake make libcmocka-dev

# config.h: GF_SMALL is 1 when the compiler optimises for size (-Os, -Oz),
# else 0; -DGF_SMALL=0/1 wins.
gf_log "small: GF_SMALL's default, per compiler and flags"
for cc in gcc clang; do
    for case in "-Os:1" "-Oz:1" "-O2:0" "-O0:0" "-Os -DGF_SMALL=0:0" \
        "-O2 -DGF_SMALL=1:1"; do
        flags=${case%:*} want=${case##*:}
        [ "$cc" = gcc ] && [ "${flags%% *}" = -Oz ] &&
            ! gcc -Oz -E -x c /dev/null >/dev/null 2>&1 && continue
        # shellcheck disable=SC2086
        got=$(printf '#include "gaussfilt/config.h"\nGF_SMALL\n' |
            "$cc" $flags -Iinclude -E -P -x c - | tail -1 | tr -d ' ')
        [ "$got" = "$want" ] ||
            gf_die "$cc $flags: GF_SMALL is '$got', expected $want"
        echo "$cc $flags: GF_SMALL=$got"
    done
done

for prec in double float; do
    single=OFF
    [ "$prec" = float ] && single=ON
    gf_log "small: build and test with GF_SMALL ($prec)"
    dir="$GF_BUILD/small-$prec"
    CC=gcc cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DGAUSSFILT_WERROR=ON -DGAUSSFILT_SMALL=ON \
        -DGAUSSFILT_SINGLE_PRECISION=$single >/dev/null ||
        gf_die "configuring the GF_SMALL build ($prec) failed"
    cmake --build "$dir" --parallel 2 >/dev/null ||
        gf_die "the GF_SMALL build ($prec) failed"
    grep -q 'GF_SMALL=1' "$dir/CMakeFiles/gaussfilt.dir/flags.make" ||
        gf_die "GF_SMALL=1 did not reach the library's compile flags"
    nm -A "$dir/libgaussfilt.a" | grep -q 'small.c.o:.* T gf_kf2_update$' ||
        gf_die "GF_SMALL build ($prec): gf_kf2_update is not small.c's"
    gf_ctest "$dir"
done
