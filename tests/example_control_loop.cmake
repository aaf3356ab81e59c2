# Installs mbrt into a scratch prefix, then configures, builds and runs
# examples/control_loop against it with find_package(mbrt), as a user would.
# Arguments: -DMBRT_BUILD=<build dir> -DMBRT_SOURCE=<source dir> -DWORK=<scratch dir>
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
if(NOT rc EQUAL 0 OR NOT out MATCHES "\"status\": \"ok\"" OR NOT err MATCHES "-I'${WORK}/prefix/include'")
  message(FATAL_ERROR "installed mbrt sim failed (exit ${rc}):\n${out}\n${err}")
endif()
