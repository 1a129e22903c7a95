# SPDX-License-Identifier: BSD-3-Clause
# cdpr_json_um(VALUE OUT): a non-negative JSON number of metres (as cdpr-sim's summary.json
# writes it, no exponent) as whole micrometres in OUT. CMake has no floating-point comparison;
# check_laps.cmake and check_eight_circle.cmake compare these.
function(cdpr_json_um value out)
    string(FIND "${value}" "e" has_e)
    if(NOT has_e EQUAL -1)
        message(FATAL_ERROR "unexpected number format: ${value}")
    endif()
    string(REGEX MATCH "^([0-9]+)\\.?([0-9]*)" _ "${value}")
    set(int "${CMAKE_MATCH_1}")
    string(SUBSTRING "${CMAKE_MATCH_2}000000" 0 6 frac)
    math(EXPR um "${int} * 1000000 + 1${frac} - 1000000")
    set(${out} ${um} PARENT_SCOPE)
endfunction()
