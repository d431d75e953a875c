/**
 * @class   vtkStrataMeshOutput
 * @brief   builds VTK outputs from core results (not wrapped)
 *
 * Shared by the StrataMesh filters: triangles into a vtkUnstructuredGrid (cells through
 * offsets and connectivity, coordinates moved back from the model's local frame), and
 * per-point or per-cell arrays from plain vectors.
 *
 * @sa vtkStrataMeshInput
 */
#ifndef vtkStrataMeshOutput_h
#define vtkStrataMeshOutput_h

#include "Geometry.h" // strata::Vec2

#include <vtkSmartPointer.h> // for vtkSmartPointer

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

class vtkDataArray;
class vtkFieldData;
class vtkUnstructuredGrid;

class vtkStrataMeshOutput
{
public:
  /// Fills `output` with the triangles (counter-clockwise in, counter-clockwise out) over
  /// points + origin (z = 0). Any allocator (the core's working arrays use
  /// strata::LargeArrayAllocator).
  template<class PointAlloc, class TriangleAlloc>
  static void SetTriangles(vtkUnstructuredGrid* output,
    const std::vector<strata::Vec2, PointAlloc>& points,
    const std::vector<std::array<int, 3>, TriangleAlloc>& triangles,
    strata::Vec2 origin)
  {
    SetTriangles(output, points.data(), points.size(), triangles.data(), triangles.size(), origin);
  }
  static void SetTriangles(vtkUnstructuredGrid* output,
    const strata::Vec2* points,
    std::size_t numberOfPoints,
    const std::array<int, 3>* triangles,
    std::size_t numberOfTriangles,
    strata::Vec2 origin);

  /// An array named `name` holding `values` (integers become a vtkIntArray, doubles a
  /// vtkDoubleArray).
  template<class T, class Alloc>
  static vtkSmartPointer<vtkDataArray> MakeArray(const char* name,
    const std::vector<T, Alloc>& values)
  {
    return MakeArray(name, values.data(), values.size());
  }
  static vtkSmartPointer<vtkDataArray> MakeArray(const char* name,
    const int* values,
    std::size_t count);
  static vtkSmartPointer<vtkDataArray> MakeArray(const char* name,
    const std::int8_t* values,
    std::size_t count);
  static vtkSmartPointer<vtkDataArray> MakeArray(const char* name,
    const double* values,
    std::size_t count);

  /// Adds a one-value array to field data (numbers as vtkDoubleArray/vtkIntArray).
  static void AddField(vtkFieldData* fd, const char* name, double value);
  static void AddField(vtkFieldData* fd, const char* name, int value);
};

#endif
