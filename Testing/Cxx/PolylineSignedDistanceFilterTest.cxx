// vtkPolylineSignedDistanceFilter and vtkPolylineSignedDistance in real VTK pipelines.
#include "vtkPolylineSignedDistance.h"
#include "vtkPolylineSignedDistanceFilter.h"

#include "AdapterTestUtilities.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSampleFunction.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using strata_test::Reader;
using strata_test::Watch;

TEST(PolylineSignedDistanceFilterTest, samples_an_image_over_the_padded_model_bounds)
{
  auto reader = Reader("lake_superior.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->SetSampleDimensions(64, 32);
  filter->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(filter->GetOutput());
  ASSERT_NE(image, nullptr);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 64);
  EXPECT_EQ(dims[1], 32);
  double mb[6], ib[6];
  reader->GetOutput()->GetBounds(mb);
  image->GetBounds(ib);
  EXPECT_NEAR(ib[0], mb[0] - 0.05 * (mb[1] - mb[0]), 1e-6 * (mb[1] - mb[0]));
  EXPECT_NEAR(ib[3], mb[3] + 0.05 * (mb[3] - mb[2]), 1e-6 * (mb[3] - mb[2]));

  vtkDataArray* d = image->GetPointData()->GetArray("SignedDistance");
  vtkDataArray* r = image->GetPointData()->GetArray("RegionId");
  vtkDataArray* c = image->GetPointData()->GetArray("NearestCurve");
  ASSERT_TRUE(d && r && c);
  int inside = 0;
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
  {
    const bool in = r->GetTuple1(i) == 0;
    inside += in;
    EXPECT_EQ(d->GetTuple1(i) > 0, in) << "point " << i;
    EXPECT_GE(c->GetTuple1(i), 0);
    EXPECT_LT(c->GetTuple1(i), 46);
  }
  EXPECT_GT(inside, 0);
}

TEST(PolylineSignedDistanceFilterTest, probes_a_dataset_and_keeps_its_type)
{
  auto reader = Reader("nested_holes.vtp");
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-120, -120, 0);
  plane->SetPoint1(120, -120, 0);
  plane->SetPoint2(-120, 120, 0);
  plane->SetResolution(30, 30);
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetInputConnection(plane->GetOutputPort());
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->Update();
  vtkPolyData* out = vtkPolyData::SafeDownCast(filter->GetOutput());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->GetNumberOfPoints(), 31 * 31);
  EXPECT_EQ(out->GetNumberOfPolys(), 30 * 30);
  EXPECT_NE(out->GetPointData()->GetArray("SignedDistance"), nullptr);
}

TEST(PolylineSignedDistanceFilterTest, implicit_function_agrees_with_the_filter)
{
  auto reader = Reader("gulf_section.vtp");
  reader->Update();
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->SetSampleDimensions(40, 20);
  filter->Update();
  vtkImageData* image = vtkImageData::SafeDownCast(filter->GetOutput());

  vtkNew<vtkPolylineSignedDistance> function;
  function->SetModel(reader->GetOutput());
  ASSERT_TRUE(function->UpdateModel());
  vtkDataArray* d = image->GetPointData()->GetArray("SignedDistance");
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
  {
    double p[3];
    image->GetPoint(i, p);
    EXPECT_DOUBLE_EQ(function->EvaluateFunction(p), d->GetTuple1(i));
  }
}

TEST(PolylineSignedDistanceFilterTest, implicit_function_works_in_vtkSampleFunction)
{
  auto reader = Reader("nested_holes.vtp");
  reader->Update();
  vtkNew<vtkPolylineSignedDistance> function;
  function->SetModel(reader->GetOutput());
  function->SetRegion(0);
  vtkNew<vtkSampleFunction> sample;
  sample->SetImplicitFunction(function);
  sample->SetModelBounds(-110, 110, -110, 110, 0, 0);
  sample->SetSampleDimensions(45, 45, 1);
  sample->ComputeNormalsOff();
  sample->Update();
  vtkDataArray* s = sample->GetOutput()->GetPointData()->GetScalars();
  ASSERT_NE(s, nullptr);
  // The outer loop spans -100..100: the sample border at +-110 is outside (negative).
  EXPECT_LT(s->GetTuple1(0), 0.0);
  double range[2];
  s->GetRange(range);
  EXPECT_LT(range[0], 0.0);
  EXPECT_GT(range[1], 0.0);
  for (vtkIdType i = 0; i < s->GetNumberOfTuples(); ++i)
  {
    EXPECT_TRUE(std::isfinite(s->GetTuple1(i)));
  }
}

