// Property ranges of the StrataMesh filters: setters keep what they are given (no silent
// clamping) and an update with a value out of its documented range fails with an error that
// names the property, its value and the range, leaving the outputs empty.
#include "vtkAdaptive48Grid.h"
#include "vtkClassify48Grid.h"
#include "vtkPhysicalCompressionTriangulator.h"
#include "vtkPolylineSignedDistance.h"
#include "vtkPolylineSignedDistanceFilter.h"

#include "AdapterTestUtilities.h"

#include <vtkCommand.h>
#include <vtkDataSet.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace
{

using strata_test::Reader;
using strata_test::Watch;

using Setter = std::function<void(vtkPhysicalCompressionTriangulator*)>;

struct BadValue
{
  const char* What;
  Setter Set;
  const char* Message;
};

const double NaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<BadValue> BadValues = {
  { "MaxLevel too high",
    [](auto* f) { f->SetMaxLevel(99); },
    "MaxLevel = 99 is out of range [-1, 60]" },
  { "MaxLevel too low",
    [](auto* f) { f->SetMaxLevel(-2); },
    "MaxLevel = -2 is out of range [-1, 60]" },
  { "LocalMaxLevel too high",
    [](auto* f) { f->SetLocalMaxLevel(61); },
    "LocalMaxLevel = 61 is out of range [-1, 60]" },
  { "LocalMaxLevel below MaxLevel",
    [](auto* f)
    {
      f->SetMaxLevel(10);
      f->SetLocalMaxLevel(8);
    },
    "LocalMaxLevel = 8 is below MaxLevel = 10" },
  { "Tolerance negative",
    [](auto* f) { f->SetTolerance(-1.0); },
    "Tolerance = -1 is out of range [0, inf)" },
  { "Tolerance NaN",
    [](auto* f) { f->SetTolerance(NaN); },
    "Tolerance = nan is out of range [0, inf)" },
  { "Tolerance infinite",
    [](auto* f) { f->SetTolerance(std::numeric_limits<double>::infinity()); },
    "Tolerance = inf is out of range [0, inf)" },
  { "MaximumEdgeLength negative",
    [](auto* f) { f->SetMaximumEdgeLength(-2.0); },
    "MaximumEdgeLength = -2 is out of range [0, inf)" },
  { "MaximumEdgeLength NaN",
    [](auto* f) { f->SetMaximumEdgeLength(NaN); },
    "MaximumEdgeLength = nan is out of range [0, inf)" },
  { "MaximumEdgeLength finer than level 22", // pinch_out: the grid's side is 1100
    [](auto* f) { f->SetMaximumEdgeLength(0.1); },
    "MaximumEdgeLength 0.100000 is below" },
  { "MinimumEdgeLength infinite",
    [](auto* f) { f->SetMinimumEdgeLength(std::numeric_limits<double>::infinity()); },
    "MinimumEdgeLength = inf is out of range [0, inf)" },
  { "MinimumEdgeLength above MaximumEdgeLength",
    [](auto* f)
    {
      f->SetMaximumEdgeLength(10.0);
      f->SetMinimumEdgeLength(20.0);
    },
    "MinimumEdgeLength = 20 is above MaximumEdgeLength = 10" },
  { "Form", [](auto* f) { f->SetForm(3); }, "Form = 3 is out of range [0, 2]" },
  { "SpringConfiguration",
    [](auto* f) { f->SetSpringConfiguration(2); },
    "SpringConfiguration = 2 is out of range [0, 1]" },
  { "SpringStiffness zero",
    [](auto* f) { f->SetSpringStiffness(0.0); },
    "SpringStiffness = 0 is out of range (0, 1000]" },
  { "SpringStiffness too high",
    [](auto* f) { f->SetSpringStiffness(1000.5); },
    "SpringStiffness = 1000.5 is out of range (0, 1000]" },
  { "Damping", [](auto* f) { f->SetDamping(-0.5); }, "Damping = -0.5 is out of range [0, 1000]" },
  { "TimeStep", [](auto* f) { f->SetTimeStep(2.0); }, "TimeStep = 2 is out of range (0, 1]" },
  { "MaxIterations",
    [](auto* f) { f->SetMaxIterations(-1); },
    "MaxIterations = -1 is out of range [0, 1000000]" },
  { "PushCriterion",
    [](auto* f) { f->SetPushCriterion(3); },
    "PushCriterion = 3 is out of range [0, 2]" },
  { "PushVelocity",
    [](auto* f) { f->SetPushVelocity(0.0); },
    "PushVelocity = 0 is out of range (0, 10]" },
  { "FeatureAngle",
    [](auto* f) { f->SetFeatureAngle(181.0); },
    "FeatureAngle = 181 is out of range [0, 180]" },
  { "BoundaryTolerance",
    [](auto* f) { f->SetBoundaryTolerance(-1.0); },
    "BoundaryTolerance = -1 is out of range [0, 10]" },
  { "MinimumAngle",
    [](auto* f) { f->SetMinimumAngle(34.0); },
    "MinimumAngle = 34 is out of range [0, 33]" },
};

} // namespace

