# Shared by the scripts in scripts/: logging, installing what is missing,
# the project's Python venv, and ctest with a running tally. Sourced, not run.

GF_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
GF_BUILD=${GF_BUILD:-$GF_ROOT/build}
GF_VENV=${GF_VENV:-$GF_ROOT/.venv}
GF_TALLY=${GF_TALLY:-$GF_BUILD/.tally}

gf_log() { printf '\n==> %s\n' "$*"; }
gf_die() { printf 'error: %s\n' "$*" >&2; exit 1; }

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
        gf_die "missing Debian packages: ${missing[*]}
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
