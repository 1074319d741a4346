#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# cmake --install of the sim build into a scratch prefix: every program is
# installed, and `PROGRAM --help` says what it does, its usage and an
# example, and exits 0; the types and the examples are there too.
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
