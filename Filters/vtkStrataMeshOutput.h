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
#include <cstdint>
#include <vector>

class vtkDataArray;
class vtkFieldData;
class vtkUnstructuredGrid;

class vtkStrataMeshOutput
{
public:
  /// Fills `output` with the triangles (counter-clockwise in, counter-clockwise out) over
  /// points + origin (z = 0).
  static void SetTriangles(vtkUnstructuredGrid* output, const std::vector<strata::Vec2>& points,
    const std::vector<std::array<int, 3>>& triangles, strata::Vec2 origin);

  /// An array named `name` holding `values` (integers become a vtkIntArray, doubles a
  /// vtkDoubleArray).
  static vtkSmartPointer<vtkDataArray> MakeArray(const char* name, const std::vector<int>& values);
  static vtkSmartPointer<vtkDataArray> MakeArray(
    const char* name, const std::vector<std::int8_t>& values);
  static vtkSmartPointer<vtkDataArray> MakeArray(
    const char* name, const std::vector<double>& values);

  /// Adds a one-value array to field data (numbers as vtkDoubleArray/vtkIntArray).
  static void AddField(vtkFieldData* fd, const char* name, double value);
  static void AddField(vtkFieldData* fd, const char* name, int value);
};

#endif
