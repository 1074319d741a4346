#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Static analysis of the core (src/, include/), all clean or the stage fails:
#   scripts/check-includes: docs/design.md's include rules;
#   cppcheck (warning, style, performance, portability) with its MISRA C:2012
#   addon: the deviations kept are in scripts/analysis/misra-suppressions.txt
#   and explained in docs/misra.md;
#   clang-tidy with scripts/analysis/clang-tidy.yaml, warnings as errors;
#   gcc -fanalyzer with the project's warnings, -Werror;
#   clang-format (15 or later) --dry-run --Werror with .clang-format, braces
#   on every body (InsertBraces), over every C and C++
#   file of src/, include/, sim/, tests/, bench/, fuzz/, examples/ and
#   firmware/: one style, checked.
# Each in the double and the float configuration.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
gf_apt cppcheck clang-tidy clang-format-16 gcc python3

an="$GF_ROOT/scripts/analysis"
fail=0

gf_log "analysis: the include rules of docs/design.md (scripts/check-includes)"
if ! python3 "$GF_ROOT/scripts/check-includes"; then
    fail=1
fi

gf_log "analysis: cppcheck $(cppcheck --version | awk '{print $2}') + MISRA C:2012 addon"
out="$GF_BUILD/analysis-cppcheck.txt"
mkdir -p "$GF_BUILD/analysis-cppcheck"
for def in -UGF_SINGLE_PRECISION -DGF_SINGLE_PRECISION; do
    # shellcheck disable=SC2086
    cppcheck --std=c99 --language=c --enable=warning,style,performance,portability \
        --addon=misra --inline-suppr --suppressions-list="$an/misra-suppressions.txt" \
        --cppcheck-build-dir="$GF_BUILD/analysis-cppcheck" \
        --error-exitcode=1 -q -Iinclude $def \
        --template='{file}:{line}:{column}: {severity}: {id}: {message}' \
        src/ 2>"$out" || true
    if [ -s "$out" ]; then
        cat "$out"
        echo "cppcheck ($def): findings above"
        fail=1
    else
        echo "cppcheck ($def): clean"
    fi
done

gf_log "analysis: $(clang-tidy --version | grep -o 'LLVM version [0-9.]*' | head -1 | sed 's/LLVM/clang-tidy/')"
for def in -UGF_SINGLE_PRECISION -DGF_SINGLE_PRECISION; do
    # shellcheck disable=SC2086
    if clang-tidy --quiet --config-file="$an/clang-tidy.yaml" src/*.c -- \
        -std=c99 -Iinclude $def 2>/dev/null; then
        echo "clang-tidy (${def:-double}): clean"
    else
        echo "clang-tidy (${def:-double}): findings above"
        fail=1
    fi
done

gf_log "analysis: gcc $(gcc -dumpversion) -fanalyzer"
warn="-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion"
warn="$warn -Wdouble-promotion -Wstrict-prototypes -Wmissing-prototypes"
warn="$warn -Wcast-qual -Wvla -Wundef -Wfloat-equal -Werror"
for def in -UGF_SINGLE_PRECISION -DGF_SINGLE_PRECISION; do
    ok=1
    for f in src/*.c; do
        # shellcheck disable=SC2086
        gcc -std=c99 -O2 -fanalyzer $warn $def -Iinclude -c "$f" -o /dev/null || ok=0
    done
    if [ $ok -eq 1 ]; then
        echo "gcc -fanalyzer (${def:-double}): clean"
    else
        echo "gcc -fanalyzer (${def:-double}): findings above"
        fail=1
    fi
done

# clang-format 15 or later: InsertBraces (.clang-format) puts braces on
# every body; Debian 12's default clang-format is 14, which has no such
# option. The newest installed one is used.
cf=
for v in 19 18 17 16 15; do
    if command -v clang-format-$v >/dev/null; then
        cf=clang-format-$v
        break
    fi
done
[ -n "$cf" ] || gf_die "analysis: no clang-format 15 or later (apt-get install clang-format-16)"
gf_log "analysis: $($cf --version | grep -o 'clang-format version [0-9.]*') over the tree"
fmt=$(git ls-files -- src include sim tests bench fuzz examples firmware python |
    grep -E '\.(c|h|cpp|hpp)$' || true)
# shellcheck disable=SC2086
if $cf --dry-run --Werror $fmt; then
    echo "clang-format: $(echo "$fmt" | wc -l) files clean"
else
    echo "clang-format: the files above differ from .clang-format's style," \
        "braces on every body included ($cf -i FILE fixes them)"
    fail=1
fi

[ $fail -eq 0 ] || gf_die "static analysis found problems"
