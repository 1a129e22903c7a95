# cdpr_strict_warnings(<target>)
#
# Warnings for our own code only (PRIVATE): third-party targets such as Unity and
# lcm-gen output are built without them.
function(cdpr_strict_warnings target)
    target_compile_options(${target} PRIVATE
        -Wall
        -Wextra
        -Wpedantic
        -Werror
        -Wconversion
        -Wdouble-promotion
        -Wfloat-equal
        -Wshadow
        -Wundef
        -Wcast-align
        -Wstrict-prototypes
        -Wmissing-prototypes)
endfunction()
