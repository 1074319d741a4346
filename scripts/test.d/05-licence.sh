#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage licence: LICENSE is the MIT licence of "the gaussfilt authors", and
# every tracked source, header, CMake, script and Python file says
# "SPDX-License-Identifier: MIT" in a comment within its first 3 lines
# (after the shebang, if any). The kinds: *.c *.h *.lcm *.java *.ld,
# CMakeLists.txt *.cmake *.cmake.in, *.sh *.py, and any other file whose
# shebang names sh, bash or python; not fuzz/corpus/ (binary inputs).
# Needs only git; names every file that lacks the line.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
command -v git >/dev/null || gf_skip "no git: cannot list the tracked files"
git rev-parse --is-inside-work-tree >/dev/null 2>&1 ||
    gf_skip "$GF_ROOT is not a git checkout: no tracked files to check"

gf_log "licence: LICENSE"
[ -f LICENSE ] || gf_die "no LICENSE file"
grep -qx 'MIT License' LICENSE || gf_die "LICENSE: no 'MIT License' title"
grep -qx 'Copyright (c) [0-9][0-9-]* the gaussfilt authors' LICENSE ||
    gf_die "LICENSE: no line 'Copyright (c) YEAR the gaussfilt authors'"
grep -q 'Permission is hereby granted, free of charge' LICENSE &&
    grep -q 'THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND' LICENSE ||
    gf_die "LICENSE: not the MIT licence text"
echo "LICENSE: MIT, $(grep -x 'Copyright (c) .*' LICENSE)"

# licensed FILE: FILE is of a kind that must carry the SPDX line.
licensed() {
    case $1 in
    fuzz/corpus/*) return 1 ;;
    *.c | *.h | *.lcm | *.java | *.ld | *.sh | *.py) return 0 ;;
    CMakeLists.txt | */CMakeLists.txt | *.cmake | *.cmake.in) return 0 ;;
    esac
    local first
    IFS= read -r first <"$1" || [ -n "$first" ] || return 1
    [[ $first =~ ^\#!.*[/\ ](sh|bash|python[0-9.]*)$ ]]
}

gf_log "licence: SPDX-License-Identifier: MIT in every tracked source, header, CMake, script and Python file"
spdx='^(//|#|/\*) SPDX-License-Identifier: MIT( \*/)?$'
checked=0 missing=()
while IFS= read -r -d '' f; do
    [ -f "$f" ] || continue # deleted in the working tree, not yet committed
    licensed "$f" || continue
    checked=$((checked + 1))
    head -n 3 "$f" | grep -qE "$spdx" || missing+=("$f")
done < <(git ls-files -z)
if [ ${#missing[@]} -gt 0 ]; then
    printf '  %s\n' "${missing[@]}" >&2
    gf_die "${#missing[@]} of $checked files have no 'SPDX-License-Identifier: MIT' line in their first 3 lines (above); add it as the first line, or the second after a shebang, in the file's comment syntax"
fi
echo "$checked files, each with SPDX-License-Identifier: MIT in its first 3 lines"
