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
template<typename ArrayT, typename T>
vtkSmartPointer<vtkDataArray> Fill(const char* name, const T* values, std::size_t count)
{
  auto array = vtkSmartPointer<ArrayT>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(count));
  for (std::size_t i = 0; i < count; ++i)
  {
    array->SetValue(static_cast<vtkIdType>(i), values[i]);
  }
  return array;
}
} // namespace

void vtkStrataMeshOutput::SetTriangles(vtkUnstructuredGrid* output,
  const strata::Vec2* points,
  std::size_t numberOfPoints,
  const std::array<int, 3>* triangles,
  std::size_t numberOfTriangles,
  strata::Vec2 origin)
{
  auto coordinates = vtkSmartPointer<vtkPoints>::New();
  coordinates->SetDataTypeToDouble();
  coordinates->SetNumberOfPoints(static_cast<vtkIdType>(numberOfPoints));
  for (std::size_t i = 0; i < numberOfPoints; ++i)
  {
    coordinates->SetPoint(
      static_cast<vtkIdType>(i), points[i].x + origin.x, points[i].y + origin.y, 0.0);
  }
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfValues(static_cast<vtkIdType>(numberOfTriangles + 1));
  connectivity->SetNumberOfValues(static_cast<vtkIdType>(3 * numberOfTriangles));
  for (std::size_t t = 0; t <= numberOfTriangles; ++t)
  {
    offsets->SetValue(static_cast<vtkIdType>(t), static_cast<vtkIdType>(3 * t));
  }
  for (std::size_t t = 0; t < numberOfTriangles; ++t)
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

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(const char* name,
  const int* values,
  std::size_t count)
{
  return Fill<vtkIntArray>(name, values, count);
}

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(const char* name,
  const std::int8_t* values,
  std::size_t count)
{
  return Fill<vtkIntArray>(
    name, values, count); // small classes, but int arrays are what users expect
}

vtkSmartPointer<vtkDataArray> vtkStrataMeshOutput::MakeArray(const char* name,
  const double* values,
  std::size_t count)
{
  return Fill<vtkDoubleArray>(name, values, count);
}

void vtkStrataMeshOutput::AddField(vtkFieldData* fd, const char* name, double value)
{
  fd->AddArray(Fill<vtkDoubleArray>(name, &value, 1));
}

void vtkStrataMeshOutput::AddField(vtkFieldData* fd, const char* name, int value)
{
  fd->AddArray(Fill<vtkIntArray>(name, &value, 1));
}
