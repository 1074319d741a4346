# SPDX-License-Identifier: MIT
# The core and its tests built with clang, warnings as errors, double and
# float (scripts/test's core stage uses gcc).
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt clang
for prec in double float; do
    single=OFF
    [ "$prec" = float ] && single=ON
    gf_log "clang: build and test ($prec)"
    CC=clang cmake -S . -B "$GF_BUILD/clang-$prec" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DGAUSSFILT_SINGLE_PRECISION=$single >/dev/null
    cmake --build "$GF_BUILD/clang-$prec" --parallel 2 >/dev/null
    gf_ctest "$GF_BUILD/clang-$prec"
done
