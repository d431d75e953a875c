#include "vtkPhysicalCompressionTriangulator.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshOutput.h"
#include "vtkStrataMeshRange.h"

#include "Mesher.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <cctype>
#include <exception>
#include <vector>

vtkStandardNewMacro(vtkPhysicalCompressionTriangulator);

vtkPhysicalCompressionTriangulator::vtkPhysicalCompressionTriangulator()
{
  this->SetNumberOfOutputPorts(2);
  const strata::CompressionParams defaults;
  this->SpringConfiguration = static_cast<int>(defaults.springConfiguration);
  this->SpringStiffness = defaults.springStiffness;
  this->Damping = defaults.damping;
  this->TimeStep = defaults.timeStep;
  this->MaxIterations = defaults.maxIterations;
  this->PushCriterion = static_cast<int>(defaults.pushCriterion);
  this->PushVelocity = defaults.pushVelocity;
  this->FeatureAngle = defaults.featureAngle;
  this->FlipDegenerate = defaults.flipDegenerate;
  this->Optimization = defaults.optimize;
  this->BoundaryTolerance = defaults.boundaryTolerance;
  this->MinimumAngle = strata::RefinementParams().minimumAngle;
  this->CurveRecovery = strata::MesherParams().curveRecovery;
  this->KeepSharpCorners = strata::MesherParams().keepSharpCorners;
  this->ThinLayerRetry = strata::MesherParams().thinLayerRetry;
}

vtkPhysicalCompressionTriangulator::~vtkPhysicalCompressionTriangulator() = default;

vtkUnstructuredGrid* vtkPhysicalCompressionTriangulator::GetOutput()
{
  return this->GetOutput(0);
}

vtkUnstructuredGrid* vtkPhysicalCompressionTriangulator::GetOutput(int port)
{
  return vtkUnstructuredGrid::SafeDownCast(this->GetOutputDataObject(port));
}

vtkPolyData* vtkPhysicalCompressionTriangulator::GetBoundaryOutput()
{
  return vtkPolyData::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkPhysicalCompressionTriangulator::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkUnstructuredGrid" : "vtkPolyData");
  return 1;
}

namespace
{

/// "grid refinement" -> "SecondsGridRefinement"
std::string StageFieldName(const std::string& stage)
{
  std::string name = "Seconds";
  bool upper = true;
  for (char c : stage)
  {
    if (!std::isalnum(static_cast<unsigned char>(c)))
    {
      upper = true;
      continue;
    }
    name += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return name;
}

void SetBoundary(vtkPolyData* output, const strata::MesherResult& result)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  std::vector<int> left, right;
  offsets->InsertNextValue(0);
  for (const strata::MesherResult::BoundaryCurve& curve : result.boundary)
  {
    for (const strata::Vec2& p : curve.points)
    {
      connectivity->InsertNextValue(
        points->InsertNextPoint(p.x + result.origin.x, p.y + result.origin.y, 0.0));
    }
    offsets->InsertNextValue(connectivity->GetNumberOfValues());
    left.push_back(curve.left);
    right.push_back(curve.right);
  }
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  lines->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetLines(lines);
  output->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("LeftRegion", left));
  output->GetCellData()->AddArray(vtkStrataMeshOutput::MakeArray("RightRegion", right));
}

} // namespace

