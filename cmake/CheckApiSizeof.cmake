# SPDX-License-Identifier: BSD-3-Clause
# Fails unless the sizeof table of docs/api.md matches the build: PROG prints `name bytes`
# lines (tests/docs/api_sizeof.c); the table between the lines `<!-- sizeof:begin -->` and
# `<!-- sizeof:end -->` has one row per object, `| `name` | bytes |` (digits, optionally
# grouped with spaces, as "221 624"). Every printed object needs a row with the same size, and
# every row an object. Each difference is named; the test fails if there is any.
#
# Usage: cmake -DPROG=<cdpr_api_sizeof> -DDOC=<docs/api.md> -P CheckApiSizeof.cmake

cmake_minimum_required(VERSION 3.25)

if(NOT PROG OR NOT DOC)
    message(FATAL_ERROR "usage: cmake -DPROG=<program> -DDOC=<api.md> -P "
                        "${CMAKE_CURRENT_LIST_FILE}")
endif()
if(NOT EXISTS "${DOC}")
    message(FATAL_ERROR "${DOC} does not exist")
endif()

execute_process(COMMAND "${PROG}" OUTPUT_VARIABLE printed RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${PROG} failed (${rc})")
endif()

# The table rows (names and sizes contain no ';', so lists of lines are safe here).
file(STRINGS "${DOC}" doc_lines)
set(inside 0)
set(seen_begin 0)
set(table_names "")
foreach(line IN LISTS doc_lines)
    if(line STREQUAL "<!-- sizeof:begin -->")
        set(inside 1)
        set(seen_begin 1)
    elseif(line STREQUAL "<!-- sizeof:end -->")
        set(inside 0)
    elseif(inside AND line MATCHES "^\\| `([^`]+)` \\| ([0-9 ]+) \\|")
        set(name "${CMAKE_MATCH_1}")
        string(REPLACE " " "" bytes "${CMAKE_MATCH_2}")
        if(DEFINED doc_${name})
            message(SEND_ERROR "${DOC}: row `${name}` appears twice in the sizeof table")
        endif()
        set(doc_${name} "${bytes}")
        list(APPEND table_names "${name}")
    endif()
endforeach()
if(NOT seen_begin)
    message(FATAL_ERROR "${DOC}: no '<!-- sizeof:begin -->' line")
endif()
if(NOT table_names)
    message(FATAL_ERROR "${DOC}: no '| `name` | bytes |' rows between the sizeof markers")
endif()

string(REPLACE "\n" ";" printed_lines "${printed}")
set(bad 0)
set(n 0)
foreach(line IN LISTS printed_lines)
    if(line STREQUAL "")
        continue()
    endif()
    if(NOT line MATCHES "^([^ ]+) ([0-9]+)$")
        message(FATAL_ERROR "${PROG}: unexpected output line '${line}'")
    endif()
    set(name "${CMAKE_MATCH_1}")
    set(bytes "${CMAKE_MATCH_2}")
    math(EXPR n "${n} + 1")
    if(NOT DEFINED doc_${name})
        message(SEND_ERROR "${DOC}: sizeof table has no row `${name}` (this build: ${bytes} bytes)")
        set(bad 1)
    elseif(NOT doc_${name} STREQUAL bytes)
        message(SEND_ERROR "${DOC}: sizeof row `${name}` says ${doc_${name}} bytes, "
                           "this build has ${bytes}")
        set(bad 1)
    endif()
    list(REMOVE_ITEM table_names "${name}")
endforeach()
foreach(name IN LISTS table_names)
    message(SEND_ERROR "${DOC}: sizeof row `${name}` names no object ${PROG} prints")
    set(bad 1)
endforeach()
if(bad)
    message(FATAL_ERROR "docs/api.md's sizeof table does not match this build (rows above)")
endif()
message(STATUS "docs/api.md's sizeof table matches all ${n} objects of this build")
