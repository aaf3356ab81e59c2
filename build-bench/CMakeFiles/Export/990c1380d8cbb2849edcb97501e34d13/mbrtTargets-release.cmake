#----------------------------------------------------------------
# Generated CMake target import file for configuration "Release".
#----------------------------------------------------------------

# Commands may need to know the format version.
set(CMAKE_IMPORT_FILE_VERSION 1)

# Import target "mbrt::mbrt_cli" for configuration "Release"
set_property(TARGET mbrt::mbrt_cli APPEND PROPERTY IMPORTED_CONFIGURATIONS RELEASE)
set_target_properties(mbrt::mbrt_cli PROPERTIES
  IMPORTED_LOCATION_RELEASE "${_IMPORT_PREFIX}/bin/mbrt"
  )

list(APPEND _cmake_import_check_targets mbrt::mbrt_cli )
list(APPEND _cmake_import_check_files_for_mbrt::mbrt_cli "${_IMPORT_PREFIX}/bin/mbrt" )

# Commands beyond this point should not need to know the version.
set(CMAKE_IMPORT_FILE_VERSION)
