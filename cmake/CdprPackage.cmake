# SPDX-License-Identifier: BSD-3-Clause
# The installed package (included by the top-level CMakeLists.txt after every library):
#  - <libdir>/cmake/cdpr/: cdprConfig.cmake, cdprConfigVersion.cmake (SameMajorVersion) and
#    one export file per component, cdpr-<component>-targets.cmake (targets cdpr::core,
#    cdpr::control, cdpr::gsl, cdpr::host, cdpr::design, cdpr::lcm + cdpr::lcmtypes, cdpr::rt);
#  - <libdir>/pkgconfig/cdpr-<component>.pc (relocatable: paths from ${pcfiledir});
#  - <datadir>/cdpr/{scenarios,scripts,lcmtypes} (host builds) and <docdir>: LICENSE,
#    README.md, CHANGELOG.md.
# Only the components this build has are installed (a cross build: core only); the config
# reports the others as not found.
include(CMakePackageConfigHelpers)

get_property(CDPR_COMPONENTS GLOBAL PROPERTY CDPR_INSTALLED_COMPONENTS)
list(REMOVE_DUPLICATES CDPR_COMPONENTS)
set(CDPR_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/cdpr)
set(CDPR_PKGCONFIG_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

foreach(component IN LISTS CDPR_COMPONENTS)
    install(EXPORT cdpr-${component}-targets
        NAMESPACE cdpr::
        FILE cdpr-${component}-targets.cmake
        DESTINATION ${CDPR_CMAKE_INSTALL_DIR}
        COMPONENT devel)
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/cdprConfig.cmake.in
    ${PROJECT_BINARY_DIR}/cdprConfig.cmake
    INSTALL_DESTINATION ${CDPR_CMAKE_INSTALL_DIR})
# Version policy: from 1.0 on, a minor version keeps the API and the object layouts
# (SameMajorVersion); while the major version is 0, a minor version may change them, so the
# check accepts the same major.minor only (find_package(cdpr 0.1) takes 0.1.x, not 0.2).
if(PROJECT_VERSION_MAJOR EQUAL 0)
    set(_cdpr_compat SameMinorVersion)
else()
    set(_cdpr_compat SameMajorVersion)
endif()
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cdprConfigVersion.cmake
    VERSION ${PROJECT_VERSION}
    COMPATIBILITY ${_cdpr_compat})
install(FILES ${PROJECT_BINARY_DIR}/cdprConfig.cmake ${PROJECT_BINARY_DIR}/cdprConfigVersion.cmake
    DESTINATION ${CDPR_CMAKE_INSTALL_DIR}
    COMPONENT devel)

# pkg-config. A static library needs its dependencies on the consumer's link line, so in the
# default (static) build every dependency is in Requires/Libs; with CDPR_SHARED the private
# ones move to Requires.private/Libs.private. Cflags carry the one definition the headers
# depend on, CDPR_REAL_IS_FLOAT (float builds); the numerics flags of the libraries' own
# compile (-std=c99, -ffp-contract=off) are not usage requirements (cmake/CdprLibrary.cmake).
file(RELATIVE_PATH CDPR_PC_PREFIX_FROM_PCFILEDIR
    /root/${CDPR_PKGCONFIG_INSTALL_DIR} /root)
string(REGEX REPLACE "/$" "" CDPR_PC_PREFIX_FROM_PCFILEDIR "${CDPR_PC_PREFIX_FROM_PCFILEDIR}")
set(CDPR_PC_CFLAGS "")
set(CDPR_PC_REAL double)
if(CDPR_REAL_FLOAT)
    set(CDPR_PC_REAL float)
    set(CDPR_PC_CFLAGS " -DCDPR_REAL_IS_FLOAT")
endif()

