// Tests of the input model: every file of Data/bad_inputs gets the outcome of its README table,
// every model of Data/ builds with its documented regions, and hand-made inputs exercise each
// rule of buildModel (forms, repairs, errors, orientation, junctions, tolerances).
#include "Model.h"

#include "CoreTestUtilities.h"
#include "Errors.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <regex>
#include <string>
#include <vector>

namespace
{

using strata::buildModel;
using strata::CellKind;
using strata::InputError;
using strata::Model;
using strata::ModelForm;
using strata::ModelParams;
using strata::RawPolylines;
using strata::Region;
using strata::Ring;
using strata::Vec2;

#define EXPECT_CONTAINS(text, part)                                                                \
  EXPECT_NE(std::string(text).find(part), std::string::npos)                                       \
    << "expected \"" << (part) << "\" in: " << (text)

RawPolylines readModel(const std::string& name)
{
  return strata_test::readVtpAscii(strata_test::dataPath(name));
}

Model buildFile(const std::string& name, const ModelParams& params = {})
{
  return buildModel(readModel(name), params);
}

/// The InputError message buildModel gives for raw (a test failure when it does not throw).
std::string inputError(const RawPolylines& raw, const ModelParams& params = {})
{
  try
  {
    buildModel(raw, params);
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  ADD_FAILURE() << "buildModel did not throw InputError";
  return {};
}

std::string fileError(const std::string& name)
{
  return inputError(readModel(name));
}

/// raw with every point mapped to offset + scale * p.
RawPolylines transformed(RawPolylines raw, double offset, double scale)
{
  for (Vec2& p : raw.points)
  {
    p = { offset + scale * p.x, offset + scale * p.y };
  }
  return raw;
}

/// A message with its coordinates and gaps masked, to compare the messages of a model and of
/// its shifted or scaled copy.
std::string masked(const std::string& message)
{
  static const std::regex coordinates(R"(\([^()]*,[^()]*\))");
  static const std::regex gap(R"(gap [^ )]+)");
  return std::regex_replace(std::regex_replace(message, coordinates, "(P)"), gap, "gap G");
}

double ringArea(const Ring& ring)
{
  double sum = 0.0;
  const std::size_t n = ring.points.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    sum += strata::cross(ring.points[i], ring.points[(i + 1) % n]);
  }
  return 0.5 * sum;
}

double regionArea(const Region& region)
{
  double sum = 0.0;
  for (const Ring& ring : region.rings)
  {
    sum += ringArea(ring);
  }
  return sum;
}

std::size_t ringCount(const Model& model)
{
  std::size_t n = 0;
  for (const Region& region : model.regions)
  {
    n += region.rings.size();
  }
  return n;
}

bool nearlyEqual(double a, double b, double relative)
{
  return std::abs(a - b) <= relative * std::max(std::abs(a), std::abs(b));
}

/// Same region ids, ring counts and areas (b's areas are a's times areaScale).
void expectSameRegions(const Model& a, const Model& b, double areaScale = 1.0)
{
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t r = 0; r < a.regions.size(); ++r)
  {
    const Region& ra = a.regions[r];
    const Region& rb = b.regions[r];
    EXPECT_EQ(ra.id, rb.id);
    EXPECT_EQ(ra.rings.size(), rb.rings.size()) << "region " << ra.id;
    EXPECT_TRUE(nearlyEqual(regionArea(ra) * areaScale, regionArea(rb), 1e-9))
      << "region " << ra.id << ": " << regionArea(ra) * areaScale << " vs " << regionArea(rb);
  }
}

/// Crossing-number test of p in the ring.
bool insideRing(Vec2 p, const Ring& ring)
{
  bool in = false;
  const std::size_t n = ring.points.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const Vec2 a = ring.points[i];
    const Vec2 b = ring.points[(i + 1) % n];
    if ((a.y > p.y) != (b.y > p.y) && a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) > p.x)
    {
      in = !in;
    }
  }
  return in;
}

bool hasEdge(const Ring& ring, int u, int v)
{
  const std::size_t n = ring.nodes.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const int a = ring.nodes[i];
    const int b = ring.nodes[(i + 1) % n];
    if ((a == u && b == v) || (a == v && b == u))
    {
      return true;
    }
  }
  return false;
}

/// Number of other rings of the region that contain ring i (tested at the midpoint of one of
/// its segments that the other ring does not have).
int depthOf(const Region& region, std::size_t i)
{
  const Ring& ring = region.rings[i];
  const std::size_t n = ring.nodes.size();
  int depth = 0;
  for (std::size_t o = 0; o < region.rings.size(); ++o)
  {
    if (o == i)
    {
      continue;
    }
    for (std::size_t k = 0; k < n; ++k)
    {
      if (!hasEdge(region.rings[o], ring.nodes[k], ring.nodes[(k + 1) % n]))
      {
        const Vec2 m = 0.5 * (ring.points[k] + ring.points[(k + 1) % n]);
        depth += insideRing(m, region.rings[o]) ? 1 : 0;
        break;
      }
    }
  }
  return depth;
}

/// Consistency of a built model: rings close over their nodes, carry one cell per segment,
/// are oriented by their even-odd depth, and every region has a positive area.
void expectWellFormed(const Model& model)
{
  for (std::size_t r = 0; r < model.regions.size(); ++r)
  {
    const Region& region = model.regions[r];
    if (r > 0)
    {
      EXPECT_LT(model.regions[r - 1].id, region.id);
    }
    EXPECT_EQ(model.regionIndex(region.id), static_cast<int>(r));
    EXPECT_GT(regionArea(region), 0.0) << "region " << region.id;
    for (std::size_t i = 0; i < region.rings.size(); ++i)
    {
      const Ring& ring = region.rings[i];
      ASSERT_GE(ring.points.size(), 3u);
      ASSERT_EQ(ring.nodes.size(), ring.points.size());
      ASSERT_EQ(ring.segmentCell.size(), ring.points.size());
      for (std::size_t k = 0; k < ring.points.size(); ++k)
      {
        ASSERT_EQ(model.nodes[ring.nodes[k]], ring.points[k]);
        EXPECT_GE(ring.segmentCell[k], 0);
        EXPECT_EQ(region.bounds.distance2(ring.points[k]), 0.0);
      }
      const bool even = depthOf(region, i) % 2 == 0;
      EXPECT_EQ(ringArea(ring) > 0.0, even)
        << "region " << region.id << " ring " << i << " depth " << depthOf(region, i);
    }
  }
}

