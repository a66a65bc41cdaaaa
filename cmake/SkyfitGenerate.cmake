# skyfit_generate(TARGET <target> SCENE <scene.json> OUTPUT_DIR <dir>
#                 LANG <glsl|c>... [NAME <base>] [PREFIX <prefix>]
#                 [BUILD_OPTIONS <option>...] [BASELINES <list>]
#                 [OUTPUTS_VARIABLE <var>])
#
# Adds a build step that writes <dir>/<base>.glsl and/or <dir>/<base>.h
# (base defaults to "skyfit") from the scene file (SPEC §5, §9), makes
# <target> depend on it and puts <dir> on its include path (PRIVATE; an
# INTERFACE library's INTERFACE, so that everything linking it includes
# the headers; none for a custom target, e.g. a shader step).
#
# The step is the custom target <target>_skyfit_<base>, and <var> (with
# OUTPUTS_VARIABLE) receives the files it writes. Another target that uses
# them depends on that custom target (add_dependencies): a custom command
# of its own that DEPENDS on the files alone had made Makefile builds run
# the step twice, at once, into the same folder.
#
# By default the step is `skyfit build`: it fits the models the scene's
# domain allows, selects per quantity the cheapest that meets its budget
# and emits it, with skyfit_transmittance(h_km, mu) and
# skyfit_sky_radiance(h_km, mu, mu_s, nu) calling the selected models, so
# the renderer's code stays the same whichever model a new atmosphere
# selects. Its tables, fits and report are kept in
# <binary dir>/skyfit/<target>/<base>/ (report.html says what was chosen
# and why), so a rebuild after an edit reuses what still applies. The
# first build samples the tables and trains the networks: minutes at the
# default resolution; BUILD_OPTIONS are passed on to `skyfit build` (e.g.
# --resolution or --quick for a smaller, faster sky). With BASELINES the
# step only writes those analytic baselines (naive, chapman, taylor, flat,
# spline, naive-sky, raymarched-sky, flat-sky, schuler-sky: `skyfit
# codegen --baselines`), in seconds.
#
# The step runs again when the scene file, the atmosphere file it names, or
# the skyfit tool changes, and not otherwise. Editing which atmosphere the
# scene names re-runs CMake's configure (the scene is a configure
# dependency), which picks up the new atmosphere file as a dependency.
# One target may call it several times with different NAMEs; with
# different PREFIXes as well (every emitted name starts <prefix>_ instead
# of skyfit_), two scenes' headers go into one translation unit or shader.
# Configure stops with a message on an unknown argument (a misspelt
# keyword, wherever it stands), an unknown baseline, a keyword
# without its value (BUILD_OPTIONS alone may be empty), BUILD_OPTIONS with
# BASELINES (codegen does not take them) and a scene whose atmosphere
# file does not exist.
include_guard(GLOBAL)
# if(... IN_LIST ...) below, also for consumers whose cmake_minimum_required
# predates it (this file is included in their policy scope)
cmake_policy(SET CMP0057 NEW)

# Reads the scene's "atmosphere" path (relative to the scene's folder);
# empty when the scene uses the built-in atmosphere.
function(_skyfit_scene_atmosphere scene out_var)
  file(READ "${scene}" _json)
  string(JSON _atmosphere ERROR_VARIABLE _missing GET "${_json}" atmosphere)
  if(_missing OR _atmosphere STREQUAL "")
    set(${out_var} "" PARENT_SCOPE)
    return()
  endif()
  # a number had been read as a file name ("names the atmosphere .../5")
  string(JSON _type ERROR_VARIABLE _bad TYPE "${_json}" atmosphere)
  if(NOT _type STREQUAL "STRING")
    message(FATAL_ERROR "skyfit_generate: ${scene}: atmosphere: expected a file path (a string), got ${_type}")
  endif()
  get_filename_component(_dir "${scene}" DIRECTORY)
  get_filename_component(_path "${_atmosphere}" ABSOLUTE BASE_DIR "${_dir}")
  set(${out_var} "${_path}" PARENT_SCOPE)