TEST(PolylineSignedDistanceFilterTest, implicit_function_gradient_points_into_the_region)
{
  auto reader = Reader("touching_loops.vtp");
  reader->Update();
  vtkNew<vtkPolylineSignedDistance> function;
  function->SetModel(reader->GetOutput());
  function->SetRegion(0);
  ASSERT_TRUE(function->UpdateModel());
  // Region 0 is one of the squares [0,10]^2 and [10,20]^2. Two units right of the square's
  // left side (and nearer to it than to any other side) the distance grows along +x.
  double left[3] = { 5, 5, 0 };
  const double x0 = function->EvaluateFunction(left) > 0 ? 0.0 : 10.0;
  double p[3] = { x0 + 2.0, x0 + 5.0, 0.0 };
  EXPECT_NEAR(function->EvaluateFunction(p), 2.0, 1e-9);
  double g[3];
  function->EvaluateGradient(p, g);
  EXPECT_NEAR(g[0], 1.0, 1e-5);
  EXPECT_NEAR(g[1], 0.0, 1e-5);
  // Outside the square, one unit left of its side, the signed distance grows toward it too.
  double q[3] = { x0 - 1.0, x0 + 5.0, 0.0 };
  if (x0 == 0.0)
  {
    EXPECT_NEAR(function->EvaluateFunction(q), -1.0, 1e-9);
    function->EvaluateGradient(q, g);
    EXPECT_NEAR(g[0], 1.0, 1e-5);
  }
}

TEST(PolylineSignedDistanceFilterTest, bad_inputs_fail_with_an_error_naming_the_defect)
{
  const std::pair<const char*, const char*> cases[] = {
    { "bad_inputs/nan_coordinate.vtp", "point 5" },
    { "bad_inputs/self_intersecting_loop.vtp", "250" },
    { "bad_inputs/unclosed_loop.vtp", "does not close" },
    { "bad_inputs/unclosed_boundary_shared.vtp", "dangling" },
    { "bad_inputs/inconsistent_labels.vtp", "inconsistent" },
    { "bad_inputs/no_region_array.vtp", "region array" },
    { "bad_inputs/crossing_curves.vtp", "cross" },
  };
  for (const auto& [file, needle] : cases)
  {
    auto reader = Reader(file);
    vtkNew<vtkPolylineSignedDistanceFilter> filter;
    filter->SetSourceConnection(reader->GetOutputPort());
    filter->SetSampleDimensions(8, 8);
    auto log = Watch(filter);
    EXPECT_EQ(filter->GetExecutive()->Update(), 0) << file;
    EXPECT_NE(log->Errors.find(needle), std::string::npos) << file << ": " << log->Errors;
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << file;
  }
}

TEST(PolylineSignedDistanceFilterTest, repairable_inputs_give_a_warning_and_the_reference_field)
{
  auto reference = Reader("bad_inputs/reference_loops_ok.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> expected;
  expected->SetSourceConnection(reference->GetOutputPort());
  expected->SetSampleDimensions(16, 16);
  expected->Update();
  vtkDataArray* e = vtkDataSet::SafeDownCast(expected->GetOutput())
                      ->GetPointData()
                      ->GetArray("SignedDistance");
  for (const char* file : { "bad_inputs/duplicate_points.vtp", "bad_inputs/zero_length_cell.vtp" })
  {
    auto reader = Reader(file);
    vtkNew<vtkPolylineSignedDistanceFilter> filter;
    filter->SetSourceConnection(reader->GetOutputPort());
    filter->SetSampleDimensions(16, 16);
    auto log = Watch(filter);
    filter->Update();
    EXPECT_TRUE(log->Errors.empty()) << file << ": " << log->Errors;
    EXPECT_FALSE(log->Warnings.empty()) << file;
    vtkDataArray* d = vtkDataSet::SafeDownCast(filter->GetOutput())
                        ->GetPointData()
                        ->GetArray("SignedDistance");
    ASSERT_NE(d, nullptr) << file;
    ASSERT_EQ(d->GetNumberOfTuples(), e->GetNumberOfTuples());
    for (vtkIdType i = 0; i < d->GetNumberOfTuples(); ++i)
    {
      EXPECT_NEAR(d->GetTuple1(i), e->GetTuple1(i), 1e-9) << file << " point " << i;
    }
  }
}

TEST(PolylineSignedDistanceFilterTest, empty_model_gives_empty_output_and_a_warning)
{
  auto reader = Reader("bad_inputs/empty.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  auto log = Watch(filter);
  filter->Update();
  EXPECT_TRUE(log->Errors.empty()) << log->Errors;
  EXPECT_FALSE(log->Warnings.empty());
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(PolylineSignedDistanceFilterTest, abort_stops_the_request)
{
  auto reader = Reader("lake_superior.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->SetSampleDimensions(1024, 1024);
  // Abort as soon as the first progress event arrives.
  vtkNew<vtkCallbackCommand> abort;
  abort->SetCallback([](vtkObject* caller, unsigned long, void*, void*)
    { static_cast<vtkAlgorithm*>(caller)->SetAbortExecuteAndUpdateTime(); });
  filter->AddObserver(vtkCommand::ProgressEvent, abort);
  auto log = Watch(filter);
  filter->Update();
  EXPECT_NE(log->Errors.find("aborted"), std::string::npos) << log->Errors;
  EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(PolylineSignedDistanceFilterTest, sample_dimensions_out_of_range_are_an_error)
{
  auto reader = Reader("lake_superior.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->SetSampleDimensions(1, 100);
  auto log = Watch(filter);
  filter->Update();
  EXPECT_NE(log->Errors.find("SampleDimensions[0] = 1"), std::string::npos) << log->Errors;
}