int nodeAt(const Model& model, Vec2 input)
{
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
  {
    if (model.nodes[n] + model.origin == input)
    {
      return static_cast<int>(n);
    }
  }
  return -1;
}

using strata_test::addCell;
using strata_test::addCurve;
using strata_test::addLoop;

/// Two unit squares side by side: region 0 = [0,1]x[0,1], region 1 = [1,2]x[0,1].
RawPolylines twoSquaresLoops()
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 }, { 0, 0 } }, 0);
  addLoop(raw, { { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1, 0 } }, 1);
  return raw;
}

RawPolylines twoSquaresShared()
{
  RawPolylines raw;
  addCurve(raw, { { 1, 0 }, { 1, 1 } }, 0, 1);                      // the shared edge, upwards
  addCurve(raw, { { 1, 1 }, { 0, 1 }, { 0, 0 }, { 1, 0 } }, 0, -1); // around region 0
  addCurve(raw, { { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 } }, 1, -1); // around region 1
  return raw;
}

bool anyWarningContains(const Model& model, const std::string& part)
{
  return std::any_of(model.warnings.begin(),
    model.warnings.end(),
    [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

//------------------------------------------------------------------------------
// Data/bad_inputs: the README table.

TEST(ModelTest, reference_ok_builds_two_regions_split_by_the_horizon)
{
  const Model model = buildFile("bad_inputs/reference_ok.vtp");
  EXPECT_EQ(model.form, ModelForm::SharedCurves);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_EQ(ringCount(model), 2u);
  EXPECT_TRUE(nearlyEqual(
    regionArea(model.regions[0]) + regionArea(model.regions[1]), 1000.0 * 500.0, 1e-12));
  EXPECT_TRUE(model.warnings.empty());
  expectWellFormed(model);
}

TEST(ModelTest, reference_loops_ok_builds_a_frame_with_a_hole_and_its_core)
{
  const Model model = buildFile("bad_inputs/reference_loops_ok.vtp");
  EXPECT_EQ(model.form, ModelForm::Loops);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_EQ(model.regions[0].rings.size(), 2u);
  EXPECT_EQ(model.regions[1].rings.size(), 1u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 100.0 * 100.0 - 20.0 * 20.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 20.0 * 20.0);
  EXPECT_TRUE(model.warnings.empty());
  expectWellFormed(model);
}

TEST(ModelTest, implicitly_closed_loops_are_joined_with_a_warning)
{
  const Model reference = buildFile("bad_inputs/reference_loops_ok.vtp");
  const Model model = buildFile("bad_inputs/implicitly_closed_loop.vtp");
  expectSameRegions(reference, model);
  ASSERT_FALSE(model.warnings.empty());
  EXPECT_CONTAINS(model.warnings[0], "cell 0");
  EXPECT_CONTAINS(model.warnings[0], "gap 25");
  EXPECT_TRUE(anyWarningContains(model, "cell 1"));
  expectWellFormed(model);
}

TEST(ModelTest, rejects_unclosed_loop_whose_closing_edge_crosses_naming_the_gap)
{
  const std::string msg = fileError("bad_inputs/unclosed_loop.vtp");
  EXPECT_CONTAINS(msg, "loop of cell 0 does not close");
  EXPECT_CONTAINS(msg, "gap 44.7");
  EXPECT_CONTAINS(msg, "first point (0, 0)");
  EXPECT_CONTAINS(msg, "last point (20, 40)");
  EXPECT_CONTAINS(msg, "closing edge crosses cell 0 at (10, 20)");
}

TEST(ModelTest, rejects_unclosed_shared_boundary_naming_the_dangling_end)
{
  const std::string msg = fileError("bad_inputs/unclosed_boundary_shared.vtp");
  EXPECT_CONTAINS(msg, "dangling curve end at (1000, 150)");
  EXPECT_CONTAINS(msg, "end of cell 1");
  EXPECT_CONTAINS(msg, "region 0 is not closed");
}

TEST(ModelTest, drops_duplicate_points_with_one_warning_per_cell)
{
  const Model reference = buildFile("bad_inputs/reference_loops_ok.vtp");
  const Model model = buildFile("bad_inputs/duplicate_points.vtp");
  expectSameRegions(reference, model);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_CONTAINS(model.warnings[0], "cell 0");
  EXPECT_CONTAINS(model.warnings[0], "2 repeated consecutive points");
  // Cell 0 keeps its 16 distinct points.
  EXPECT_EQ(model.curves[0].nodes.size(), 16u);
  expectWellFormed(model);
}

TEST(ModelTest, ignores_zero_length_and_one_point_cells_with_warnings)
{
  const Model reference = buildFile("bad_inputs/reference_loops_ok.vtp");
  const Model model = buildFile("bad_inputs/zero_length_cell.vtp");
  expectSameRegions(reference, model);
  EXPECT_EQ(model.curves.size(), 3u);
  ASSERT_EQ(model.warnings.size(), 2u);
  EXPECT_CONTAINS(model.warnings[0], "cell 3");
  EXPECT_CONTAINS(model.warnings[0], "zero length");
  EXPECT_CONTAINS(model.warnings[1], "cell 4");
  EXPECT_CONTAINS(model.warnings[1], "one point");
  expectWellFormed(model);
}

TEST(ModelTest, rejects_nan_coordinate_naming_the_point)
{
  const std::string msg = fileError("bad_inputs/nan_coordinate.vtp");
  EXPECT_CONTAINS(msg, "point 5 (cell 0) has a non-finite coordinate x = nan");
}

TEST(ModelTest, utm_offset_gives_the_regions_of_the_reference)
{
  const Model reference = buildFile("bad_inputs/reference_ok.vtp");
  const Model model = buildFile("bad_inputs/utm_offset_1e7.vtp");
  expectSameRegions(reference, model);
  EXPECT_EQ(model.nodes.size(), reference.nodes.size());
  EXPECT_EQ(model.junctions, reference.junctions);
  EXPECT_DOUBLE_EQ(model.origin.x, reference.origin.x + 1e7);
  EXPECT_DOUBLE_EQ(model.origin.y, reference.origin.y + 1e7);
  EXPECT_NEAR(model.size(), reference.size(), 1e-6);
  EXPECT_TRUE(model.warnings.empty());
}

TEST(ModelTest, tiny_scale_gives_the_regions_of_the_reference_scaled)
{
  const Model reference = buildFile("bad_inputs/reference_ok.vtp");
  const Model model = buildFile("bad_inputs/tiny_scale_1e-6.vtp");
  expectSameRegions(reference, model, 1e-12);
  EXPECT_EQ(model.nodes.size(), reference.nodes.size());
  EXPECT_EQ(model.junctions, reference.junctions);
  EXPECT_TRUE(nearlyEqual(model.size(), 1e-6 * reference.size(), 1e-12));
  EXPECT_TRUE(model.warnings.empty());
}

TEST(ModelTest, rejects_self_intersecting_loop_naming_the_crossing)
{
  const std::string msg = fileError("bad_inputs/self_intersecting_loop.vtp");
  EXPECT_CONTAINS(msg, "cell 1 intersects itself at (250, 50)");
}

TEST(ModelTest, rejects_inconsistent_labels_naming_both_cells)
{
  const std::string msg = fileError("bad_inputs/inconsistent_labels.vtp");
  EXPECT_CONTAINS(msg, "inconsistent region labels");
  EXPECT_CONTAINS(msg, "cell 0 says region 1");
  EXPECT_CONTAINS(msg, "cell 2 says region 0");
  EXPECT_CONTAINS(msg, "for the same face (near (");
}

TEST(ModelTest, rejects_input_without_region_arrays)
{
  const std::string msg = fileError("bad_inputs/no_region_array.vtp");
  EXPECT_CONTAINS(msg, "no region arrays");
  EXPECT_CONTAINS(msg, "RegionId");
  EXPECT_CONTAINS(msg, "LeftRegion and RightRegion");
}

TEST(ModelTest, empty_input_gives_an_empty_model_with_a_warning)
{
  const Model model = buildFile("bad_inputs/empty.vtp");
  EXPECT_TRUE(model.empty());
  EXPECT_TRUE(model.regions.empty());
  EXPECT_TRUE(model.nodes.empty());
  EXPECT_EQ(model.size(), 1.0);
  EXPECT_EQ(model.regionIndex(0), -1);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_EQ(model.warnings[0], "empty input: no cells");
}

TEST(ModelTest, rejects_crossing_curves_naming_the_cells_and_the_point)
{
  const std::string msg = fileError("bad_inputs/crossing_curves.vtp");
  EXPECT_CONTAINS(msg, "cell 0 and cell 4 cross at (");
  EXPECT_CONTAINS(msg, "without a shared vertex");
}

TEST(ModelTest, reads_polygon_cells_as_loops_with_warnings)
{
  const Model model = buildFile("bad_inputs/polygon_cells.vtp");
  ASSERT_EQ(model.regions.size(), 1u);
  EXPECT_EQ(model.regions[0].id, 0);
  EXPECT_EQ(model.regions[0].rings.size(), 2u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 100.0 * 100.0 - 20.0 * 20.0);
  ASSERT_EQ(model.warnings.size(), 2u);
  EXPECT_CONTAINS(model.warnings[0], "cell 0 is a polygon cell");
  EXPECT_CONTAINS(model.warnings[1], "cell 1 is a polygon cell");
  expectWellFormed(model);
}

TEST(ModelTest, shifted_and_scaled_bad_inputs_give_the_same_errors_and_warnings)
{
  for (const char* name : { "unclosed_loop.vtp",
         "unclosed_boundary_shared.vtp",
         "self_intersecting_loop.vtp",
         "inconsistent_labels.vtp",
         "crossing_curves.vtp",
         "nan_coordinate.vtp",
         "implicitly_closed_loop.vtp",
         "duplicate_points.vtp",
         "zero_length_cell.vtp",
         "polygon_cells.vtp",
         "reference_ok.vtp" })
  {
    SCOPED_TRACE(name);
    const RawPolylines raw = readModel(std::string("bad_inputs/") + name);
    for (const auto& [offset, scale] :
      { std::make_pair(1e7, 1.0), std::make_pair(0.0, 1e-6), std::make_pair(-3e5, 1e3) })
    {
      SCOPED_TRACE("offset " + std::to_string(offset) + " scale " + std::to_string(scale));
      const RawPolylines moved = transformed(raw, offset, scale);
      std::string expected, got;
      std::vector<std::string> expectedWarnings, gotWarnings;
      try
      {
        const Model m = buildModel(raw);
        for (const std::string& w : m.warnings)
        {
          expectedWarnings.push_back(masked(w));
        }
        const Model n = buildModel(moved);
        for (const std::string& w : n.warnings)
        {
          gotWarnings.push_back(masked(w));
        }
        expectSameRegions(m, n, scale * scale);
        EXPECT_EQ(m.junctions, n.junctions);
      }
      catch (const InputError&)
      {
        expected = masked(inputError(raw));
        got = masked(inputError(moved));
        EXPECT_FALSE(expected.empty());
      }
      EXPECT_EQ(expected, got);
      EXPECT_EQ(expectedWarnings, gotWarnings);
    }
  }
}

TEST(ModelTest, shifted_error_reports_the_point_in_input_coordinates)
{
  const RawPolylines raw =
    transformed(readModel("bad_inputs/self_intersecting_loop.vtp"), 1e7, 1.0);
  EXPECT_CONTAINS(inputError(raw), "cell 1 intersects itself at (10000250, 10000050)");
}

//------------------------------------------------------------------------------
// The models of Data/.

struct DataModel
{
  const char* file;
  ModelForm form;
  std::size_t regions;
};

const DataModel kDataModels[] = {
  { "lake_superior.vtp", ModelForm::Loops, 1 },
  { "lake_superior_full.vtp", ModelForm::Loops, 1 },
  { "countries_westeurope.vtp", ModelForm::SharedCurves, 9 },
  { "countries_westeurope_loops.vtp", ModelForm::Loops, 9 },
  { "geology_marmousi.vtp", ModelForm::SharedCurves, 9 },
  { "pinch_out.vtp", ModelForm::SharedCurves, 3 },
  { "thin_layer.vtp", ModelForm::SharedCurves, 3 },
  { "nested_holes.vtp", ModelForm::Loops, 1 },
  { "touching_loops.vtp", ModelForm::Loops, 2 },
  { "salt_dome.vtp", ModelForm::SharedCurves, 6 },
  { "salt_dome_loops.vtp", ModelForm::Loops, 6 },
  { "gulf_section.vtp", ModelForm::SharedCurves, 15 },
  { "gulf_section_loops.vtp", ModelForm::Loops, 15 },
  { "guitar.vtp", ModelForm::Loops, 1 },
};

TEST(ModelTest, every_data_model_builds_with_its_documented_regions)
{
  for (const DataModel& data : kDataModels)
  {
    SCOPED_TRACE(data.file);
    const RawPolylines raw = readModel(data.file);
    Model model;
    ASSERT_NO_THROW(model = buildModel(raw));
    EXPECT_EQ(model.form, data.form);
    EXPECT_EQ(model.regions.size(), data.regions);
    EXPECT_EQ(model.curves.size(), raw.numberOfCells());
    EXPECT_TRUE(model.warnings.empty()) << model.warnings.front();
    for (std::size_t r = 0; r < model.regions.size(); ++r)
    {
      EXPECT_EQ(model.regions[r].id, static_cast<int>(r));
    }
    // Local coordinates: the model is centred on the origin.
    EXPECT_NEAR(model.bounds.center().x, 0.0, 1e-9 * model.size());
    EXPECT_NEAR(model.bounds.center().y, 0.0, 1e-9 * model.size());
    expectWellFormed(model);
  }
}

TEST(ModelTest, lake_superior_is_one_region_with_45_island_holes)
{
  for (const char* file : { "lake_superior.vtp", "lake_superior_full.vtp" })
  {
    SCOPED_TRACE(file);
    const Model model = buildFile(file);
    ASSERT_EQ(model.regions.size(), 1u);
    const Region& water = model.regions[0];
    ASSERT_EQ(water.rings.size(), 46u);
    const auto outer = std::count_if(water.rings.begin(),
      water.rings.end(),
      [](const Ring& ring) { return ringArea(ring) > 0.0; });
    EXPECT_EQ(outer, 1);
    EXPECT_TRUE(model.junctions.empty());
  }
}

TEST(ModelTest, nested_holes_alternate_orientation_by_depth)
{
  const Model model = buildFile("nested_holes.vtp");
  ASSERT_EQ(model.regions.size(), 1u);
  const Region& region = model.regions[0];
  ASSERT_EQ(region.rings.size(), 4u);
  std::vector<int> depths;
  for (std::size_t i = 0; i < 4; ++i)
  {
    depths.push_back(depthOf(region, i));
    EXPECT_EQ(ringArea(region.rings[i]) > 0.0, depths.back() % 2 == 0);
  }
  std::sort(depths.begin(), depths.end());
  EXPECT_EQ(depths, (std::vector<int>{ 0, 1, 2, 3 }));
  double evenOdd = 0.0;
  for (std::size_t i = 0; i < 4; ++i)
  {
    evenOdd += (depthOf(region, i) % 2 == 0 ? 1.0 : -1.0) * std::abs(ringArea(region.rings[i]));
  }
  EXPECT_TRUE(nearlyEqual(regionArea(region), evenOdd, 1e-12));
}

TEST(ModelTest, loops_and_shared_curves_variants_have_the_same_region_areas)
{
  for (const auto& [shared, loops] : { std::make_pair("salt_dome.vtp", "salt_dome_loops.vtp"),
         std::make_pair("gulf_section.vtp", "gulf_section_loops.vtp"),
         std::make_pair("countries_westeurope.vtp", "countries_westeurope_loops.vtp") })
  {
    SCOPED_TRACE(shared);
    const Model a = buildFile(shared);
    const Model b = buildFile(loops);
    expectSameRegions(a, b);
    EXPECT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(a.junctions.size(), b.junctions.size());
  }
}

TEST(ModelTest, countries_loops_repeat_shared_borders_without_error)
{
  const Model model = buildFile("countries_westeurope_loops.vtp");
  EXPECT_EQ(model.regions.size(), 9u);
  // 17 junctions of 3+ borders (Data/README.md).
  EXPECT_EQ(model.junctions.size(), 17u);
  EXPECT_EQ(buildFile("countries_westeurope.vtp").junctions.size(), 17u);
}

TEST(ModelTest, marmousi_has_113_junctions)
{
  const Model model = buildFile("geology_marmousi.vtp");
  EXPECT_EQ(model.junctions.size(), 113u);
  EXPECT_TRUE(std::is_sorted(model.junctions.begin(), model.junctions.end()));
  EXPECT_EQ(
    std::adjacent_find(model.junctions.begin(), model.junctions.end()), model.junctions.end());
}

TEST(ModelTest, touching_loops_have_a_junction_at_the_shared_vertex)
{
  const Model model = buildFile("touching_loops.vtp");
  ASSERT_EQ(model.regions.size(), 2u);
  const int shared = nodeAt(model, { 10, 10 });
  ASSERT_GE(shared, 0);
  EXPECT_EQ(model.junctions, std::vector<int>{ shared });
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 100.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 100.0);
}

TEST(ModelTest, pinch_out_and_thin_layer_keep_their_thin_regions)
{
  const Model pinch = buildFile("pinch_out.vtp");
  ASSERT_EQ(pinch.regions.size(), 3u);
  EXPECT_GT(regionArea(pinch.regions[1]), 0.0);
  const Model thin = buildFile("thin_layer.vtp");
  ASSERT_EQ(thin.regions.size(), 3u);
  // The wavy layer is 1.0 thick and 1000 wide.
  EXPECT_NEAR(regionArea(thin.regions[1]), 1000.0, 1.0);
}

//------------------------------------------------------------------------------
// Hand-made inputs.

TEST(ModelTest, two_squares_sharing_an_edge_give_the_same_regions_in_both_forms)
{
  const Model loops = buildModel(twoSquaresLoops());
  const Model shared = buildModel(twoSquaresShared());
  EXPECT_EQ(loops.form, ModelForm::Loops);
  EXPECT_EQ(shared.form, ModelForm::SharedCurves);
  for (const Model* model : { &loops, &shared })
  {
    ASSERT_EQ(model->regions.size(), 2u);
    EXPECT_EQ(model->nodes.size(), 6u);
    EXPECT_DOUBLE_EQ(model->origin.x, 1.0);
    EXPECT_DOUBLE_EQ(model->origin.y, 0.5);
    for (const Region& region : model->regions)
    {
      ASSERT_EQ(region.rings.size(), 1u);
      EXPECT_DOUBLE_EQ(ringArea(region.rings[0]), 1.0);
      EXPECT_EQ(region.rings[0].points.size(), 4u);
      EXPECT_DOUBLE_EQ(region.bounds.width(), 1.0);
    }
    EXPECT_DOUBLE_EQ(model->regions[0].bounds.min.x, -1.0);
    EXPECT_DOUBLE_EQ(model->regions[1].bounds.max.x, 1.0);
    // The ends of the shared edge are the junctions.
    const std::vector<int> ends = { nodeAt(*model, { 1, 0 }), nodeAt(*model, { 1, 1 }) };
    std::vector<int> junctions = model->junctions;
    std::vector<int> expected = ends;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(junctions, expected);
    EXPECT_DOUBLE_EQ(model->size(), std::sqrt(5.0));
    EXPECT_TRUE(model->warnings.empty());
    expectWellFormed(*model);
  }
  expectSameRegions(loops, shared);
  // Shared curves: region 1's ring uses the shared edge (cell 0) and its own boundary (cell 2).
  const std::vector<std::int64_t>& cells = shared.regions[1].rings[0].segmentCell;
  EXPECT_EQ(std::count(cells.begin(), cells.end(), 0), 1);
  EXPECT_EQ(std::count(cells.begin(), cells.end(), 2), 3);
}

TEST(ModelTest, loops_are_oriented_counter_clockwise_whatever_the_input_orientation)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 0, 1 }, { 1, 1 }, { 1, 0 } }, 3); // clockwise, not repeated
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 1u);
  EXPECT_EQ(model.regions[0].id, 3);
  EXPECT_EQ(model.regionIndex(3), 0);
  EXPECT_EQ(model.regionIndex(0), -1);
  EXPECT_DOUBLE_EQ(ringArea(model.regions[0].rings[0]), 1.0);
  EXPECT_TRUE(model.curves[0].closed);
  EXPECT_TRUE(anyWarningContains(model, "cell 0: loop closed by joining"));
}

