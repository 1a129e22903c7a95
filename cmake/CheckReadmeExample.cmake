# SPDX-License-Identifier: BSD-3-Clause
# Fails unless README.md's core example is the compiled one: the first ```c block after the
# heading "## Using the core" must be byte-identical to the lines between "/* [readme] */" and
# "/* [/readme] */" of examples/quickstart.c (markers excluded). On a difference it names the
# first line that differs, with both versions.
#
# Usage: cmake -DREADME=<README.md> -DSOURCE=<quickstart.c> -P CheckReadmeExample.cmake

cmake_minimum_required(VERSION 3.25)

if(NOT README OR NOT SOURCE)
    message(FATAL_ERROR "usage: cmake -DREADME=<README.md> -DSOURCE=<file.c> -P "
                        "${CMAKE_CURRENT_LIST_FILE}")
endif()
foreach(f "${README}" "${SOURCE}")
    if(NOT EXISTS "${f}")
        message(FATAL_ERROR "${f} does not exist")
    endif()
endforeach()

# Text between the first occurrence of `begin` (searched from `from`) and the next `end`.
function(cdpr_between text from begin end out_var what)
    string(FIND "${text}" "${from}" at)
    if(at EQUAL -1)
        message(FATAL_ERROR "${what}: no '${from}'")
    endif()
    string(SUBSTRING "${text}" ${at} -1 text)
    string(FIND "${text}" "${begin}" b)
    if(b EQUAL -1)
        message(FATAL_ERROR "${what}: no '${begin}' after '${from}'")
    endif()
    string(LENGTH "${begin}" blen)
    math(EXPR b "${b} + ${blen}")
    string(SUBSTRING "${text}" ${b} -1 text)
    string(FIND "${text}" "${end}" e)
    if(e EQUAL -1)
        message(FATAL_ERROR "${what}: '${begin}' is never closed by '${end}'")
    endif()
    # Keep the newline that ends the last line of the region.
    math(EXPR e "${e} + 1")
    string(SUBSTRING "${text}" 0 ${e} text)
    set(${out_var} "${text}" PARENT_SCOPE)
endfunction()

file(READ "${README}" readme)
file(READ "${SOURCE}" source)
cdpr_between("${readme}" "\n## Using the core\n" "\n```c\n" "\n```\n" shown "${README}")
cdpr_between("${source}" "/* [readme] */\n" "/* [readme] */\n" "\n/* [/readme] */\n" code
             "${SOURCE}")

if(shown STREQUAL code)
    string(LENGTH "${code}" n)
    message(STATUS "README.md's core example equals the [readme] region of ${SOURCE} (${n} bytes)")
    return()
endif()

# Find the first differing line (string(FIND) per line: the texts contain ';', so no lists).
set(line 1)
while(TRUE)
    string(FIND "${shown}" "\n" a)
    string(FIND "${code}" "\n" b)
    if(a EQUAL -1)
        set(la "${shown}")
    else()
        string(SUBSTRING "${shown}" 0 ${a} la)
    endif()
    if(b EQUAL -1)
        set(lb "${code}")
    else()
        string(SUBSTRING "${code}" 0 ${b} lb)
    endif()
    if(NOT la STREQUAL lb OR a EQUAL -1 OR b EQUAL -1)
        break()
    endif()
    math(EXPR a "${a} + 1")
    math(EXPR b "${b} + 1")
    string(SUBSTRING "${shown}" ${a} -1 shown)
    string(SUBSTRING "${code}" ${b} -1 code)
    math(EXPR line "${line} + 1")
endwhile()
message(FATAL_ERROR "README.md's core example differs from the [readme] region of ${SOURCE} "
                    "at line ${line} of the block:\n  README.md: '${la}'\n  quickstart.c: '${lb}'\n"
                    "Copy the region between the markers into README.md's ```c block.")
