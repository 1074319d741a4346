# SPDX-License-Identifier: MIT
# Shared by the arm-none-eabi toolchain files: GF_TARGET_CPU_FLAGS is set by
# the including file. Bare metal: libraries only in try_compile (no
# startup code for an executable), the sysroot is the toolchain's own.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_RANLIB arm-none-eabi-ranlib)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# -ffunction-sections/-fdata-sections let --gc-sections drop what a firmware
# image does not call.
set(CMAKE_C_FLAGS_INIT
    "${GF_TARGET_CPU_FLAGS} -ffunction-sections -fdata-sections")
# CMake passes the C flags (CPU flags included) to the link as well.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