TEST(ModelTest, shared_curves_island_makes_a_hole_in_the_surrounding_region)
{
  RawPolylines raw;
  addCurve(raw, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 }, { 0, 0 } }, 0, -1);
  addCurve(raw, { { 4, 4 }, { 4, 6 }, { 6, 6 }, { 6, 4 }, { 4, 4 } }, 0, 1); // clockwise: 1 inside
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_EQ(model.regions[0].rings.size(), 2u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 96.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 4.0);
  EXPECT_TRUE(model.curves[0].closed);
  EXPECT_EQ(model.curves[0].nodes.size(), 4u);
  EXPECT_TRUE(model.junctions.empty());
  expectWellFormed(model);
}

/// Box [0,10]x[0,10]: region 0 below the horizon y = 5, above it region 1 left of the fault
/// x = 5 and region 2 right of it. The horizon is one cell through (5,5) when splitHorizon is
/// false (then its LeftRegion cannot be right on both sides of the fault).
RawPolylines faultedBox(bool splitHorizon, double faultBottom = 5.0)
{
  RawPolylines raw;
  addCurve(raw, { { 0, 5 }, { 0, 0 }, { 10, 0 }, { 10, 5 } }, 0, -1); // cell 0
  if (splitHorizon)
  {
    addCurve(raw, { { 0, 5 }, { 5, 5 } }, 1, 0);  // cell 1
    addCurve(raw, { { 5, 5 }, { 10, 5 } }, 2, 0); // cell 2
  }
  else
  {
    addCurve(raw, { { 0, 5 }, { 5, 5 }, { 10, 5 } }, 1, 0); // cell 1
  }
  addCurve(raw, { { 10, 5 }, { 10, 10 }, { 5, 10 } }, 2, -1);
  addCurve(raw, { { 5, 10 }, { 0, 10 }, { 0, 5 } }, 1, -1);
  addCurve(raw, { { 5, faultBottom }, { 5, 10 } }, 1, 2); // the fault, last cell
  return raw;
}

