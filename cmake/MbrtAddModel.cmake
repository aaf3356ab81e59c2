# mbrt_add_model(<target> MODEL <model.yaml>
#                [NAME <name>] [SCHEME <scheme>] [STEP <h>] [EULER_UPDATES <k>] [PROJECT_INITIAL] [LCM]
#                [WARNINGS] [C_INTERFACE] [GEN_OPTIONS <mbrt gen options>...] [DATA <files>...])
#
# Generates the model's step with `mbrt gen` at build time (again whenever the
# model file or the generator changes) and adds it as a static library
# <target>. Include "<name>.hpp" (name from the model file, or NAME to build
# several variants of one model into one program) and call
# mbrt::models::<name>::step(); C programs include "<name>_c.h" and call
# <name>_step() (the C interface is compiled into the library too, unless
# the calling directory sets MBRT_MODEL_C_INTERFACE to OFF and the model is
# not marked C_INTERFACE; docs/c_interface.md). With LCM (models with inputs and outputs),
# lcm-gen also runs on the model's message types and "<name>_lcm.hpp" packs
# Outputs and Inputs into them ("<name>_can.hpp" packs them into CAN frames as
# "<name>.dbc" describes); the target then links liblcm. GEN_OPTIONS
# passes further `mbrt gen` options (e.g. --ali3p-projection cuadrado,
# --no-specialize, or --can-fd for the CAN layout in CAN FD frames). WARNINGS
# compiles the generated code with mbrt_enable_warnings(), as warnings only.
# DATA lists files the model reads (a modal body's `file:`), so that a change
# to them generates it again.
#
# mbrt_add_model_pch(<target>)
#
# Optional, for a directory of many models: adds <target>, a precompiled
# header of the runtime headers that generated code includes (every scheme's),
# and sets MBRT_MODEL_PCH to it in the calling directory, so that the models
# mbrt_add_model adds there afterwards (and in its subdirectories) reuse it
# (target_precompile_headers REUSE_FROM) instead of parsing those headers
# each. A model's flags must be the header's: LCM models (-fno-strict-aliasing)
# and, where generated warnings are not errors anyway, WARNINGS models compile
# without it. Without a call nothing changes.
#
# mbrt_add_model_bundle(<target> [BATCH_SIZE <n>])
#
# Optional, for a directory of many models (a test suite): adds <target>, one
# static library into which the models mbrt_add_model adds afterwards in the
# same directory compile, n to a translation unit (CMake's unity build,
# default 16). GCC instantiates the Eigen templates of the runtime headers
# again in every translation unit, and models of one mechanism in several
# schemes share most of theirs: a batch compiles them once (about half the
# CPU time of compiling models one by one, more for variants of one model,
# so add those one after another). Each model keeps its target, then an
# interface library (its include directory and the bundle), so programs link
# it as before. LCM models, WARNINGS models whose warnings are not errors and
# models added in other directories compile on their own, C interfaces
# (<name>_c.cpp) one by one.
include(${CMAKE_CURRENT_LIST_DIR}/MbrtWarnings.cmake)

# A static library of generated code's flags with one placeholder source:
# the bundle and the precompiled header's target start as one.
function(_mbrt_models_library target role)
  set(source "${CMAKE_CURRENT_BINARY_DIR}/mbrt_models/${target}.cpp")
  if(NOT EXISTS "${source}")
    file(WRITE "${source}" "// The ${role} of the generated models.\n")
  endif()
  add_library(${target} STATIC "${source}")
  target_link_libraries(${target} PUBLIC mbrt::mbrt)
  target_compile_features(${target} PUBLIC cxx_std_17)
  if(MBRT_GENERATED_WARNINGS_ARE_ERRORS)
    mbrt_enable_warnings(${target})
  endif()
endfunction()

function(mbrt_add_model_bundle target)
  cmake_parse_arguments(ARG "" "BATCH_SIZE" "" ${ARGN})
  if(NOT ARG_BATCH_SIZE)
    set(ARG_BATCH_SIZE 16)
  endif()
  _mbrt_models_library(${target} bundle)
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${ARG_BATCH_SIZE})
  if(MBRT_MODEL_PCH)
    target_precompile_headers(${target} REUSE_FROM ${MBRT_MODEL_PCH})
  endif()
  set(MBRT_MODEL_BUNDLE ${target} PARENT_SCOPE)
endfunction()

function(mbrt_add_model_pch target)
  _mbrt_models_library(${target} "precompiled header")
  target_precompile_headers(${target} PRIVATE
    <algorithm> <array> <cmath> <cstddef>
    <mbrt/model_api.hpp> <mbrt/runtime.hpp> <mbrt/reactions.hpp> <mbrt/sin_cos.hpp>
    <mbrt/natural_partitioning.hpp> <mbrt/schemes/staggered.hpp> <mbrt/schemes/tree.hpp>
    <mbrt/schemes/ali3p.hpp> <mbrt/schemes/rk4_projected.hpp> <mbrt/schemes/staggered4.hpp>)
  set(MBRT_MODEL_PCH ${target} PARENT_SCOPE)
endfunction()

