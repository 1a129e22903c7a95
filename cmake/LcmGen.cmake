# SPDX-License-Identifier: BSD-3-Clause
# LCM support: find liblcm 1.3 and generate message bindings with lcm-gen at build time.
#
# cdpr_find_lcm()
#   Defines the imported target lcm::lcm (headers + liblcm) and the cache variable
#   LCM_GEN_EXECUTABLE. LCM 1.3.1 (Debian bookworm) ships no CMake package config, so this
#   uses find_path/find_library; a later LCM's lcmConfig.cmake is not needed. Fails with a
#   message naming the Debian packages when something is missing.
#
# cdpr_lcmgen(TARGET <name> FILES <a.lcm>... [PYTHON_DIR <dir>] [JAVA_JAR <file>])
#   Runs `lcm-gen -c` at build time into ${CMAKE_CURRENT_BINARY_DIR}/<name>/ and compiles the
#   generated C as the static library <name>. Consumers include "lcmtypes/<pkg>_<type>.h".
#   The struct names are read from the .lcm files at configure time (re-read when a file
#   changes), so a file may hold several structs and need not be named after them.
#   - The generated C is our own code's only exception to the strict warning set: it trips
#     -Wunused-parameter, -Wpedantic (function pointer <-> void * in the hash helpers) and
#     -Wsign-conversion (int64_t <-> uint64_t hash), so exactly those three are relaxed; its
#     include directory is a SYSTEM one for consumers.
#   - _publish/_subscribe are not generated (--c-no-pubsub): the generated subscribe
#     allocates on every message; cdpr_lcm subscribes with lcm_subscribe and decodes into
#     preallocated structs itself.
#   - PYTHON_DIR: also emit Python classes (`lcm-gen -p`) into <dir>/<pkg>/ (target
#     <name>_python, part of ALL). They only need Python's `struct` module to encode and
#     decode, not the lcm Python module.
#   - JAVA_JAR: when javac, jar and LCM's lcm.jar (Debian: liblcm-java) are found, also emit
#     Java classes, compile them against lcm.jar and pack <file> (target <name>_java, part
#     of ALL); lcm-spy decodes our channels with it on its CLASSPATH. Otherwise a STATUS
#     message says what is missing and nothing else changes.

include(${CMAKE_CURRENT_LIST_DIR}/CdprLibrary.cmake)

function(cdpr_find_lcm)
    if(TARGET lcm::lcm)
        return()
    endif()
    find_path(LCM_INCLUDE_DIR NAMES lcm/lcm.h DOC "LCM headers (Debian: liblcm-dev)")
    find_library(LCM_LIBRARY NAMES lcm DOC "liblcm (Debian: liblcm-dev)")
    find_program(LCM_GEN_EXECUTABLE NAMES lcm-gen DOC "lcm-gen (Debian: liblcm-bin)")
    if(NOT LCM_INCLUDE_DIR OR NOT LCM_LIBRARY OR NOT LCM_GEN_EXECUTABLE)
        message(FATAL_ERROR
            "CDPR_WITH_LCM=ON needs LCM: headers '${LCM_INCLUDE_DIR}', library '${LCM_LIBRARY}', "
            "lcm-gen '${LCM_GEN_EXECUTABLE}'. Install liblcm-dev and liblcm-bin "
            "(scripts/setup.sh does), or configure with -DCDPR_WITH_LCM=OFF.")
    endif()
    add_library(lcm::lcm UNKNOWN IMPORTED GLOBAL)
    set_target_properties(lcm::lcm PROPERTIES
        IMPORTED_LOCATION "${LCM_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${LCM_INCLUDE_DIR}")
    message(STATUS "LCM: ${LCM_LIBRARY}, lcm-gen: ${LCM_GEN_EXECUTABLE}")
endfunction()

