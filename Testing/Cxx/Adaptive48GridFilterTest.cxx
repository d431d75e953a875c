// vtkAdaptive48Grid and vtkClassify48Grid in real VTK pipelines.
#include "vtkAdaptive48Grid.h"
#include "vtkClassify48Grid.h"

#include "AdapterTestUtilities.h"

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTriangle.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

using strata_test::Reader;
using strata_test::SignedArea;

TEST(Adaptive48GridFilterTest, grid_is_counter_clockwise_right_triangles_tiling_a_square)
{
  auto reader = Reader("salt_dome.vtp");
  vtkNew<vtkAdaptive48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  filter->SetMaxLevel(10);
  filter->Update();
  vtkUnstructuredGrid* grid = filter->GetOutput();
  ASSERT_GT(grid->GetNumberOfCells(), 100);
  double area = 0.0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(grid->GetCellType(c), VTK_TRIANGLE);
    const double a = SignedArea(grid, c);
    EXPECT_GT(a, 0.0) << "cell " << c;
    area += a;
  }
  double bounds[6];
  grid->GetBounds(bounds);
  EXPECT_NEAR(bounds[1] - bounds[0], bounds[3] - bounds[2], 1e-9 * (bounds[1] - bounds[0]));
  EXPECT_NEAR(area, (bounds[1] - bounds[0]) * (bounds[3] - bounds[2]), 1e-9 * area);
  EXPECT_NE(grid->GetCellData()->GetArray("Level"), nullptr);
  EXPECT_NE(grid->GetPointData()->GetArray("Level"), nullptr);
  vtkDataArray* maxLevel = grid->GetFieldData()->GetArray("MaxLevel");
  ASSERT_NE(maxLevel, nullptr);
  EXPECT_EQ(maxLevel->GetTuple1(0), 10);
}

TEST(Adaptive48GridFilterTest, output_level_gives_nested_coarser_meshes_of_the_same_hierarchy)
{
  auto reader = Reader("gulf_section.vtp");
  vtkNew<vtkAdaptive48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  filter->SetMaxLevel(12);
  filter->Update();
  const vtkIdType finest = filter->GetOutput()->GetNumberOfCells();
  std::map<int, vtkIdType> counts;
  for (int level = 0; level <= 8; level += 2)
  {
    filter->SetOutputLevel(level);
    filter->Update();
    counts[level] = filter->GetOutput()->GetNumberOfCells();
  }
  EXPECT_EQ(counts[0], 4); // the square around its centre
  EXPECT_EQ(counts[2], 16); // two levels halve the legs: every triangle in four
  for (int level = 2; level <= 8; level += 2)
  {
    EXPECT_GE(counts[level], counts[level - 2]) << level;
  }
  filter->SetOutputLevel(-1);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), finest);
}

TEST(Adaptive48GridFilterTest, raising_max_level_refines_further)
{
  auto reader = Reader("lake_superior.vtp");
  vtkNew<vtkAdaptive48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  filter->SetMaxLevel(10);
  filter->SetLocalMaxLevel(12);
  filter->Update();
  const vtkIdType coarse = filter->GetOutput()->GetNumberOfCells();
  filter->SetMaxLevel(12);
  filter->SetLocalMaxLevel(14);
  filter->Update();
  const vtkIdType fine = filter->GetOutput()->GetNumberOfCells();
  EXPECT_GT(fine, coarse);
  // The same grid built from scratch.
  vtkNew<vtkAdaptive48Grid> fresh;
  fresh->SetInputConnection(reader->GetOutputPort());
  fresh->SetMaxLevel(12);
  fresh->SetLocalMaxLevel(14);
  fresh->Update();
  EXPECT_EQ(fresh->GetOutput()->GetNumberOfCells(), fine);
}

TEST(Adaptive48GridFilterTest, classification_arrays_are_consistent)
{
  auto reader = Reader("salt_dome.vtp");
  vtkNew<vtkClassify48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  filter->SetMaxLevel(10);
  filter->Update();
  vtkUnstructuredGrid* grid = filter->GetOutput();
  vtkPolyData* edges = filter->GetEdgesOutput();
  ASSERT_TRUE(grid && edges);
  vtkDataArray* vclass = grid->GetPointData()->GetArray("VertexClass");
  vtkDataArray* vregion = grid->GetPointData()->GetArray("VertexRegion");
  vtkDataArray* cregion = grid->GetCellData()->GetArray("CellRegion");
  vtkDataArray* eclass = edges->GetCellData()->GetArray("EdgeClass");
  vtkDataArray* eregion = edges->GetCellData()->GetArray("EdgeRegion");
  ASSERT_TRUE(vclass && vregion && cregion && eclass && eregion);
  std::map<int, int> regionsSeen;
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i)
  {
    const int c = static_cast<int>(vclass->GetTuple1(i));
    const int r = static_cast<int>(vregion->GetTuple1(i));
    EXPECT_TRUE(c >= 0 && c <= 2);
    if (c == 0)
    {
      EXPECT_EQ(r, -1) << "exterior vertex " << i;
    }
    if (c == 2)
    {
      EXPECT_GE(r, 0) << "interior vertex " << i;
      ++regionsSeen[r];
    }
  }
  EXPECT_EQ(regionsSeen.size(), 6u); // salt_dome has six regions
  // Every grid edge once; edges between an interior and an exterior vertex are intersections.
  EXPECT_GT(edges->GetNumberOfCells(), grid->GetNumberOfCells());
  for (vtkIdType e = 0; e < edges->GetNumberOfCells(); ++e)
  {
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    edges->GetCellPoints(e, npts, ids);
    ASSERT_EQ(npts, 2);
    const int c0 = static_cast<int>(vclass->GetTuple1(ids[0]));
    const int c1 = static_cast<int>(vclass->GetTuple1(ids[1]));
    const int r0 = static_cast<int>(vregion->GetTuple1(ids[0]));
    const int r1 = static_cast<int>(vregion->GetTuple1(ids[1]));
    if (c0 == 1 || c1 == 1 || r0 != r1)
    {
      EXPECT_EQ(eclass->GetTuple1(e), 2) << "edge " << e;
    }
  }
}

TEST(Adaptive48GridFilterTest, bad_model_fails_the_request_with_its_error)
{
  auto reader = Reader("bad_inputs/self_intersecting_loop.vtp");
  vtkNew<vtkClassify48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  auto log = strata_test::Watch(filter);
  filter->Update();
  EXPECT_NE(log->Errors.find("250"), std::string::npos) << log->Errors;
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
}

TEST(Adaptive48GridFilterTest, empty_model_gives_empty_outputs)
{
  auto reader = Reader("bad_inputs/empty.vtp");
  vtkNew<vtkClassify48Grid> filter;
  filter->SetInputConnection(reader->GetOutputPort());
  vtkNew<vtkCallbackCommand> quiet; // the warning is expected
  filter->AddObserver(vtkCommand::WarningEvent, quiet);
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
  EXPECT_EQ(filter->GetEdgesOutput()->GetNumberOfCells(), 0);
}