function(mbrt_add_model target)
  cmake_parse_arguments(ARG "PROJECT_INITIAL;LCM;WARNINGS;C_INTERFACE" "MODEL;NAME;SCHEME;STEP;EULER_UPDATES" "GEN_OPTIONS;DATA" ${ARGN})
  if(NOT ARG_MODEL)
    message(FATAL_ERROR "mbrt_add_model(${target}): MODEL <file.yaml> is required")
  endif()
  get_filename_component(model "${ARG_MODEL}" ABSOLUTE)
  if(NOT EXISTS "${model}")
    message(FATAL_ERROR "mbrt_add_model(${target}): model file ${model} does not exist")
  endif()
  # The file names follow the model's name: read it at configure time.
  file(STRINGS "${model}" name_line REGEX "^name:[ \t]*[a-z][a-z0-9_]*")
  string(REGEX REPLACE "^name:[ \t]*([a-z][a-z0-9_]*).*" "\\1" name "${name_line}")
  if(NOT name)
    message(FATAL_ERROR "mbrt_add_model(${target}): ${model} has no top-level 'name:'")
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${model}")

  set(options "")
  if(ARG_NAME)
    set(name ${ARG_NAME})
    list(APPEND options --name ${ARG_NAME})
  endif()
  if(ARG_SCHEME)
    list(APPEND options --scheme ${ARG_SCHEME})
  endif()
  if(ARG_STEP)
    list(APPEND options --h ${ARG_STEP})
  endif()
  if(ARG_EULER_UPDATES)
    list(APPEND options --euler-updates ${ARG_EULER_UPDATES})
  endif()
  if(ARG_PROJECT_INITIAL)
    list(APPEND options --project-initial)
  endif()
  list(APPEND options ${ARG_GEN_OPTIONS})

  set(dir "${CMAKE_CURRENT_BINARY_DIR}/mbrt_models/${target}")
  set(outputs "${dir}/${name}.hpp" "${dir}/${name}.cpp" "${dir}/${name}_c.h" "${dir}/${name}_c.cpp")
  set(lcm_gen "")
  if(ARG_LCM)
    find_program(LCM_GEN lcm-gen REQUIRED)
    find_library(LCM_LIBRARY lcm REQUIRED)
    list(APPEND outputs "${dir}/${name}_lcm.hpp" "${dir}/${name}_lcm/state_t.hpp" "${dir}/${name}_lcm/command_t.hpp"
      "${dir}/${name}_can.hpp" "${dir}/${name}.dbc")
    set(lcm_gen COMMAND ${LCM_GEN} -x --cpp-hpath "${dir}" "${dir}/${name}.lcm")
  endif()
  add_custom_command(
    OUTPUT ${outputs}
    COMMAND mbrt::mbrt_cli gen "${model}" -o "${dir}" ${options}
    ${lcm_gen}
    DEPENDS "${model}" ${ARG_DATA} mbrt::mbrt_cli
    COMMENT "mbrt: generating ${name} from ${ARG_MODEL}"
    VERBATIM)
  set(sources ${outputs})
  if(DEFINED MBRT_MODEL_C_INTERFACE AND NOT MBRT_MODEL_C_INTERFACE AND NOT ARG_C_INTERFACE)
    list(REMOVE_ITEM sources "${dir}/${name}_c.cpp")
  endif()
  set(bundle "")
  if(MBRT_MODEL_BUNDLE AND NOT ARG_LCM AND (MBRT_GENERATED_WARNINGS_ARE_ERRORS OR NOT ARG_WARNINGS))
    get_target_property(bundle_dir ${MBRT_MODEL_BUNDLE} SOURCE_DIR)
    if(bundle_dir STREQUAL CMAKE_CURRENT_SOURCE_DIR)
      set(bundle ${MBRT_MODEL_BUNDLE})
    endif()
  endif()
  if(bundle)
    target_sources(${bundle} PRIVATE ${sources})
    # The C interface's file-scope helpers (Work, copy, ...) are per model.
    set_source_files_properties("${dir}/${name}_c.cpp" PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE "${dir}")
    target_link_libraries(${target} INTERFACE ${bundle})
    return()
  endif()
  add_library(${target} STATIC ${sources})
  target_include_directories(${target} PUBLIC "${dir}")
  target_link_libraries(${target} PUBLIC mbrt::mbrt)
  if(ARG_LCM)
    target_link_libraries(${target} PUBLIC ${LCM_LIBRARY})
    # lcm_coretypes.h reads doubles through int64_t pointers: with strict
    # aliasing, optimized builds encode stale bytes.
    target_compile_options(${target} PUBLIC -fno-strict-aliasing)
  endif()
  target_compile_features(${target} PUBLIC cxx_std_17)
  if(MBRT_GENERATED_WARNINGS_ARE_ERRORS)
    mbrt_enable_warnings(${target})
  elseif(ARG_WARNINGS)
    mbrt_enable_warnings(${target} NO_ERROR)
  endif()
  if(MBRT_MODEL_PCH AND NOT ARG_LCM AND (MBRT_GENERATED_WARNINGS_ARE_ERRORS OR NOT ARG_WARNINGS))
    target_precompile_headers(${target} REUSE_FROM ${MBRT_MODEL_PCH})
  endif()
endfunction()
