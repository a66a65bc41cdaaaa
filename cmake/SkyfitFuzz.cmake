# SKYFIT_FUZZ=ON (clang only) builds one libFuzzer executable per loader of
# user input, tests/fuzz/fuzz_<loader>.c -> fuzz_<loader>, plus
# fuzz_make_seed_corpus (writes the binary seeds). The fuzz targets link
# skyfit_fuzz_loaders: the sources of skyfit_core that the loaders reach
# (SKYFIT_FUZZ_LOADER_SOURCES below), compiled with coverage
# instrumentation and ASan+UBSan so that the fuzzers see into the loaders
# and any memory error or undefined behaviour is a crash. They had linked
# the whole of skyfit_core, instrumented: the static archive gave each
# target the same 25 objects, but the fuzz build compiled all ~190 sources
# (the fitters, Ceres's C++ shim, the report writers) with clang, ASan and
# -O2 -g first: most of the ~550 s tests/cli_fuzz_short.sh took in ctest
# -j2. skyfit_core keeps its instrumentation here for any other target of
# this build folder.
# Used by bench/fuzz.sh and tests/cli_fuzz_short.sh in their own build
# folder; the normal build does not see tests/fuzz/ (tests/CMakeLists.txt
# globs tests/test_*.c and tests/cli_*.sh only). Included after skyfit_core
# is defined.
option(SKYFIT_FUZZ "Build the libFuzzer targets tests/fuzz/fuzz_*.c (needs clang)" OFF)

if(SKYFIT_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR
      "SKYFIT_FUZZ needs clang with libFuzzer, not ${CMAKE_C_COMPILER_ID}: configure with "
      "CC=clang CXX=clang++ (Debian packages clang libclang-rt-14-dev libomp-dev)")
  endif()
  set(SKYFIT_FUZZ_SANITIZERS -fsanitize=address,undefined -fno-sanitize-recover=all
    -fno-omit-frame-pointer -g)
  target_compile_options(skyfit_core PRIVATE -fsanitize=fuzzer-no-link ${SKYFIT_FUZZ_SANITIZERS})
  target_link_options(skyfit_core INTERFACE -fsanitize=address,undefined)

  # What the loaders reach: exactly the members of libskyfit_core.a that
  # the linker takes for the five fuzz targets (and make_seed_corpus). A
  # loader that comes to call into another source fails the fuzz build
  # with an undefined reference (tests/cli_fuzz_short.sh fails, it is not
  # skipped): add that source here. To list them again, link each target
  # against a normal build's archive with -Wl,-Map=FILE and read its
  # "Archive member included" section.
  set(SKYFIT_FUZZ_LOADER_SOURCES
    util/atomic_file.c util/data_path.c util/error.c util/exr_fd_write.c
    util/json_exact.c util/json_read.c util/read_file.c util/sort_doubles.c
    models/atmosphere.c models/atmosphere_canonical.c models/atmosphere_default.c
    models/atmosphere_file.c models/color_space.c models/phase.c models/quadrature.c
    models/ray_geometry.c models/scene_default.c models/scene_domain.c
    models/scene_file.c models/spectral_data.c models/spectral_recipes.c
    models/spectral_recipes_json.c models/weights_file.c
    data/table.c data/table_exr.c)
  list(TRANSFORM SKYFIT_FUZZ_LOADER_SOURCES PREPEND ${CMAKE_CURRENT_SOURCE_DIR}/)
  add_library(skyfit_fuzz_loaders STATIC ${SKYFIT_FUZZ_LOADER_SOURCES})
  # the same flags, definitions and dependencies as skyfit_core's
  target_include_directories(skyfit_fuzz_loaders PUBLIC
    $<TARGET_PROPERTY:skyfit_core,INTERFACE_INCLUDE_DIRECTORIES>)
  target_compile_definitions(skyfit_fuzz_loaders PUBLIC
    $<TARGET_PROPERTY:skyfit_core,INTERFACE_COMPILE_DEFINITIONS>)
  target_link_libraries(skyfit_fuzz_loaders PUBLIC skyfit::deps m)
  target_compile_options(skyfit_fuzz_loaders PRIVATE -fsanitize=fuzzer-no-link ${SKYFIT_FUZZ_SANITIZERS})
  target_link_options(skyfit_fuzz_loaders INTERFACE -fsanitize=address,undefined)

  set(SKYFIT_FUZZ_DIR ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz)
  file(GLOB SKYFIT_FUZZ_SOURCES CONFIGURE_DEPENDS ${SKYFIT_FUZZ_DIR}/fuzz_*.c)
  foreach(src ${SKYFIT_FUZZ_SOURCES})
    get_filename_component(name ${src} NAME_WE)
    add_executable(${name} ${src})
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer ${SKYFIT_FUZZ_SANITIZERS})
    target_link_options(${name} PRIVATE -fsanitize=fuzzer,address,undefined)
    target_compile_definitions(${name} PRIVATE SKYFIT_FUZZ_DIR="${SKYFIT_FUZZ_DIR}")
    target_link_libraries(${name} PRIVATE skyfit_fuzz_loaders)
  endforeach()
  # The eval CSV reader lives with the CLI, not in skyfit_core.
  target_sources(fuzz_csv_points PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/cli/csv_points.c)

  add_executable(fuzz_make_seed_corpus ${SKYFIT_FUZZ_DIR}/make_seed_corpus.c)
  target_link_libraries(fuzz_make_seed_corpus PRIVATE skyfit_fuzz_loaders)
  add_custom_target(fuzz_targets)
  foreach(src ${SKYFIT_FUZZ_SOURCES})
    get_filename_component(name ${src} NAME_WE)
    add_dependencies(fuzz_targets ${name})
  endforeach()
  message(STATUS "skyfit: libFuzzer targets under tests/fuzz/")
endif()
