# cmake -DPREFIX=<install prefix> -DFORBIDDEN="<dir>;<dir>" -P check_relocatable.cmake
# Fails if an installed package file (CMake config, pkg-config file) names one of FORBIDDEN (the
# source, crate or build directory, which contains the test prefix itself): the package must
# find everything relative to its own location.
file(GLOB_RECURSE files "${PREFIX}/*.cmake" "${PREFIX}/*.pc")
if(NOT files)
  message(FATAL_ERROR "no package files under ${PREFIX}")
endif()
foreach(f IN LISTS files)
  file(READ "${f}" text)
  foreach(dir IN LISTS FORBIDDEN)
    string(FIND "${text}" "${dir}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${f} names the build-time path ${dir}")
    endif()
  endforeach()
endforeach()
list(LENGTH files n)
message(STATUS "${n} package files name no build-time path")
