#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The golden tests on an emulated Cortex-M4F: every tests/test_*.c, built
# unchanged for QEMU's mps2-an386 (float build, newlib + semihosting) and
# run from ctest. cmocka is not packaged for arm-none-eabi, so its source
# comes from Debian's source package (the deb-src entry is added if the
# machine has none) and is built for the target by firmware/CMakeLists.txt.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
. "$GF_ROOT/scripts/firmware.sh"

gf_apt qemu-system-arm xz-utils

# cmocka's source, unpacked into $GF_BUILD/cmocka-src (not committed).
src="$GF_BUILD/cmocka-src"
if [ ! -f "$src/src/cmocka.c" ]; then
    gf_log "qemu: fetching cmocka's Debian source package"
    dl="$GF_BUILD/cmocka-dl"
    rm -rf "$dl" && mkdir -p "$dl"
    if ! (cd "$dl" && apt-get source --download-only cmocka) >/dev/null 2>&1; then
        [ "$(id -u)" -eq 0 ] || gf_skip "cmocka's source needs a deb-src line for
       the Debian archive; as root: add one (Types: deb-src) and apt-get update"
        gf_log "qemu: adding a deb-src entry for the Debian archive"
        . /etc/os-release
        cat >/etc/apt/sources.list.d/gaussfilt-deb-src.sources <<SRC
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: ${VERSION_CODENAME:-bookworm}
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
        apt-get update -q >/dev/null || gf_die "apt-get update failed"
        (cd "$dl" && apt-get source --download-only cmocka) >/dev/null 2>&1 ||
            gf_die "apt-get source --download-only cmocka failed"
    fi
    orig=$(ls "$dl"/cmocka_*.orig.tar.* | head -1)
    [ -n "$orig" ] || gf_die "no cmocka orig tarball in $dl"
    rm -rf "$src" && mkdir -p "$src"
    tar -xf "$orig" -C "$src" --strip-components=1
    grep -Eq 'project\(cmocka VERSION 1\.1\.' "$src/CMakeLists.txt" ||
        gf_die "cmocka's source is not version 1.x; firmware/cmocka/config.h is for 1.1"
fi

# The firmware build: -Os, as firmware projects build (the same code as
# any other optimisation level).
gf_log "qemu: the tests on mps2-an386 (Cortex-M4F, float, -Os)"
dir=$(gf_fw_build cortex-m4f float -DGF_FW_CMOCKA_DIR="$src" | tail -1)
gf_ctest "$dir"
