#include "vtkStrataMeshAlgorithm.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshRange.h"

#include "Grid48.h"

#include <vtkAlgorithm.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkGenericCell.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>
#include <vtkStaticPointLocator.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

namespace
{

/// A target edge length field over a vtkDataSet, evaluated at input (x, y). Not thread safe
/// (scratch cell, weights and id list): Grid48 calls it from the refining thread only.
class TargetField
{
public:
  /// `values`: one component, every value finite and > 0 (checked by the caller).
  TargetField(vtkDataSet* data, vtkDataArray* values, double grading)
    : Values(values)
    , Grading(grading)
  {
    double bounds[6];
    data->GetBounds(bounds);
    this->Z = std::min(std::max(0.0, bounds[4]), bounds[5]);
    const double diagonal = std::sqrt((bounds[1] - bounds[0]) * (bounds[1] - bounds[0]) +
      (bounds[3] - bounds[2]) * (bounds[3] - bounds[2]) +
      (bounds[5] - bounds[4]) * (bounds[5] - bounds[4]));
    this->Tolerance2 = (1e-9 * diagonal) * (1e-9 * diagonal);
    this->Interpolated = HasSurfaceCells(data);
    if (this->Interpolated)
    {
      this->Data = data;
      this->Image = vtkImageData::SafeDownCast(data);
      if (!this->Image)
      {
        this->Cells = vtkSmartPointer<vtkStaticCellLocator>::New();
        this->Cells->SetDataSet(data);
        this->Cells->BuildLocator();
      }
      this->Weights.resize(static_cast<std::size_t>(std::max(data->GetMaxCellSize(), 8)));
    }
    else
    {
      // The points projected onto z = 0: distances are measured in the model's plane.
      auto flat = vtkSmartPointer<vtkPoints>::New();
      flat->SetDataTypeToDouble();
      flat->SetNumberOfPoints(data->GetNumberOfPoints());
      this->Smallest = std::numeric_limits<double>::infinity();
      for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i)
      {
        double x[3];
        data->GetPoint(i, x);
        flat->SetPoint(i, x[0], x[1], 0.0);
        this->Smallest = std::min(this->Smallest, values->GetComponent(i, 0));
      }
      auto cloud = vtkSmartPointer<vtkPolyData>::New();
      cloud->SetPoints(flat);
      this->Points = vtkSmartPointer<vtkStaticPointLocator>::New();
      this->Points->SetDataSet(cloud);
      this->Points->BuildLocator();
      this->Cloud = cloud;
    }
  }

  /// The wanted edge length at input (x, y); NaN (no wish) outside an interpolated field.
  double operator()(double x, double y)
  {
    double q[3] = { x, y, this->Interpolated ? this->Z : 0.0 };
    if (this->Interpolated)
    {
      int subId = 0;
      double pcoords[3];
      vtkIdType cell = -1;
      if (this->Image)
      {
        cell = this->Image->FindCell(
          q, nullptr, this->Cell, -1, this->Tolerance2, subId, pcoords, this->Weights.data());
        if (cell >= 0)
        {
          this->Image->GetCell(cell, this->Cell);
        }
      }
      else
      {
        cell = this->Cells->FindCell(
          q, this->Tolerance2, this->Cell, subId, pcoords, this->Weights.data());
      }
      if (cell < 0)
      {
        return std::numeric_limits<double>::quiet_NaN();
      }
      vtkIdList* ids = this->Cell->GetPointIds();
      double value = 0.0;
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        value +=
          this->Weights[static_cast<std::size_t>(k)] * this->Values->GetComponent(ids->GetId(k), 0);
      }
      return value;
    }
    // min over p of (h_p + G |q - p|): from the nearest point's value, only points within
    // (best - smallest value) / G can do better.
    const vtkIdType nearest = this->Points->FindClosestPoint(q);
    if (nearest < 0)
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    double best = this->Law(nearest, q);
    const double radius = (best - this->Smallest) / this->Grading;
    if (radius > 0.0)
    {
      this->Points->FindPointsWithinRadius(radius, q, this->Ids);
      for (vtkIdType k = 0; k < this->Ids->GetNumberOfIds(); ++k)
      {
        best = std::min(best, this->Law(this->Ids->GetId(k), q));
      }
    }
    return best;
  }

  /// Whether the dataset has cells of dimension 2 or more (a surface or a volume to
  /// interpolate in), rather than only points, vertices or lines.
  static bool HasSurfaceCells(vtkDataSet* data)
  {
    if (auto* image = vtkImageData::SafeDownCast(data))
    {
      return image->GetDataDimension() >= 2;
    }
    for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c)
    {
      if (vtkCellTypes::GetDimension(static_cast<unsigned char>(data->GetCellType(c))) >= 2)
      {
        return true;
      }
    }
    return false;
  }