function(cdpr_lcmgen)
    cmake_parse_arguments(PARSE_ARGV 0 arg "" "TARGET;PYTHON_DIR;JAVA_JAR" "FILES")
    if(NOT arg_TARGET OR NOT arg_FILES)
        message(FATAL_ERROR "cdpr_lcmgen: TARGET and FILES are required")
    endif()
    cdpr_find_lcm()

    # Names of the generated files: <package>_<struct>.{c,h} (C), <package>/<struct>.py,
    # <package>/<struct>.java. Parsed from the sources; comments are stripped first.
    set(c_sources "")
    set(c_headers "")
    set(py_files "")
    set(java_files "")
    set(out ${CMAKE_CURRENT_BINARY_DIR}/${arg_TARGET})
    foreach(file IN LISTS arg_FILES)
        set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${file})
        file(READ ${file} text)
        string(REGEX REPLACE "//[^\n]*" "" text "${text}")
        string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
        if(NOT text MATCHES "package[ \t\r\n]+([A-Za-z0-9_.]+)[ \t\r\n]*;")
            message(FATAL_ERROR "cdpr_lcmgen: ${file} has no package declaration")
        endif()
        set(package ${CMAKE_MATCH_1})
        string(REPLACE "." "_" c_package ${package})
        string(REPLACE "." "/" dir_package ${package})
        string(REGEX MATCHALL "struct[ \t\r\n]+[A-Za-z0-9_]+" structs "${text}")
        if(NOT structs)
            message(FATAL_ERROR "cdpr_lcmgen: ${file} declares no struct")
        endif()
        foreach(s IN LISTS structs)
            string(REGEX REPLACE "^struct[ \t\r\n]+" "" s "${s}")
            list(APPEND c_sources ${out}/src/${c_package}_${s}.c)
            list(APPEND c_headers ${out}/include/lcmtypes/${c_package}_${s}.h)
            list(APPEND py_files ${arg_PYTHON_DIR}/${dir_package}/${s}.py)
            list(APPEND java_files ${out}/java/${dir_package}/${s}.java)
        endforeach()
    endforeach()

    add_custom_command(
        OUTPUT ${c_sources} ${c_headers}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${out}/src ${out}/include/lcmtypes
        COMMAND ${LCM_GEN_EXECUTABLE} --c --c-no-pubsub --cinclude lcmtypes
                --c-cpath ${out}/src --c-hpath ${out}/include/lcmtypes ${arg_FILES}
        DEPENDS ${arg_FILES} ${LCM_GEN_EXECUTABLE}
        COMMENT "lcm-gen: C bindings of ${arg_TARGET}"
        VERBATIM)

    # Static, or shared with CDPR_SHARED (cmake/CdprLibrary.cmake; every symbol of the
    # generated code is a cdpr_* one of its headers, so the version script is a pattern).
    if(CDPR_SHARED)
        add_library(${arg_TARGET} SHARED ${c_sources} ${c_headers})
        set(map ${CMAKE_CURRENT_BINARY_DIR}/${arg_TARGET}.map)
        file(CONFIGURE OUTPUT ${map} CONTENT
            "/* Generated by cmake/LcmGen.cmake. */\n{\n    global:\n        cdpr_*;\n    local:\n        *;\n};\n")
        cdpr_shared_properties(${arg_TARGET} ${map})
    else()
        add_library(${arg_TARGET} STATIC ${c_sources} ${c_headers})
    endif()
    cdpr_numerics(${arg_TARGET})
    # Installed (lib/lcm/CMakeLists.txt) as include/lcmtypes/<pkg>_<type>.h.
    target_include_directories(${arg_TARGET} SYSTEM PUBLIC $<BUILD_INTERFACE:${out}/include>)
    set(CDPR_LCMTYPES_INCLUDE_DIR ${out}/include PARENT_SCOPE)
    target_link_libraries(${arg_TARGET} PUBLIC lcm::lcm)
    cdpr_strict_warnings(${arg_TARGET})
    target_compile_options(${arg_TARGET} PRIVATE
        -Wno-unused-parameter -Wno-pedantic -Wno-sign-conversion)

    if(arg_PYTHON_DIR)
        add_custom_command(
            OUTPUT ${py_files}
            COMMAND ${CMAKE_COMMAND} -E make_directory ${arg_PYTHON_DIR}
            COMMAND ${LCM_GEN_EXECUTABLE} --python --ppath ${arg_PYTHON_DIR} ${arg_FILES}
            DEPENDS ${arg_FILES} ${LCM_GEN_EXECUTABLE}
            COMMENT "lcm-gen: Python bindings of ${arg_TARGET} in ${arg_PYTHON_DIR}"
            VERBATIM)
        add_custom_target(${arg_TARGET}_python ALL DEPENDS ${py_files})
    endif()

    if(arg_JAVA_JAR)
        find_package(Java QUIET COMPONENTS Development)
        find_file(LCM_JAR NAMES lcm.jar PATHS /usr/share/java /usr/local/share/java
                  DOC "LCM's Java library (Debian: liblcm-java), for lcm-spy bindings")
        if(NOT Java_JAVAC_EXECUTABLE OR NOT Java_JAR_EXECUTABLE OR NOT LCM_JAR)
            message(STATUS "lcm-gen: no Java bindings (javac '${Java_JAVAC_EXECUTABLE}', "
                           "jar '${Java_JAR_EXECUTABLE}', lcm.jar '${LCM_JAR}'; "
                           "Debian: default-jdk-headless liblcm-java)")
        else()
            add_custom_command(
                OUTPUT ${arg_JAVA_JAR}
                COMMAND ${CMAKE_COMMAND} -E rm -rf ${out}/java ${out}/classes
                COMMAND ${CMAKE_COMMAND} -E make_directory ${out}/java ${out}/classes
                COMMAND ${LCM_GEN_EXECUTABLE} --java --jpath ${out}/java ${arg_FILES}
                COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -cp ${LCM_JAR} -d ${out}/classes
                        ${java_files}
                COMMAND ${Java_JAR_EXECUTABLE} cf ${arg_JAVA_JAR} -C ${out}/classes .
                DEPENDS ${arg_FILES} ${LCM_GEN_EXECUTABLE}
                COMMENT "lcm-gen: Java bindings of ${arg_TARGET} -> ${arg_JAVA_JAR}"
                VERBATIM)
            add_custom_target(${arg_TARGET}_java ALL DEPENDS ${arg_JAVA_JAR})
        endif()
    endif()
endfunction()
