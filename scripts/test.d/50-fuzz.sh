# Bounded fuzzing (about a minute per fuzz target source): libFuzzer with
# ASan + UBSan on the core API, gf_real double (40 s) and float (20 s),
# starting from the committed seed corpus. The long run is scripts/fuzz.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"
bash scripts/fuzz --time "${GF_FUZZ_SECONDS:-40}" core-double
bash scripts/fuzz --time "$(( (${GF_FUZZ_SECONDS:-40} + 1) / 2 ))" core-float
