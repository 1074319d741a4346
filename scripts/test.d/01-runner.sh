#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage runner: scripts/test itself. --help and -h print the usage (the
# script's header) and exit 0, an unknown stage is still an error, and the
# closing counts agree with ctest's: scripts/test runs stages made here
# (GF_TEST_D) in a scratch build directory, one with a ctest of 3 tests of
# which 1 fails, one with no ctest that passes, one that fails, one that
# skips, and one whose 2 ctest tests pass before it fails.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt cmake # ctest

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

gf_log "runner: scripts/test --help, -h"
for h in --help -h; do
    out=$(bash scripts/test "$h") || gf_die "scripts/test $h: exit status $?"
    grep -q '^  scripts/test NAME\.\.\. ' <<<"$out" ||
        gf_die "scripts/test $h does not print the usage: $out"
    grep -q '^The last line$\|scripts/test: N passed, N failed' <<<"$out" ||
        gf_die "scripts/test $h does not say what the last line counts"
    ! grep -q '^#\|SPDX' <<<"$out" ||
        gf_die "scripts/test $h prints the comment signs or the licence line"
    first=$(grep -m1 -v '^#!\|SPDX' scripts/test | sed 's/^# //')
    [ "$(head -1 <<<"$out")" = "$first" ] ||
        gf_die "scripts/test $h does not start with the header's first line ($first): $(head -1 <<<"$out")"
    echo "scripts/test $h: exit 0, $(wc -l <<<"$out") lines of usage"
done
if out=$(bash scripts/test no-such-stage 2>&1); then
    gf_die "scripts/test no-such-stage passed"
fi
grep -q "no stage 'no-such-stage'" <<<"$out" ||
    gf_die "scripts/test no-such-stage does not name the stage: $out"
echo "scripts/test no-such-stage: refused ($out)"

gf_log "runner: the closing counts against ctest's"
mkdir -p "$tmp/stages"
# ctest_dir DIR RESULT...: a ctest directory of one test per RESULT
# (true or false), no CMake needed
ctest_dir() {
    local dir=$1 i=0 r
    shift
    mkdir -p "$dir"
    for r in "$@"; do
        i=$((i + 1))
        echo "add_test(t$i \"$r\")"
    done >"$dir/CTestTestfile.cmake"
}
ctest_dir "$tmp/ct-1of3" true true false
ctest_dir "$tmp/ct-2" true true
stage() { # stage FILE BODY: a stage script that sources lib.sh
    printf '#!/usr/bin/env bash\nset -euo pipefail\n. scripts/lib.sh\n%s\n' \
        "$2" >"$tmp/stages/$1"
}
stage 10-ctfail.sh "gf_ctest '$tmp/ct-1of3'"
stage 20-plainpass.sh "true"
stage 30-plainfail.sh "exit 1"
stage 40-skip.sh "gf_skip 'not here'"
stage 50-ctpassfail.sh "gf_ctest '$tmp/ct-2'; echo 'a check after ctest fails' >&2; exit 1"

# run_fake NAME...: scripts/test on the stages above in a scratch GF_BUILD;
# sets out and rc
run_fake() {
    rm -rf "$tmp/build"
    rc=0
    out=$(GF_TEST_D="$tmp/stages" GF_BUILD="$tmp/build" GF_TALLY="$tmp/build/.tally" \
        bash scripts/test "$@" 2>&1) || rc=$?
}
# want NAMES RC LAST: scripts/test NAMES exits RC (0 or not) and ends with LAST
want() {
    local last
    run_fake $1
    last=$(tail -1 <<<"$out")
    if [ "$last" != "$3" ] || { [ "$2" -eq 0 ] && [ "$rc" -ne 0 ]; } ||
        { [ "$2" -ne 0 ] && [ "$rc" -eq 0 ]; }; then
        sed 's/^/  | /' <<<"$out" >&2
        gf_die "scripts/test $1: exit status $rc and '$last', expected '$3' (exit $2)"
    fi
    echo "scripts/test $1: $last"
}
# ctest's "1 tests failed out of 3" is the whole count of the stage
want ctfail 1 "scripts/test: 2 passed, 1 failed"
grep -q '1 tests failed out of 3' <<<"$out" || gf_die "ctest did not run 3 tests"
want plainpass 0 "scripts/test: 1 passed, 0 failed"
want plainfail 1 "scripts/test: 0 passed, 1 failed"
want skip 0 "scripts/test: 0 passed, 0 failed"
grep -q '^skip: not here$' <<<"$out" || gf_die "the skip: line is missing"
# ctest passed; the stage failed after it: one failure more
want ctpassfail 1 "scripts/test: 2 passed, 1 failed"
want "ctfail plainpass plainfail skip ctpassfail" 1 "scripts/test: 5 passed, 3 failed"
grep -q '^failed stages: ctfail plainfail ctpassfail$' <<<"$out" ||
    gf_die "the failed stages are not named: $(grep '^failed' <<<"$out")"
grep -q '^skipped (see their skip: lines above): skip$' <<<"$out" ||
    gf_die "the skipped stage is not named"
echo "runner: passed"
