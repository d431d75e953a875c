#include "vtkAdaptive48Grid.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshOutput.h"
#include "vtkStrataMeshRange.h"

#include "GridSession.h"

#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <exception>
#include <sstream>

vtkStandardNewMacro(vtkAdaptive48Grid);

vtkAdaptive48Grid::vtkAdaptive48Grid() = default;
vtkAdaptive48Grid::~vtkAdaptive48Grid() = default;

vtkUnstructuredGrid* vtkAdaptive48Grid::GetOutput()
{
  return this->GetOutput(0);
}

vtkUnstructuredGrid* vtkAdaptive48Grid::GetOutput(int port)
{
  return vtkUnstructuredGrid::SafeDownCast(this->GetOutputDataObject(port));
}

int vtkAdaptive48Grid::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkUnstructuredGrid");
  return 1;
}

std::shared_ptr<strata::GridSession> vtkAdaptive48Grid::UpdateSession(vtkPolyData* input,
  const strata::Grid48Params& params)
{
  std::ostringstream key;
  key << input << ' ' << input->GetMTime() << ' ' << this->Form << ' '
      << (this->RegionArrayName ? this->RegionArrayName : "") << ' '
      << (this->LeftRegionArrayName ? this->LeftRegionArrayName : "") << ' '
      << (this->RightRegionArrayName ? this->RightRegionArrayName : "");
  try
  {
    if (!this->Session || this->SessionKey != key.str())
    {
      this->Session.reset();
      this->Session = std::make_shared<strata::GridSession>(vtkStrataMeshInput::ToRaw(input,
        vtkStrataMeshInput::MakeSelection(this->Form,
          this->RegionArrayName,
          this->LeftRegionArrayName,
          this->RightRegionArrayName)));
      this->SessionKey = key.str();
    }
    if (!this->Session->empty())
    {
      this->Session->refine(params, strata::ProgressReporter(this->ProgressCallback(), 0.0, 0.8));
    }
  }
  catch (...)
  {
    this->Session.reset(); // a failed or aborted refinement is not reused
    throw;
  }
  return this->Session;
}

std::shared_ptr<strata::GridSession> vtkAdaptive48Grid::ExtractMesh(vtkPolyData* input,
  vtkDataSet* target,
  strata::TriangleMesh& mesh,
  const std::function<void(strata::GridSession&, const strata::TriangleMesh&)>& more)
{
  strata::Grid48Params params;
  if (!this->CheckProperties() || !this->FillGridParams(target, params))
  {
    return nullptr;
  }
  std::shared_ptr<strata::GridSession> session;
  try
  {
    session = this->UpdateSession(input, params);
    if (!session->empty())
    {
      mesh = session->extract(this->OutputLevel);
      if (more)
      {
        more(*session, mesh);
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    return nullptr;
  }
  for (const std::string& warning : session->warnings())
  {
    vtkWarningMacro(<< warning);
  }
  return session;
}

int vtkAdaptive48Grid::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector, 0);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output");
    return 0;
  }
  strata::TriangleMesh mesh;
  const std::shared_ptr<strata::GridSession> session =
    this->ExtractMesh(input, vtkDataSet::GetData(inputVector[1], 0), mesh);
  if (!session)
  {
    return 0;
  }
  if (session->empty())
  {
    return 1; // empty model: empty output (with the warning reported)
  }

  vtkStrataMeshOutput::SetTriangles(output, mesh.points, mesh.triangles, session->model().origin);
  output->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("Level", mesh.triangleLevel));
  output->GetPointData()->AddArray(vtkStrataMeshOutput::MakeArray("Level", mesh.pointLevel));
  const strata::Grid48Params& used = session->grid().params();
  vtkFieldData* fd = output->GetFieldData();
  vtkStrataMeshOutput::AddField(fd, "MaxLevel", used.maxLevel);
  vtkStrataMeshOutput::AddField(fd, "LocalMaxLevel", used.localMaxLevel);
  vtkStrataMeshOutput::AddField(fd, "Tolerance", used.tolerance);
  if (used.targetEdgeLength)
  {
    vtkStrataMeshOutput::AddField(fd, "TargetMaxLevel", used.targetMaxLevel);
  }
  vtkStrataMeshOutput::AddField(
    fd, "GridMemoryBytes", static_cast<double>(session->grid().memoryBytes()));
  this->UpdateProgress(1.0);
  return 1;
}

bool vtkAdaptive48Grid::CheckProperties()
{
  bool valid = this->Superclass::CheckProperties();
  valid &= vtkStrataMeshRange::Check(this, "OutputLevel", this->OutputLevel, -1, 60);
  return valid;
}

void vtkAdaptive48Grid::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "OutputLevel: " << this->OutputLevel << "\n";
}