TEST(ModelTest, faulted_box_with_a_split_horizon_gives_three_regions)
{
  const Model model = buildModel(faultedBox(true));
  ASSERT_EQ(model.regions.size(), 3u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 50.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 25.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[2]), 25.0);
  std::vector<int> expected;
  for (const Vec2 p : { Vec2{ 0, 5 }, Vec2{ 10, 5 }, Vec2{ 5, 5 }, Vec2{ 5, 10 } })
  {
    expected.push_back(nodeAt(model, p));
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(model.junctions, expected);
  expectWellFormed(model);
}

TEST(ModelTest, rejects_a_fault_ending_inside_a_horizon_with_one_label_above_it)
{
  // The fault ends at an interior vertex of the horizon: that is a junction, not a dangling
  // end, and the horizon's single LeftRegion contradicts the fault.
  const std::string msg = inputError(faultedBox(false));
  EXPECT_CONTAINS(msg, "inconsistent region labels");
  EXPECT_CONTAINS(msg, "cell 1 says region 1");
  EXPECT_EQ(msg.find("dangling"), std::string::npos) << msg;
}

TEST(ModelTest, rejects_a_fault_that_stops_short_naming_its_dangling_end)
{
  const std::string msg = inputError(faultedBox(true, 6.0));
  EXPECT_CONTAINS(
    msg, "dangling curve end at (5, 6) (end of cell 5): regions 1 and 2 are not closed");
}