TEST(PropertyValidationTest, setters_keep_values_out_of_range)
{
  vtkNew<vtkPhysicalCompressionTriangulator> mesher;
  mesher->SetMaxLevel(99);
  mesher->SetLocalMaxLevel(-7);
  mesher->SetSpringStiffness(0.0);
  mesher->SetFeatureAngle(400.0);
  mesher->SetPushCriterion(9);
  EXPECT_EQ(mesher->GetMaxLevel(), 99);
  EXPECT_EQ(mesher->GetLocalMaxLevel(), -7);
  EXPECT_EQ(mesher->GetSpringStiffness(), 0.0);
  EXPECT_EQ(mesher->GetFeatureAngle(), 400.0);
  EXPECT_EQ(mesher->GetPushCriterion(), 9);
  vtkNew<vtkPolylineSignedDistance> function;
  function->SetRegion(-5);
  EXPECT_EQ(function->GetRegion(), -5);
}

TEST(PropertyValidationTest, triangulator_names_each_property_out_of_range_and_fails)
{
  auto reader = Reader("pinch_out.vtp");
  for (const BadValue& bad : BadValues)
  {
    vtkNew<vtkPhysicalCompressionTriangulator> mesher;
    mesher->SetInputConnection(reader->GetOutputPort());
    bad.Set(mesher);
    auto log = Watch(mesher);
    mesher->Update();
    EXPECT_TRUE(log->Has(bad.Message)) << bad.What << ": " << log->Errors;
    EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0) << bad.What;
    EXPECT_EQ(mesher->GetBoundaryOutput()->GetNumberOfCells(), 0) << bad.What;
  }
}

TEST(PropertyValidationTest, every_bad_property_is_reported_at_once)
{
  auto reader = Reader("pinch_out.vtp");
  vtkNew<vtkPhysicalCompressionTriangulator> mesher;
  mesher->SetInputConnection(reader->GetOutputPort());
  mesher->SetMaxLevel(99);
  mesher->SetDamping(-1.0);
  mesher->SetFeatureAngle(-3.0);
  auto log = Watch(mesher);
  mesher->Update();
  EXPECT_TRUE(log->Has("MaxLevel = 99 is out of range [-1, 60]")) << log->Errors;
  EXPECT_TRUE(log->Has("Damping = -1 is out of range [0, 1000]")) << log->Errors;
  EXPECT_TRUE(log->Has("FeatureAngle = -3 is out of range [0, 180]")) << log->Errors;
}

TEST(PropertyValidationTest, a_failed_update_empties_the_outputs_and_a_fixed_value_recovers)
{
  auto reader = Reader("pinch_out.vtp");
  vtkNew<vtkPhysicalCompressionTriangulator> mesher;
  mesher->SetInputConnection(reader->GetOutputPort());
  mesher->SetMaxLevel(10);
  mesher->Update();
  ASSERT_GT(mesher->GetOutput()->GetNumberOfCells(), 0);

  mesher->SetMaxLevel(99);
  {
    auto log = Watch(mesher);
    mesher->Update();
    EXPECT_TRUE(log->Has("MaxLevel = 99")) << log->Errors;
  }
  EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(mesher->GetBoundaryOutput()->GetNumberOfCells(), 0);

  mesher->SetMaxLevel(10);
  auto log = Watch(mesher);
  mesher->Update();
  EXPECT_TRUE(log->Errors.empty()) << log->Errors;
  EXPECT_GT(mesher->GetOutput()->GetNumberOfCells(), 0);
}

