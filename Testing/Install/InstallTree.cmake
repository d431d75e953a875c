# cmake -DBUILD_DIR=<build> -DPREFIX=<dir> -DSOURCE_DIR=<source> -DPLUGIN_DIR=<rel. path>
#       -DCMAKE_DIR=<rel. path> -DHEADERS_DIR=<rel. path> [-DCONFIG=<config>]
#       -P InstallTree.cmake
# (PLUGIN_DIR, CMAKE_DIR, HEADERS_DIR: where the plugin, the CMake package and the headers
# go, relative to the prefix, e.g. lib/paraview-5.11/plugins/StrataMesh, lib/cmake/StrataMesh,
# include/StrataMesh_Plugins.)
# Installs the build tree into an empty PREFIX and checks what an outside project gets: the
# module's library and public headers, the plugin, the CMake package; and nothing of the
# core (no core header, no StrataMeshCore in the exported interface, no source paths).
cmake_minimum_required(VERSION 3.16)
foreach (_var IN ITEMS BUILD_DIR PREFIX SOURCE_DIR PLUGIN_DIR CMAKE_DIR HEADERS_DIR)
  if (NOT DEFINED ${_var})
    message(FATAL_ERROR "${_var} is not set")
  endif ()
endforeach ()

file(REMOVE_RECURSE "${PREFIX}")
set(_config_args)
if (CONFIG)
  set(_config_args --config "${CONFIG}")
endif ()
execute_process(
  COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}" ${_config_args}
  RESULT_VARIABLE _result
  OUTPUT_VARIABLE _output
  ERROR_VARIABLE _output)
if (NOT _result EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${_result}):\n${_output}")
endif ()

set(_failures "")
macro (_fail message)
  string(APPEND _failures "  ${message}\n")
endmacro ()

# What must be there.
set(_headers
  vtkAdaptive48Grid.h
  vtkClassify48Grid.h
  vtkPhysicalCompressionTriangulator.h
  vtkPolylineSignedDistance.h
  vtkPolylineSignedDistanceFilter.h
  vtkStrataMeshAlgorithm.h
  StrataMeshFiltersModule.h)
set(_expected
  "${PLUGIN_DIR}/StrataMesh.so"
  "${PLUGIN_DIR}/libStrataMeshFilters.so"
  "${CMAKE_DIR}/StrataMeshConfig.cmake"
  "${CMAKE_DIR}/StrataMeshConfigVersion.cmake"
  "${CMAKE_DIR}/StrataMesh-targets.cmake"
  "${CMAKE_DIR}/StrataMeshPlugins-targets.cmake")
foreach (_header IN LISTS _headers)
  list(APPEND _expected "${HEADERS_DIR}/${_header}")
endforeach ()
foreach (_file IN LISTS _expected)
  if (NOT EXISTS "${PREFIX}/${_file}")
    _fail("missing: ${_file}")
  endif ()
endforeach ()

# Nothing of the core: no core header installed, none included by an installed header.
file(GLOB _core_headers RELATIVE "${SOURCE_DIR}/Filters/Core" "${SOURCE_DIR}/Filters/Core/*.h")
file(GLOB_RECURSE _installed RELATIVE "${PREFIX}" "${PREFIX}/*")
foreach (_file IN LISTS _installed)
  get_filename_component(_name "${_file}" NAME)
  if (_name IN_LIST _core_headers)
    _fail("core header installed: ${_file}")
  endif ()
  if (_file MATCHES "StrataMeshCore")
    _fail("core library installed: ${_file}")
  endif ()
  if (_file MATCHES "\\.h$")
    file(STRINGS "${PREFIX}/${_file}" _includes REGEX "^[ \t]*#[ \t]*include")
    foreach (_include IN LISTS _includes)
      if (_include MATCHES "[<\"]([^>\"]+)[>\"]")
        if (CMAKE_MATCH_1 IN_LIST _core_headers)
          _fail("${_file} includes the core header ${CMAKE_MATCH_1}")
        endif ()
      endif ()
    endforeach ()
  endif ()
  if (_file MATCHES "\\.cmake$")
    file(READ "${PREFIX}/${_file}" _content)
    foreach (_leak IN ITEMS "StrataMeshCore" "StrataMesh::Core" "${SOURCE_DIR}" "${BUILD_DIR}")
      string(FIND "${_content}" "${_leak}" _at)
      if (NOT _at EQUAL -1)
        _fail("${_file} mentions ${_leak}")
      endif ()
    endforeach ()
  endif ()
endforeach ()

if (_failures)
  message(FATAL_ERROR "The install tree in ${PREFIX} is wrong:\n${_failures}")
endif ()
list(LENGTH _installed _count)
message(STATUS "Installed ${_count} files into ${PREFIX}; headers, library, plugin and "
  "CMake package present; nothing of the core.")