TEST(ModelTest, shared_curves_island_may_touch_the_outer_boundary_at_an_interior_vertex)
{
  RawPolylines raw;
  addCurve(raw, { { 0, 0 }, { 5, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 }, { 0, 0 } }, 0, -1);
  addCurve(raw, { { 5, 0 }, { 7, 3 }, { 3, 3 }, { 5, 0 } }, 1, 0); // counter-clockwise
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 94.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 6.0);
  EXPECT_EQ(model.junctions, std::vector<int>{ nodeAt(model, { 5, 0 }) });
  expectWellFormed(model);
}

TEST(ModelTest, rejects_a_region_labelled_outside_the_outer_boundary)
{
  RawPolylines raw = twoSquaresShared();
  raw.rightRegion[1] = 5;
  raw.rightRegion[2] = 5;
  const std::string msg = inputError(raw);
  EXPECT_CONTAINS(msg, "region 5 is unbounded");
}

TEST(ModelTest, rejects_a_border_given_twice_in_the_shared_curves_form)
{
  RawPolylines raw = twoSquaresShared();
  addCurve(raw, { { 1, 1 }, { 1, 0 } }, 0, 1);
  const std::string msg = inputError(raw);
  EXPECT_CONTAINS(msg, "cell 0 and cell 3 both run along the segment");
}

TEST(ModelTest, loops_may_repeat_a_neighbours_border)
{
  const Model model = buildModel(twoSquaresLoops());
  // 8 loop segments, the shared one counted once: 7 unique edges over 6 nodes.
  EXPECT_EQ(model.junctions.size(), 2u);
  EXPECT_EQ(model.curves.size(), 2u);
}

