#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage lcm: the LCM message types, filter node and simulators (sim/),
# built against PyPI lcm 1.5 in .venv, and their tests: encode/decode of
# every type, the node's handling (duplicates, order, malformed, non-finite,
# track limit), its models and edges (configuration and its errors' lines,
# linear models of any size, model_t, range-bearing, channel spelling,
# sequence resync, PF no_summary, --strict, other nodes' beliefs), its UKF3
# and PF3 robot filters in process, memq:// in process, and real processes
# over udpm (Tables 1.1, 2.1, 4.2 from the wire, malformed packets,
# exercise 4 through EKF, UKF and PF nodes, log replay, configured car,
# robot and linear (n = 4, 6) nodes' NEES/NIS consistency and scripts/nees
# on their logs, a run-time model, --strict, two nodes on one track,
# docs/node.md's quick start as written, refusals and the kernel's drops
# never in silence, the Python example on a replayed
# log, the Java types decoding a demo-like log and lcm-spy's plugin naming
# its codes, a generated model's beliefs byte for byte those of the
# package's gaussfilt.float64.EKF, so the package is installed here too),
# in a private network namespace when root; and scripts/nees,
# scripts/plot and examples/beliefs.py on logs a node replayed (lcm_tools).
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
. "$(dirname "$0")/../lcm.sh"
cd "$GF_ROOT"

if [ "$(id -u)" -eq 0 ]; then
    gf_apt default-jdk-headless # javac, jar: the Java types jar
elif ! command -v javac >/dev/null; then
    echo "lcm: no JDK here: the Java types jar and its test are skipped" \
        "(sudo apt-get install default-jdk-headless)"
fi
# beliefs.py --plot; codegen; the package's build requirement (numpy too)
gf_lcm_setup 'matplotlib>=3.5' 'numpy>=1.21' 'sympy>=1.9' 'scikit-build-core>=1.0' 'cmake>=3.26'
# the package of this checkout (the generated model's beliefs against
# gaussfilt.float64.EKF), built offline as the python stage builds it
gf_log "lcm: pip install ./python (offline, into $GF_VENV)"
"$GF_VENV/bin/python" -m pip install -q --disable-pip-version-check \
    --no-build-isolation --no-index --force-reinstall --no-deps ./python ||
    gf_die "pip install ./python failed"
gf_log "lcm: configure and build sim/ (LCM from $GF_LCM_CMAKE_DIR)"
gf_lcm_build "$GF_BUILD/sim"
gf_log "lcm: ctest (message types, node, models, memq, udpm)"
gf_ctest "$GF_BUILD/sim" -R '^lcm_'
