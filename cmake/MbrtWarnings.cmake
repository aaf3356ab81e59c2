# mbrt_enable_warnings(<target>... [NO_ERROR])
#
# Compiles the targets with -Wall -Wextra -Wswitch-enum: a switch over one of
# the project's enums lists every enumerator, so a new joint or element type
# shows each switch that must handle it. With GCC, the compiler the project's
# code is kept clean with, warnings are errors unless NO_ERROR is given.
# Eigen and the other dependencies come in through -isystem and stay quiet.
function(mbrt_enable_warnings)
  cmake_parse_arguments(ARG "NO_ERROR" "" "" ${ARGN})
  set(flags -Wall -Wextra -Wswitch-enum)
  # The Release build is the gate: a sanitized build at -O1 sees other
  # (maybe-uninitialized) diagnostics and only warns.
  if(NOT ARG_NO_ERROR AND NOT MBRT_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    list(APPEND flags -Werror)
  endif()
  # GCC 12 flags libstdc++'s own memcpy in basic_string::insert, inlined from
  # "literal" + std::string(...), as overlapping (GCC bug 105651, fixed in 13).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    list(APPEND flags -Wno-restrict)
  endif()
  foreach(target ${ARG_UNPARSED_ARGUMENTS})
    target_compile_options(${target} PRIVATE ${flags})
  endforeach()
endfunction()
