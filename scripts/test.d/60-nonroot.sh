#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/test as a user who is not root, in a throwaway copy of the tree
# (under /tmp, owned by that user, deleted afterwards). Run as root, which
# creates the user (gf-nonroot) once.
#   - A build/ made by root, and a build/ configured before the checkout
#     moved: scripts/test stops, names the directory and the fix, and leaves
#     it as it was.
#   - A .venv/ made by root, and one made before the checkout moved: the
#     same for the venv.
#   - Debian packages it cannot install: the stage says "skip:" and ends
#     as skipped.
#   - scripts/test core net: core passes, net (network namespaces) is
#     skipped with a visible line, and the run still ends with
#     "scripts/test: N passed, 0 failed".
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"

[ "$(id -u)" -eq 0 ] || gf_skip "stage nonroot needs root (it creates a user)"
user=gf-nonroot
if ! id "$user" >/dev/null 2>&1; then
    gf_log "nonroot: creating the user $user"
    useradd --create-home --shell /bin/bash "$user" ||
        gf_die "useradd $user failed"
fi
home=$(getent passwd "$user" | cut -d: -f6)

tmp=$(mktemp -d /tmp/gf-nonroot.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
chmod 755 "$tmp"
copy=$tmp/gaussfilt
mkdir "$copy"
tar -C "$GF_ROOT" --exclude=./build --exclude=./.venv --exclude=./out \
    --exclude=./.git -cf - . | tar -C "$copy" -xf -
chown -R "$user:" "$copy"

# as_user DIR COMMAND: runs COMMAND in DIR as the user, in a clean
# environment; prints its output and exit status (last line: rc=N).
as_user() {
    local dir=$1
    shift
    set +e
    runuser -u "$user" -- env -i PATH=/usr/local/bin:/usr/bin:/bin \
        HOME="$home" LANG=C.UTF-8 bash -c "cd '$dir' && $*" 2>&1
    echo "rc=$?"
    set -e
}

# expect OUTPUT RC PATTERN WHAT: the output ends with rc=RC and matches
# PATTERN (grep -E).
expect() {
    local out=$1 rc=$2 pattern=$3 what=$4
    tail -1 <<<"$out" | grep -qx "rc=$rc" ||
        gf_die "$what: expected exit $rc, got $(tail -1 <<<"$out"); output:
$out"
    grep -qE "$pattern" <<<"$out" ||
        gf_die "$what: output does not match '$pattern':
$out"
    echo "$what: $(grep -E "$pattern" <<<"$out" | head -1)"
}

gf_log "nonroot: a build/ made by root"
mkdir -p "$copy/build/core-double"
out=$(as_user "$copy" scripts/test core)
expect "$out" 1 "build was made by another user \(root.*\): remove it" "build/ of root"
[ -d "$copy/build/core-double" ] && [ "$(stat -c %U "$copy/build")" = root ] ||
    gf_die "build/ of root was changed"
rm -rf "$copy/build"

gf_log "nonroot: a build/ configured before the checkout moved"
out=$(as_user "$copy" cmake -S . -B build/core-double -DGAUSSFILT_BUILD_TESTS=OFF)
expect "$out" 0 "Build files have been written" "configure as $user"
mv "$copy" "$tmp/moved"
out=$(as_user "$tmp/moved" scripts/test core)
expect "$out" 1 "build/ was configured for $copy.*: remove it" "moved build/"
grep -q "CMAKE_CACHEFILE_DIR:INTERNAL=$copy/build/core-double" \
    "$tmp/moved/build/core-double/CMakeCache.txt" || gf_die "the moved build/ was rebuilt over"
mv "$tmp/moved" "$copy"
rm -rf "$copy/build"

gf_log "nonroot: a .venv/ made by root, and one made before the checkout moved"
python3 -m venv --without-pip "$copy/.venv"
out=$(as_user "$copy" ". scripts/lib.sh && gf_venv")
expect "$out" 1 "\.venv was made by another user \(root\): remove it" ".venv/ of root"
rm -rf "$copy/.venv"
out=$(as_user "$copy" "python3 -m venv --without-pip .venv")
expect "$out" 0 "" "python3 -m venv as $user"
mv "$copy" "$tmp/moved"
out=$(as_user "$tmp/moved" ". scripts/lib.sh && gf_venv")
expect "$out" 1 "\.venv was made for $copy/\.venv .*remove it" "moved .venv/"
mv "$tmp/moved" "$copy"
rm -rf "$copy/.venv"

gf_log "nonroot: a Debian package it cannot install"
out=$(as_user "$copy" ". scripts/lib.sh && GF_STAGE=x gf_apt gaussfilt-no-such-package")
expect "$out" 77 "^skip: missing Debian packages: gaussfilt-no-such-package" "apt as $user"

gf_log "nonroot: scripts/test core net as $user"
out=$(as_user "$copy" scripts/test core net)
sed 's/^/  | /' <<<"$out" | grep -E '\[[0-9]+/[0-9]+\]|skip:|scripts/test:' || true
expect "$out" 0 "^skip: stage net needs root" "net as $user"
grep -qE "^\[2/2\] net: skipped in [0-9]+ s$" <<<"$out" ||
    gf_die "net was not reported as skipped:
$out"
last=$(sed '$d' <<<"$out" | tail -1)
grep -qE '^scripts/test: [1-9][0-9]* passed, 0 failed$' <<<"$last" ||
    gf_die "scripts/test as $user did not end with its closing line: '$last'"
echo "scripts/test core net as $user ends with: $last"
