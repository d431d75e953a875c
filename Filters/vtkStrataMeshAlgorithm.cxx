#include "vtkStrataMeshAlgorithm.h"

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

void vtkStrataMeshAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Form: " << this->Form << "\n";
  os << indent << "RegionArrayName: " << (this->RegionArrayName ? this->RegionArrayName : "(none)")
     << "\n";
  os << indent << "LeftRegionArrayName: "
     << (this->LeftRegionArrayName ? this->LeftRegionArrayName : "(none)") << "\n";
  os << indent << "RightRegionArrayName: "
     << (this->RightRegionArrayName ? this->RightRegionArrayName : "(none)") << "\n";
  os << indent << "MaxLevel: " << this->MaxLevel << "\n";
  os << indent << "LocalMaxLevel: " << this->LocalMaxLevel << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
}
