// The target edge length field (input 1 of the meshing filters) through real VTK pipelines:
// an image interpolated in its cells, a points-only field (wells), bad values and arrays,
// and the resumable grid of vtkAdaptive48Grid when the field changes.
#include "vtkAdaptive48Grid.h"
#include "vtkPhysicalCompressionTriangulator.h"

#include "AdapterTestUtilities.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using strata_test::Reader;
using strata_test::Watch;

namespace
{

struct Box
{
  double x0, x1, y0, y1;
  double width() const { return this->x1 - this->x0; }
};

Box Bounds(const std::string& model)
{
  auto reader = Reader(model);
  reader->Update();
  const double* b = reader->GetOutput()->GetBounds();
  return { b[0], b[1], b[2], b[3] };
}

// Longest edge and centroid of a triangle cell.
double LongestEdge(vtkUnstructuredGrid* mesh, vtkIdType cell, double centroid[2] = nullptr)
{
  const vtkIdType* ids = nullptr;
  vtkIdType n = 0;
  mesh->GetCellPoints(cell, n, ids);
  double longest = 0.0;
  double c[2] = { 0.0, 0.0 };
  for (vtkIdType k = 0; k < n; ++k)
  {
    double a[3], b[3];
    mesh->GetPoint(ids[k], a);
    mesh->GetPoint(ids[(k + 1) % n], b);
    longest = std::max(longest, std::hypot(a[0] - b[0], a[1] - b[1]));
    c[0] += a[0] / n;
    c[1] += a[1] / n;
  }
  if (centroid)
  {
    centroid[0] = c[0];
    centroid[1] = c[1];
  }
  return longest;
}

// The ratios (>= 1) of the longest edges of two triangles sharing an edge: the worst and the
// 99th percentile.
std::pair<double, double> NeighbourRatios(vtkUnstructuredGrid* mesh)
{
  std::map<std::pair<vtkIdType, vtkIdType>, vtkIdType> firstCell;
  std::vector<double> ratios;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    const vtkIdType* ids = nullptr;
    vtkIdType n = 0;
    mesh->GetCellPoints(c, n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      const auto key = std::minmax(ids[k], ids[(k + 1) % n]);
      const auto [it, inserted] = firstCell.emplace(key, c);
      if (!inserted)
      {
        const double a = LongestEdge(mesh, c);
        const double b = LongestEdge(mesh, it->second);
        ratios.push_back(std::max(a, b) / std::min(a, b));
      }
    }
  }
  if (ratios.empty())
  {
    return { 1.0, 1.0 };
  }
  std::sort(ratios.begin(), ratios.end());
  return { ratios.back(), ratios[ratios.size() * 99 / 100] };
}

// An image over `box` (padded by 10%) with `small` in the disc (centre, radius) and `large`
// elsewhere, in the point array `name`.
vtkSmartPointer<vtkImageData> DiscImage(const Box& box,
  const double centre[2],
  double radius,
  double small,
  double large,
  const char* name = "TargetEdgeLength")
{
  const int n = 101;
  const double pad = 0.1 * box.width();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, 1);
  image->SetOrigin(box.x0 - pad, box.y0 - pad, 0.0);
  image->SetSpacing(
    (box.x1 - box.x0 + 2 * pad) / (n - 1), (box.y1 - box.y0 + 2 * pad) / (n - 1), 1.0);
  auto values = vtkSmartPointer<vtkDoubleArray>::New();
  values->SetName(name);
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType i = 0; i < image->GetNumberOfPoints(); ++i)
  {
    double p[3];
    image->GetPoint(i, p);
    values->SetValue(i, std::hypot(p[0] - centre[0], p[1] - centre[1]) < radius ? small : large);
  }
  image->GetPointData()->AddArray(values);
  return image;
}

// Points only (no cells), each with its target edge length.
vtkSmartPointer<vtkPolyData> Wells(const std::vector<std::array<double, 3>>& wells)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto values = vtkSmartPointer<vtkDoubleArray>::New();
  values->SetName("h");
  for (const auto& w : wells)
  {
    points->InsertNextPoint(w[0], w[1], 0.0);
    values->InsertNextValue(w[2]);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(points);
  data->GetPointData()->AddArray(values);
  return data;
}

// The longest edge of the mesh.
double EdgeRangeLongest(vtkUnstructuredGrid* mesh)
{
  double longest = 0.0;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    longest = std::max(longest, LongestEdge(mesh, c));
  }
  return longest;
}

