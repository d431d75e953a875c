#include "vtkStrataMeshOutput.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

namespace
{
template <typename ArrayT, typename T>
vtkSmartPointer<vtkDataArray> Fill(const char* name, const std::vector<T>& values)
{
  auto array = vtkSmartPointer<ArrayT>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  return array;
}
} // namespace

void vtkStrataMeshOutput::SetTriangles(vtkUnstructuredGrid* output,
  const std::vector<strata::Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
  strata::Vec2 origin)
{
  auto coordinates = vtkSmartPointer<vtkPoints>::New();
  coordinates->SetDataTypeToDouble();
  coordinates->SetNumberOfPoints(static_cast<vtkIdType>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    coordinates->SetPoint(
      static_cast<vtkIdType>(i), points[i].x + origin.x, points[i].y + origin.y, 0.0);
  }
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfValues(static_cast<vtkIdType>(triangles.size() + 1));
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(3 * triangles.size()));
  for (std::size_t t = 0; t <= triangles.size(); ++t)
  {
    offsets->SetValue(static_cast<vtkIdType>(t), static_cast<vtkIdType>(3 * t));
  }
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      connectivity->SetValue(static_cast<vtkIdType>(3 * t + k), triangles[t][k]);
    }
  }
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);
  output->SetPoints(coordinates);
  output->SetCells(VTK_TRIANGLE, cells);
}

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(
  const char* name, const std::vector<int>& values)
{
  return Fill<vtkIntArray>(name, values);
}

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(
  const char* name, const std::vector<std::int8_t>& values)
{
  return Fill<vtkIntArray>(name, values); // small classes, but int arrays are what users expect
}

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(
  const char* name, const std::vector<double>& values)
{
  return Fill<vtkDoubleArray>(name, values);
}

void vtkStrataMeshOutput::AddField(vtkFieldData* fd, const char* name, double value)
{
  fd->AddArray(Fill<vtkDoubleArray>(name, std::vector<double>{ value }));
}

void vtkStrataMeshOutput::AddField(vtkFieldData* fd, const char* name, int value)
{
  fd->AddArray(Fill<vtkIntArray>(name, std::vector<int>{ value }));
}