TEST(ModelTest, loops_of_one_region_side_by_side_keep_their_area)
{
  // A 3 x 3 block of unit squares, all region 0: the middle square shares all its edges. By the
  // even-odd rule the 12 inner edges are no border: the region is one ring, the outline, and
  // the curves keep only the outline's 12 edges.
  RawPolylines raw;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      const double x = i, y = j;
      addLoop(raw, { { x, y }, { x + 1, y }, { x + 1, y + 1 }, { x, y + 1 } }, 0);
    }
  }
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 1u);
  ASSERT_EQ(model.regions[0].rings.size(), 1u);
  EXPECT_EQ(model.regions[0].rings[0].nodes.size(), 12u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 9.0);
  EXPECT_EQ(model.nodes.size(), 16u);
  std::size_t segments = 0;
  for (const strata::Curve& c : model.curves)
  {
    EXPECT_FALSE(c.closed);
    segments += c.nodes.size() - 1;
  }
  EXPECT_EQ(segments, 12u);
  // Without the inner edges every node of the outline has degree 2.
  EXPECT_TRUE(model.junctions.empty());
  EXPECT_TRUE(anyWarningContains(model, "region 0: 12 segments have the region on both sides"));
  expectWellFormed(model);
}

TEST(ModelTest, a_region_given_as_two_loops_side_by_side_is_the_region_of_one)
{
  // Region 0 as the two unit squares of [0,2]x[0,1], region 1 beside it: the same rings,
  // curves' segments and junctions as region 0 given as one loop, and a warning naming the
  // border between the two loops.
  RawPolylines halves;
  addLoop(halves, { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } }, 0);
  addLoop(halves, { { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 } }, 0);
  addLoop(halves, { { 2, 0 }, { 3, 0 }, { 3, 1 }, { 2, 1 } }, 1);
  RawPolylines whole;
  addLoop(whole, { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 0, 1 } }, 0);
  addLoop(whole, { { 2, 0 }, { 3, 0 }, { 3, 1 }, { 2, 1 } }, 1);
  const Model a = buildModel(halves);
  const Model b = buildModel(whole);
  expectSameRegions(a, b);
  ASSERT_EQ(a.regions[0].rings.size(), 1u);
  EXPECT_EQ(a.regions[0].rings[0].nodes.size(), 6u);
  EXPECT_EQ(a.junctions.size(), b.junctions.size());
  EXPECT_TRUE(anyWarningContains(a,
    "region 0: 1 segment has the region on both sides (the "
    "first from (1, 0) to (1, 1), between cell 0 and cell 1)"));
  EXPECT_FALSE(anyWarningContains(b, "on both sides"));
  expectWellFormed(a);
}

TEST(ModelTest, a_loop_running_back_along_itself_loses_the_spike_with_a_warning)
{
  // A spike of no width from (10, 5) into the square and back: on both of its sides lies the
  // square's region, so it is no border. Rings and junctions are those of the square alone.
  RawPolylines spiked;
  addLoop(
    spiked, { { 0, 0 }, { 10, 0 }, { 10, 5 }, { 6, 5 }, { 10, 5 }, { 10, 10 }, { 0, 10 } }, 0);
  RawPolylines plain;
  addLoop(plain, { { 0, 0 }, { 10, 0 }, { 10, 5 }, { 10, 10 }, { 0, 10 } }, 0);
  const Model a = buildModel(spiked);
  const Model b = buildModel(plain);
  expectSameRegions(a, b);
  EXPECT_EQ(a.regions[0].rings[0].nodes.size(), 5u);
  EXPECT_TRUE(a.junctions.empty());
  EXPECT_TRUE(anyWarningContains(a,
    "region 0: 1 segment has the region on both sides (the first "
    "from (10, 5) to (6, 5), where cell 0 runs back along itself)"));
  expectWellFormed(a);
}

TEST(ModelTest, rejects_an_island_whose_surrounding_region_has_no_hole_for_it)
{
  // Loops form: region 1's square lies inside region 0's, which has no loop around the hole.
  RawPolylines loops;
  addLoop(loops, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 } }, 0);
  addLoop(loops, { { 4, 4 }, { 6, 4 }, { 6, 6 }, { 4, 6 } }, 1);
  std::string msg = inputError(loops);
  EXPECT_CONTAINS(msg,
    "regions 1 and 0 overlap: the border of region 1 at (5, 4) (cell 1) lies "
    "inside region 0 (cell 0)");
  EXPECT_CONTAINS(msg, "needs a loop around the hole");
  // With the hole loop it is the island of a frame.
  addLoop(loops, { { 4, 4 }, { 6, 4 }, { 6, 6 }, { 4, 6 } }, 0);
  const Model model = buildModel(loops);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 96.0);
  // Shared curves form: the island's outer side labelled -1 instead of 0.
  RawPolylines shared;
  addCurve(shared, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 }, { 0, 0 } }, 0, -1);
  addCurve(shared, { { 4, 4 }, { 6, 4 }, { 6, 6 }, { 4, 6 }, { 4, 4 } }, 1, -1);
  msg = inputError(shared);
  EXPECT_CONTAINS(msg,
    "regions 1 and 0 overlap: the border of region 1 at (5, 4) (cell 1) lies "
    "inside region 0 (cell 0)");
  EXPECT_CONTAINS(msg, "has 0 on that side, not -1");
  // Two islands side by side, neither inside the other, are two pieces of one model.
  RawPolylines apart;
  addCurve(apart, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 }, { 0, 0 } }, 0, -1);
  addCurve(apart, { { 14, 4 }, { 16, 4 }, { 16, 6 }, { 14, 6 }, { 14, 4 } }, 1, -1);
  EXPECT_EQ(buildModel(apart).regions.size(), 2u);
}

TEST(ModelTest, an_overlap_thinner_than_a_millionth_of_the_model_is_let_through)
{
  // Region 1's copy of the shared border bends into region 0 by `poke` at (1, 0.5): a sliver
  // of overlap. Noise (1e-8, 4.5e-9 of the model's size) builds; 1e-3 is an overlap.
  for (const double poke : { 1e-8, 1e-3 })
  {
    RawPolylines raw;
    addLoop(raw, { { 0, 0 }, { 1, 0 }, { 1, 0.5 }, { 1, 1 }, { 0, 1 } }, 0);
    addLoop(raw, { { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1 - poke, 0.5 } }, 1);
    if (poke < 1e-6)
    {
      EXPECT_EQ(buildModel(raw).regions.size(), 2u);
    }
    else
    {
      EXPECT_CONTAINS(
        inputError(raw), "regions 0 and 1 overlap: the border of region 0 at (1, 0.25)");
    }
  }
}