// Count and mean longest edge of the triangles whose centroid is within [r0, r1) of centre.
std::pair<int, double> Ring(vtkUnstructuredGrid* mesh, const double centre[2], double r0, double r1)
{
  int count = 0;
  double sum = 0.0;
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    double g[2];
    const double longest = LongestEdge(mesh, c, g);
    const double d = std::hypot(g[0] - centre[0], g[1] - centre[1]);
    if (d >= r0 && d < r1)
    {
      ++count;
      sum += longest;
    }
  }
  return { count, count ? sum / count : 0.0 };
}

// A triangulator with default settings reading `reader`'s output.
vtkSmartPointer<vtkPhysicalCompressionTriangulator> Triangulator(vtkAlgorithm* reader)
{
  auto mesher = vtkSmartPointer<vtkPhysicalCompressionTriangulator>::New();
  mesher->SetInputConnection(reader->GetOutputPort());
  return mesher;
}

} // namespace

TEST(TargetEdgeLengthFilterTest, an_image_field_refines_its_disc_and_coarsens_elsewhere)
{
  const Box box = Bounds("salt_dome.vtp");
  const double w = box.width();
  const double centre[2] = { box.x0 + 0.3 * w, 0.5 * (box.y0 + box.y1) };
  const double radius = 0.1 * w;
  const double small = w / 150.0;
  const double large = w / 10.0;

  auto reader = Reader("salt_dome.vtp");
  auto plain = Triangulator(reader);
  plain->Update();
  auto mesher = Triangulator(reader);
  mesher->SetTargetEdgeLengthData(DiscImage(box, centre, radius, small, large));
  auto log = Watch(mesher);
  mesher->Update();
  ASSERT_TRUE(log->Errors.empty()) << log->Errors;
  vtkUnstructuredGrid* mesh = mesher->GetOutput();
  ASSERT_GT(mesh->GetNumberOfCells(), 100);

  // Inside the disc: edges near the target (the compression stretches some, below twice).
  const auto inside = Ring(mesh, centre, 0.0, 0.8 * radius);
  const auto insidePlain = Ring(plain->GetOutput(), centre, 0.0, 0.8 * radius);
  EXPECT_GT(inside.first, 2 * insidePlain.first);
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    double g[2];
    const double longest = LongestEdge(mesh, c, g);
    if (std::hypot(g[0] - centre[0], g[1] - centre[1]) < 0.8 * radius)
    {
      EXPECT_LE(longest, 2.0 * small) << "triangle " << c;
    }
  }
  // Far from the disc the field asks for large edges: coarser than the automatic levels.
  const auto far = Ring(mesh, centre, radius + 2.0 * large, HUGE_VAL);
  const auto farPlain = Ring(plain->GetOutput(), centre, radius + 2.0 * large, HUGE_VAL);
  EXPECT_LT(far.first, farPlain.first);
  EXPECT_GT(far.second, farPlain.second);
  // Grading after the compression (the grid's is sqrt(2) at most).
  const auto ratio = NeighbourRatios(mesh);
  const auto ratioPlain = NeighbourRatios(plain->GetOutput());
  std::cout << "salt_dome image field: " << mesh->GetNumberOfCells() << " triangles ("
            << plain->GetOutput()->GetNumberOfCells() << " without), disc " << inside.first << " ("
            << insidePlain.first << "), far " << far.first << " (" << farPlain.first
            << "); ratio of the longest edges of edge neighbours: worst " << ratio.first
            << ", 99th percentile " << ratio.second << " (without the field " << ratioPlain.first
            << ", " << ratioPlain.second << ")\n";
  EXPECT_LE(ratio.first, 3.0);
  EXPECT_LE(ratio.second, 2.0);
}

