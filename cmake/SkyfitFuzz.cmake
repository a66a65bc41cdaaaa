# SKYFIT_FUZZ=ON (clang only) builds one libFuzzer executable per loader of
# user input, tests/fuzz/fuzz_<loader>.c -> fuzz_<loader>, plus
# fuzz_make_seed_corpus (writes the binary seeds). skyfit_core is compiled
# with coverage instrumentation and ASan+UBSan so that the fuzzers see into
# the loaders and any memory error or undefined behaviour is a crash.
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

  set(SKYFIT_FUZZ_DIR ${CMAKE_CURRENT_SOURCE_DIR}/tests/fuzz)
  file(GLOB SKYFIT_FUZZ_SOURCES CONFIGURE_DEPENDS ${SKYFIT_FUZZ_DIR}/fuzz_*.c)
  foreach(src ${SKYFIT_FUZZ_SOURCES})
    get_filename_component(name ${src} NAME_WE)
    add_executable(${name} ${src})
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer ${SKYFIT_FUZZ_SANITIZERS})
    target_link_options(${name} PRIVATE -fsanitize=fuzzer,address,undefined)
    target_compile_definitions(${name} PRIVATE SKYFIT_FUZZ_DIR="${SKYFIT_FUZZ_DIR}")
    target_link_libraries(${name} PRIVATE skyfit_core)
  endforeach()
  # The eval CSV reader lives with the CLI, not in skyfit_core.
  target_sources(fuzz_csv_points PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/cli/csv_points.c)

  add_executable(fuzz_make_seed_corpus ${SKYFIT_FUZZ_DIR}/make_seed_corpus.c)
  target_link_libraries(fuzz_make_seed_corpus PRIVATE skyfit_core)
  add_custom_target(fuzz_targets)
  foreach(src ${SKYFIT_FUZZ_SOURCES})
    get_filename_component(name ${src} NAME_WE)
    add_dependencies(fuzz_targets ${name})
  endforeach()
  message(STATUS "skyfit: libFuzzer targets under tests/fuzz/")
endif()
