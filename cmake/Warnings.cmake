# SPDX-License-Identifier: BSD-3-Clause
# cdpr_strict_warnings(<target>)
#
# Warnings for our own code only (PRIVATE): third-party targets such as Unity and
# lcm-gen output are built without them. -Werror only with CDPR_WERROR: ON by default when
# cdpr is the top-level project (and set in every preset CI uses), OFF when cdpr, or lib/core
# alone, is added to another build with add_subdirectory, so a consumer's newer compiler
# with new warnings does not break the consumer's build.
if(NOT DEFINED CDPR_WERROR)
    if(PROJECT_NAME STREQUAL "cdpr" AND PROJECT_IS_TOP_LEVEL)
        set(_cdpr_werror_default ON)
    else()
        set(_cdpr_werror_default OFF)
    endif()
    option(CDPR_WERROR "Treat warnings as errors in cdpr's own targets" ${_cdpr_werror_default})
    unset(_cdpr_werror_default)
endif()

function(cdpr_strict_warnings target)
    target_compile_options(${target} PRIVATE
        -Wall
        -Wextra
        -Wpedantic
        -Wconversion
        -Wdouble-promotion
        -Wfloat-equal
        -Wshadow
        -Wundef
        -Wcast-align
        -Wstrict-prototypes
        -Wmissing-prototypes)
    if(CDPR_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()