TEST(TargetEdgeLengthFilterTest, a_points_only_field_refines_around_the_wells)
{
  const Box box = Bounds("salt_dome.vtp");
  const double w = box.width();
  const double y = 0.5 * (box.y0 + box.y1);
  const double small = w / 200.0;
  const double a[2] = { box.x0 + 0.25 * w, y };
  const double b[2] = { box.x0 + 0.75 * w, y };
  auto reader = Reader("salt_dome.vtp");
  auto plain = Triangulator(reader);
  plain->Update();
  auto mesher = Triangulator(reader);
  mesher->SetTargetEdgeLengthData(Wells({ { a[0], a[1], small }, { b[0], b[1], 2.0 * small } }));
  // No array named TargetEdgeLength: the only point array, "h", is used.
  auto log = Watch(mesher);
  mesher->Update();
  ASSERT_TRUE(log->Errors.empty()) << log->Errors;
  vtkUnstructuredGrid* mesh = mesher->GetOutput();
  const double grading = mesher->GetTargetEdgeLengthGrading();
  EXPECT_EQ(grading, 0.5);
  // Near each well the edges follow h_p + G d (at most twice that after the compression).
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    double g[2];
    const double longest = LongestEdge(mesh, c, g);
    const double wanted = std::min(small + grading * std::hypot(g[0] - a[0], g[1] - a[1]),
      2.0 * small + grading * std::hypot(g[0] - b[0], g[1] - b[1]));
    if (wanted < w / 40.0)
    {
      EXPECT_LE(longest, 2.0 * wanted) << "triangle " << c;
    }
  }
  const auto nearA = Ring(mesh, a, 0.0, 4.0 * small);
  const auto nearB = Ring(mesh, b, 0.0, 4.0 * small);
  EXPECT_GT(nearA.first, Ring(plain->GetOutput(), a, 0.0, 4.0 * small).first);
  EXPECT_LT(nearA.second, nearB.second); // the first well asks for half the size
  const auto ratio = NeighbourRatios(mesh);
  std::cout << "salt_dome two wells: " << mesh->GetNumberOfCells() << " triangles ("
            << plain->GetOutput()->GetNumberOfCells() << " without); ratio of the longest edges "
            << "of edge neighbours: worst " << ratio.first << ", 99th percentile " << ratio.second
            << "\n";
  // The law grows without bound (to 0.4 of the width here), so MaxLevel is coarsened to
  // about 3 and the compression stretches the few boundary triangles most.
  EXPECT_LE(ratio.first, 3.0);
  EXPECT_LE(ratio.second, 2.5);
  // MaximumEdgeLength caps the far sizes (and sets MaxLevel): the usual use with wells.
  mesher->SetMaximumEdgeLength(w / 20.0);
  mesher->Update();
  ASSERT_TRUE(log->Errors.empty()) << log->Errors;
  const auto capped = NeighbourRatios(mesh);
  std::cout << "  with MaximumEdgeLength = width / 20: " << mesh->GetNumberOfCells()
            << " triangles; worst " << capped.first << ", 99th percentile " << capped.second
            << "\n";
  EXPECT_LE(EdgeRangeLongest(mesh), 2.0 * w / 20.0);
  EXPECT_LE(capped.first, 3.0);
  EXPECT_LE(capped.second, 2.0);
  EXPECT_GT(
    Ring(mesh, a, 0.0, 4.0 * small).first, Ring(plain->GetOutput(), a, 0.0, 4.0 * small).first);
}