endfunction()

function(skyfit_generate)
  cmake_parse_arguments(SG "" "TARGET;SCENE;OUTPUT_DIR;NAME;PREFIX;OUTPUTS_VARIABLE" "LANG;BASELINES;BUILD_OPTIONS"
                        ${ARGN})
  # A misspelt keyword (PREFX) had been dropped without a word, the build
  # failing later in the compiler on names without their prefix.
  if(SG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "skyfit_generate: unknown arguments: ${SG_UNPARSED_ARGUMENTS} (keywords: TARGET SCENE "
                        "OUTPUT_DIR LANG NAME PREFIX BASELINES BUILD_OPTIONS OUTPUTS_VARIABLE)")
  endif()
  # After a keyword of several values the misspelt one lands among its
  # values (LANG c BASELINES naive PREFX p): caught here too, not by skyfit
  # at build time ("unknown baseline 'PREFX'"). skyfit's own options and
  # values are never capitalised words.
  foreach(keyword LANG BASELINES BUILD_OPTIONS)
    foreach(value IN LISTS SG_${keyword})
      if(value MATCHES "^[A-Z][A-Z_]*$")
        message(FATAL_ERROR "skyfit_generate: unknown argument ${value} after ${keyword} (keywords: TARGET SCENE "
                            "OUTPUT_DIR LANG NAME PREFIX BASELINES BUILD_OPTIONS OUTPUTS_VARIABLE)")
      endif()
    endforeach()
  endforeach()
  set(known_baselines naive chapman taylor flat spline naive-sky raymarched-sky flat-sky
                       schuler-sky)   # skyfit codegen --baselines
  string(REPLACE "," ";" baseline_names "${SG_BASELINES}")
  list(REMOVE_ITEM baseline_names "")   # "naive,chapman,": codegen skips the empty name too
  foreach(baseline IN LISTS baseline_names)
    if(NOT baseline IN_LIST known_baselines)
      message(FATAL_ERROR "skyfit_generate: BASELINES: unknown baseline '${baseline}' (naive, chapman, taylor, "
                          "flat, spline, naive-sky, raymarched-sky, flat-sky, schuler-sky)")
    endif()
  endforeach()
  # (BUILD_OPTIONS ${empty_variable} is fine; an empty BASELINES had run
  # the whole skyfit build instead)
  foreach(keyword TARGET SCENE OUTPUT_DIR NAME PREFIX LANG BASELINES OUTPUTS_VARIABLE)
    if(keyword IN_LIST SG_KEYWORDS_MISSING_VALUES)
      message(FATAL_ERROR "skyfit_generate: ${keyword} needs a value")
    endif()
  endforeach()
  if(SG_BASELINES AND SG_BUILD_OPTIONS)
    message(FATAL_ERROR "skyfit_generate: BUILD_OPTIONS are options of skyfit build; with BASELINES the headers "
                        "come from skyfit codegen, which does not take them")
  endif()
  foreach(required TARGET SCENE OUTPUT_DIR LANG)
    if(NOT SG_${required})
      message(FATAL_ERROR "skyfit_generate: ${required} is required")
    endif()
  endforeach()
  if(NOT SG_NAME)
    set(SG_NAME skyfit)
  endif()
  # NAME is a file name and part of the work folder's path (as skyfit
  # codegen --name takes it)
  if(NOT SG_NAME MATCHES "^[A-Za-z0-9_-]+$")
    message(FATAL_ERROR "skyfit_generate: NAME '${SG_NAME}' must be letters, digits, '_' and '-'")
  endif()
  if(NOT TARGET ${SG_TARGET})
    message(FATAL_ERROR "skyfit_generate: TARGET ${SG_TARGET} is not a target of this project (define it first)")
  endif()
  get_filename_component(scene "${SG_SCENE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_filename_component(out_dir "${SG_OUTPUT_DIR}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  if(NOT EXISTS "${scene}")
    message(FATAL_ERROR "skyfit_generate: scene file ${scene} does not exist")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${scene}")
  _skyfit_scene_atmosphere("${scene}" atmosphere)
  # A missing file among the DEPENDS had stopped the build with the
  # generator's "no rule to make target", not skyfit's message.
  if(atmosphere AND NOT EXISTS "${atmosphere}")
    message(FATAL_ERROR "skyfit_generate: scene ${scene} names the atmosphere ${atmosphere}, which does not exist")
  endif()

  set(outputs)
  set(langs)
  foreach(lang ${SG_LANG})
    if(lang STREQUAL "glsl")
      list(APPEND outputs "${out_dir}/${SG_NAME}.glsl")
    elseif(lang STREQUAL "c")
      list(APPEND outputs "${out_dir}/${SG_NAME}.h")
    else()
      message(FATAL_ERROR "skyfit_generate: LANG must be glsl and/or c, got '${lang}'")
    endif()
    list(APPEND langs ${lang})
  endforeach()
  string(REPLACE ";" "," lang_arg "${langs}")
  set(prefix_arg)
  if(SG_PREFIX)
    set(prefix_arg --prefix ${SG_PREFIX})
  endif()

  if(SG_BASELINES)
    string(REPLACE ";" "," baselines_arg "${SG_BASELINES}")
    set(command skyfit::skyfit codegen --scene "${scene}" --baselines ${baselines_arg} --lang ${lang_arg}
        --out "${out_dir}" --name ${SG_NAME} ${prefix_arg} --quiet)
  else()
    # The header of a language not asked for stays in the work folder: one
    # per target and name (skyfit-<target>-<name> had been one folder for
    # target app-gl, name sky and target app, name gl-sky).
    set(work "${CMAKE_CURRENT_BINARY_DIR}/skyfit/${SG_TARGET}/${SG_NAME}")
    set(c_header "${work}/${SG_NAME}.h")
    set(glsl_header "${work}/${SG_NAME}.glsl")
    if("c" IN_LIST langs)
      set(c_header "${out_dir}/${SG_NAME}.h")
    endif()
    if("glsl" IN_LIST langs)
      set(glsl_header "${out_dir}/${SG_NAME}.glsl")
    endif()
    set(command skyfit::skyfit build "${scene}" --out "${work}" --header-c "${c_header}" --header-glsl
        "${glsl_header}" --no-views --quiet ${prefix_arg} ${SG_BUILD_OPTIONS})
  endif()

  add_custom_command(
    OUTPUT ${outputs}
    COMMAND ${CMAKE_COMMAND} -E make_directory "${out_dir}"
    COMMAND ${command}
    DEPENDS "${scene}" ${atmosphere} "$<TARGET_FILE:skyfit::skyfit>"
    COMMENT "skyfit: generating ${SG_NAME} headers from ${scene}"
    VERBATIM)
  add_custom_target(${SG_TARGET}_skyfit_${SG_NAME} DEPENDS ${outputs})
  add_dependencies(${SG_TARGET} ${SG_TARGET}_skyfit_${SG_NAME})
  # (PRIVATE alone had stopped configure on an INTERFACE library or a
  # custom target with CMake's own error)
  get_target_property(target_type ${SG_TARGET} TYPE)
  if(target_type STREQUAL "INTERFACE_LIBRARY")
    target_include_directories(${SG_TARGET} INTERFACE "${out_dir}")
  elseif(NOT target_type STREQUAL "UTILITY")
    target_include_directories(${SG_TARGET} PRIVATE "${out_dir}")
  endif()
  if(SG_OUTPUTS_VARIABLE)
    set(${SG_OUTPUTS_VARIABLE} ${outputs} PARENT_SCOPE)
  endif()
endfunction()
