# SPDX-License-Identifier: MIT
# Cross-compiling for an Arm Cortex-M0+ (no FPU: soft-float ABI, floating
# point in libgcc) with Debian's gcc-arm-none-eabi and newlib.
#   cmake -S . -B build/m0p -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-cortex-m0plus.cmake \
#         -DCMAKE_BUILD_TYPE=MinSizeRel -DGAUSSFILT_SINGLE_PRECISION=ON \
#         -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF
set(GF_TARGET_CPU_FLAGS "-mcpu=cortex-m0plus -mthumb -mfloat-abi=soft")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