TEST(PropertyValidationTest, values_on_the_range_bounds_are_accepted)
{
  auto reader = Reader("pinch_out.vtp");
  vtkNew<vtkPhysicalCompressionTriangulator> mesher;
  mesher->SetInputConnection(reader->GetOutputPort());
  mesher->SetMaxLevel(10);
  mesher->SetLocalMaxLevel(10);
  mesher->SetTolerance(0.0);
  mesher->SetSpringConfiguration(0);
  mesher->SetSpringStiffness(1000.0);
  mesher->SetDamping(0.0);
  mesher->SetTimeStep(1.0);
  mesher->SetMaxIterations(0);
  mesher->SetPushCriterion(2);
  mesher->SetPushVelocity(10.0);
  mesher->SetFeatureAngle(180.0);
  mesher->SetMaximumEdgeLength(0.0);
  mesher->SetMinimumEdgeLength(0.0);
  mesher->SetMinimumAngle(33.0);
  auto log = Watch(mesher);
  mesher->Update();
  EXPECT_FALSE(log->Has("out of range")) << log->Errors;
  EXPECT_FALSE(log->Has("below MaxLevel")) << log->Errors;
}

TEST(PropertyValidationTest, grid_filters_name_their_properties_out_of_range)
{
  auto reader = Reader("pinch_out.vtp");
  {
    vtkNew<vtkAdaptive48Grid> grid;
    grid->SetInputConnection(reader->GetOutputPort());
    grid->SetOutputLevel(61);
    grid->SetMaxLevel(-3);
    grid->SetMinimumEdgeLength(-1.0);
    auto log = Watch(grid);
    grid->Update();
    EXPECT_TRUE(log->Has("MinimumEdgeLength = -1 is out of range [0, inf)")) << log->Errors;
    EXPECT_TRUE(log->Has("OutputLevel = 61 is out of range [-1, 60]")) << log->Errors;
    EXPECT_TRUE(log->Has("MaxLevel = -3 is out of range [-1, 60]")) << log->Errors;
    EXPECT_EQ(grid->GetOutput()->GetNumberOfCells(), 0);
  }
  {
    vtkNew<vtkClassify48Grid> grid;
    grid->SetInputConnection(reader->GetOutputPort());
    grid->SetMaxLevel(8);
    grid->SetBoundaryTolerance(-1e-3);
    auto log = Watch(grid);
    grid->Update();
    EXPECT_TRUE(log->Has("BoundaryTolerance = -0.001 is out of range [0, inf)")) << log->Errors;
    EXPECT_EQ(grid->GetOutput()->GetNumberOfCells(), 0);
    EXPECT_EQ(grid->GetEdgesOutput()->GetNumberOfCells(), 0);
  }
}

TEST(PropertyValidationTest, signed_distance_filter_names_form_and_sample_dimensions)
{
  auto reader = Reader("pinch_out.vtp");
  vtkNew<vtkPolylineSignedDistanceFilter> filter;
  filter->SetSourceConnection(reader->GetOutputPort());
  filter->SetForm(5);
  filter->SetSampleDimensions(64, 20000);
  auto log = Watch(filter);
  filter->Update();
  EXPECT_TRUE(log->Has("Form = 5 is out of range [0, 2]")) << log->Errors;
  EXPECT_TRUE(log->Has("SampleDimensions[1] = 20000 is out of range [2, 16384]")) << log->Errors;
  EXPECT_FALSE(log->Has("SampleDimensions[0]")) << log->Errors;
}

TEST(PropertyValidationTest, implicit_function_names_region_and_form_and_gives_nan)
{
  auto reader = Reader("pinch_out.vtp");
  reader->Update();
  vtkNew<vtkPolylineSignedDistance> function;
  function->SetModel(reader->GetOutput());
  double x[3] = { 0.0, 0.0, 0.0 };
  {
    function->SetRegion(-2);
    auto log = Watch(function);
    EXPECT_TRUE(std::isnan(function->EvaluateFunction(x)));
    EXPECT_TRUE(log->Has("Region = -2 is out of range [-1, ")) << log->Errors;
  }
  {
    function->SetRegion(-1);
    function->SetForm(4);
    auto log = Watch(function);
    EXPECT_FALSE(function->UpdateModel());
    EXPECT_TRUE(log->Has("Form = 4 is out of range [0, 2]")) << log->Errors;
  }
  function->SetForm(0);
  EXPECT_TRUE(function->UpdateModel());
  EXPECT_FALSE(std::isnan(function->EvaluateFunction(x)));
}
