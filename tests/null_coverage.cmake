# SPDX-License-Identifier: MIT
# Fails unless tests/test_null.c calls every function declared in
# include/gaussfilt/*.h: a public function added later needs its NULL
# cases there. Run by ctest as `null_coverage`:
#   cmake -DGF_ROOT=<source dir> -P null_coverage.cmake
file(GLOB headers "${GF_ROOT}/include/gaussfilt/*.h")
file(READ "${GF_ROOT}/tests/test_null.c" test_src)
set(missing "")
foreach(h ${headers})
    file(READ "${h}" text)
    # A declaration: a line opening with a type and a gf_ name, then "(".
    string(REGEX MATCHALL "\n[a-z_0-9 ]+[ *]gf_[a-z0-9_]+\\(" decls "${text}")
    foreach(d ${decls})
        string(REGEX MATCH "gf_[a-z0-9_]+\\($" fn "${d}")
        string(REGEX REPLACE "\\($" "" fn "${fn}")
        if(fn MATCHES "^gf_(angle_wrap|exp|log|atan2|status_str)$")
            continue() # no pointer argument
        endif()
        string(FIND "${test_src}" "${fn}(" at)
        if(at EQUAL -1)
            list(APPEND missing "${fn}")
        endif()
    endforeach()
endforeach()
if(missing)
    message(FATAL_ERROR "test_null.c has no NULL case for: ${missing}")
endif()
