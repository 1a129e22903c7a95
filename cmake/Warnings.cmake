# SPDX-License-Identifier: BSD-3-Clause
# cdpr_strict_warnings(<target>)
#
# Warnings for our own code only (PRIVATE): third-party targets such as Unity and
# lcm-gen output are built without them. -Werror only with CDPR_WERROR: ON by default when
# cdpr is the top-level project (and set in every preset CI uses), OFF when cdpr, or lib/core
# alone, is added to another build with add_subdirectory, so a consumer's newer compiler
# with new warnings does not break the consumer's build.
include(${CMAKE_CURRENT_LIST_DIR}/CdprLibrary.cmake) # cdpr_top_level_option
cdpr_top_level_option(CDPR_WERROR "Treat warnings as errors in cdpr's own targets")

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
