#include "vtkPolylineSignedDistance.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshRange.h"

#include "DistanceField.h"

#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>

vtkStandardNewMacro(vtkPolylineSignedDistance);

struct vtkPolylineSignedDistance::Internals
{
  vtkSmartPointer<vtkPolyData> Model;
  std::mutex Mutex;
  std::atomic<vtkMTimeType> BuiltTime{ 0 }; // GetMTime() when the field was last built
  std::atomic<bool> Valid{ false };
  strata::Model Core;
  std::unique_ptr<strata::DistanceField> Field;
};

vtkPolylineSignedDistance::vtkPolylineSignedDistance()
  : Internal(new Internals)
{
  this->SetRegionArrayName("RegionId");
  this->SetLeftRegionArrayName("LeftRegion");
  this->SetRightRegionArrayName("RightRegion");
}

vtkPolylineSignedDistance::~vtkPolylineSignedDistance()
{
  this->SetRegionArrayName(nullptr);
  this->SetLeftRegionArrayName(nullptr);
  this->SetRightRegionArrayName(nullptr);
}

void vtkPolylineSignedDistance::SetModel(vtkPolyData* model)
{
  if (this->Internal->Model != model)
  {
    this->Internal->Model = model;
    this->Modified();
  }
}

vtkPolyData* vtkPolylineSignedDistance::GetModel()
{
  return this->Internal->Model;
}

vtkMTimeType vtkPolylineSignedDistance::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Internal->Model)
  {
    t = std::max(t, this->Internal->Model->GetMTime());
  }
  return t;
}

bool vtkPolylineSignedDistance::UpdateModel()
{
  vtkMTimeType t = this->GetMTime();
  if (this->Internal->BuiltTime == t) // fast path, no lock: evaluation runs in threads
  {
    return this->Internal->Valid;
  }
  std::lock_guard<std::mutex> lock(this->Internal->Mutex);
  t = this->GetMTime();
  if (this->Internal->BuiltTime == t)
  {
    return this->Internal->Valid;
  }
  this->Internal->Valid = false;
  this->Internal->BuiltTime = t;
  this->Internal->Field.reset();
  if (!this->Internal->Model)
  {
    return false;
  }
  const bool validForm = vtkStrataMeshRange::Check(this, "Form", this->Form, 0, 2);
  if (!vtkStrataMeshRange::Check(this, "Region", this->Region, -1, VTK_INT_MAX) || !validForm)
  {
    return false;
  }
  try
  {
    this->Internal->Core = vtkStrataMeshInput::BuildModel(this->Internal->Model,
      vtkStrataMeshInput::MakeSelection(
        this->Form, this->RegionArrayName, this->LeftRegionArrayName, this->RightRegionArrayName));
    if (this->Region >= 0 && this->Internal->Core.regionIndex(this->Region) < 0)
    {
      vtkErrorMacro(<< "Region " << this->Region << " is not in the model");
      return false;
    }
    this->Internal->Field = std::make_unique<strata::DistanceField>(this->Internal->Core);
    for (const std::string& warning : this->Internal->Core.warnings)
    {
      vtkWarningMacro(<< warning); // once per model build (an empty model: every value -inf)
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    return false;
  }
  this->Internal->Valid = true;
  return true;
}

double vtkPolylineSignedDistance::EvaluateFunction(double x[3])
{
  if (!this->UpdateModel())
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  thread_local strata::DistanceField::Scratch scratch;
  const strata::Model& model = this->Internal->Core;
  const strata::Vec2 p{ x[0] - model.origin.x, x[1] - model.origin.y };
  const strata::DistanceField& field = *this->Internal->Field;
  if (this->Region < 0)
  {
    return field.query(p, scratch).signedDistance;
  }
  return field.signedDistance(static_cast<std::size_t>(model.regionIndex(this->Region)), p, scratch);
}

void vtkPolylineSignedDistance::EvaluateGradient(double x[3], double g[3])
{
  g[0] = g[1] = g[2] = 0.0;
  if (!this->UpdateModel())
  {
    g[0] = g[1] = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double h = 1e-7 * this->Internal->Core.size();
  for (int axis = 0; axis < 2; ++axis)
  {
    double a[3] = { x[0], x[1], x[2] };
    double b[3] = { x[0], x[1], x[2] };
    a[axis] -= h;
    b[axis] += h;
    g[axis] = (this->EvaluateFunction(b) - this->EvaluateFunction(a)) / (2.0 * h);
  }
}

void vtkPolylineSignedDistance::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Model: " << this->Internal->Model.Get() << "\n";
  os << indent << "Region: " << this->Region << "\n";
  vtkStrataMeshInput::PrintSelection(os,
    indent,
    this->Form,
    this->RegionArrayName,
    this->LeftRegionArrayName,
    this->RightRegionArrayName);
}
