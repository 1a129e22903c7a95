# SPDX-License-Identifier: BSD-3-Clause
# Provides the target unity::framework (ThrowTheSwitch Unity) for the tests.
#
# Resolution order (see the project's UNITY.md notes; Unity's sources are never vendored):
#   1. an installed Unity (upstream's CMake package exports unity::framework);
#   2. UNITY_ROOT: a folder with unity.c, unity.h, unity_internals.h (defaults to the
#      environment variable CDPR_UNITY_ROOT, which scripts/setup.sh exports);
#   3. CDPR_UNITY_TARBALL: Debian's ntpsec orig tarball, which carries Unity in tests/unity
#      (scripts/setup.sh downloads it with `apt-get source`), checked by SHA-256;
#   4. online: the upstream repository at a pinned tag.
#
# In every branch UNITY_INCLUDE_DOUBLE is a PUBLIC (interface) definition: without it the
# double assertions still compile but fail at run time ("Unity Double Precision Disabled").

include(FetchContent)

set(UNITY_ROOT "" CACHE PATH "Folder holding unity.c, unity.h and unity_internals.h")

if(DEFINED ENV{CDPR_CACHE})
    set(_cdpr_cache_dir "$ENV{CDPR_CACHE}")
else()
    set(_cdpr_cache_dir "$ENV{HOME}/.cache/cdpr")
endif()
set(CDPR_UNITY_TARBALL "${_cdpr_cache_dir}/src/ntpsec_1.2.2+dfsg1.orig.tar.xz"
    CACHE FILEPATH "Debian's ntpsec orig tarball (carries Unity 2.5.1 in tests/unity)")
set(_cdpr_unity_tarball_sha256
    53e527e3d04d551d41af2d359c2715c2de5f5bfa2a695d4ec1a811b3e9137f63)

# Builds a static `unity` from a plain source folder. No strict warnings (not our code);
# SYSTEM so its headers do not trip our warnings in the tests that include them.
function(_cdpr_unity_from_folder dir)
    foreach(f unity.c unity.h unity_internals.h)
        if(NOT EXISTS "${dir}/${f}")
            message(FATAL_ERROR "Unity: ${dir} has no ${f}")
        endif()
    endforeach()
    add_library(unity STATIC "${dir}/unity.c")
    target_include_directories(unity SYSTEM PUBLIC "${dir}")
    target_compile_definitions(unity PUBLIC UNITY_INCLUDE_DOUBLE)
    add_library(unity::framework ALIAS unity)
endfunction()

# The environment only supplies a default: an explicit -DUNITY_ROOT=... always wins, and a
# cache entry left empty keeps following the environment of each configure run.
set(_cdpr_unity_root "${UNITY_ROOT}")
if(NOT _cdpr_unity_root AND DEFINED ENV{CDPR_UNITY_ROOT})
    set(_cdpr_unity_root "$ENV{CDPR_UNITY_ROOT}")
endif()

find_package(unity CONFIG QUIET)

if(unity_FOUND)
    message(STATUS "Unity: installed package (${unity_DIR})")
    # Imported target: the definition must reach the test sources. If the installed library
    # was built without double support, this turns the silent run-time failure into a link
    # error.
    target_compile_definitions(unity::framework INTERFACE UNITY_INCLUDE_DOUBLE)

elseif(_cdpr_unity_root)
    message(STATUS "Unity: source folder ${_cdpr_unity_root}")
    _cdpr_unity_from_folder("${_cdpr_unity_root}")

elseif(EXISTS "${CDPR_UNITY_TARBALL}")
    message(STATUS "Unity: from ${CDPR_UNITY_TARBALL}")
    # SOURCE_SUBDIR names a folder without a CMakeLists.txt, so MakeAvailable only unpacks
    # the tarball; we compile nothing but tests/unity/unity.c from it.
    FetchContent_Declare(cdpr_unity_ntpsec
        URL "${CDPR_UNITY_TARBALL}"
        URL_HASH SHA256=${_cdpr_unity_tarball_sha256}
        SOURCE_SUBDIR tests/unity)
    FetchContent_MakeAvailable(cdpr_unity_ntpsec)
    _cdpr_unity_from_folder("${cdpr_unity_ntpsec_SOURCE_DIR}/tests/unity")

else()
    message(STATUS "Unity: not found locally, fetching v2.6.1 online "
                   "(offline machines: run scripts/setup.sh first)")
    FetchContent_Declare(cdpr_unity_upstream
        GIT_REPOSITORY https://github.com/ThrowTheSwitch/Unity.git
        GIT_TAG v2.6.1
        GIT_SHALLOW TRUE
        SYSTEM)
    FetchContent_MakeAvailable(cdpr_unity_upstream)
    # Upstream's CMakeLists defines `unity` and the alias unity::framework.
    target_compile_definitions(unity PUBLIC UNITY_INCLUDE_DOUBLE)
endif()
