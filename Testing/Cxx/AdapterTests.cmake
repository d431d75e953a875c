# Adapter tests: the VTK filters through real VTK pipelines (reader -> filter -> checks).
set(_adapter_tests
  Adaptive48GridFilterTest
  PhysicalCompressionTriangulatorTest
  PolylineSignedDistanceFilterTest
  TargetEdgeLengthFilterTest
  )
foreach (_test IN LISTS _adapter_tests)
  add_executable(${_test} ${_test}.cxx)
  target_link_libraries(${_test} PRIVATE
    StrataMesh::Filters VTK::IOXML VTK::ImagingHybrid VTK::FiltersSources GTest::gtest_main)
  target_compile_definitions(${_test} PRIVATE STRATAMESH_DATA_DIR="${PROJECT_SOURCE_DIR}/Data")
  gtest_discover_tests(${_test} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "adapter")
endforeach ()

# Property ranges: every filter names a property out of range and fails (no silent clamping).
add_executable(PropertyValidationTest PropertyValidationTest.cxx)
target_link_libraries(PropertyValidationTest PRIVATE
  StrataMesh::Filters VTK::IOXML GTest::gtest_main)
target_compile_definitions(PropertyValidationTest PRIVATE
  STRATAMESH_DATA_DIR="${PROJECT_SOURCE_DIR}/Data")
gtest_discover_tests(PropertyValidationTest DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "adapter")
