# SPDX-License-Identifier: MIT
# Cross-compiling for an Arm Cortex-M4F (single-precision FPU, hard-float
# ABI) with Debian's gcc-arm-none-eabi and newlib. Use with the float build:
#   cmake -S . -B build/m4f -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-cortex-m4f.cmake \
#         -DCMAKE_BUILD_TYPE=MinSizeRel -DGAUSSFILT_SINGLE_PRECISION=ON \
#         -DGAUSSFILT_BUILD_TESTS=OFF -DGAUSSFILT_BUILD_EXAMPLES=OFF
set(GF_TARGET_CPU_FLAGS
    "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
