# SPDX-License-Identifier: MIT
# cmake -DNM=... -DOBJCOPY=... -DIN=lib.a -DOUT=lib.a -P rename_float.cmake
# Copies the archive IN to OUT with every defined gf_ symbol renamed gff_
# (definitions and the references to them), so a float copy of the core can
# be linked beside a double one.
execute_process(COMMAND ${NM} --defined-only ${IN}
                OUTPUT_VARIABLE syms RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "nm ${IN} failed")
endif()
# (whole names only: a local clone such as gf_rng_normal.part.0 is not a
# second gf_rng_normal; and each name once, since objcopy refuses a name
# listed twice and a static inline helper of src/gf_internal.h left out of
# line is defined, locally, in every object that uses it)
string(REGEX MATCHALL "[^\n ]+ [A-Za-z] gf_[A-Za-z0-9_]+\n" lines "${syms}\n")
set(names "")
foreach(line IN LISTS lines)
    string(REGEX REPLACE ".* gf_([A-Za-z0-9_]+)\n" "\\1" name "${line}")
    list(APPEND names "${name}")
endforeach()
list(REMOVE_DUPLICATES names)
set(map "")
foreach(name IN LISTS names)
    string(APPEND map "gf_${name} gff_${name}\n")
endforeach()
if(map STREQUAL "")
    message(FATAL_ERROR "no gf_ symbols in ${IN}")
endif()
file(WRITE ${OUT}.syms "${map}")
execute_process(COMMAND ${OBJCOPY} --redefine-syms=${OUT}.syms ${IN} ${OUT}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "objcopy --redefine-syms failed on ${IN}")
endif()