int vtkPhysicalCompressionTriangulator::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkUnstructuredGrid* mesh = vtkUnstructuredGrid::GetData(outputVector, 0);
  vtkPolyData* boundary = vtkPolyData::GetData(outputVector, 1);
  if (!input || !mesh || !boundary)
  {
    vtkErrorMacro(<< "missing input or output");
    return 0;
  }
  if (!this->CheckProperties())
  {
    return 0;
  }

  strata::MesherParams params;
  if (!this->FillGridParams(vtkDataSet::GetData(inputVector[1], 0), params.grid))
  {
    return 0;
  }
  strata::CompressionParams& c = params.compression;
  c.springConfiguration = static_cast<strata::SpringConfiguration>(this->SpringConfiguration);
  c.springStiffness = this->SpringStiffness;
  c.damping = this->Damping;
  c.timeStep = this->TimeStep;
  c.maxIterations = this->MaxIterations;
  c.pushCriterion = static_cast<strata::PushCriterion>(this->PushCriterion);
  c.pushVelocity = this->PushVelocity;
  c.featureAngle = this->FeatureAngle;
  c.flipDegenerate = this->FlipDegenerate != 0;
  c.optimize = this->Optimization != 0;
  c.boundaryTolerance = this->BoundaryTolerance;
  params.refinement.minimumAngle = this->MinimumAngle;
  params.curveRecovery = this->CurveRecovery != 0;
  params.keepSharpCorners = this->KeepSharpCorners != 0;
  params.thinLayerRetry = this->ThinLayerRetry != 0;

  strata::MesherResult result;
  try
  {
    result = strata::triangulate(vtkStrataMeshInput::ToRaw(input,
                                   vtkStrataMeshInput::MakeSelection(this->Form,
                                     this->RegionArrayName,
                                     this->LeftRegionArrayName,
                                     this->RightRegionArrayName)),
      params,
      this->ProgressCallback());
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  for (const std::string& warning : result.warnings)
  {
    vtkWarningMacro(<< warning);
  }
  if (result.triangles.empty())
  {
    return 1; // empty model: empty outputs (with the warning above)
  }

  vtkStrataMeshOutput::SetTriangles(mesh, result.points, result.triangles, result.origin);
  vtkCellData* cd = mesh->GetCellData();
  cd->AddArray(vtkStrataMeshOutput::MakeArray("RegionId", result.regionId));
  cd->AddArray(vtkStrataMeshOutput::MakeArray("MinimumAngle", result.minAngle));
  cd->AddArray(vtkStrataMeshOutput::MakeArray("MaximumAngle", result.maxAngle));
  cd->AddArray(vtkStrataMeshOutput::MakeArray("RadiusRatio", result.radiusRatio));
  cd->AddArray(vtkStrataMeshOutput::MakeArray("Area", result.area));
  cd->AddArray(vtkStrataMeshOutput::MakeArray("Level", result.level));
  cd->SetActiveScalars("RegionId");
  vtkPointData* pd = mesh->GetPointData();
  pd->AddArray(vtkStrataMeshOutput::MakeArray("VertexClass", result.vertexClass));
  auto displacement = vtkSmartPointer<vtkDoubleArray>::New();
  displacement->SetName("Displacement");
  displacement->SetNumberOfComponents(3);
  displacement->SetNumberOfTuples(static_cast<vtkIdType>(result.displacement.size()));
  for (std::size_t i = 0; i < result.displacement.size(); ++i)
  {
    displacement->SetTuple3(
      static_cast<vtkIdType>(i), result.displacement[i].x, result.displacement[i].y, 0.0);
  }
  pd->AddArray(displacement);

  const strata::MesherResult::Summary& s = result.summary;
  vtkFieldData* fd = mesh->GetFieldData();
  vtkStrataMeshOutput::AddField(fd, "NumberOfTriangles", static_cast<int>(s.triangles));
  vtkStrataMeshOutput::AddField(fd, "NumberOfVertices", static_cast<int>(s.vertices));
  vtkStrataMeshOutput::AddField(fd, "MinimumAngle", s.minAngle);
  vtkStrataMeshOutput::AddField(fd, "MaximumAngle", s.maxAngle);
  vtkStrataMeshOutput::AddField(fd, "PercentAngles30To60", s.percentAngles30to60);
  vtkStrataMeshOutput::AddField(fd, "PercentTriangles30To60", s.percentTriangles30to60);
  vtkStrataMeshOutput::AddField(fd, "MaxBoundaryDeviation", s.maxBoundaryDeviation);
  vtkStrataMeshOutput::AddField(fd, "MaxRelativeBoundaryDeviation", s.maxRelativeDeviation);
  vtkStrataMeshOutput::AddField(fd, "MaxBoundaryVertexDistance", s.maxBoundaryVertexDistance);
  vtkStrataMeshOutput::AddField(fd, "MaxRegionAreaError", s.maxRegionAreaError);
  vtkStrataMeshOutput::AddField(fd, "MaxRegionMisplacedArea", s.maxRegionMisplacedArea);
  vtkStrataMeshOutput::AddField(fd, "FinestEdgeLength", s.finestEdgeLength);
  vtkStrataMeshOutput::AddField(fd, "Iterations", s.iterations);
  vtkStrataMeshOutput::AddField(fd, "BoundarySplits", static_cast<int>(s.boundarySplits));
  vtkStrataMeshOutput::AddField(fd, "RefinementVertices", static_cast<int>(s.refinementVertices));
  vtkStrataMeshOutput::AddField(fd, "CurveVertices", static_cast<int>(s.curveVertices));
  vtkStrataMeshOutput::AddField(
    fd, "TrianglesAtSharpCorners", static_cast<int>(s.trianglesAtSharpCorners));
  vtkStrataMeshOutput::AddField(
    fd, "TrianglesBelowMinimumAngle", static_cast<int>(s.trianglesBelowMinimumAngle));
  vtkStrataMeshOutput::AddField(fd, "MinimumAngleUnforced", s.minAngleUnforced);
  vtkStrataMeshOutput::AddField(fd, "LocalMaxLevel", s.localMaxLevel);
  if (params.keepSharpCorners)
  {
    vtkStrataMeshOutput::AddField(fd, "KeptCorners", static_cast<int>(result.keptCorners.size()));
    vtkStrataMeshOutput::AddField(
      fd, "KeptCornerTriangles", static_cast<int>(s.keptCornerTriangles));
  }
  vtkStrataMeshOutput::AddField(fd, "ThinLayerMesh", s.thinLayerMesh ? 1 : 0);
  auto unresolved = vtkSmartPointer<vtkIntArray>::New();
  unresolved->SetName("UnresolvedRegions");
  for (int id : result.unresolvedRegions)
  {
    unresolved->InsertNextValue(id);
  }
  fd->AddArray(unresolved);
  auto broken = vtkSmartPointer<vtkIntArray>::New();
  broken->SetName("BrokenRegions");
  for (int id : result.brokenRegions)
  {
    broken->InsertNextValue(id);
  }
  fd->AddArray(broken);
  // Each region's areas, in the model's order of regions.
  std::vector<int> regionIds;
  std::vector<double> modelAreas, meshAreas, misplacedAreas;
  for (const strata::MesherResult::RegionArea& ra : result.regionAreas)
  {
    regionIds.push_back(ra.id);
    modelAreas.push_back(ra.model);
    meshAreas.push_back(ra.mesh);
    misplacedAreas.push_back(ra.misplaced);
  }
  const std::size_t regions = regionIds.size();
  fd->AddArray(vtkStrataMeshOutput::MakeArray("RegionIds", regionIds.data(), regions));
  fd->AddArray(vtkStrataMeshOutput::MakeArray("RegionModelArea", modelAreas.data(), regions));
  fd->AddArray(vtkStrataMeshOutput::MakeArray("RegionMeshArea", meshAreas.data(), regions));
  fd->AddArray(
    vtkStrataMeshOutput::MakeArray("RegionMisplacedArea", misplacedAreas.data(), regions));
  for (const auto& [stage, seconds] : s.secondsPerStage)
  {
    vtkStrataMeshOutput::AddField(fd, StageFieldName(stage).c_str(), seconds);
  }
  vtkStrataMeshOutput::AddField(fd, "SecondsTotal", s.totalSeconds);

  SetBoundary(boundary, result);
  this->UpdateProgress(1.0);
  return 1;
}

