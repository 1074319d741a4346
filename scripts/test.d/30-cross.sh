#!/usr/bin/env bash
# Cross-builds of the core, warnings as errors, for every firmware target
# (Cortex-M4F, Cortex-M0+, RV32IMAFC) in float and double, and the link
# check: a minimal image running KF2 and EKF3 pulls in no malloc, free,
# printf or exit. At -Os, as firmware projects build.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
. "$GF_ROOT/scripts/firmware.sh"

for target in $GF_FW_TARGETS; do
    for prec in float double; do
        gf_log "cross: $target ($prec)"
        dir=$(gf_fw_build "$target" "$prec" | tail -1)
        "$(gf_fw_prefix "$target")size" "$dir/gaussfilt/libgaussfilt.a" |
            awk 'NR == 1 || /obj/'
        gf_fw_link_check "$target" "$dir"
    done
done
