#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cmake --install of the sim build into a scratch prefix: every program is
# installed, and `PROGRAM --help` says what it does, its usage and an
# example, and exits 0; gf_node's usage is docs/demo.md's, and the fields
# docs/node.md's diagnostics row names are node_status_t's; the types and
# the examples are there too.
#
#   install.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1 work=$2
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work.log" 2>&1 ||
    { cat "$work.log"; echo "install: cmake --install failed" >&2; exit 1; }
for p in gf_node gf_sim gf_setmodel gf_check gf_logcmp gf_ex4check; do
    exe=$work/prefix/bin/$p
    [ -x "$exe" ] || { echo "install: no $exe" >&2; exit 1; }
    out=$("$exe" --help) || { echo "install: $p --help exit status $?" >&2; exit 1; }
    grep -q "^$p: " <<<"$out" || { echo "install: $p --help does not say what it does" >&2; exit 1; }
    grep -q "usage: $p" <<<"$out" || { echo "install: $p --help has no usage" >&2; exit 1; }
    grep -q "^example" <<<"$out" || { echo "install: $p --help has no example" >&2; exit 1; }
    echo "install: $p --help ok ($(wc -l <<<"$out") lines)"
done
# gf_node's usage as docs/demo.md prints it, and --queue as docs/node.md
# says it: the node's own input queue (not LCM's)
docs=$(cd "$(dirname "$0")/../.." && pwd)/docs
usage=$("$work/prefix/bin/gf_node" --help | sed -n '/^usage: gf_node/,/^$/p' |
    sed -e 's/^usage: //' -e 's/^ *//' | tr -s ' \n' ' ')
documented=$(sed -n '/^    gf_node \[--config/,/^$/p' "$docs/demo.md" |
    sed -e 's/^ *//' | tr -s ' \n' ' ')
[ -n "$usage" ] && [ "$usage" = "$documented" ] ||
    { printf 'install: gf_node --help usage: %s\n docs/demo.md: %s\n' "$usage" "$documented" >&2; exit 1; }
"$work/prefix/bin/gf_node" --help | grep -q "^  --queue N  *the node's input queue, in messages" ||
    { echo "install: gf_node --help: --queue is not the node's input queue" >&2; exit 1; }
grep -q "own input queue" "$docs/node.md" ||
    { echo "install: docs/node.md no longer says what --queue is" >&2; exit 1; }
# docs/node.md's side-by-side with robot_localization: every field its
# diagnostics row names is one of node_status_t's (or its tracks', results')
types=$(cd "$(dirname "$0")/../.." && pwd)/lcm_types
row=$(grep '^| `diagnostic_updater`' "$docs/node.md") ||
    { echo "install: docs/node.md has no diagnostics row" >&2; exit 1; }
fields=$(grep -o '`[a-z_]*`' <<<"$row" | tr -d '`' | grep -Ev '^(diagnostic_updater|node_status_t)$' | sort -u)
[ "$(wc -l <<<"$fields")" -ge 10 ] || { echo "install: the diagnostics row names too few fields" >&2; exit 1; }
for f in $fields; do
    grep -Eq "^ +[a-z_0-9]+ +$f(\[[a-z]+\])?;" "$types"/node_status_t.lcm \
        "$types"/track_status_t.lcm "$types"/node_results_t.lcm ||
        { echo "install: docs/node.md's diagnostics row names $f, no field of node_status_t" >&2; exit 1; }
done
grep -q 'GF_NODE_STATUS' <<<"$row" || { echo "install: the diagnostics row does not name GF_NODE_STATUS" >&2; exit 1; }
for f in share/gaussfilt/lcm_types/model_t.lcm share/gaussfilt/examples/node.conf \
    share/gaussfilt/examples/beliefs.py; do
    [ -f "$work/prefix/$f" ] || { echo "install: no $f" >&2; exit 1; }
done
if [ -f "$build/sim/gaussfilt_lcm_types.jar" ]; then
    [ -f "$work/prefix/share/java/gaussfilt_lcm_types.jar" ] ||
        { echo "install: the Java types jar is not installed" >&2; exit 1; }
fi
# the installed node runs the installed configuration
"$work/prefix/bin/gf_sim" --url "file://$work/in.lcmlog?mode=w" \
    --config "$work/prefix/share/gaussfilt/examples/node.conf" --model rover \
    --track 200 --steps 20 --session 1 >/dev/null
"$work/prefix/bin/gf_node" --config "$work/prefix/share/gaussfilt/examples/node.conf" \
    --url "file://$work/in.lcmlog?speed=0" --out-url "file://$work/out.lcmlog?mode=w" |
    grep -q 'summary received=40 applied=40 ' ||
    { echo "install: the installed node did not apply the rover's 40 inputs" >&2; exit 1; }
echo "install: passed"
