# Finds the four Debian libraries of SPEC §2 and bundles them in the
# interface target skyfit::deps. A missing one stops configuration with the
# name of the Debian package that provides it.
find_package(PkgConfig QUIET)

function(skyfit_require_pkg prefix module debian_package)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(${prefix} QUIET IMPORTED_TARGET ${module})
  endif()
  if(NOT ${prefix}_FOUND)
    message(FATAL_ERROR
      "skyfit needs ${module}: install the Debian package '${debian_package}' "
      "(apt-get install ${debian_package}; pkg-config is needed too).")
  endif()
endfunction()

skyfit_require_pkg(SKYFIT_CJSON libcjson libcjson-dev)
skyfit_require_pkg(SKYFIT_NLOPT nlopt libnlopt-dev)
skyfit_require_pkg(SKYFIT_OPENEXR OpenEXR libopenexr-dev)
skyfit_require_pkg(SKYFIT_PNG libpng libpng-dev)

find_package(Ceres QUIET)
if(NOT Ceres_FOUND)
  message(FATAL_ERROR
    "skyfit needs Ceres Solver: install the Debian package 'libceres-dev' "
    "(apt-get install libceres-dev).")
endif()

find_package(OpenMP QUIET COMPONENTS C)

add_library(skyfit_deps INTERFACE)
target_link_libraries(skyfit_deps INTERFACE
  PkgConfig::SKYFIT_CJSON PkgConfig::SKYFIT_NLOPT PkgConfig::SKYFIT_OPENEXR PkgConfig::SKYFIT_PNG
  Ceres::ceres)
if(OpenMP_C_FOUND)
  target_link_libraries(skyfit_deps INTERFACE OpenMP::OpenMP_C)
endif()
add_library(skyfit::deps ALIAS skyfit_deps)

# The emitted-code tests (tests/test_codegen_headers.c) compile the emitted
# GLSL with glslangValidator and run it on Mesa's llvmpipe through headless
# EGL; examples need libpng. Missing ones stop configuration when tests
# are built.
if(NOT DEFINED BUILD_TESTING OR BUILD_TESTING)
  find_program(SKYFIT_GLSLANG glslangValidator)
  if(NOT SKYFIT_GLSLANG)
    message(FATAL_ERROR "skyfit's tests need glslangValidator: install the Debian package "
      "'glslang-tools' (apt-get install glslang-tools), or configure with -DBUILD_TESTING=OFF.")
  endif()
  find_library(SKYFIT_EGL_LIBRARY EGL)
  find_library(SKYFIT_GL_LIBRARY GL)
  find_path(SKYFIT_EGL_INCLUDE EGL/egl.h)
  if(NOT SKYFIT_EGL_LIBRARY OR NOT SKYFIT_GL_LIBRARY OR NOT SKYFIT_EGL_INCLUDE)
    message(FATAL_ERROR "skyfit's tests run GLSL on Mesa's software renderer through EGL: "
      "install the Debian packages 'libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri' "
      "(apt-get install ...), or configure with -DBUILD_TESTING=OFF.")
  endif()
endif()