TEST(ModelTest, rejects_two_regions_on_one_side_of_a_border)
{
  // Region 1 is given the loop of region 0: both lie inside the same square.
  RawPolylines raw = twoSquaresLoops();
  addLoop(raw, { { 0, 0 }, { 0, 1 }, { 1, 1 }, { 1, 0 } }, 1); // clockwise: orientation is free
  EXPECT_CONTAINS(inputError(raw),
    "regions 0 and 1 overlap: cell 0 and cell 2 both put their "
    "region on the same side of the segment from (");
}

TEST(ModelTest, rejects_a_loop_given_twice)
{
  // By the even-odd rule the two copies cancel and leave region 0 nothing.
  RawPolylines raw = twoSquaresLoops();
  addLoop(raw, { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } }, 0);
  const std::string msg = inputError(raw);
  EXPECT_CONTAINS(msg, "cell 0 and cell 2 both put region 0 on the same side of the segment");
  EXPECT_CONTAINS(msg, "a loop given twice");
}

TEST(ModelTest, a_hole_touching_its_outer_loop_along_a_border_is_no_overlap)
{
  // A 2 x 2 checkerboard: region 0 is the squares [0,1]^2 and [1,2]^2, region 1 the box with
  // both as holes. Each hole shares two sides with the box's loop (those cancel for region 1)
  // and touches the other hole at (1, 1).
  RawPolylines raw;
  const std::vector<Vec2> low{ { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
  const std::vector<Vec2> high{ { 1, 1 }, { 2, 1 }, { 2, 2 }, { 1, 2 } };
  addLoop(raw, low, 0);
  addLoop(raw, high, 0);
  addLoop(
    raw, { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 2, 2 }, { 1, 2 }, { 0, 2 }, { 0, 1 } }, 1);
  addLoop(raw, low, 1);
  addLoop(raw, high, 1);
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 2u);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[0]), 2.0);
  EXPECT_DOUBLE_EQ(regionArea(model.regions[1]), 2.0);
  // Region 1 is the two other squares, traced apart at (1, 1); the cancelled sides are region
  // 0's borders, so they stay curves and no warning is given.
  EXPECT_EQ(model.regions[1].rings.size(), 2u);
  EXPECT_FALSE(anyWarningContains(model, "on both sides"));
  expectWellFormed(model);
}

TEST(ModelTest, rejects_vertex_touching_another_loop_without_a_shared_vertex)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 } }, 0);
  addLoop(raw, { { 10, 5 }, { 20, 0 }, { 20, 10 } }, 1); // (10,5) is on cell 0's edge
  EXPECT_CONTAINS(inputError(raw), "cell 0 and cell 1 touch at (10, 5) without a shared vertex");
}

TEST(ModelTest, rejects_collinear_overlap_of_two_loops)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 } }, 0);
  addLoop(raw, { { 10, 8 }, { 10, 2 }, { 20, 2 }, { 20, 8 } }, 1); // first edge on x = 10
  EXPECT_CONTAINS(inputError(raw), "cell 0 and cell 1 overlap at (10, 8) without a shared vertex");
}

TEST(ModelTest, rejects_a_loop_that_folds_back_on_itself)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 10, 0 }, { 5, 0 }, { 5, 5 } }, 0);
  EXPECT_CONTAINS(inputError(raw), "cell 0 intersects itself at (");
}

TEST(ModelTest, touching_at_a_shared_vertex_is_allowed)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 5, 5 }, { 0, 10 } }, 0);
  addLoop(raw, { { 5, 5 }, { 10, 10 }, { 0, 10 } }, 1); // fills the notch, shares 3 vertices
  const Model model = buildModel(raw);
  EXPECT_EQ(model.regions.size(), 2u);
  expectWellFormed(model);
}

TEST(ModelTest, merge_tolerance_is_relative_to_the_model_size)
{
  // The loop's last point misses its first by 1e-5 of the diagonal.
  for (double scale : { 1.0, 1e-6, 1e6 })
  {
    SCOPED_TRACE(scale);
    RawPolylines raw;
    const double miss = 1e-5 * std::sqrt(2.0) * scale;
    addLoop(raw, { { 0, 0 }, { scale, 0 }, { scale, scale }, { 0, scale }, { 0, miss } }, 0);
    ModelParams merging;
    merging.mergeTolerance = 1e-4;
    const Model merged = buildModel(raw, merging);
    EXPECT_EQ(merged.curves[0].nodes.size(), 4u);
    EXPECT_TRUE(merged.warnings.empty());
    const Model strict = buildModel(raw);
    EXPECT_EQ(strict.curves[0].nodes.size(), 5u);
    EXPECT_TRUE(anyWarningContains(strict, "loop closed by joining"));
  }
}

TEST(ModelTest, merged_points_drop_consecutive_duplicates)
{
  RawPolylines raw;
  addLoop(raw, { { 0, 0 }, { 1, 0 }, { 1 + 1e-9, 1e-9 }, { 1, 1 }, { 0, 1 }, { 0, 0 } }, 0);
  ModelParams params;
  params.mergeTolerance = 1e-6;
  const Model model = buildModel(raw, params);
  EXPECT_EQ(model.curves[0].nodes.size(), 4u);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_CONTAINS(model.warnings[0], "cell 0: dropped 1 repeated consecutive point");
}

TEST(ModelTest, rejects_merge_tolerance_out_of_range)
{
  for (double tol : { -1e-12, 2e-3, std::nan("") })
  {
    ModelParams params;
    params.mergeTolerance = tol;
    EXPECT_THROW(buildModel(twoSquaresLoops(), params), strata::ParameterError) << tol;
  }
  ModelParams zero;
  zero.mergeTolerance = 0.0;
  EXPECT_EQ(buildModel(twoSquaresLoops(), zero).regions.size(), 2u);
  ModelParams largest;
  largest.mergeTolerance = 1e-3;
  EXPECT_EQ(buildModel(twoSquaresLoops(), largest).regions.size(), 2u);
}

TEST(ModelTest, rejects_region_id_below_minus_one_naming_the_cell)
{
  RawPolylines raw = twoSquaresLoops();
  raw.regionId[1] = -2;
  EXPECT_CONTAINS(inputError(raw), "cell 1 has RegionId -2");
  RawPolylines shared = twoSquaresShared();
  shared.rightRegion[2] = -7;
  EXPECT_CONTAINS(inputError(shared), "cell 2 has RightRegion -7");
}

TEST(ModelTest, rejects_point_ids_out_of_range)
{
  RawPolylines raw = twoSquaresLoops();
  raw.connectivity[7] = 99;
  EXPECT_CONTAINS(inputError(raw), "cell 1 refers to point 99");
  raw.connectivity[7] = -1;
  EXPECT_CONTAINS(inputError(raw), "cell 1 refers to point -1");
}

