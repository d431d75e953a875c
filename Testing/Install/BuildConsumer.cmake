# cmake -DCONSUMER_SOURCE=<Testing/Consumer> -DCONSUMER_BUILD=<dir> -DPREFIX=<install prefix>
#       -DGENERATOR=<generator> -DC_COMPILER=<cc> -DCXX_COMPILER=<c++> -DBUILD_TYPE=<config>
#       -P BuildConsumer.cmake
# Configures and builds the outside project Testing/Consumer against the installed StrataMesh
# (found through CMAKE_PREFIX_PATH only), from an empty build folder.
cmake_minimum_required(VERSION 3.16)
foreach (_var IN ITEMS CONSUMER_SOURCE CONSUMER_BUILD PREFIX GENERATOR)
  if (NOT DEFINED ${_var})
    message(FATAL_ERROR "${_var} is not set")
  endif ()
endforeach ()

file(REMOVE_RECURSE "${CONSUMER_BUILD}")
set(_args
  -S "${CONSUMER_SOURCE}" -B "${CONSUMER_BUILD}" -G "${GENERATOR}"
  "-DCMAKE_PREFIX_PATH=${PREFIX}"
  # Only the prefix: not the user's package registry.
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
if (BUILD_TYPE)
  list(APPEND _args "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}")
endif ()
if (C_COMPILER)
  list(APPEND _args "-DCMAKE_C_COMPILER=${C_COMPILER}")
endif ()
if (CXX_COMPILER)
  list(APPEND _args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif ()
execute_process(COMMAND "${CMAKE_COMMAND}" ${_args}
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
message(STATUS "configure:\n${_output}")
if (NOT _result EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed (${_result})")
endif ()

# The package must come from the prefix just installed.
file(STRINGS "${CONSUMER_BUILD}/CMakeCache.txt" _dir REGEX "^StrataMesh_DIR:")
string(REGEX REPLACE "^StrataMesh_DIR:[A-Z]+=" "" _dir "${_dir}")
get_filename_component(_prefix "${PREFIX}" REALPATH)
get_filename_component(_dir "${_dir}" REALPATH)
string(FIND "${_dir}/" "${_prefix}/" _at)
if (NOT _at EQUAL 0)
  message(FATAL_ERROR "StrataMesh was found in ${_dir}, not under ${_prefix}")
endif ()

set(_build_args)
if (BUILD_TYPE)
  set(_build_args --config "${BUILD_TYPE}")
endif ()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${CONSUMER_BUILD}" ${_build_args}
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
message(STATUS "build:\n${_output}")
if (NOT _result EQUAL 0)
  message(FATAL_ERROR "building the consumer failed (${_result})")
endif ()
