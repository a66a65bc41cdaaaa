# SKYFIT_SANITIZE=ON builds everything (library, CLI, tests, benchmarks) with
# AddressSanitizer + UndefinedBehaviorSanitizer, stopping at the first
# finding (-fno-sanitize-recover=all), so a sanitized ctest run fails on any
# report. Used by scripts/test_sanitized.sh in its own build folder; the
# normal build is unaffected. Must be included before any target is created
# (add_compile_options applies to targets defined after it).
option(SKYFIT_SANITIZE "Build with -fsanitize=address,undefined (scripts/test_sanitized.sh)" OFF)

if(SKYFIT_SANITIZE)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "GNU|Clang")
    message(FATAL_ERROR "SKYFIT_SANITIZE needs gcc or clang, not ${CMAKE_C_COMPILER_ID}")
  endif()
  # float-cast-overflow: a float converted to an integer type that cannot
  # hold it (NaN, or out of range: an index from a bad coordinate) is
  # undefined behaviour (C11 6.3.1.4) that -fsanitize=undefined leaves out.
  # float-divide-by-zero is not added: IEEE 754 defines it (C11 Annex F) and
  # the code relies on it for infinities.
  set(SKYFIT_SANITIZE_FLAGS
    -fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_compile_options(${SKYFIT_SANITIZE_FLAGS})
  add_link_options(-fsanitize=address,undefined,float-cast-overflow)
  message(STATUS "skyfit: sanitized build (${SKYFIT_SANITIZE_FLAGS})")
endif()