TEST(TargetEdgeLengthFilterTest, the_points_only_law_matches_brute_force_on_many_points)
{
  // 2000 random wells: every grid triangle above the floor is no longer than the law
  // min_p (h_p + G |x - p|) evaluated by brute force at its corners.
  const Box box = Bounds("pinch_out.vtp");
  const double w = box.width();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(box.x0, box.x1), uy(box.y0, box.y1),
    uh(w / 300.0, w / 20.0);
  std::vector<std::array<double, 3>> wells(2000);
  for (auto& p : wells)
  {
    p = { ux(rng), uy(rng), uh(rng) };
  }
  auto reader = Reader("pinch_out.vtp");
  vtkNew<vtkAdaptive48Grid> grid;
  grid->SetInputConnection(reader->GetOutputPort());
  grid->SetTargetEdgeLengthData(Wells(wells));
  grid->SetTargetEdgeLengthGrading(0.3);
  auto log = Watch(grid);
  grid->Update();
  ASSERT_TRUE(log->Errors.empty()) << log->Errors;
  vtkUnstructuredGrid* out = grid->GetOutput();
  const int floorLevel =
    static_cast<int>(out->GetFieldData()->GetArray("TargetMaxLevel")->GetTuple1(0));
  vtkDataArray* level = out->GetCellData()->GetArray("Level");
  const auto law = [&](const double x[3])
  {
    double best = HUGE_VAL;
    for (const auto& p : wells)
    {
      best = std::min(best, p[2] + 0.3 * std::hypot(x[0] - p[0], x[1] - p[1]));
    }
    return best;
  };
  int checked = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    if (level->GetTuple1(c) >= floorLevel)
    {
      continue;
    }
    const double longest = LongestEdge(out, c);
    const vtkIdType* ids = nullptr;
    vtkIdType n = 0;
    out->GetCellPoints(c, n, ids);
    for (vtkIdType k = 0; k < n; ++k)
    {
      double x[3];
      out->GetPoint(ids[k], x);
      EXPECT_LE(longest, law(x) * (1 + 1e-9)) << "triangle " << c;
    }
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(TargetEdgeLengthFilterTest, bad_values_and_missing_arrays_fail_the_request_naming_them)
{
  const Box box = Bounds("pinch_out.vtp");
  const double centre[2] = { box.x0, box.y0 };
  auto reader = Reader("pinch_out.vtp");
  for (const double bad : { -1.0, 0.0, std::nan(""), HUGE_VAL })
  {
    auto image = DiscImage(box, centre, 1.0, 5.0, 50.0);
    image->GetPointData()->GetArray("TargetEdgeLength")->SetTuple1(137, bad);
    vtkNew<vtkPhysicalCompressionTriangulator> mesher;
    mesher->SetInputConnection(reader->GetOutputPort());
    mesher->SetTargetEdgeLengthData(image);
    auto log = Watch(mesher);
    mesher->Update();
    EXPECT_TRUE(log->Has("point 137")) << log->Errors;
    EXPECT_TRUE(log->Has("TargetEdgeLength")) << log->Errors;
    EXPECT_EQ(mesher->GetOutput()->GetNumberOfCells(), 0);
  }
  // Two point arrays, neither named as asked: the error names what is missing and what is there.
  auto image = DiscImage(box, centre, 1.0, 5.0, 50.0, "a");
  auto other = vtkSmartPointer<vtkDoubleArray>::New();
  other->SetName("b");
  other->SetNumberOfTuples(image->GetNumberOfPoints());
  other->Fill(1.0);
  image->GetPointData()->AddArray(other);
  vtkNew<vtkAdaptive48Grid> grid;
  grid->SetInputConnection(reader->GetOutputPort());
  grid->SetTargetEdgeLengthData(image);
  grid->SetTargetEdgeLengthArray("size");
  auto log = Watch(grid);
  grid->Update();
  EXPECT_TRUE(log->Has("'size'")) << log->Errors;
  EXPECT_TRUE(log->Has("'a', 'b'")) << log->Errors;
  EXPECT_EQ(grid->GetOutput()->GetNumberOfCells(), 0);
  // Named: it works.
  log->Errors.clear();
  grid->SetTargetEdgeLengthArray("b");
  grid->Update();
  EXPECT_TRUE(log->Errors.empty()) << log->Errors;
  EXPECT_GT(grid->GetOutput()->GetNumberOfCells(), 0);
  std::ostringstream printed;
  grid->Print(printed);
  EXPECT_NE(printed.str().find("TargetEdgeLength input: connected"), std::string::npos);
  EXPECT_NE(printed.str().find("TargetEdgeLengthArray: b"), std::string::npos);
  EXPECT_NE(printed.str().find("TargetEdgeLengthGrading: 0.5"), std::string::npos);
  // Grading out of its range (0, 10].
  grid->SetTargetEdgeLengthGrading(0.0);
  grid->Update();
  EXPECT_TRUE(log->Has("TargetEdgeLengthGrading = 0 is out of range (0, 10]")) << log->Errors;
}

TEST(TargetEdgeLengthFilterTest, the_grid_follows_a_changed_or_removed_field)
{
  const Box box = Bounds("salt_dome.vtp");
  const double w = box.width();
  const double centre[2] = { box.x0 + 0.5 * w, 0.5 * (box.y0 + box.y1) };
  auto reader = Reader("salt_dome.vtp");
  auto count = [&](vtkDataSet* field)
  {
    vtkNew<vtkAdaptive48Grid> fresh;
    fresh->SetInputConnection(reader->GetOutputPort());
    fresh->SetTargetEdgeLengthData(field);
    fresh->Update();
    return fresh->GetOutput()->GetNumberOfCells();
  };
  auto image = DiscImage(box, centre, 0.1 * w, w / 100.0, w / 10.0);
  vtkNew<vtkAdaptive48Grid> grid;
  grid->SetInputConnection(reader->GetOutputPort());
  grid->SetTargetEdgeLengthData(image);
  grid->Update();
  const vtkIdType first = grid->GetOutput()->GetNumberOfCells();
  EXPECT_EQ(first, count(image));
  // Smaller targets in the same image: the grid is rebuilt, finer.
  vtkDataArray* values = image->GetPointData()->GetArray("TargetEdgeLength");
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    values->SetTuple1(i, 0.5 * values->GetTuple1(i));
  }
  values->Modified();
  grid->Update();
  const vtkIdType second = grid->GetOutput()->GetNumberOfCells();
  EXPECT_GT(second, first);
  EXPECT_EQ(second, count(image));
  // Back to the original values: coarser again (no stale refinement kept).
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    values->SetTuple1(i, 2.0 * values->GetTuple1(i));
  }
  values->Modified();
  grid->Update();
  EXPECT_EQ(grid->GetOutput()->GetNumberOfCells(), first);
  // Removed: the automatic grid.
  grid->SetTargetEdgeLengthData(nullptr);
  grid->Update();
  EXPECT_EQ(grid->GetOutput()->GetNumberOfCells(), count(nullptr));
  EXPECT_NE(grid->GetOutput()->GetNumberOfCells(), first);
}
