#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage runner: scripts/test itself. --help and -h print the usage (the
# script's header) and exit 0, an unknown stage is still an error, and the
# closing counts agree with ctest's: scripts/test runs stages made here
# (GF_TEST_D) in a scratch build directory, one with a ctest of 3 tests of
# which 1 fails, one with no ctest that passes, one that fails, one that
# skips, and one whose 2 ctest tests pass before it fails. Then every
# program in scripts/: --help and -h print its usage and do nothing else.
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

# Every program in scripts/ (its executables; lib.sh, lcm.sh and
# firmware.sh are sourced, not run): --help and -h print its usage on
# stdout, exit 0 within 3 s, write nothing on stderr, and change nothing:
# no file of the checkout created or modified, no build or venv made
# (GF_BUILD and GF_VENV point at paths that must stay absent).
gf_log "runner: --help and -h of every script in scripts/"
touch "$tmp/before"
sleep 1 # file times: anything written from here on is newer
n=0
for script in scripts/*; do
    [ -f "$script" ] && [ -x "$script" ] || continue
    name=$(basename "$script")
    for h in --help -h; do
        start=$(date +%s%N)
        rc=0
        GF_BUILD="$tmp/no-build" GF_VENV="$tmp/no-venv" timeout 20 \
            "$script" "$h" >"$tmp/help.out" 2>"$tmp/help.err" </dev/null || rc=$?
        ms=$((($(date +%s%N) - start) / 1000000))
        [ "$rc" -eq 0 ] || gf_die "$script $h: exit status $rc: $(head -5 "$tmp/help.err" "$tmp/help.out")"
        [ ! -s "$tmp/help.err" ] || gf_die "$script $h writes on stderr: $(head -5 "$tmp/help.err")"
        [ "$ms" -lt 3000 ] || gf_die "$script $h took $ms ms: does it do more than print its usage?"
        [ "$(wc -l <"$tmp/help.out")" -ge 3 ] || gf_die "$script $h: no usage: $(cat "$tmp/help.out")"
        grep -q "$name" "$tmp/help.out" || gf_die "$script $h: the usage does not name $name"
        ! grep -q '^#\|SPDX-License-Identifier' "$tmp/help.out" ||
            gf_die "$script $h prints the comment signs or the licence line"
        [ ! -e "$tmp/no-build" ] && [ ! -e "$tmp/no-venv" ] ||
            gf_die "$script $h made a build directory or a venv"
        changed=$(find . -path ./.git -prune -o -newer "$tmp/before" -print | head -5)
        [ -z "$changed" ] || gf_die "$script $h changed files of the checkout: $changed"
        n=$((n + 1))
    done
    echo "$script --help, -h: exit 0, $(wc -l <"$tmp/help.out") lines of usage, ${ms} ms"
done
[ "$n" -ge 30 ] || gf_die "only $((n / 2)) scripts in scripts/ checked"
echo "runner: passed"