private:
  double Law(vtkIdType point, const double q[3])
  {
    double p[3];
    this->Cloud->GetPoint(point, p);
    return this->Values->GetComponent(point, 0) +
      this->Grading * std::hypot(q[0] - p[0], q[1] - p[1]);
  }

  vtkSmartPointer<vtkDataArray> Values;
  double Grading = 0.5;
  bool Interpolated = false;
  double Z = 0.0;
  double Tolerance2 = 0.0;
  // Interpolated fields.
  vtkSmartPointer<vtkDataSet> Data;
  vtkImageData* Image = nullptr; // Data, when it is an image (no locator needed)
  vtkSmartPointer<vtkStaticCellLocator> Cells;
  vtkSmartPointer<vtkGenericCell> Cell = vtkSmartPointer<vtkGenericCell>::New();
  std::vector<double> Weights;
  // Points-only fields.
  vtkSmartPointer<vtkPolyData> Cloud;
  vtkSmartPointer<vtkStaticPointLocator> Points;
  vtkSmartPointer<vtkIdList> Ids = vtkSmartPointer<vtkIdList>::New();
  double Smallest = 0.0;
};

} // namespace

vtkStrataMeshAlgorithm::vtkStrataMeshAlgorithm()
{
  this->SetNumberOfInputPorts(2);
  this->SetRegionArrayName("RegionId");
  this->SetLeftRegionArrayName("LeftRegion");
  this->SetRightRegionArrayName("RightRegion");
  this->SetTargetEdgeLengthArray("TargetEdgeLength");
}

vtkStrataMeshAlgorithm::~vtkStrataMeshAlgorithm()
{
  this->SetRegionArrayName(nullptr);
  this->SetLeftRegionArrayName(nullptr);
  this->SetRightRegionArrayName(nullptr);
  this->SetTargetEdgeLengthArray(nullptr);
}

int vtkStrataMeshAlgorithm::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

void vtkStrataMeshAlgorithm::SetTargetEdgeLengthConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkStrataMeshAlgorithm::SetTargetEdgeLengthData(vtkDataSet* data)
{
  this->SetInputData(1, data);
}

bool vtkStrataMeshAlgorithm::FillGridParams(vtkDataSet* target, strata::Grid48Params& params)
{
  params.maxLevel = this->MaxLevel;
  params.localMaxLevel = this->LocalMaxLevel;
  params.tolerance = this->Tolerance;
  params.maxEdgeLength = this->MaximumEdgeLength;
  params.minEdgeLength = this->MinimumEdgeLength;
  params.thinLayerRefinement = this->ThinLayerRefinement != 0;
  params.targetEdgeLength = nullptr;
  params.targetEdgeLengthId = 0;
  if (!target)
  {
    return true;
  }
  const std::string wanted = this->TargetEdgeLengthArray ? this->TargetEdgeLengthArray : "";
  vtkPointData* pd = target->GetPointData();
  vtkDataArray* values = wanted.empty() ? nullptr : pd->GetArray(wanted.c_str());
  if (!values && pd->GetNumberOfArrays() == 1 && pd->GetArray(0) &&
    pd->GetArray(0)->GetNumberOfComponents() == 1)
  {
    values = pd->GetArray(0); // the only point array
  }
  if (!values)
  {
    std::ostringstream names;
    for (int i = 0; i < pd->GetNumberOfArrays(); ++i)
    {
      const char* name = pd->GetArrayName(i);
      names << (i ? ", " : "") << '\'' << (name ? name : "(unnamed)") << '\'';
    }
    vtkErrorMacro(<< "TargetEdgeLength input (a " << target->GetClassName()
                  << "): no point array named '" << wanted << "' (TargetEdgeLengthArray), and not "
                  << "exactly one one-component point array to use instead; its point arrays: "
                  << (pd->GetNumberOfArrays() ? names.str() : std::string("none")));
    return false;
  }
  const char* name = values->GetName() ? values->GetName() : "(unnamed)";
  if (values->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro(<< "TargetEdgeLength input: the point array '" << name << "' has "
                  << values->GetNumberOfComponents() << " components, not 1");
    return false;
  }
  if (target->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "TargetEdgeLength input: the dataset has no points");
    return false;
  }
  if (values->GetNumberOfTuples() != target->GetNumberOfPoints())
  {
    vtkErrorMacro(<< "TargetEdgeLength input: the point array '" << name << "' has "
                  << values->GetNumberOfTuples() << " values for " << target->GetNumberOfPoints()
                  << " points");
    return false;
  }
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    const double v = values->GetComponent(i, 0);
    if (!(v > 0.0) || !std::isfinite(v))
    {
      vtkErrorMacro(<< "TargetEdgeLength input: point " << i << " of the point array '" << name
                    << "' has the value " << v
                    << "; target edge lengths must be finite and > 0 (model units)");
      return false;
    }
  }
  std::ostringstream key;
  key << target << ' ' << target->GetMTime() << ' ' << values << ' '
      << this->TargetEdgeLengthGrading;
  if (key.str() != this->TargetKey)
  {
    this->TargetKey = key.str();
    ++this->TargetId;
  }
  auto field = std::make_shared<TargetField>(target, values, this->TargetEdgeLengthGrading);
  params.targetEdgeLength = [field](strata::Vec2 p) { return (*field)(p.x, p.y); };
  params.targetEdgeLengthId = this->TargetId;
  return true;
}

