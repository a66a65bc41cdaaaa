# Install rules (SPEC §9, build integration): the skyfit tool, its shipped
# data (share/skyfit/physical, found at run time through
# SKYFIT_INSTALLED_DATA_DIR, util/data_path.h) and the CMake package that
# lets a renderer's build call skyfit_generate() after find_package(skyfit).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SKYFIT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/skyfit)

target_compile_definitions(skyfit_core PUBLIC
  SKYFIT_INSTALLED_DATA_DIR="${CMAKE_INSTALL_FULL_DATADIR}/skyfit/physical")

install(TARGETS skyfit RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/physical/
        DESTINATION ${CMAKE_INSTALL_DATADIR}/skyfit/physical)

configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/skyfitConfig.cmake.in
  ${PROJECT_BINARY_DIR}/skyfitConfig.cmake
  INSTALL_DESTINATION ${SKYFIT_INSTALL_CMAKEDIR}
  PATH_VARS CMAKE_INSTALL_BINDIR)
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/skyfitConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/skyfitConfig.cmake
  ${PROJECT_BINARY_DIR}/skyfitConfigVersion.cmake
  ${PROJECT_SOURCE_DIR}/cmake/SkyfitGenerate.cmake
  DESTINATION ${SKYFIT_INSTALL_CMAKEDIR})
