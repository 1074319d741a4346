# SPDX-License-Identifier: MIT
# Shared by the scripts in scripts/: logging, installing what is missing,
# the project's Python venv, and ctest with a running tally. Sourced, not run.

GF_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
GF_BUILD=${GF_BUILD:-$GF_ROOT/build}
GF_VENV=${GF_VENV:-$GF_ROOT/.venv}
GF_TALLY=${GF_TALLY:-$GF_BUILD/.tally}

gf_log() { printf '\n==> %s\n' "$*"; }
gf_die() { printf 'error: %s\n' "$*" >&2; exit 1; }

# gf_skip REASON: ends a stage of scripts/test as skipped (exit 77), with the
# reason on a line of its own. Outside a stage it is an error.
gf_skip() {
    if [ -n "${GF_STAGE:-}" ]; then
        printf 'skip: %s\n' "$*"
        exit 77
    fi
    gf_die "$*"
}

# gf_readme_block NAME: the lines between <!-- NAME --> and <!-- /NAME -->
# in README.md or the page of docs/ that holds them, without the ```
# fences, so that the tests run what the documentation shows. Fails if the
# block is missing or empty.
gf_readme_block() {
    local text
    text=$(awk -v start="<!-- $1 -->" -v stop="<!-- /$1 -->" '
        $0 == stop { inside = 0 }
        inside && !/^```/ { print }
        $0 == start { inside = 1 }' "$GF_ROOT/README.md" "$GF_ROOT"/docs/*.md)
    [ -n "$text" ] || gf_die "README.md and docs/ have no block <!-- $1 --> ... <!-- /$1 -->"
    printf '%s\n' "$text"
}

# gf_check_names LIBRARY float|double [NM]: every function LIBRARY defines
# has its precision in its link name (include/gaussfilt/names.h for the
# API, src/gf_names.h for the internal functions), and every name they
# rename is defined. gf_status_str alone keeps its name.
gf_check_names() {
    local lib=$1 prec=$2 nm=${3:-nm} suffix=_f64 defined listed bad
    [ "$prec" = float ] && suffix=_f32
    defined=$("$nm" --defined-only -g "$lib" | awk 'NF == 3 {print $3}' | sort -u)
    listed=$(sed -nE 's/^#define (gf_[a-z0-9_]+) GF_NAME\(\1\)$/\1/p' \
        "$GF_ROOT/include/gaussfilt/names.h" "$GF_ROOT/src/gf_names.h" | sort -u)
    [ -n "$defined" ] || gf_die "$lib defines no symbol"
    bad=$(grep -vxE "gf_status_str|gf_[a-z0-9_]+$suffix" <<<"$defined" || true)
    [ -z "$bad" ] || gf_die "$lib ($prec) defines $(tr '\n' ' ' <<<"$bad")without \
the precision in the name; add to include/gaussfilt/names.h (API) or
       src/gf_names.h (internal), for each:
       #define NAME GF_NAME(NAME)"
    bad=$(comm -23 <(sed "s/\$/$suffix/" <<<"$listed" | sort) <(printf '%s\n' "$defined") | tr '\n' ' ')
    [ -z "$bad" ] || gf_die "names.h or src/gf_names.h renames what $lib ($prec) does not define: $bad"
    echo "$(wc -l <<<"$listed") function names carry $suffix; gf_status_str keeps its name"
}

# gf_apt PKG...: installs the Debian packages that are not installed yet.
# As root it runs apt-get; otherwise it stops and names the command to run.
gf_apt() {
    local missing=() p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'ok installed' ||
            missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if [ "$(id -u)" -ne 0 ]; then
        gf_skip "missing Debian packages: ${missing[*]} (not root: cannot install them)
       install them with: sudo apt-get install ${missing[*]}"
    fi
    gf_log "installing Debian packages: ${missing[*]}"
    if [ ! -f "$GF_BUILD/.apt-updated" ]; then
        apt-get update -q >/dev/null || gf_die "apt-get update failed"
        mkdir -p "$GF_BUILD" && touch "$GF_BUILD/.apt-updated"
    fi
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
        "${missing[@]}" >/dev/null ||
        gf_die "apt-get install ${missing[*]} failed"
}

# gf_venv PKG...: makes the project's .venv (once) and pip-installs the
# given requirement specifiers that are not satisfied yet.
gf_venv() {
    gf_check_venv
    if [ ! -x "$GF_VENV/bin/python" ]; then
        gf_log "creating Python venv in $GF_VENV"
        python3 -m venv "$GF_VENV" 2>/dev/null || {
            gf_apt python3-venv
            python3 -m venv "$GF_VENV"
        } || gf_die "cannot create a venv with python3 -m venv"
    fi
    [ $# -eq 0 ] && return 0
    if ! "$GF_VENV/bin/python" - "$@" <<'PY' 2>/dev/null; then
import sys
from importlib.metadata import distribution
from packaging.requirements import Requirement
for spec in sys.argv[1:]:
    r = Requirement(spec)
    if not r.specifier.contains(distribution(r.name).version, prereleases=True):
        sys.exit(1)
PY
        gf_log "installing into .venv: $*"
        "$GF_VENV/bin/python" -m pip install -q --disable-pip-version-check \
            packaging "$@" || gf_die "pip install $* failed (is PyPI reachable?)"
    fi
}

# gf_py_package: the Python package gaussfilt (python/, docs/python.md) in
# the project's .venv, once: its build requirements from PyPI, then the
# package built from this checkout, offline (pip install ./python).
gf_py_package() {
    gf_venv 'numpy>=1.21' 'scikit-build-core>=1.0' 'cmake>=3.26'
    "$GF_VENV/bin/python" -c 'import gaussfilt' 2>/dev/null && return 0
    gf_apt cmake make gcc libc6-dev
    gf_log "installing the Python package gaussfilt into .venv (pip install ./python)"
    "$GF_VENV/bin/python" -m pip install -q --disable-pip-version-check \
        --no-build-isolation --no-index --no-deps "$GF_ROOT/python" ||
        gf_die "pip install ./python failed"
}

# gf_ctest BUILD_DIR [ctest args...]: runs ctest and adds its counts to the
# tally that scripts/test prints at the end.
gf_ctest() {
    local dir=$1 out rc
    shift
    out=$(mktemp)
    set +e
    ctest --test-dir "$dir" --output-on-failure "$@" 2>&1 | tee "$out"
    rc=${PIPESTATUS[0]}
    set -e
    local line total failed
    line=$(grep -E 'tests? passed, [0-9]+ tests? failed out of [0-9]+' "$out" | tail -1)
    rm -f "$out"
    if [ -n "$line" ]; then
        failed=$(sed -E 's/.* ([0-9]+) tests? failed out of.*/\1/' <<<"$line")
        total=$(sed -E 's/.*out of ([0-9]+).*/\1/' <<<"$line")
        mkdir -p "$(dirname "$GF_TALLY")"
        echo "$((total - failed)) $failed" >>"$GF_TALLY"
    fi
    return "$rc"
}

# gf_check_build: build/ (GF_BUILD) and every CMake tree in it are this
# user's, and every tree was configured here. A tree made by another user, or in a checkout that has
# moved since, is named with its fix; nothing is rebuilt over it.
gf_check_build() {
    local cache dir was me owner root_p build_p
    [ -e "$GF_BUILD" ] || return 0
    me=$(id -un)
    root_p=$(cd "$GF_ROOT" && pwd -P)
    build_p=$(cd "$GF_BUILD" && pwd -P)
    for cache in "$GF_BUILD" "$GF_BUILD"/*/CMakeCache.txt "$GF_BUILD"/*/*/CMakeCache.txt; do
        [ -e "$cache" ] || continue
        owner=$(stat -c %U "$cache")
        [ "$owner" = "$me" ] && [ -w "$cache" ] ||
            gf_die "$GF_BUILD was made by another user ($owner${cache#"$GF_BUILD"}): remove it as that user (rm -rf $GF_BUILD), or build elsewhere: export GF_BUILD=\$HOME/gaussfilt-build"
    done
    for cache in "$GF_BUILD"/*/CMakeCache.txt "$GF_BUILD"/*/*/CMakeCache.txt; do
        [ -f "$cache" ] || continue
        dir=$(cd "$(dirname "$cache")" && pwd -P)
        was=$(sed -n 's/^CMAKE_CACHEFILE_DIR:INTERNAL=//p' "$cache")
        if [ -n "$was" ] && [ "$was" != "$dir" ] && [ "$was" != "$(dirname "$cache")" ]; then
            gf_die "$(basename "$GF_BUILD")/ was configured for $(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache") \
(${cache#"$GF_BUILD"/} says $was), and this checkout is $GF_ROOT: remove it: rm -rf $GF_BUILD"
        fi
        was=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cache")
        case $was in
        "" | "$GF_ROOT" | "$GF_ROOT"/* | "$GF_BUILD"/* | "$root_p" | "$root_p"/* | "$build_p"/*) ;;
        *) gf_die "$(basename "$GF_BUILD")/ was configured for the sources in $was \
(${cache#"$GF_BUILD"/}), not this checkout, $GF_ROOT: remove it: rm -rf $GF_BUILD" ;;
        esac
    done
}

# gf_check_venv: the project's .venv (GF_VENV) is this user's and was made
# for this path; otherwise names the fix instead of building over it.
gf_check_venv() {
    local was
    [ -e "$GF_VENV" ] || return 0
    if [ ! -w "$GF_VENV" ] || [ -n "$(find "$GF_VENV" -maxdepth 1 ! -user "$(id -u)" -print -quit 2>/dev/null)" ]; then
        gf_die "$GF_VENV was made by another user ($(stat -c %U "$GF_VENV")): remove it as that user (rm -rf $GF_VENV), or use another: export GF_VENV=\$HOME/gaussfilt-venv"
    fi
    was=$(sed -n 's/^VIRTUAL_ENV=["'"'"']\{0,1\}\([^"'"'"']*\).*/\1/p' "$GF_VENV/bin/activate" 2>/dev/null | head -1)
    if [ -n "$was" ] && [ "$was" != "$GF_VENV" ] &&
        [ "$(cd "$was" 2>/dev/null && pwd -P)" != "$(cd "$GF_VENV" && pwd -P)" ]; then
        gf_die "$GF_VENV was made for $was (the checkout moved; its programs point there): remove it: rm -rf $GF_VENV"
    fi
}

# gf_usage [FILE]: the usage of FILE (default: the running script), its
# header comment without the "#": the comment lines after the shebang and
# the licence line, up to the first line of code.
gf_usage() {
    awk 'NR == 1 && /^#!/ { next }
         /SPDX-License-Identifier/ { next }
         /^#/ { sub(/^# ?/, ""); print; next }
         { exit }' "${1:-$0}"
}

# -h or --help anywhere on the command line of a script that sources this
# file: its usage on stdout, exit 0, and nothing else (before any check,
# build or install).
if [ "${BASH_SOURCE[1]:-}" = "$0" ]; then
    for gf_arg in "$@"; do
        case $gf_arg in
        -h | --help)
            gf_usage
            exit 0
            ;;
        esac
    done
    unset gf_arg
fi

# Every script that sources this file checks build/ first.
gf_check_build "$@"
