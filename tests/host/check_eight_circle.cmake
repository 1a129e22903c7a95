# SPDX-License-Identifier: BSD-3-Clause
# Regression guard of scenarios/eight-circle.yaml (ctest eight_circle): reads the summary.json
# that cdpr-sim wrote to DIR. Loose guards around the measured run (docs/validation.md §6,
# "The eight-cable robot in closed loop": lap 1 0.704 m with the 1.47 m start offset, lap 2
# 0.339 m; every feed-forward IK of the distribution solved), not targets:
#   status ok, ik_failures 0, 2 laps, lap 2 <= 0.5 m and lap 2 <= 0.7 x lap 1.
#   cmake -DDIR=... -P check_eight_circle.cmake
include(${CMAKE_CURRENT_LIST_DIR}/json_um.cmake)
file(READ "${DIR}/summary.json" j)
string(JSON status GET "${j}" status)
string(JSON ik GET "${j}" ik_failures)
string(JSON n LENGTH "${j}" lap_rms_m)
set(fail "")
if(NOT status STREQUAL "ok")
    string(APPEND fail " status ${status};")
endif()
if(NOT ik EQUAL 0)
    string(APPEND fail " ${ik} feed-forward IK failures;")
endif()
if(NOT n EQUAL 2)
    string(APPEND fail " ${n} laps, not 2;")
else()
    string(JSON lap1 GET "${j}" lap_rms_m 0)
    string(JSON lap2 GET "${j}" lap_rms_m 1)
    cdpr_json_um("${lap1}" lap1_um)
    cdpr_json_um("${lap2}" lap2_um)
    if(lap2_um GREATER 500000)
        string(APPEND fail " lap 2 RMS ${lap2} m > 0.5 m;")
    endif()
    math(EXPR bound "${lap1_um} * 7 / 10")
    if(lap2_um GREATER bound)
        string(APPEND fail " lap 2 RMS ${lap2} m > 0.7 x lap 1 (${lap1} m);")
    endif()
endif()
if(fail)
    message(FATAL_ERROR "eight-circle:${fail}")
endif()
message(STATUS "eight-circle: lap 1 ${lap1} m, lap 2 ${lap2} m, no IK failure")
