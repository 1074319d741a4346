# SPDX-License-Identifier: MIT
# Shared by the firmware stages (scripts/test.d/3*-*.sh) and
# scripts/footprint: the cross targets, their toolchains, and building the
# firmware project for one of them. Sourced after lib.sh, not run.

# The targets: name, toolchain file (cmake/toolchain-NAME.cmake), the binutils
# prefix, and the Debian packages that provide the toolchain and C library.
GF_FW_TARGETS="cortex-m4f cortex-m0plus riscv32"

gf_fw_prefix() {
    case $1 in
    riscv32) echo riscv64-unknown-elf- ;;
    *) echo arm-none-eabi- ;;
    esac
}

gf_fw_packages() {
    case $1 in
    riscv32) echo gcc-riscv64-unknown-elf picolibc-riscv64-unknown-elf ;;
    *) echo gcc-arm-none-eabi libnewlib-arm-none-eabi ;;
    esac
}

# gf_fw_build TARGET PREC [cmake -D args...]: configures and builds the
# firmware project (the library, its .ci call graph files and the footprint
# images) for TARGET in PREC (float or double), warnings as errors, at -Os
# (GF_FW_OPT=O2: at -O2 instead). Prints the build directory's path on the
# last line. GF_FW_VARIANT=NAME builds in a directory of its own.
gf_fw_build() {
    local target=$1 prec=$2 single=OFF
    shift 2
    [ "$prec" = float ] && single=ON
    local opt=(-DCMAKE_BUILD_TYPE=MinSizeRel)
    case ${GF_FW_OPT:-Os} in
    Os) ;;
    O2) opt=(-DCMAKE_BUILD_TYPE=Release "-DCMAKE_C_FLAGS_RELEASE=-O2 -DNDEBUG") ;;
    *) gf_die "GF_FW_OPT is '$GF_FW_OPT': Os or O2" ;;
    esac
    # shellcheck disable=SC2046
    gf_apt cmake make $(gf_fw_packages "$target") >&2
    local dir="$GF_BUILD/fw-$target-$prec${GF_FW_VARIANT:+-$GF_FW_VARIANT}"
    cmake -S "$GF_ROOT/firmware" -B "$dir" \
        -DCMAKE_TOOLCHAIN_FILE="$GF_ROOT/cmake/toolchain-$target.cmake" \
        "${opt[@]}" -DGAUSSFILT_WERROR=ON \
        -DGAUSSFILT_SINGLE_PRECISION=$single "$@" \
        >/dev/null ||
        gf_die "configuring the firmware build for $target ($prec) failed"
    cmake --build "$dir" --parallel 2 >&2 ||
        gf_die "the firmware build for $target ($prec) failed"
    echo "$dir"
}

# The symbols a filter image must not contain: allocation, stdio, exit.
GF_FW_FORBIDDEN='malloc|_malloc_r|calloc|_calloc_r|realloc|_realloc_r|free|_free_r|printf|_printf_r|vfprintf|_vfprintf_r|iprintf|puts|putchar|exit|_exit|abort|atexit'

# The minimal images (firmware/min_image.c) that run filters.
GF_FW_IMAGES="kf2 ekf3 kf4 kf2_ekf3"

# gf_fw_link_check TARGET DIR: no minimal image in DIR links any of
# GF_FW_FORBIDDEN, and in the float build none links double arithmetic.
# Prints what the KF2 + EKF3 image links besides the core.
gf_fw_link_check() {
    local target=$1 dir=$2 nm bad img elf single=0
    nm="$(gf_fw_prefix "$target")nm"
    grep -q 'GAUSSFILT_SINGLE_PRECISION:BOOL=ON' "$dir/CMakeCache.txt" && single=1
    for img in $GF_FW_IMAGES; do
        elf=$dir/gf_fw_$img.elf
        [ -f "$elf" ] || gf_die "$elf is missing"
        bad=$("$nm" "$elf" | awk '{print $NF}' |
            grep -Ex "$GF_FW_FORBIDDEN" | tr '\n' ' ' || true)
        [ -z "$bad" ] || gf_die "$target: gf_fw_$img links $bad"
        # In the float build a double libm call or soft-double helper means
        # a float was promoted somewhere.
        if [ $single = 1 ]; then
            bad=$("$nm" "$elf" | awk '{print $NF}' |
                grep -Ex '__aeabi_d[a-z0-9]+|__[a-z]+df[0-9]|(sin|cos|sqrt|ceil|floor|atan2|log|fabs)' |
                tr '\n' ' ' || true)
            [ -z "$bad" ] || gf_die "$target (float): double arithmetic pulled in by gf_fw_$img: $bad"
        fi
    done
    [ $single = 0 ] ||
        echo "$target (float): no double libm function or soft-double helper in any image"
    echo "$target: the images ($GF_FW_IMAGES) link no malloc/free/printf/exit;" \
        "functions in the KF2 + EKF3 image besides the core's: $("$nm" --defined-only "$dir/gf_fw_kf2_ekf3.elf" |
            awk '$2 ~ /^[Tt]$/ && $3 !~ /^(gf_|main$|Reset_Handler$|Fault_Handler$|_start$|\$)/ {print $3}' |
            sort -u | tr '\n' ' ')"
}
