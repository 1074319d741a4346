# SPDX-License-Identifier: MIT
# Bounded fuzzing (about a minute per fuzz target source): libFuzzer with
# ASan + UBSan on the core API, gf_real double (40 s) and float (20 s), and
# on the LCM node's message handling (60 s), starting from the committed
# seed corpora. The long run is scripts/fuzz.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
s=${GF_FUZZ_SECONDS:-40}
bash scripts/fuzz --time "$s" core-double
bash scripts/fuzz --time "$(( (s + 1) / 2 ))" core-float
bash scripts/fuzz --time "$(( s * 3 / 2 ))" node
