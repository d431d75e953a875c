#include "vtkClassify48Grid.h"

#include "vtkStrataMeshOutput.h"
#include "vtkStrataMeshRange.h"

#include "GridSession.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <limits>

vtkStandardNewMacro(vtkClassify48Grid);

vtkClassify48Grid::vtkClassify48Grid()
{
  this->SetNumberOfOutputPorts(2);
}

vtkClassify48Grid::~vtkClassify48Grid() = default;

vtkPolyData* vtkClassify48Grid::GetEdgesOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkClassify48Grid::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkUnstructuredGrid" : "vtkPolyData");
  return 1;
}

int vtkClassify48Grid::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* grid = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkPolyData* edges = vtkPolyData::GetData(outputVector, 1);
  if (!input || !grid || !edges)
  {
    vtkErrorMacro(<< "missing input or output");
    return 0;
  }
  strata::TriangleMesh mesh;
  strata::Classification classes;
  const std::shared_ptr<strata::GridSession> session = this->ExtractMesh(input,
    vtkDataSet::GetData(inputVector[1], 0),
    mesh,
    [&](strata::GridSession& s, const strata::TriangleMesh& m)
    {
      strata::ClassificationParams params;
      params.boundaryTolerance = this->BoundaryTolerance;
      classes = s.classify(m, params, strata::ProgressReporter(this->ProgressCallback(), 0.8, 1.0));
    });
  if (!session)
  {
    return 0;
  }
  if (session->empty())
  {
    return 1; // empty model: empty outputs (with the warning reported)
  }

  const strata::Vec2 origin = session->model().origin;
  vtkStrataMeshOutput::SetTriangles(grid, mesh.points, mesh.triangles, origin);
  grid->GetPointData()->AddArray(
    vtkStrataMeshOutput::MakeArray("VertexClass", classes.vertexClass));
  grid->GetPointData()->AddArray(
    vtkStrataMeshOutput::MakeArray("VertexRegion", classes.vertexRegion));
  grid->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("CellRegion", classes.cellRegion));
  grid->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("Level", mesh.triangleLevel));

  // The edges as two-point lines over the same points.
  edges->SetPoints(grid->GetPoints());
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  const vtkIdType numberOfEdges = static_cast<vtkIdType>(classes.edges.size());
  offsets->SetNumberOfValues(numberOfEdges + 1);
  connectivity->SetNumberOfValues(2 * numberOfEdges);
  for (vtkIdType e = 0; e <= numberOfEdges; ++e)
  {
    offsets->SetValue(e, 2 * e);
  }
  for (vtkIdType e = 0; e < numberOfEdges; ++e)
  {
    connectivity->SetValue(2 * e, classes.edges[static_cast<std::size_t>(e)][0]);
    connectivity->SetValue(2 * e + 1, classes.edges[static_cast<std::size_t>(e)][1]);
  }
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  lines->SetData(offsets, connectivity);
  edges->SetLines(lines);
  edges->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("EdgeClass", classes.edgeClass));
  edges->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("EdgeRegion", classes.edgeRegion));
  this->UpdateProgress(1.0);
  return 1;
}

bool vtkClassify48Grid::CheckProperties()
{
  const double inf = std::numeric_limits<double>::infinity();
  bool valid = this->Superclass::CheckProperties();
  valid &= vtkStrataMeshRange::Check(this, "BoundaryTolerance", this->BoundaryTolerance, 0.0, inf);
  return valid;
}

void vtkClassify48Grid::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BoundaryTolerance: " << this->BoundaryTolerance << "\n";
}
