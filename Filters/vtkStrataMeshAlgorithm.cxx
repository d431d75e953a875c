#include "vtkStrataMeshAlgorithm.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshRange.h"

#include <limits>

vtkStrataMeshAlgorithm::vtkStrataMeshAlgorithm()
{
  this->SetRegionArrayName("RegionId");
  this->SetLeftRegionArrayName("LeftRegion");
  this->SetRightRegionArrayName("RightRegion");
}

vtkStrataMeshAlgorithm::~vtkStrataMeshAlgorithm()
{
  this->SetRegionArrayName(nullptr);
  this->SetLeftRegionArrayName(nullptr);
  this->SetRightRegionArrayName(nullptr);
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
}
