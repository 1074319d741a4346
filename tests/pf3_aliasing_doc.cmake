# SPDX-License-Identifier: MIT
# Fails unless include/gaussfilt/pf3.h tells the caller of gf_pf3_predict
# that u must not point into the particle array (the prediction reads u
# again for every particle while it rewrites them, and cannot copy a u
# whose length only the callback knows). Run by ctest as
# `pf3_aliasing_documented`:
#   cmake -DGF_ROOT=<source dir> -P pf3_aliasing_doc.cmake
file(READ "${GF_ROOT}/include/gaussfilt/pf3.h" text)
string(REGEX REPLACE "\n// " " " text "${text}")
string(FIND "${text}" "u must not point into the particle array" at)
if(at EQUAL -1)
    message(FATAL_ERROR "pf3.h does not say that gf_pf3_predict's u must "
        "not point into the particle array")
endif()
