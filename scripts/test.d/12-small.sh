# The core and its tests with GF_SMALL (-DGAUSSFILT_SMALL=ON: the compact
# KF2/EKF3 predict/update of src/small.c instead of the fast paths), gcc,
# warnings as errors, double and float: the same tests must pass.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt gcc cmake make libcmocka-dev
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
    grep -q GF_SMALL "$dir/CMakeFiles/gaussfilt.dir/flags.make" ||
        gf_die "GF_SMALL did not reach the library's compile flags"
    gf_ctest "$dir"
done
