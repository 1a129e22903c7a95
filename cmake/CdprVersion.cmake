# SPDX-License-Identifier: BSD-3-Clause
# The project's version, in one place: the top-level project() and lib/core (also when a
# firmware build adds lib/core alone with add_subdirectory) read it from here. Bump it with
# an entry in CHANGELOG.md; cdpr/version.h (cmake/version.h.in) and the package files follow.
set(CDPR_VERSION 0.1.0)
string(REGEX MATCH "^([0-9]+)\\.([0-9]+)\\.([0-9]+)$" _cdpr_version_ok "${CDPR_VERSION}")
if(NOT _cdpr_version_ok)
    message(FATAL_ERROR "CDPR_VERSION '${CDPR_VERSION}' is not MAJOR.MINOR.PATCH")
endif()
set(CDPR_VERSION_MAJOR ${CMAKE_MATCH_1})
set(CDPR_VERSION_MINOR ${CMAKE_MATCH_2})
set(CDPR_VERSION_PATCH ${CMAKE_MATCH_3})
unset(_cdpr_version_ok)
