# Installs mbrt into a scratch prefix, then configures, builds and runs
# examples/control_loop against it with find_package(mbrt), as a user would,
# and once more with `mbrt gen` and a compiler call from pkg-config.
# Arguments: -DMBRT_BUILD=<build dir> -DMBRT_SOURCE=<source dir> -DWORK=<scratch dir> -DCXX=<C++ compiler>
file(REMOVE_RECURSE "${WORK}")
foreach(step
    "install;--install;${MBRT_BUILD};--prefix;${WORK}/prefix"
    "configure;-S;${MBRT_SOURCE}/examples/control_loop;-B;${WORK}/build;-DCMAKE_PREFIX_PATH=${WORK}/prefix;-DCMAKE_BUILD_TYPE=Release"
    "build;--build;${WORK}/build")
  list(POP_FRONT step name)
  execute_process(COMMAND ${CMAKE_COMMAND} ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "example ${name} failed:\n${out}")
  endif()
endforeach()
execute_process(COMMAND "${WORK}/build/control_loop" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
message("${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "control_loop failed (exit ${rc})")
endif()
# The installed mbrt simulates on its own, with the installed headers.
execute_process(COMMAND ${CMAKE_COMMAND} -E env MBRT_CACHE_DIR=${WORK}/cache
  "${WORK}/prefix/bin/mbrt" sim "${MBRT_SOURCE}/examples/control_loop/double_pendulum.yaml" --t-end 0.1 --verbose
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "\"status\": ?\"ok\"" OR NOT err MATCHES "-I'${WORK}/prefix/include'")
  message(FATAL_ERROR "installed mbrt sim failed (exit ${rc}):\n${out}\n${err}")
endif()

# Without CMake: mbrt gen, then the compiler with pkg-config's flags.
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} "${WORK}/prefix/share/pkgconfig")
execute_process(COMMAND "${PKG_CONFIG}" --cflags mbrt RESULT_VARIABLE rc OUTPUT_VARIABLE cflags ERROR_VARIABLE err
  OUTPUT_STRIP_TRAILING_WHITESPACE)
separate_arguments(cflags UNIX_COMMAND "${cflags}")
set(mbrt_include "")
foreach(flag ${cflags})
  if(flag MATCHES "^-I(.*share/pkgconfig.*)$")
    file(REAL_PATH "${CMAKE_MATCH_1}" mbrt_include)
  endif()
endforeach()
file(REAL_PATH "${WORK}/prefix/include" expected_include)
if(NOT rc EQUAL 0 OR NOT mbrt_include STREQUAL expected_include)
  message(FATAL_ERROR "pkg-config --cflags mbrt (exit ${rc}): '${cflags}' does not name ${expected_include} ${err}")
endif()
foreach(step
    "${WORK}/prefix/bin/mbrt;gen;${MBRT_SOURCE}/examples/control_loop/double_pendulum.yaml;-o;${WORK}/pc"
    "${CXX};-O2;${cflags};-I${WORK}/pc;${MBRT_SOURCE}/examples/control_loop/main.cpp;${WORK}/pc/double_pendulum.cpp;-o;${WORK}/pc/control_loop"
    "${WORK}/pc/control_loop")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "with pkg-config: ${step} failed (exit ${rc}):\n${out}")
  endif()
endforeach()
message("with pkg-config: ${out}")
