#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The whole ctest suite under AddressSanitizer and UndefinedBehaviorSanitizer
# (host gcc), in double and in float. Any report aborts the test that made
# it (-fno-sanitize-recover), so ctest fails.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
gf_apt cmake make gcc libc6-dev libcmocka-dev

flags="-fsanitize=address,undefined -fno-sanitize-recover=all"
flags="$flags -fno-omit-frame-pointer -g -O1"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for prec in double float; do
    single=OFF
    [ "$prec" = float ] && single=ON
    dir="$GF_BUILD/sanitize-$prec"
    gf_log "sanitize: ASan + UBSan, whole ctest suite ($prec)"
    cmake -S "$GF_ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Debug \
        -DGAUSSFILT_SINGLE_PRECISION=$single \
        -DCMAKE_C_FLAGS="$flags" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
    cmake --build "$dir" --parallel 2
    gf_ctest "$dir"
done