bool vtkPhysicalCompressionTriangulator::CheckProperties()
{
  using Range = vtkStrataMeshRange;
  bool valid = this->Superclass::CheckProperties();
  valid &= Range::Check(this, "SpringConfiguration", this->SpringConfiguration, 0, 1);
  valid &= Range::Check(this, "SpringStiffness", this->SpringStiffness, 0.0, 1e3, Range::OPEN);
  valid &= Range::Check(this, "Damping", this->Damping, 0.0, 1e3);
  valid &= Range::Check(this, "TimeStep", this->TimeStep, 0.0, 1.0, Range::OPEN);
  valid &= Range::Check(this, "MaxIterations", this->MaxIterations, 0, 1000000);
  valid &= Range::Check(this, "PushCriterion", this->PushCriterion, 0, 2);
  valid &= Range::Check(this, "PushVelocity", this->PushVelocity, 0.0, 10.0, Range::OPEN);
  valid &= Range::Check(this, "FeatureAngle", this->FeatureAngle, 0.0, 180.0);
  valid &= Range::Check(this, "BoundaryTolerance", this->BoundaryTolerance, 0.0, 10.0);
  valid &=
    Range::Check(this, "MinimumAngle", this->MinimumAngle, 0.0, strata::kLargestMinimumAngle);
  return valid;
}

void vtkPhysicalCompressionTriangulator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SpringConfiguration: " << this->SpringConfiguration
     << (this->SpringConfiguration == EDGE_SPRINGS ? " (edge springs)"
                                                   : " (edge and projection springs)")
     << "\n";
  os << indent << "SpringStiffness: " << this->SpringStiffness << "\n";
  os << indent << "Damping: " << this->Damping << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "MaxIterations: " << this->MaxIterations << "\n";
  static const char* const criteria[] = { " (all candidates)", " (one side)", " (closest)" };
  os << indent << "PushCriterion: " << this->PushCriterion
     << (this->PushCriterion >= 0 && this->PushCriterion <= 2 ? criteria[this->PushCriterion] : "")
     << "\n";
  os << indent << "PushVelocity: " << this->PushVelocity << "\n";
  os << indent << "FeatureAngle: " << this->FeatureAngle << "\n";
  os << indent << "FlipDegenerate: " << this->FlipDegenerate << "\n";
  os << indent << "Optimization: " << this->Optimization << "\n";
  os << indent << "BoundaryTolerance: " << this->BoundaryTolerance << "\n";
  os << indent << "MinimumAngle: " << this->MinimumAngle << "\n";
  os << indent << "CurveRecovery: " << this->CurveRecovery << "\n";
  os << indent << "KeepSharpCorners: " << this->KeepSharpCorners << "\n";
  os << indent << "ThinLayerRetry: " << this->ThinLayerRetry << "\n";
}