# _cdpr_pkgconfig(<component> <description> <public requires> <private requires>
#                 <libs> <private libs>): cdpr-<component>.pc when the build has the component.
function(_cdpr_pkgconfig component description requires requires_private libs libs_private)
    if(NOT component IN_LIST CDPR_COMPONENTS)
        return()
    endif()
    if(NOT CDPR_SHARED)
        string(STRIP "${requires} ${requires_private}" requires)
        string(STRIP "${libs} ${libs_private}" libs)
        set(requires_private "")
        set(libs_private "")
    endif()
    set(CDPR_PC_NAME cdpr-${component})
    set(CDPR_PC_DESCRIPTION "${description}")
    set(CDPR_PC_REQUIRES "${requires}")
    set(CDPR_PC_REQUIRES_PRIVATE "${requires_private}")
    set(CDPR_PC_LIBS "${libs}")
    set(CDPR_PC_LIBS_PRIVATE "${libs_private}")
    configure_file(${CMAKE_CURRENT_FUNCTION_LIST_DIR}/cdpr.pc.in
                   ${PROJECT_BINARY_DIR}/pkgconfig/cdpr-${component}.pc @ONLY)
    install(FILES ${PROJECT_BINARY_DIR}/pkgconfig/cdpr-${component}.pc
            DESTINATION ${CDPR_PKGCONFIG_INSTALL_DIR} COMPONENT devel)
endfunction()

_cdpr_pkgconfig(core "cdpr core: cable-robot model, integrator and plant (C99, libm only)"
    "" "" "-lcdpr_core" "-lm")
_cdpr_pkgconfig(control "cdpr example controller: trajectories and the tracker (C99, libm only)"
    "cdpr-core" "" "-lcdpr_control" "-lm")
_cdpr_pkgconfig(gsl "cdpr GSL reference solvers (links GSL: GPL-3)"
    "cdpr-core gsl" "" "-lcdpr_gsl" "")
_cdpr_pkgconfig(host "cdpr host layer: robots, scenario files, outputs, batch runner"
    "cdpr-core cdpr-control" "libcyaml yaml-0.1" "-lcdpr_host" "-lm")
_cdpr_pkgconfig(design "cdpr linear design: the loop's linearisation and margins (LAPACK)"
    "cdpr-host" "lapack" "-lcdpr_design" "-lm")
_cdpr_pkgconfig(lcm "cdpr LCM bridge and message types (links liblcm: LGPL-2.1+)"
    "cdpr-core lcm" "" "-lcdpr_lcm -lcdpr_lcmtypes" "-pthread -lm")
_cdpr_pkgconfig(rt "cdpr real-time nodes (plant node, tracker node)"
    "cdpr-host cdpr-lcm" "" "-lcdpr_rt" "-pthread -lm")

# Data of the host tools, and the licence (every build).
if(NOT CMAKE_CROSSCOMPILING)
    # The robot files and sweeps beside the scenarios, so that the installed scenarios' and
    # sweeps' relative paths (../robots/..., ../scenarios/...) hold in the prefix too.
    foreach(_cdpr_data scenarios robots sweeps)
        install(DIRECTORY ${PROJECT_SOURCE_DIR}/${_cdpr_data}/
            DESTINATION ${CMAKE_INSTALL_DATADIR}/cdpr/${_cdpr_data} COMPONENT data
            FILES_MATCHING PATTERN "*.yaml")
    endforeach()
    file(GLOB _cdpr_gp CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/scripts/*.gp)
    install(FILES ${_cdpr_gp} DESTINATION ${CMAKE_INSTALL_DATADIR}/cdpr/scripts COMPONENT data)
    file(GLOB _cdpr_lcm CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/lcmtypes/*.lcm)
    install(FILES ${_cdpr_lcm} ${PROJECT_SOURCE_DIR}/lcmtypes/README.md
        DESTINATION ${CMAKE_INSTALL_DATADIR}/cdpr/lcmtypes COMPONENT data)
endif()
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md
              ${PROJECT_SOURCE_DIR}/CHANGELOG.md
    DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