std::function<bool(double, const char*)> vtkStrataMeshAlgorithm::ProgressCallback()
{
  return [this](double fraction, const char* stage)
  {
    this->SetProgressText(stage);
    this->UpdateProgress(fraction);
    return !this->CheckAbort();
  };
}

bool vtkStrataMeshAlgorithm::CheckProperties()
{
  const double inf = std::numeric_limits<double>::infinity();
  bool valid = vtkStrataMeshRange::Check(this, "Form", this->Form, 0, 2);
  valid &= vtkStrataMeshRange::Check(this, "MaxLevel", this->MaxLevel, -1, 60);
  if (vtkStrataMeshRange::Check(this, "LocalMaxLevel", this->LocalMaxLevel, -1, 60))
  {
    if (this->LocalMaxLevel != -1 && this->MaxLevel != -1 && this->LocalMaxLevel < this->MaxLevel)
    {
      vtkErrorMacro(<< "LocalMaxLevel = " << this->LocalMaxLevel << " is below MaxLevel = "
                    << this->MaxLevel << ": it must be -1 (automatic) or in [MaxLevel, 60]");
      valid = false;
    }
  }
  else
  {
    valid = false;
  }
  valid &= vtkStrataMeshRange::Check(this, "Tolerance", this->Tolerance, 0.0, inf);
  const bool maxLength =
    vtkStrataMeshRange::Check(this, "MaximumEdgeLength", this->MaximumEdgeLength, 0.0, inf);
  const bool minLength =
    vtkStrataMeshRange::Check(this, "MinimumEdgeLength", this->MinimumEdgeLength, 0.0, inf);
  valid &= maxLength && minLength;
  valid &= vtkStrataMeshRange::Check(this,
    "TargetEdgeLengthGrading",
    this->TargetEdgeLengthGrading,
    0.0,
    10.0,
    vtkStrataMeshRange::OPEN);
  if (maxLength && minLength && this->MaximumEdgeLength > 0.0 &&
    this->MinimumEdgeLength > this->MaximumEdgeLength)
  {
    vtkErrorMacro(<< "MinimumEdgeLength = " << this->MinimumEdgeLength
                  << " is above MaximumEdgeLength = " << this->MaximumEdgeLength
                  << ": it must be 0 (no cap) or in [0, MaximumEdgeLength]");
    valid = false;
  }
  return valid;
}

void vtkStrataMeshAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkStrataMeshInput::PrintSelection(os,
    indent,
    this->Form,
    this->RegionArrayName,
    this->LeftRegionArrayName,
    this->RightRegionArrayName);
  os << indent << "MaxLevel: " << this->MaxLevel << "\n";
  os << indent << "LocalMaxLevel: " << this->LocalMaxLevel << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "MaximumEdgeLength: " << this->MaximumEdgeLength << "\n";
  os << indent << "MinimumEdgeLength: " << this->MinimumEdgeLength << "\n";
  os << indent << "ThinLayerRefinement: " << this->ThinLayerRefinement << "\n";
  os << indent << "TargetEdgeLength input: "
     << (this->GetNumberOfInputConnections(1) > 0 ? "connected" : "(none)") << "\n";
  os << indent << "TargetEdgeLengthArray: "
     << (this->TargetEdgeLengthArray ? this->TargetEdgeLengthArray : "(none)") << "\n";
  os << indent << "TargetEdgeLengthGrading: " << this->TargetEdgeLengthGrading << "\n";
}
