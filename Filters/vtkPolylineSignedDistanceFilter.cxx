#include "vtkPolylineSignedDistanceFilter.h"

#include "vtkStrataMeshInput.h"
#include "vtkStrataMeshRange.h"

#include "SignedDistance.h"

#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <exception>
#include <string>

vtkStandardNewMacro(vtkPolylineSignedDistanceFilter);

vtkPolylineSignedDistanceFilter::vtkPolylineSignedDistanceFilter()
{
  this->SetNumberOfInputPorts(2);
  this->SetRegionArrayName("RegionId");
  this->SetLeftRegionArrayName("LeftRegion");
  this->SetRightRegionArrayName("RightRegion");
}

vtkPolylineSignedDistanceFilter::~vtkPolylineSignedDistanceFilter()
{
  this->SetRegionArrayName(nullptr);
  this->SetLeftRegionArrayName(nullptr);
  this->SetRightRegionArrayName(nullptr);
}

void vtkPolylineSignedDistanceFilter::SetSourceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkPolylineSignedDistanceFilter::SetSourceData(vtkPolyData* source)
{
  this->SetInputData(1, source);
}

int vtkPolylineSignedDistanceFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  return 1;
}

vtkDataSet* vtkPolylineSignedDistanceFilter::GetProbe(vtkInformationVector** inputVector)
{
  if (inputVector[0]->GetNumberOfInformationObjects() == 0)
  {
    return nullptr;
  }
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[0], 0);
  vtkPolyData* source = vtkPolyData::GetData(inputVector[1], 0);
  return probe == source ? nullptr : probe;
}

bool vtkPolylineSignedDistanceFilter::CheckProperties(bool sampling)
{
  bool valid = vtkStrataMeshRange::Check(this, "Form", this->Form, 0, 2);
  for (int axis = 0; sampling && axis < 2; ++axis)
  {
    const std::string name = "SampleDimensions[" + std::to_string(axis) + "]";
    valid &= vtkStrataMeshRange::Check(this, name.c_str(), this->SampleDimensions[axis], 2, 16384);
  }
  return valid;
}

int vtkPolylineSignedDistanceFilter::RequestDataObject(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject* output = vtkDataObject::GetData(outInfo);
  vtkDataSet* probe = GetProbe(inputVector);
  const char* wanted = probe ? probe->GetClassName() : "vtkImageData";
  if (!output || !output->IsA(wanted))
  {
    vtkSmartPointer<vtkDataObject> created;
    if (probe)
    {
      created.TakeReference(probe->NewInstance());
    }
    else
    {
      created = vtkSmartPointer<vtkImageData>::New();
    }
    outInfo->Set(vtkDataObject::DATA_OBJECT(), created);
  }
  return 1;
}

int vtkPolylineSignedDistanceFilter::RequestInformation(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (GetProbe(inputVector))
  {
    // Structured probes keep their extent (vtkDataSetAlgorithm's default behaviour).
    vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
    if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      outInfo->CopyEntry(inInfo, vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
    }
    return 1;
  }
  // The image's extent is known before the data; its origin and spacing come with the data.
  if (!this->CheckProperties(true))
  {
    return 0;
  }
  const int extent[6] = { 0, this->SampleDimensions[0] - 1, 0, this->SampleDimensions[1] - 1, 0,
    0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  return 1;
}

int vtkPolylineSignedDistanceFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The whole model is needed whatever part of the output is asked for.
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  if (sourceInfo)
  {
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

int vtkPolylineSignedDistanceFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* source = vtkPolyData::GetData(inputVector[1], 0);
  vtkDataSet* probe = GetProbe(inputVector);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!source || !output)
  {
    vtkErrorMacro(<< "the polyline model (input 1, Source) is missing");
    return 0;
  }
  if (!this->CheckProperties(probe == nullptr))
  {
    output->Initialize();
    return 0;
  }

  // Points to sample: the probe's, or an image over the model's padded bounds.
  if (probe)
  {
    output->ShallowCopy(probe);
  }
  else
  {
    vtkImageData* image = vtkImageData::SafeDownCast(output);
    double bounds[6];
    source->GetBounds(bounds);
    if (source->GetNumberOfPoints() == 0)
    {
      bounds[0] = bounds[2] = 0.0;
      bounds[1] = bounds[3] = 1.0;
    }
    const double pad[2] = { 0.05 * (bounds[1] - bounds[0]), 0.05 * (bounds[3] - bounds[2]) };
    image->SetExtent(0, this->SampleDimensions[0] - 1, 0, this->SampleDimensions[1] - 1, 0, 0);
    image->SetOrigin(bounds[0] - pad[0], bounds[2] - pad[1], 0.0);
    double spacing[3] = { 1.0, 1.0, 1.0 };
    for (int axis = 0; axis < 2; ++axis)
    {
      const double width = bounds[2 * axis + 1] - bounds[2 * axis] + 2.0 * pad[axis];
      spacing[axis] = width > 0.0 ? width / (this->SampleDimensions[axis] - 1) : 1.0;
    }
    image->SetSpacing(spacing);
  }

  const vtkIdType n = output->GetNumberOfPoints();
  std::vector<strata::Vec2> queries(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    queries[static_cast<std::size_t>(i)] = { p[0], p[1] };
  }

  strata::SignedDistanceResult result;
  try
  {
    const strata::RawPolylines raw = vtkStrataMeshInput::ToRaw(source,
      vtkStrataMeshInput::MakeSelection(
        this->Form, this->RegionArrayName, this->LeftRegionArrayName, this->RightRegionArrayName));
    result = strata::computeSignedDistance(raw,
      queries,
      {},
      [this](double fraction, const char* stage)
      {
        this->SetProgressText(stage);
        this->UpdateProgress(fraction);
        return !this->CheckAbort();
      });
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< e.what());
    output->Initialize();
    return 0;
  }
  for (const std::string& warning : result.warnings)
  {
    vtkWarningMacro(<< warning);
  }
  if (result.signedDistance.size() != queries.size())
  {
    // Empty model: empty output (VTK's convention), with the warning above.
    output->Initialize();
    return 1;
  }

  auto distance = vtkSmartPointer<vtkDoubleArray>::New();
  distance->SetName("SignedDistance");
  auto region = vtkSmartPointer<vtkIntArray>::New();
  region->SetName("RegionId");
  auto nearest = vtkSmartPointer<vtkIdTypeArray>::New();
  nearest->SetName("NearestCurve");
  distance->SetNumberOfValues(n);
  region->SetNumberOfValues(n);
  nearest->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const std::size_t k = static_cast<std::size_t>(i);
    distance->SetValue(i, result.signedDistance[k]);
    region->SetValue(i, result.regionId[k]);
    nearest->SetValue(i, static_cast<vtkIdType>(result.nearestCurve[k]));
  }
  vtkPointData* pd = output->GetPointData();
  pd->AddArray(distance);
  pd->AddArray(region);
  pd->AddArray(nearest);
  pd->SetActiveScalars("SignedDistance");
  return 1;
}

void vtkPolylineSignedDistanceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  vtkStrataMeshInput::PrintSelection(os,
    indent,
    this->Form,
    this->RegionArrayName,
    this->LeftRegionArrayName,
    this->RightRegionArrayName);
  os << indent << "SampleDimensions: " << this->SampleDimensions[0] << " "
     << this->SampleDimensions[1] << "\n";
}
