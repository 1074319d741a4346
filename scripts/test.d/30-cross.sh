#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cross-builds of the core, warnings as errors, for every firmware target
# (Cortex-M4F, Cortex-M0+, RV32IMAFC) in float and double, and the link
# check: the minimal images (KF2, EKF3, gf_kf, KF2 + EKF3) pull in no
# malloc, free, printf or exit, and every link name carries the precision. The firmware
# project takes gaussfilt by add_subdirectory() and links no libm of its own:
# the gaussfilt target brings it.
#
# Then docs/firmware.md's vendoring routes for a Cortex-M4F, with the page's own
# text: gaussfilt configured with only the toolchain file (no cmocka, no
# option); the CMake snippet cross-built (Release and MinSizeRel); and the
# arm-none-eabi-gcc line on copied sources. Each links a bare-metal image
# (tests/consumer/bare_metal.c, firmware/startup.c, firmware/mps2-an386.ld)
# whose only libm function is sqrtf (exp, log and atan2 are the core's own).
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
        gf_check_names "$dir/gaussfilt/libgaussfilt.a" "$prec" \
            "$(gf_fw_prefix "$target")nm"
    done
done

# bare_metal_check WHAT ELF: ELF links, with libm's sqrtf in it, not its
# atan2f, logf or expf (the core's gf_atan2 and gf_log instead), and none of
# the symbols a filter image must not contain.
bare_metal_check() {
    local what=$1 elf=$2 syms bad f
    [ -f "$elf" ] || gf_die "$what: no $elf"
    syms=$(arm-none-eabi-nm "$elf" | awk '$2 ~ /^[Tt]$/ {print $3}')
    grep -qx sqrtf <<<"$syms" || gf_die "$what: sqrtf is not in the image"
    for f in gf_atan2_f32 gf_log_f32; do
        grep -qx "$f" <<<"$syms" || gf_die "$what: $f is not in the image"
    done
    for f in atan2f logf expf; do
        ! grep -qx "$f" <<<"$syms" || gf_die "$what: libm's $f is in the image"
    done
    bad=$(grep -Ex "$GF_FW_FORBIDDEN" <<<"$syms" | tr '\n' ' ' || true)
    [ -z "$bad" ] || gf_die "$what: the image links $bad"
    echo "$what: links; libm's sqrtf in the image, gf_atan2 and gf_log, not atan2f or logf; $(arm-none-eabi-size "$elf" | awk 'NR == 2 {print $1 + $2 " B of flash"}')"
}

b=$GF_BUILD/cross-vendor
rm -rf "$b"
mkdir -p "$b"
startup=$GF_ROOT/firmware/startup.c
ld=$GF_ROOT/firmware/mps2-an386.ld
m4f=$GF_ROOT/cmake/toolchain-cortex-m4f.cmake

gf_log "cross: gaussfilt configured with only a toolchain file (Cortex-M4F)"
cmake -S "$GF_ROOT" -B "$b/top" -DCMAKE_TOOLCHAIN_FILE="$m4f" >"$b/top.log" 2>&1 ||
    gf_die "cmake with only -DCMAKE_TOOLCHAIN_FILE failed (see $b/top.log)"
cmake --build "$b/top" --parallel 2 >>"$b/top.log" 2>&1 ||
    gf_die "the cross build with defaults failed (see $b/top.log)"
grep -q 'GAUSSFILT_BUILD_TESTS:BOOL=OFF' "$b/top/CMakeCache.txt" ||
    gf_die "cross-compiling: GAUSSFILT_BUILD_TESTS is not OFF by default"
echo "configured and built with defaults: tests and examples off, libgaussfilt.a built"

gf_log "cross: docs/firmware.md's CMake snippet, add_subdirectory() of a copy (Cortex-M4F)"
v=$b/snippet
mkdir -p "$v/src/gaussfilt/include"
cp "$GF_ROOT/CMakeLists.txt" "$v/src/gaussfilt/"
cp -r "$GF_ROOT/include/gaussfilt" "$v/src/gaussfilt/include/"
cp -r "$GF_ROOT/src" "$v/src/gaussfilt/"
gf_readme_block vendor-cmake >"$v/src/CMakeLists.txt"
printf '#include "%s"\n#include "%s"\n' "$GF_ROOT/tests/consumer/bare_metal.c" \
    "$startup" >"$v/src/main.c"
for type in Release MinSizeRel; do
    cmake -S "$v/src" -B "$v/$type" -DCMAKE_TOOLCHAIN_FILE="$m4f" \
        -DCMAKE_BUILD_TYPE=$type -DGAUSSFILT_SINGLE_PRECISION=ON \
        -DCMAKE_EXE_LINKER_FLAGS="-nostartfiles -T $ld --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections" \
        >"$v/$type.log" 2>&1 ||
        gf_die "the documented CMake snippet does not configure for Cortex-M4F (see $v/$type.log)"
    cmake --build "$v/$type" >>"$v/$type.log" 2>&1 ||
        gf_die "the documented CMake snippet does not build for Cortex-M4F at $type (see $v/$type.log)"
    bare_metal_check "CMake snippet, Cortex-M4F, $type" "$v/$type/app"
done

gf_log "cross: docs/firmware.md's arm-none-eabi-gcc line on copied sources"
c=$b/copied
mkdir -p "$c/gaussfilt/include"
cp -r "$GF_ROOT/include/gaussfilt" "$c/gaussfilt/include/"
cp -r "$GF_ROOT/src" "$c/gaussfilt/"
cp "$GF_ROOT/tests/consumer/bare_metal.c" "$c/main.c"
line=$(gf_readme_block vendor-cc | sed -n '/^arm-none-eabi-gcc/,/^$/p' | sed '/^$/d')
[ -n "$line" ] || gf_die "docs/firmware.md's vendor-cc block has no arm-none-eabi-gcc line"
echo "$line"
(cd "$c" && STARTUP=$startup LDSCRIPT=$ld bash -euc "$line") ||
    gf_die "the docs/firmware.md's arm-none-eabi-gcc line failed"
bare_metal_check "copied sources, the documented compiler line, Cortex-M4F" "$c/app.elf"