TEST(ModelTest, rejects_infinite_coordinate_naming_the_point)
{
  RawPolylines raw = twoSquaresLoops();
  raw.points[6].y = -HUGE_VAL;
  EXPECT_CONTAINS(inputError(raw), "point 6 (cell 1) has a non-finite coordinate y = -inf");
}

TEST(ModelTest, rejects_region_arrays_of_the_wrong_size)
{
  RawPolylines raw = twoSquaresLoops();
  raw.regionId.push_back(0);
  EXPECT_CONTAINS(inputError(raw), "RegionId has 3 values but the input has 2 cells");
  RawPolylines shared = twoSquaresShared();
  shared.leftRegion.pop_back();
  shared.form = ModelForm::SharedCurves;
  EXPECT_CONTAINS(inputError(shared), "LeftRegion has 2 values but the input has 3 cells");
}

TEST(ModelTest, explicit_form_needs_its_arrays)
{
  RawPolylines raw = twoSquaresLoops();
  raw.form = ModelForm::SharedCurves;
  EXPECT_CONTAINS(inputError(raw), "Shared curves form needs a LeftRegion cell array");
  RawPolylines shared = twoSquaresShared();
  shared.form = ModelForm::Loops;
  EXPECT_CONTAINS(inputError(shared), "Loops form needs a RegionId cell array");
  // With both kinds of arrays, Auto picks the Shared curves form and Loops can be forced.
  RawPolylines both = twoSquaresShared();
  both.regionId = { 0, 0, 1 };
  EXPECT_EQ(buildModel(both).form, ModelForm::SharedCurves);
  both.form = ModelForm::Loops;
  const Model asLoops = buildModel(both);
  EXPECT_EQ(asLoops.form, ModelForm::Loops);
  EXPECT_EQ(asLoops.regions.size(), 2u);
  EXPECT_TRUE(anyWarningContains(asLoops, "cell 0 is a loop with fewer than 3 distinct points"));
}

TEST(ModelTest, ignores_non_line_cells_and_polygons_of_shared_curves_with_warnings)
{
  RawPolylines raw = twoSquaresShared();
  addCurve(raw, { { 5, 5 }, { 6, 5 }, { 6, 6 } }, 0, 1);
  raw.kinds.back() = CellKind::Other;
  addCurve(raw, { { 7, 5 }, { 8, 5 }, { 8, 6 } }, 0, 1);
  raw.kinds.back() = CellKind::Polygon;
  const Model model = buildModel(raw);
  EXPECT_EQ(model.curves.size(), 3u);
  ASSERT_EQ(model.warnings.size(), 2u);
  EXPECT_CONTAINS(model.warnings[0], "cell 3 is not a line cell");
  EXPECT_CONTAINS(model.warnings[1], "cell 4 is a polygon cell");
  // The ignored cells do not count for the bounds either.
  EXPECT_DOUBLE_EQ(model.size(), std::sqrt(5.0));
}

TEST(ModelTest, rejects_input_without_usable_line_cells)
{
  RawPolylines raw = twoSquaresLoops();
  raw.kinds = { CellKind::Other, CellKind::Other };
  const std::string msg = inputError(raw);
  EXPECT_CONTAINS(msg, "no usable line cells (StrataMesh reads VTK_LINE / VTK_POLY_LINE cells)");
  EXPECT_CONTAINS(msg, "cell 0");

  RawPolylines degenerate;
  addLoop(degenerate, { { 1, 1 }, { 1, 1 } }, 0);
  EXPECT_CONTAINS(inputError(degenerate), "no usable line cells");
}

TEST(ModelTest, ignores_exterior_loops_and_short_loops_with_warnings)
{
  RawPolylines raw = twoSquaresLoops();
  addLoop(raw, { { 5, 5 }, { 6, 5 }, { 6, 6 } }, -1);
  addLoop(raw, { { 7, 5 }, { 8, 5 }, { 7, 5 } }, 0);
  const Model model = buildModel(raw);
  EXPECT_EQ(model.curves.size(), 2u);
  EXPECT_EQ(model.regions.size(), 2u);
  ASSERT_EQ(model.warnings.size(), 2u);
  EXPECT_CONTAINS(model.warnings[0], "cell 2 is a loop of region -1");
  EXPECT_CONTAINS(model.warnings[1], "cell 3 is a loop with fewer than 3 distinct points");
}

TEST(ModelTest, drops_shared_curves_with_the_same_region_on_both_sides)
{
  RawPolylines raw = twoSquaresShared();
  addCurve(raw, { { 0.5, 0.2 }, { 0.5, 0.8 } }, 0, 0); // a fault inside region 0
  const Model model = buildModel(raw);
  EXPECT_EQ(model.curves.size(), 3u);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_CONTAINS(model.warnings[0], "cell 3 has region 0 on both sides");
}

TEST(ModelTest, many_warnings_of_one_kind_are_summarised)
{
  RawPolylines raw = twoSquaresLoops();
  for (int i = 0; i < 50; ++i)
  {
    addLoop(raw, { { 0.5, 0.5 } }, 0);
  }
  const Model model = buildModel(raw);
  ASSERT_EQ(model.warnings.size(), 21u);
  EXPECT_CONTAINS(model.warnings.back(), "and 30 more such warnings");
}

TEST(ModelTest, builds_a_long_wiggly_loop_and_finds_one_crossing_in_it)
{
  RawPolylines raw;
  std::vector<Vec2> points;
  const int n = 20000;
  for (int i = 0; i < n; ++i)
  {
    const double t = 2.0 * std::acos(-1.0) * i / n;
    const double r = 100.0 * (1.0 + 0.2 * std::sin(40.0 * t));
    points.push_back({ r * std::cos(t), r * std::sin(t) });
  }
  addLoop(raw, points, 0);
  const Model model = buildModel(raw);
  ASSERT_EQ(model.regions.size(), 1u);
  EXPECT_EQ(model.regions[0].rings[0].points.size(), static_cast<std::size_t>(n));
  // Move point 5000 just across the middle of segment 5002-5003: its segments cross that one.
  raw.points[5000] = raw.points[5002] + 0.5 * (raw.points[5003] - raw.points[5002]);
  raw.points[5000].x += 1e-3 * (raw.points[5003].y - raw.points[5002].y);
  const std::string msg = inputError(raw);
  EXPECT_CONTAINS(msg, "cell 0 intersects itself at (");
}

} // namespace
