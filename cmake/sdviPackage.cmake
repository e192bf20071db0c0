# SPDX-License-Identifier: GPL-3.0-or-later
# The installed package: sdvi::<module> targets (every sdvi_module()), the umbrella
# sdvi::sdvi, sdvi/version.h, sdviConfig.cmake + version file, and sdvi.pc for pkg-config.
include(CMakePackageConfigHelpers)

configure_file(${PROJECT_SOURCE_DIR}/cmake/version.h.in
               ${PROJECT_BINARY_DIR}/generated/include/sdvi/version.h @ONLY)
target_include_directories(sdvi_core PUBLIC $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated/include>)
install(FILES ${PROJECT_BINARY_DIR}/generated/include/sdvi/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sdvi)

# The umbrella target: every module.
add_library(sdvi_all INTERFACE)
target_link_libraries(sdvi_all INTERFACE ${SDVI_MODULES})
set_target_properties(sdvi_all PROPERTIES EXPORT_NAME sdvi)
add_library(sdvi::sdvi ALIAS sdvi_all)
install(TARGETS sdvi_all EXPORT sdviTargets)

set(SDVI_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sdvi)
install(EXPORT sdviTargets NAMESPACE sdvi:: DESTINATION ${SDVI_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/sdviConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/sdviConfig.cmake
                              INSTALL_DESTINATION ${SDVI_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sdviConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sdviConfig.cmake ${PROJECT_BINARY_DIR}/sdviConfigVersion.cmake
        DESTINATION ${SDVI_CMAKE_DIR})

# pkg-config: static libraries, listed from the top of the layering down.
set(SDVI_PC_LIBS "")
list(REVERSE SDVI_MODULES)
foreach(t ${SDVI_MODULES})
  string(APPEND SDVI_PC_LIBS " -l${t}")
endforeach()
list(REVERSE SDVI_MODULES)
file(RELATIVE_PATH SDVI_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/sdvi.pc.in ${PROJECT_BINARY_DIR}/sdvi.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sdvi.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(TARGETS sdvi RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/sdvi)
