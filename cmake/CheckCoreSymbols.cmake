# SPDX-License-Identifier: BSD-3-Clause
# Fails if the core library (or lib/control, which keeps the same rules) references a symbol it must never need: heap allocation, stdio,
# GSL (GPL-3, host only), LCM or threads. The core must stay allocation-free and portable to
# bare-metal firmware, and this catches a stray call before it reaches a target.
#
# Usage: cmake -DNM=<nm> -DLIB=<libcdpr_core.a> -P CheckCoreSymbols.cmake

if(NOT NM OR NOT LIB)
    message(FATAL_ERROR "usage: cmake -DNM=<nm> -DLIB=<library> -P ${CMAKE_CURRENT_LIST_FILE}")
endif()
if(NOT EXISTS "${LIB}")
    message(FATAL_ERROR "${LIB} does not exist (build cdpr_core first)")
endif()

# One name per line (POSIX output: "<name> U"), so each line can be matched whole.
execute_process(
    COMMAND "${NM}" -u --format=posix "${LIB}"
    OUTPUT_VARIABLE undefined
    RESULT_VARIABLE nm_result)
if(NOT nm_result EQUAL 0)
    message(FATAL_ERROR "${NM} -u ${LIB} failed (${nm_result})")
endif()

set(forbidden_regex
    "^(malloc|calloc|realloc|free|printf|fprintf|puts|fopen|gsl_.*|lcm_.*|pthread_.*) U")

string(REPLACE "\n" ";" lines "${undefined}")
set(bad "")
foreach(line IN LISTS lines)
    if(line MATCHES "${forbidden_regex}")
        list(APPEND bad "${CMAKE_MATCH_1}")
    endif()
endforeach()

if(bad)
    list(REMOVE_DUPLICATES bad)
    list(JOIN bad ", " bad_text)
    get_filename_component(_name "${LIB}" NAME)
    message(FATAL_ERROR "${_name} references forbidden symbols: ${bad_text}")
endif()
get_filename_component(_name "${LIB}" NAME)
message(STATUS "${_name}: no forbidden undefined symbols")
