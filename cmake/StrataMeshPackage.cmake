# The CMake package StrataMesh: StrataMeshConfig.cmake and its version file, for the install
# tree (lib/cmake/StrataMesh) and for the build tree (<build>/lib/cmake/StrataMesh, which has
# the install tree's layout). paraview_plugin_build(INSTALL_EXPORT ...) in the top
# CMakeLists.txt writes and installs the exported targets next to them:
#   StrataMesh-targets.cmake, StrataMesh-vtk-module-properties.cmake,
#   StrataMesh-vtk-module-find-packages.cmake     the module StrataMesh::Filters
#   StrataMeshPlugins-targets.cmake               the plugin StrataMesh::StrataMesh
#   StrataMeshPlugins-Plugins-targets-depends.cmake   loads the module files in order
# Included from the top CMakeLists.txt after paraview_plugin_build; uses
# STRATAMESH_CMAKE_DESTINATION and STRATAMESH_PLUGIN_SUBDIRECTORY.
include(CMakePackageConfigHelpers)

if (NOT BUILD_SHARED_LIBS)
  # The installed StrataMesh::Filters does not carry the core (linked as a build-only
  # dependency), which only a shared library may leave out of its interface.
  message(WARNING "BUILD_SHARED_LIBS is OFF: the installed CMake package is not usable.")
endif ()

# Values substituted into StrataMeshConfig.cmake.
set(STRATAMESH_PARAVIEW_VERSION "${ParaView_VERSION_MAJOR}.${ParaView_VERSION_MINOR}")
set(STRATAMESH_PARAVIEW_DIR "${ParaView_DIR}")
set(STRATAMESH_PLUGIN_DIR "${CMAKE_INSTALL_LIBDIR}/${STRATAMESH_PLUGIN_SUBDIRECTORY}/StrataMesh")

set(_stratamesh_build_cmake_dir "${CMAKE_BINARY_DIR}/${STRATAMESH_CMAKE_DESTINATION}")
set(_stratamesh_config_in "${CMAKE_CURRENT_LIST_DIR}/StrataMeshConfig.cmake.in")

# Install tree: paths relative to the installed file (the prefix may be moved).
configure_package_config_file("${_stratamesh_config_in}"
  "${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/StrataMeshConfig.cmake.install"
  INSTALL_DESTINATION "${STRATAMESH_CMAKE_DESTINATION}"
  PATH_VARS STRATAMESH_PLUGIN_DIR)
# Build tree: the same file with the build directory as prefix.
configure_package_config_file("${_stratamesh_config_in}"
  "${_stratamesh_build_cmake_dir}/StrataMeshConfig.cmake"
  INSTALL_DESTINATION "${STRATAMESH_CMAKE_DESTINATION}"
  INSTALL_PREFIX "${CMAKE_BINARY_DIR}"
  PATH_VARS STRATAMESH_PLUGIN_DIR)
# 0.x: a minor version may break the interface.
write_basic_package_version_file("${_stratamesh_build_cmake_dir}/StrataMeshConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMinorVersion)

install(
  FILES "${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/StrataMeshConfig.cmake.install"
  DESTINATION "${STRATAMESH_CMAKE_DESTINATION}"
  RENAME "StrataMeshConfig.cmake"
  COMPONENT development)
install(
  FILES "${_stratamesh_build_cmake_dir}/StrataMeshConfigVersion.cmake"
  DESTINATION "${STRATAMESH_CMAKE_DESTINATION}"
  COMPONENT development)
