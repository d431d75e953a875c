// End-to-end tests of the triangulation pipeline on every model in Data/.
#include "Mesher.h"
#include "Compression.h"
#include "CoreTestUtilities.h"
#include "Errors.h"
#include "Quality.h"
#include "StripTree.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace
{
using strata::Vec2;

// A result's warnings, one per line (to search, and to print when an expectation fails).
std::string allWarnings(const strata::MesherResult& r)
{
  std::string all;
  for (const std::string& w : r.warnings)
  {
    all += w + "\n";
  }
  return all;
}

// Expects each of `texts` in r's warnings (a failure names the text and gives them all).
void expectWarningsSay(const strata::MesherResult& r, std::initializer_list<const char*> texts)
{
  const std::string warnings = allWarnings(r);
  for (const char* text : texts)
  {
    EXPECT_NE(warnings.find(text), std::string::npos) << text << "\n" << warnings;
  }
}

// The mesh ThinLayerRetry's levels kept is the one at `level` and meets issue 4's bounds: the
// boundary within half a local edge, the areas within 0.5%, its boundary vertices on the curves,
// and no triangle that no input corner forces below `angleAbove` degrees.
void expectKeptLevelMeetsTheBounds(const strata::RawPolylines& raw,
  const strata::MesherResult& r,
  int level,
  double angleAbove)
{
  EXPECT_EQ(r.summary.localMaxLevel, level);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_GT(r.summary.minAngleUnforced, angleAbove);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * strata::buildModel(raw).size());
}

// How many meshes of a finer level were made and not kept (stages of the one kept).
long discardedLevelRuns(const strata::MesherResult& r)
{
  return std::count_if(r.summary.secondsPerStage.begin(),
    r.summary.secondsPerStage.end(),
    [](const auto& stage) { return stage.first == "discarded level run"; });
}

struct Case
{
  const char* file;
  int maxLevel;           // -1: automatic
  double minAngle;        // lower bound of the smallest angle (0: not checked)
  double regionAreaError; // largest relative error of a region's area (1: not checked)
  int offCurve = 0;       // known residual boundary vertices off the curves (none now)
};

// Levels keep the suite fast; the paper's three models at about the paper's triangle counts.
const Case kCases[] = {
  { "lake_superior.vtp", 9, 11.5, 0.02 }, // ~1 950 triangles (paper: 1 906, 11.5 deg)
  { "salt_dome.vtp", 10, 10.4, 0.02 },    // ~6 000 triangles (paper: 6 183, 10.4 deg)
  { "gulf_section.vtp", 10, 5.25, 0.04 }, // ~10 000 triangles (paper: 11 015, 5.25 deg);
                                          // 12.7 deg with Grid48's junction refinement
  { "salt_dome_loops.vtp", 9, 0, 0.02 },
  { "gulf_section_loops.vtp", 9, 0, 1 },
  { "lake_superior_full.vtp", 10, 0, 0.02 },
  { "guitar.vtp", 12, 0, 0.02 },
  { "nested_holes.vtp", 8, 0, 0.02 },
  { "touching_loops.vtp", 8, 0, 0.02 },
  { "pinch_out.vtp", 9, 0, 1 },            // the wedge pinches out below the resolution
  { "thin_layer.vtp", 9, 0, 1 },           // a layer 1/1000 thick: aliased (paper 6.6)
  { "countries_westeurope.vtp", 9, 0, 1 }, // Monaco and Liechtenstein: below resolution
  { "countries_westeurope_loops.vtp", 9, 0, 1 },
  { "geology_marmousi.vtp", 9, 0, 1 }, // one-pixel bands
};

strata::MesherResult mesh(const Case& c)
{
  strata::MesherParams p;
  p.grid.maxLevel = c.maxLevel;
  return strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath(c.file)), p);
}

class MesherModels : public ::testing::TestWithParam<Case>
{
};

// Readable names in test listings.
void PrintTo(const Case& c, std::ostream* os)
{
  *os << c.file << " at level " << c.maxLevel;
}

std::string caseName(const ::testing::TestParamInfo<Case>& info)
{
  std::string s = info.param.file;
  s = s.substr(0, s.find('.'));
  return s;
}
} // namespace

TEST_P(MesherModels, InvariantsHold)
{
  const Case c = GetParam();
  const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(c.file));
  const strata::Model model = strata::buildModel(raw);
  const strata::MesherResult r = mesh(c);
  ASSERT_GT(r.triangles.size(), 100u);

  // No inverted, degenerate or overlapping triangle: every triangle counter-clockwise, every
  // edge in at most two triangles, and in opposite directions when in two.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : r.triangles)
  {
    ASSERT_GT(strata::orient2d(r.points[t[0]], r.points[t[1]], r.points[t[2]]), 0.0);
    for (int k = 0; k < 3; ++k)
    {
      const std::pair<int, int> edge(t[k], t[(k + 1) % 3]);
      ASSERT_EQ(++directed[edge], 1) << "edge used twice in one direction";
    }
  }
  // Every vertex of the approximated boundary lies on an input curve.
  const strata::BoundaryRails rails(model, 0.0);
  strata::StripTreeScratch scratch;
  const double tolerance = 1e-9 * model.size();
  std::size_t boundaryVertices = 0, off = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i)
  {
    if (r.vertexClass[i] == strata::VertexBoundary)
    {
      ++boundaryVertices;
      double d = 0.0;
      rails.closest(r.points[i], scratch, &d);
      off += d > tolerance;
    }
  }
  EXPECT_GT(boundaryVertices, 10u);
  EXPECT_LE(off, static_cast<std::size_t>(c.offCurve))
    << c.file << ": boundary vertices off the curves";
  if (off == 0)
  {
    EXPECT_LE(r.summary.maxBoundaryVertexDistance, tolerance);
  }
  else
  {
    EXPECT_FALSE(r.warnings.empty()); // a residual is reported
  }

  // Areas: the whole model within 2%, each region within its case's bound.
  double modelArea = 0.0, meshArea = 0.0;
  for (const auto& ra : r.regionAreas)
  {
    modelArea += ra.model;
    meshArea += ra.mesh;
    if (c.regionAreaError < 1.0)
    {
      EXPECT_NEAR(ra.mesh, ra.model, c.regionAreaError * ra.model) << "region " << ra.id;
    }
  }
  EXPECT_NEAR(meshArea, modelArea, 0.02 * modelArea);
  if (c.minAngle > 0.0)
  {
    EXPECT_GE(r.summary.minAngle, c.minAngle);
  }
}

INSTANTIATE_TEST_SUITE_P(DataModels, MesherModels, ::testing::ValuesIn(kCases), caseName);

TEST(MesherTest, ResultIsCompleteAndConsistent)
{
  const strata::MesherResult r = mesh({ "salt_dome.vtp", 9, 0, 1 });
  const std::size_t nt = r.triangles.size(), np = r.points.size();
  EXPECT_EQ(r.regionId.size(), nt);
  EXPECT_EQ(r.level.size(), nt);
  EXPECT_EQ(r.minAngle.size(), nt);
  EXPECT_EQ(r.maxAngle.size(), nt);
  EXPECT_EQ(r.radiusRatio.size(), nt);
  EXPECT_EQ(r.area.size(), nt);
  EXPECT_EQ(r.vertexClass.size(), np);
  EXPECT_EQ(r.displacement.size(), np);
  EXPECT_EQ(r.summary.triangles, nt);
  EXPECT_EQ(r.summary.vertices, np);
  EXPECT_GT(r.summary.iterations, 0);
  EXPECT_NE(r.origin, (Vec2{ 0.0, 0.0 }));
  double least = 180.0;
  for (std::size_t t = 0; t < nt; ++t)
  {
    EXPECT_GE(r.regionId[t], 0);
    EXPECT_GT(r.area[t], 0.0);
    least = std::min(least, r.minAngle[t]);
  }
  EXPECT_EQ(least, r.summary.minAngle);
  EXPECT_GT(r.summary.percentAngles30to60, 50.0);
  EXPECT_GT(r.summary.percentTriangles30to60, 80.0);
  EXPECT_GT(r.summary.maxBoundaryDeviation, 0.0);
  // Stages, in pipeline order, and their sum.
  std::vector<std::string> names;
  double sum = 0.0;
  for (const auto& s : r.summary.secondsPerStage)
  {
    names.push_back(s.first);
    sum += s.second;
  }
  const std::vector<std::string> expected = { "model",
    "distance field",
    "grid",
    "classification",
    "compression set-up",
    "simulation",
    "face classification",
    "optimization",
    "refinement",
    "output" };
  EXPECT_EQ(names, expected);
  EXPECT_LE(sum, r.summary.totalSeconds + 1e-6);
  // The boundary in the Shared curves form: six regions and the exterior, each piece with two
  // different labels, every piece made of vertices of the mesh.
  ASSERT_FALSE(r.boundary.empty());
  std::map<std::pair<double, double>, int> vertex;
  for (const Vec2& p : r.points)
  {
    vertex[{ p.x, p.y }] = 1;
  }
  for (const auto& b : r.boundary)
  {
    EXPECT_NE(b.left, b.right);
    EXPECT_GE(b.left, 0);
    EXPECT_GE(b.points.size(), 2u);
    for (const Vec2& p : b.points)
    {
      EXPECT_EQ(vertex.count({ p.x, p.y }), 1u);
    }
  }
}

// The parts that run on two threads (the spring steps of large systems, the region queries of
// the waves of new pushes) split their work the same way on every run: the same input gives
// the same mesh, bit for bit. The gulf at its automatic levels (78 k triangles) takes both.
TEST(MesherTest, TheSameInputGivesTheSameMeshEveryRun)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("gulf_section.vtp"));
  const strata::MesherResult first = strata::triangulate(raw);
  const strata::MesherResult second = strata::triangulate(raw);
  ASSERT_GT(first.triangles.size(), 50000u);
  EXPECT_EQ(first.points, second.points);
  EXPECT_EQ(first.triangles, second.triangles);
  EXPECT_EQ(first.regionId, second.regionId);
  EXPECT_EQ(first.summary.iterations, second.summary.iterations);
}

// UTM-sized coordinates and a model a millimetre wide give meshes of the reference's quality:
// everything is computed relative to the model's bounds. (Not the same cells: the shifted
// file's coordinates differ from the reference's by up to 4e-10, and ties that are exact on
// the reference's round coordinates go a few cells the other way; README, Input.)
TEST(MesherTest, FarFromTheOriginAndTinyModelsGiveTheReferencesQuality)
{
  const strata::MesherResult ref = strata::triangulate(
    strata_test::readVtpAscii(strata_test::dataPath("bad_inputs/reference_ok.vtp")));
  ASSERT_GT(ref.triangles.size(), 1000u);
  for (const auto& [file, scale] : { std::pair<const char*, double>{ "utm_offset_1e7.vtp", 1.0 },
         std::pair<const char*, double>{ "tiny_scale_1e-6.vtp", 1e-6 } })
  {
    const strata::MesherResult r = strata::triangulate(
      strata_test::readVtpAscii(strata_test::dataPath(std::string("bad_inputs/") + file)));
    SCOPED_TRACE(file);
    const double ratio =
      static_cast<double>(r.triangles.size()) / static_cast<double>(ref.triangles.size());
    EXPECT_NEAR(ratio, 1.0, 0.05);
    EXPECT_GE(r.summary.minAngle, 30.0 - 0.05);
    EXPECT_LE(r.summary.maxAngle, 130.0);
    EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
    EXPECT_NEAR(r.summary.finestEdgeLength,
      scale * ref.summary.finestEdgeLength,
      1e-9 * scale * ref.summary.finestEdgeLength);
    ASSERT_EQ(r.regionAreas.size(), ref.regionAreas.size());
    for (std::size_t i = 0; i < r.regionAreas.size(); ++i)
    {
      EXPECT_EQ(r.regionAreas[i].id, ref.regionAreas[i].id);
      EXPECT_NEAR(r.regionAreas[i].model,
        scale * scale * ref.regionAreas[i].model,
        1e-9 * scale * scale * ref.regionAreas[i].model);
      EXPECT_NEAR(r.regionAreas[i].mesh,
        scale * scale * ref.regionAreas[i].mesh,
        1e-3 * scale * scale * ref.regionAreas[i].model);
    }
  }
}

TEST(MesherTest, BoundaryCurvesHaveTheirRegionOnTheLeft)
{
  // A square region: its outer border is one closed curve, counter-clockwise around it.
  strata::RawPolylines raw;
  raw.points = { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 } };
  raw.offsets = { 0, 5 };
  raw.connectivity = { 0, 1, 2, 3, 0 };
  raw.regionId = { 3 };
  strata::MesherParams p;
  p.grid.maxLevel = 6;
  const strata::MesherResult r = strata::triangulate(raw, p);
  ASSERT_EQ(r.boundary.size(), 1u);
  const auto& b = r.boundary[0];
  EXPECT_EQ(b.left, 3);
  EXPECT_EQ(b.right, -1);
  EXPECT_EQ(b.points.front(), b.points.back());
  double twiceArea = 0.0;
  for (std::size_t i = 0; i + 1 < b.points.size(); ++i)
  {
    twiceArea += strata::cross(b.points[i], b.points[i + 1]);
  }
  EXPECT_NEAR(0.5 * twiceArea, 100.0, 5.0); // counter-clockwise around the region
  EXPECT_GT(r.summary.minAngle, 20.0);
}

TEST(MesherTest, EmptyInputGivesAnEmptyMeshWithAWarning)
{
  strata::RawPolylines raw;
  raw.regionId = {};
  raw.form = strata::ModelForm::Loops;
  const strata::MesherResult r = strata::triangulate(raw);
  EXPECT_TRUE(r.triangles.empty());
  EXPECT_FALSE(r.warnings.empty());
}

TEST(MesherTest, MalformedInputThrowsInputError)
{
  EXPECT_THROW(strata::triangulate(strata_test::readVtpAscii(
                 strata_test::dataPath("bad_inputs/self_intersecting_loop.vtp"))),
    strata::InputError);
}

TEST(MesherTest, ARegionGivenAsLoopsSideBySideIsMeshedAsTheRegionOfOneLoop)
{
  // The border between two loops of region 0 is no border (the even-odd rule): the mesh is
  // the mesh of region 0 given as one loop, triangle for triangle, with one warning more.
  strata::RawPolylines halves;
  strata_test::addLoop(halves, { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 }, { 0, 0 } }, 0);
  strata_test::addLoop(halves, { { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 1, 0 } }, 0);
  strata_test::addLoop(halves, { { 2, 0 }, { 3, 0 }, { 3, 1 }, { 2, 1 }, { 2, 0 } }, 1);
  strata::RawPolylines whole;
  strata_test::addLoop(
    whole, { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 2, 1 }, { 1, 1 }, { 0, 1 }, { 0, 0 } }, 0);
  strata_test::addLoop(whole, { { 2, 0 }, { 3, 0 }, { 3, 1 }, { 2, 1 }, { 2, 0 } }, 1);
  const strata::MesherResult a = strata::triangulate(halves);
  const strata::MesherResult b = strata::triangulate(whole);
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  EXPECT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size() && i < b.points.size(); ++i)
  {
    EXPECT_EQ(a.points[i], b.points[i]) << "point " << i;
  }
  EXPECT_EQ(a.regionId, b.regionId);
  EXPECT_EQ(a.warnings.size(), b.warnings.size() + 1) << allWarnings(a);
  expectWarningsSay(a, { "region 0: 1 segment has the region on both sides" });
}

TEST(MesherTest, ParameterErrorsComeBeforeAnyWork)
{
  strata::MesherParams p;
  p.compression.timeStep = 5.0;
  int calls = 0;
  EXPECT_THROW(strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("guitar.vtp")),
                 p,
                 [&](double, const char*) { return ++calls > 0; }),
    strata::ParameterError);
  EXPECT_EQ(calls, 0);
  p = {};
  p.grid.maxLevel = 99;
  EXPECT_THROW(
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("guitar.vtp")), p),
    strata::ParameterError);
}

TEST(MesherTest, ProgressIsMonotoneAndAbortIsHonouredWithin200ms)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("gulf_section.vtp"));
  strata::MesherParams p;
  p.grid.maxLevel = 18; // about 1e5 triangles
  using Clock = std::chrono::steady_clock;
  // Progress: fractions never decrease, and calls are never more than 0.2 s apart. This mesh is
  // made once (no ThinLayerRetry mesh): its run covers most of the range, the output stage
  // starting at 0.75 (at 0.46 before 2026-12-03, the rest left to retries that did not come).
  {
    double last = -1.0, longest = 0.0, writing = -1.0;
    Clock::time_point previous = Clock::now();
    bool monotone = true;
    const strata::MesherResult r = strata::triangulate(raw,
      p,
      [&](double f, const char* stage)
      {
        const Clock::time_point now = Clock::now();
        longest = std::max(longest, std::chrono::duration<double>(now - previous).count());
        previous = now;
        monotone &= f >= last - 1e-12;
        last = f;
        if (writing < 0.0 && std::string(stage) == "writing the mesh")
        {
          writing = f;
        }
        return true;
      });
    EXPECT_TRUE(monotone);
    EXPECT_NEAR(last, 1.0, 1e-12);
    EXPECT_LT(longest, 0.2);
    ASSERT_EQ(allWarnings(r).find("made too"), std::string::npos);
    ASSERT_EQ(allWarnings(r).find("made again"), std::string::npos);
    EXPECT_GT(writing, 0.7);
  }
  // Abort in the middle of the simulation.
  Clock::time_point asked{};
  bool abortRequested = false;
  const Clock::time_point start = Clock::now();
  try
  {
    strata::triangulate(raw,
      p,
      [&](double f, const char*)
      {
        if (f > 0.4 && !abortRequested)
        {
          abortRequested = true;
          asked = Clock::now();
        }
        return !abortRequested;
      });
    FAIL() << "not aborted";
  }
  catch (const strata::Aborted&)
  {
    EXPECT_TRUE(abortRequested);
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - asked).count(), 0.2);
  }
  (void)start;
}

// Beyond the paper: boundary edges that cut a corner or a bend of their curve are split at the
// curve. On Lake Superior (default levels) this lowers the largest boundary deviation, keeps
// the smallest angle above 15 degrees, and the inserted vertices lie on the curves.
TEST(MesherTest, BoundaryRefinementBringsTheBoundaryCloserToTheCurves)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("lake_superior.vtp"));
  const strata::Model model = strata::buildModel(raw);
  strata::MesherParams p;
  p.curveRecovery = false; // it pulls the boundary onto the curves too
  p.compression.boundaryTolerance = 0.0;
  const strata::MesherResult off = strata::triangulate(raw, p);
  p.compression.boundaryTolerance = strata::CompressionParams().boundaryTolerance;
  const strata::MesherResult on = strata::triangulate(raw, p);
  EXPECT_EQ(off.summary.boundarySplits, 0u);
  ASSERT_GT(on.summary.boundarySplits, 0u);
  EXPECT_LT(on.summary.maxBoundaryDeviation, 0.95 * off.summary.maxBoundaryDeviation);
  // Splits only make faces with angles in [15, 140] degrees.
  EXPECT_GE(on.summary.minAngle, std::min(15.0, off.summary.minAngle));
  // Inserted vertices are on the curves (the one known stray vertex of this model, see
  // InvariantsHold, is there with or without refinement).
  EXPECT_LE(on.summary.maxBoundaryVertexDistance,
    std::max(off.summary.maxBoundaryVertexDistance, 1e-9 * model.size()));
  EXPECT_LE(on.summary.maxRegionAreaError, off.summary.maxRegionAreaError + 0.005);
  for (const auto& t : on.triangles)
  {
    ASSERT_GT(strata::orient2d(on.points[t[0]], on.points[t[1]], on.points[t[2]]), 0.0);
  }
}

// Regions too thin for the finest triangles are reported by id (and named in a warning),
// never silently dropped: thin_layer's layer is 1/1000 of the model thick, here with no edge
// shorter than 4 (the curve recovery keeps it at the default sizes).
TEST(MesherTest, UnresolvedRegionsAreReportedById)
{
  strata::MesherParams coarse;
  coarse.grid.minEdgeLength = 4.0;
  const strata::MesherResult thin =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("thin_layer.vtp")), coarse);
  ASSERT_FALSE(thin.unresolvedRegions.empty());
  const std::string warnings = allWarnings(thin);
  for (const auto& ra : thin.regionAreas)
  {
    const bool listed =
      std::find(thin.unresolvedRegions.begin(), thin.unresolvedRegions.end(), ra.id) !=
      thin.unresolvedRegions.end();
    EXPECT_EQ(listed, ra.mesh < 0.5 * ra.model) << "region " << ra.id;
    if (listed)
    {
      EXPECT_NE(warnings.find(std::to_string(ra.id) + " ("), std::string::npos) << warnings;
    }
  }
  const strata::MesherResult salt =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")));
  EXPECT_TRUE(salt.unresolvedRegions.empty());
}

namespace
{
// Issue 5's boundary bound as Testing/Benchmark/quality_table.py measures it: the largest
// distance from points every eighth of a mesh boundary edge to the model's curves, and from
// points every half finest edge along the curves to the mesh boundary, each over the local
// edge there: the mean edge length of the triangles beside the mesh boundary edge the sample
// lies on, or nearest it (the mesher's definition), and between those samples wherever the
// distance's Lipschitz bound leaves room for more (within 0.005 local edges); the points above
// half their local edge beside a region narrower than the finest edge are left out (the
// issue's exemption; for a mesh point, its nearest curve point beside one).
double boundaryDeviationOverLocalEdge(const strata::Model& model, const strata::MesherResult& r)
{
  const double finest = r.summary.finestEdgeLength;
  std::vector<Vec2> ma, mb, ba, bb;
  const strata::BoundaryRails rails(model, 0.0);
  for (std::size_t ci = 0; ci < rails.numberOfChains(); ++ci)
  {
    const auto& chain = rails.chain(static_cast<int>(ci));
    for (std::size_t i = 0; i < chain.numberOfSegments(); ++i)
    {
      ma.push_back(chain.points[i]);
      mb.push_back(chain.points[(i + 1) % chain.points.size()]);
    }
  }
  // The mesh boundary's edges (one triangle, or two of different regions) and their local
  // edges.
  std::map<std::pair<int, int>, std::vector<int>> sides;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int u = r.triangles[t][k], v = r.triangles[t][(k + 1) % 3];
      sides[{ std::min(u, v), std::max(u, v) }].push_back(static_cast<int>(t));
    }
  }
  const auto meanEdge = [&](int t)
  {
    const auto& tri = r.triangles[t];
    return strata::meanEdgeLength(r.points[tri[0]], r.points[tri[1]], r.points[tri[2]]);
  };
  std::vector<double> local;
  for (const auto& [edge, ts] : sides)
  {
    if (ts.size() == 1 || r.regionId[ts[0]] != r.regionId[ts[1]])
    {
      ba.push_back(r.points[edge.first]);
      bb.push_back(r.points[edge.second]);
      local.push_back(ts.size() == 1 ? meanEdge(ts[0]) : 0.5 * (meanEdge(ts[0]) + meanEdge(ts[1])));
    }
  }
  const strata::StripTree modelTree(ma, mb), meshTree(ba, bb);
  strata::StripTreeScratch scratch;
  // Whether a region beside curve segment s is narrower than the finest edge at x (a hair
  // inside the segment), on either side: another curve within it along the normal, or the
  // disc of that diameter touching x, shrunk by 10%, cut by a curve (the mesher's and the
  // table's definition).
  const auto narrow = [&](Vec2 x, std::size_t s)
  {
    // (1e-4 of the way to the middle, at most 0.5% of the finest edge: the mesher's hair.)
    x = x +
      (1e-4 * std::min(1.0, 100.0 * finest / strata::norm(mb[s] - ma[s]))) *
        (0.5 * (ma[s] + mb[s]) - x);
    const Vec2 u = (1.0 / strata::norm(mb[s] - ma[s])) * (mb[s] - ma[s]);
    for (const Vec2 n : { Vec2{ -u.y, u.x }, Vec2{ u.y, -u.x } })
    {
      if (modelTree.nearest(x + 0.5 * finest * n, scratch).distance2 <
        std::pow(0.9 * 0.5 * finest, 2))
      {
        return true;
      }
      for (std::size_t k = 0; k < ma.size(); ++k)
      {
        const Vec2 e = mb[k] - ma[k], w = ma[k] - x;
        const double den = strata::cross(n, e);
        if (k == s || den == 0.0)
        {
          continue;
        }
        const double along = strata::cross(w, e) / den, at = strata::cross(w, n) / den;
        if (at >= 0.0 && at <= 1.0 && along > 1e-9 * (1.0 + std::fabs(x.x) + std::fabs(x.y)) &&
          along < finest)
        {
          return true;
        }
      }
    }
    return false;
  };
  // A point of the search: its distance to the other side, and whether it is exempt (above
  // half its local edge, beside a region narrower than the finest edge).
  struct Point
  {
    Vec2 x;
    double d;
    bool exempt;
  };
  double worst = 0.0;
  const auto count = [&](const Point& p, double ratio)
  {
    worst = p.exempt ? worst : std::max(worst, ratio);
    return p;
  };
  // Mesh -> curves: a point of boundary edge s.
  const auto meshPoint = [&](Vec2 x, std::size_t s)
  {
    const strata::NearestSegment nearest = modelTree.nearest(x, scratch);
    const double ratio = std::sqrt(nearest.distance2) / local[s];
    const auto m = static_cast<std::size_t>(nearest.segment);
    // (Exempt when its nearest curve point is beside a region narrower than the finest edge.)
    return count({ x,
                   std::sqrt(nearest.distance2),
                   ratio > 0.5 && narrow(ma[m] + nearest.t * (mb[m] - ma[m]), m) },
      ratio);
  };
  // Curves -> mesh: a point of curve segment s.
  const auto curvePoint = [&](Vec2 x, std::size_t s)
  {
    const strata::NearestSegment nearest = meshTree.nearest(x, scratch);
    const double ratio = std::sqrt(nearest.distance2) / local[nearest.segment];
    return count({ x, std::sqrt(nearest.distance2), ratio > 0.5 && narrow(x, s) }, ratio);
  };
  // The shortest local edge of the mesh boundary edges within r of the curve stretch ab.
  const strata::SegmentGrid meshCells(ba, bb, finest, std::size_t(1) << 20);
  const auto shortestNear = [&](Vec2 a, Vec2 b, double r)
  {
    double shortest = std::numeric_limits<double>::infinity();
    if (!meshCells.smallestValueNear(a, b, r, local, shortest))
    {
      for (std::size_t e = 0; e < ba.size(); ++e)
      {
        if (strata::segmentSegmentDistance2(a, b, ba[e], bb[e]) <= r * r)
        {
          shortest = std::min(shortest, local[e]);
        }
      }
    }
    return shortest;
  };
  // Between two neighbouring points u and v (the mesher's search, Method, step 9): no point
  // between them is farther than max(du, dv, (du + dv + |uv|) / 2) from the other side, over
  // at least the shortest local edge within that of the gap; when that exceeds the largest
  // ratio so far by more than kTolerance and an end is not exempt, the gap is halved.
  constexpr double kTolerance = 0.005;
  const auto between = [&](const auto& self,
                         const Point& u,
                         const Point& v,
                         int depth,
                         auto&& shortestLocal,
                         auto&& evaluate) -> void
  {
    const double gap = strata::norm(v.x - u.x);
    const double bound = std::max({ u.d, v.d, 0.5 * (u.d + v.d + gap) });
    const double shortest = shortestLocal(u.x, v.x, bound);
    if (depth >= 30 || (u.exempt && v.exempt) || !(bound > (worst + kTolerance) * shortest) ||
      !(gap > kTolerance * shortest))
    {
      return;
    }
    const Point m = evaluate(0.5 * (u.x + v.x));
    self(self, u, m, depth + 1, shortestLocal, evaluate);
    self(self, m, v, depth + 1, shortestLocal, evaluate);
  };
  for (std::size_t s = 0; s < ba.size(); ++s)
  {
    const auto evaluate = [&](Vec2 x) { return meshPoint(x, s); };
    const auto shortestLocal = [&](Vec2, Vec2, double) { return local[s]; };
    Point u = evaluate(ba[s]);
    for (int k = 1; k <= 8; ++k)
    {
      const Point v = evaluate(ba[s] + (k / 8.0) * (bb[s] - ba[s]));
      between(between, u, v, 0, shortestLocal, evaluate);
      u = v;
    }
  }
  for (std::size_t s = 0; s < ma.size(); ++s)
  {
    const int n =
      std::max(1, static_cast<int>(std::ceil(strata::norm(mb[s] - ma[s]) / (0.5 * finest))));
    const auto evaluate = [&](Vec2 x) { return curvePoint(x, s); };
    Point u = evaluate(ma[s]);
    for (int k = 1; k <= n; ++k)
    {
      const Point v = evaluate(ma[s] + (static_cast<double>(k) / n) * (mb[s] - ma[s]));
      between(between, u, v, 0, shortestNear, evaluate);
      u = v;
    }
  }
  return worst;
}

// Default settings (automatic levels) on every model: issue 5's bounds (smallest angle >= 25,
// largest <= 130, >= 95% of triangles with smallest angle >= 30, every region's area within
// 0.5%, the boundary within half the local edge outside regions narrower than the finest edge)
// on all 16 models.
struct DefaultCase
{
  const char* file;
  double minAngle;       // smallest angle at least
  double maxAngle;       // largest angle at most
  double percentAbove30; // percent of triangles whose smallest angle is >= 30, at least
  double deviation;      // boundaryDeviationOverLocalEdge at most (issue 5: 0.5)
};

// Marmousi met the boundary bound last: 0.59 local edges while the chord that ends a lens of
// region 4, where it is one finest edge wide, went straight across it (its middle half the
// lens's width from the sides, beside triangles shorter than the finest edge); the extended
// wedges' slanted cuts (Method, step 8) took it within. The gulf's Loops form and
// lake_superior_full meet it with ThinLayerRetry's mesh refined around the places the first
// one misses (0.64 and 0.63 before).
const DefaultCase kDefaultCases[] = {
  { "lake_superior_full.vtp", 25, 130, 95, 0.5 }, // issue 5's bounds
  { "salt_dome.vtp", 25, 130, 95, 0.5 },
  { "guitar.vtp", 25, 130, 95, 0.5 },
  { "nested_holes.vtp", 25, 130, 95, 0.5 },
  { "touching_loops.vtp", 25, 130, 95, 0.5 },
  { "countries_westeurope.vtp", 25, 130, 95, 0.5 },
  { "countries_westeurope_loops.vtp", 25, 130, 95, 0.5 },
  { "salt_dome_loops.vtp", 25, 130, 95, 0.5 },
  { "pinch_out.vtp", 25, 130, 95, 0.5 },
  { "lake_superior.vtp", 25, 130, 95, 0.5 },
  { "gulf_section.vtp", 25, 130, 95, 0.5 },
  { "gulf_section_loops.vtp", 25, 130, 95, 0.5 }, // ThinLayerRetry's zoned mesh (0.64 before)
  { "thin_layer.vtp", 25, 130, 95, 0.5 },
  { "geology_marmousi.vtp", 29.9, 130, 95, 0.5 }, // 25.9 without 7''s collapses
  { "faulted_section.vtp", 25, 130, 95, 0.5 },    // a 15-degree pinch-out tip in a large triangle
  { "faulted_thin_layers.vtp", 25, 130, 95, 0.5 },
};

class DefaultQuality : public ::testing::TestWithParam<DefaultCase>
{
};

std::string defaultCaseName(const ::testing::TestParamInfo<DefaultCase>& info)
{
  std::string s = info.param.file;
  return s.substr(0, s.find('.'));
}
} // namespace

TEST_P(DefaultQuality, AnglesAreasAndBoundaryStayWithinTheirBounds)
{
  const DefaultCase c = GetParam();
  const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(c.file));
  const strata::MesherResult r = strata::triangulate(raw);
  // Every vertex of the approximated boundary on an input curve (the ones the compression
  // left off are snapped, or merged into a neighbour on a curve, before the Delaunay
  // refinement), hence no such warning.
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * strata::buildModel(raw).size());
  for (const std::string& w : r.warnings)
  {
    EXPECT_EQ(w.find("could not be placed"), std::string::npos) << w;
  }
  ASSERT_GT(r.triangles.size(), 100u);
  std::size_t above30 = 0;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    above30 += r.minAngle[t] >= 30.0;
  }
  EXPECT_GE(r.summary.minAngle, c.minAngle);
  EXPECT_LE(r.summary.maxAngle, c.maxAngle);
  EXPECT_GE(100.0 * above30 / r.triangles.size(), c.percentAbove30);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005); // issue 5's 0.5%, on every model
  EXPECT_LE(r.summary.maxRegionMisplacedArea, 0.005); // lost plus added, too
  const strata::Model model = strata::buildModel(raw);
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, r), c.deviation);
  // The mesher's own measure agrees (a sample beside a thin spike's apex, taken for wide,
  // made lake_superior three times over for the same mesh).
  EXPECT_LE(r.summary.maxRelativeDeviation, c.deviation);
  // Each corner of the model's box that is a point of its curves (a section's box) is a mesh
  // vertex, as the junctions are (thin_layer's (1000, 0) was cut by a chord before).
  const strata::Box2 b = model.bounds;
  for (const Vec2 corner : { b.min, Vec2{ b.max.x, b.min.y }, b.max, Vec2{ b.min.x, b.max.y } })
  {
    if (std::find(model.nodes.begin(), model.nodes.end(), corner) == model.nodes.end())
    {
      continue;
    }
    double nearest = HUGE_VAL;
    for (const Vec2& x : r.points)
    {
      nearest = std::min(nearest, strata::norm(x - corner));
    }
    EXPECT_LE(nearest, 1e-9 * model.size())
      << "box corner (" << corner.x + model.origin.x << ", " << corner.y + model.origin.y << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(DataModels,
  DefaultQuality,
  ::testing::ValuesIn(kDefaultCases),
  defaultCaseName);

// With the Optimization off (the paper's method) the compression leaves two vertices of
// lake_superior's approximated boundary off the curves (measured: 129 and 3251 units, in a
// channel narrower than its triangles). The warning says how far the farthest one is and
// where: a vertex of the mesh's boundary, that far from the curves.
TEST(MesherTest, WarningNamesWhereTheBoundaryVertexFarthestOffTheCurvesLies)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("lake_superior.vtp"));
  const strata::Model model = strata::buildModel(raw);
  strata::MesherParams paper;
  paper.compression.optimize = false;
  const strata::MesherResult r = strata::triangulate(raw, paper);
  ASSERT_GT(r.summary.maxBoundaryVertexDistance, 1e-9 * model.size());
  std::string warning;
  for (const std::string& w : r.warnings)
  {
    if (w.find("a vertex of the approximated boundary lies") != std::string::npos)
    {
      warning = w;
    }
  }
  ASSERT_FALSE(warning.empty()) << allWarnings(r);
  double d = 0.0, x = 0.0, y = 0.0;
  ASSERT_EQ(std::sscanf(warning.c_str(),
              "a vertex of the approximated boundary lies %lf model units off the input "
              "curves, at (%lf, %lf)",
              &d,
              &x,
              &y),
    3)
    << warning;
  EXPECT_NEAR(d, r.summary.maxBoundaryVertexDistance, 1e-5 * d);
  // The mesh vertex there (the coordinates are input ones, printed to 9 digits).
  const Vec2 at{ x - r.origin.x, y - r.origin.y };
  std::size_t nearest = 0;
  for (std::size_t i = 1; i < r.points.size(); ++i)
  {
    if (strata::norm2(r.points[i] - at) < strata::norm2(r.points[nearest] - at))
    {
      nearest = i;
    }
  }
  ASSERT_LT(strata::norm(r.points[nearest] - at), 1e-7 * model.size()) << warning;
  EXPECT_EQ(r.vertexClass[nearest], strata::VertexBoundary);
  const strata::BoundaryRails rails(model, 0.0);
  strata::StripTreeScratch scratch;
  double off = 0.0;
  rails.closest(r.points[nearest], scratch, &off);
  EXPECT_NEAR(off, d, 1e-5 * d);
  // With the default settings the same model's boundary vertices are all on the curves: no
  // such warning.
  const strata::MesherResult defaults = strata::triangulate(raw);
  EXPECT_EQ(
    allWarnings(defaults).find("a vertex of the approximated boundary lies"), std::string::npos);
}

// The Delaunay refinement (MinimumAngle, default 30) against none (MinimumAngle 0): the
// smallest angle does not drop, every vertex of the approximated boundary is still on a curve
// (the boundary edges it splits are split on their curve), a region area within issue 5's
// 0.5% stays within it (others get no worse than 0.1% of the area), and with the
// Optimization off (the paper) nothing is refined.
TEST(MesherTest, RefinementRaisesTheSmallestAngleKeepingBoundaryVerticesOnCurves)
{
  for (const char* file : { "salt_dome.vtp", "pinch_out.vtp", "countries_westeurope.vtp" })
  {
    const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
    strata::MesherParams off;
    off.refinement.minimumAngle = 0.0;
    const strata::MesherResult a = strata::triangulate(raw, off);
    const strata::MesherResult b = strata::triangulate(raw);
    EXPECT_EQ(a.summary.refinementVertices, 0u) << file;
    EXPECT_GT(b.summary.refinementVertices, 0u) << file;
    EXPECT_GE(b.summary.minAngle, a.summary.minAngle) << file;
    EXPECT_GE(b.summary.minAngle, 23.0) << file;
    const strata::Model model = strata::buildModel(raw);
    EXPECT_LE(b.summary.maxBoundaryVertexDistance, 1e-9 * model.size()) << file;
    ASSERT_EQ(a.regionAreas.size(), b.regionAreas.size());
    for (std::size_t i = 0; i < a.regionAreas.size(); ++i)
    {
      const double m = a.regionAreas[i].model;
      const double before = std::fabs(a.regionAreas[i].mesh - m);
      EXPECT_LE(
        std::fabs(b.regionAreas[i].mesh - m), before <= 5e-3 * m ? 5e-3 * m : before + 1e-3 * m)
        << file << " region " << a.regionAreas[i].id;
    }
  }
  strata::MesherParams paper;
  paper.compression.optimize = false;
  const strata::MesherResult p =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("pinch_out.vtp")), paper);
  EXPECT_EQ(p.summary.refinementVertices, 0u);
  strata::MesherParams bad;
  bad.refinement.minimumAngle = 35.0;
  EXPECT_THROW(
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("pinch_out.vtp")), bad),
    strata::ParameterError);
}

// Curve recovery (on by default) brings back what the compression lost: thin_layer's 1-unit
// layer (8% of its area kept without), pinch_out's wedge up to near its tip, the countries'
// micro-states, with region areas within issue 5's 0.5% (the retry with half the recovery
// margin brings the layer and Monaco back); every boundary vertex stays on a curve, and the
// smallest angle does not drop (measured: thin_layer 30.0 and 0.01% against 12.9 and 92%
// without, pinch_out 30.0 and 0.13% against 23.1 and 5.2%, countries 30.0 and 0.21% against
// 27.9 and 17%; the fidelity splits took the countries from 0.45 to 0.21%).
TEST(MesherTest, CurveRecoveryKeepsMoreOfThinLayersWithBoundaryVerticesOnCurves)
{
  for (const char* file : { "thin_layer.vtp", "pinch_out.vtp", "countries_westeurope.vtp" })
  {
    const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
    strata::MesherParams off;
    off.curveRecovery = false;
    const strata::MesherResult a = strata::triangulate(raw, off);
    const strata::MesherResult b = strata::triangulate(raw);
    EXPECT_EQ(a.summary.curveVertices, 0u) << file;
    EXPECT_GT(b.summary.curveVertices, 0u) << file;
    EXPECT_LT(b.summary.maxRegionAreaError, 0.5 * a.summary.maxRegionAreaError) << file;
    EXPECT_LE(b.summary.maxBoundaryVertexDistance, 1e-9 * strata::buildModel(raw).size()) << file;
    EXPECT_GE(b.summary.minAngle, a.summary.minAngle - 0.1) << file;
    EXPECT_LE(b.summary.maxRegionAreaError, 0.005) << file; // issue 5's bound
  }
}

// A square with a peninsula 300 long whose tip is a 40-degree corner, on a coarse grid (level 6,
// 7 near the model's vertices) with the finest edge of the junction level: the compression
// leaves the tip 23 short of its apex and two of its base corners 5-7 off. The curve recovery
// takes a model corner inside a probed triangle as its point first, so every corner of the
// model (between MinimumAngle and FeatureAngle) is a mesh vertex, with MinimumAngle kept.
TEST(MesherTest, CurveRecoveryBringsBackTheCornersTheCompressionLost)
{
  const double half = 300.0 * std::tan(20.0 * M_PI / 180.0);
  const std::vector<strata::Vec2> corners = { { 0, 0 },
    { 1000, 0 },
    { 1000, 500 - half },
    { 1300, 500 },
    { 1000, 500 + half },
    { 1000, 1000 },
    { 0, 1000 } };
  strata::RawPolylines raw;
  strata_test::addClosedLoop(raw, corners, 0);
  strata::MesherParams p;
  p.grid.maxLevel = 6;
  p.grid.localMaxLevel = 7;
  const strata::MesherResult r = strata::triangulate(raw, p);
  for (const strata::Vec2& c : corners)
  {
    double nearest = HUGE_VAL;
    for (const strata::Vec2& x : r.points)
    {
      nearest = std::min(nearest, strata::norm(x + r.origin - c));
    }
    EXPECT_LE(nearest, 1e-9 * 1300.0) << "corner (" << c.x << ", " << c.y << ")";
  }
  EXPECT_GE(r.summary.minAngle, p.refinement.minimumAngle - 1e-6);
  EXPECT_LE(r.summary.maxRegionAreaError, 1e-4);
}

// faulted_thin_layers (a random faulted section), whose layers one to two finest edges thick
// end at the faults in 1- to 15-degree pinch-outs: with ThinLayerRefinement the grid gets cells
// as wide as those layers, and the boundary stays within issue 5's half local edge (0.47), as
// without it (0.46 since the layers' tips at junctions are extended, Method, step 8; 0.73
// before), every other bound still held.
TEST(MesherTest, ThinLayerRefinementKeepsAFaultedSectionsBoundaryWithinHalfTheLocalEdge)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("faulted_thin_layers.vtp"));
  const strata::Model model = strata::buildModel(raw);
  strata::MesherParams p;
  const strata::MesherResult plain = strata::triangulate(raw, p);
  p.grid.thinLayerRefinement = true;
  const strata::MesherResult thin = strata::triangulate(raw, p);
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, plain), 0.5);
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, thin), 0.5);
  EXPECT_FALSE(plain.summary.thinLayerMesh);
  EXPECT_TRUE(thin.summary.thinLayerMesh);
  EXPECT_GE(thin.summary.minAngle, p.refinement.minimumAngle - 0.05);
  EXPECT_LE(thin.summary.maxAngle, 130.0);
  EXPECT_LE(thin.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(thin.summary.maxBoundaryVertexDistance, 1e-9 * model.size());
  EXPECT_EQ(thin.summary.finestEdgeLength, plain.summary.finestEdgeLength);
}

// When the user sets ThinLayerRefinement and its mesh misses the bounds, the mesh without it
// is made too and kept when it is better; a warning gives both meshes' figures, and the time of
// the discarded run is a stage. cut_corner_section (random_sections.py 22 23): with the thin
// layers a layer is cut (0.68 local edges off), without them it is whole (0.09). (Until the
// sixty-seventh session this was Marmousi, whose thin layer mesh left a piece of a layer to its
// neighbour, 0.85 local edges off; since the thin layers are looked for beside the grid's
// triangles too, that mesh meets the bounds: 0.44 local edges, 29.98 degrees, in 0.4 s.)
// Marmousi by default: the mesh without it misses the boundary bound by a hair (0.50 local
// edges), and the one refined around that place only is kept (0.40).
TEST(MesherTest, ThinLayerRefinementKeepsTheMeshWithoutItWhenItsOwnMissesTheBounds)
{
  const strata::RawPolylines corner =
    strata_test::readVtpAscii(strata_test::dataPath("cut_corner_section.vtp"));
  strata::MesherParams p;
  p.grid.thinLayerRefinement = true;
  const strata::MesherResult thin = strata::triangulate(corner, p);
  EXPECT_FALSE(thin.summary.thinLayerMesh);
  EXPECT_TRUE(thin.brokenRegions.empty());
  EXPECT_GE(thin.summary.minAngle, 29.95);
  EXPECT_LE(thin.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(thin.summary.maxRelativeDeviation, 0.5);
  expectWarningsSay(thin,
    { "the mesh with ThinLayerRefinement missed the angle, area or boundary bound",
      "1 regions cut, boundary deviation 0.6793 local edges), so a mesh without "
      "ThinLayerRefinement was made too",
      "; the second one is kept" });
  // (The discarded run's time is a stage.)
  const auto& stages = thin.summary.secondsPerStage;
  const auto stage = std::find_if(stages.begin(),
    stages.end(),
    [&](const std::pair<std::string, double>& s) { return s.first == "discarded run"; });
  ASSERT_NE(stage, stages.end());
  EXPECT_GE(thin.summary.totalSeconds, stage->second);

  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("geology_marmousi.vtp"));
  strata::MesherParams once;
  once.thinLayerRetry = false;
  const strata::MesherResult plain = strata::triangulate(raw, once);
  EXPECT_FALSE(plain.summary.thinLayerMesh);
  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_GT(plain.summary.maxRelativeDeviation, 0.5);
  EXPECT_TRUE(d.summary.thinLayerMesh);
  EXPECT_LE(d.summary.maxRelativeDeviation, 0.5);
  EXPECT_GE(d.summary.minAngle, 29.95);
  const std::string zoned = allWarnings(d);
  EXPECT_NE(zoned.find("around the misses was made too"), std::string::npos) << zoned;
  EXPECT_NE(zoned.find("the second one is kept"), std::string::npos) << zoned;
}

// A region narrower than the finest edge cannot be represented: its loss does not count in
// the relative deviation. An island 0.2 units wide and 60 long, with no edge shorter than 2:
// its curve lies up to 50 units from the mesh's boundary.
TEST(MesherTest, TheRelativeDeviationLeavesOutRegionsNarrowerThanTheFinestEdge)
{
  strata::RawPolylines model;
  const std::vector<Vec2> island = { { 20, 50 }, { 80, 50 }, { 80, 50.2 }, { 20, 50.2 } };
  strata_test::addClosedLoop(model, { { 0, 0 }, { 100, 0 }, { 100, 100 }, { 0, 100 } }, 0);
  strata_test::addClosedLoop(model, island, 0);
  strata_test::addClosedLoop(model, island, 1);
  strata::MesherParams p;
  p.grid.minEdgeLength = 2.0;
  const strata::MesherResult r = strata::triangulate(model, p);
  ASSERT_EQ(r.unresolvedRegions, std::vector<int>{ 1 });
  EXPECT_GT(r.summary.maxBoundaryDeviation, 4.0);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_FALSE(r.summary.thinLayerMesh);
}

// Summary::maxBoundaryDeviation is the largest distance over every sample the output stage
// measures, both ways: from each approximated boundary edge's start and 7 points between (and
// each boundary curve's end) to the input curves; from each curve segment's
// min(512, max(5, ceil(length / (finest edge / 4)))) + 1 evenly spaced points (and each open
// curve's end) to the approximated boundary. The output stage skips the curve samples between
// two whose bounds (the distance's Lipschitz and convexity bounds, and the bound along one
// boundary curve, 2026-12-05) show they change nothing; here every sample is measured, by strip
// trees, and the largest must be the same. On an island narrower than the finest edge, left
// out of the mesh, the largest is in the middle of a long side, among the samples that may be
// skipped (with the bound along one boundary curve taken as 0, this case fails).
TEST(MesherTest, TheBoundaryDeviationIsTheLargestDistanceOverEverySample)
{
  struct Case
  {
    std::string name;
    strata::RawPolylines raw;
    strata::MesherParams params;
    bool largestInside; // the largest distance is a curve sample's between a segment's ends
  };
  std::vector<Case> cases;
  for (const char* file : { "pinch_out.vtp", "gulf_section.vtp", "lake_superior.vtp" })
  {
    cases.push_back({ file, strata_test::readVtpAscii(strata_test::dataPath(file)), {}, false });
  }
  {
    // A lake of radius 30 (a 96-gon) in a box, an island 0.2 wide and 26 long across its
    // middle: the island's long sides lie 16 and 18 units from the lake's shore at their ends,
    // 30 near their middle. (The shore's own deviations come first, so that skips are allowed.)
    Case island{ "thin island in a lake", {}, {}, true };
    std::vector<Vec2> shore;
    for (int k = 0; k < 96; ++k)
    {
      const double angle = 2.0 * 3.14159265358979323846 * k / 96;
      shore.push_back({ 50.0 + 30.0 * std::cos(angle), 50.0 + 30.0 * std::sin(angle) });
    }
    const std::vector<Vec2> ring = { { 36, 50 }, { 62, 50 }, { 62, 50.2 }, { 36, 50.2 } };
    strata_test::addClosedLoop(island.raw, { { 0, 0 }, { 100, 0 }, { 100, 100 }, { 0, 100 } }, 0);
    strata_test::addClosedLoop(island.raw, shore, 0);
    strata_test::addClosedLoop(island.raw, shore, 1);
    strata_test::addClosedLoop(island.raw, ring, 1);
    strata_test::addClosedLoop(island.raw, ring, 2);
    island.params.grid.minEdgeLength = 2.0;
    cases.push_back(std::move(island));
  }
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.name);
    const strata::MesherResult r = strata::triangulate(c.raw, c.params);
    const strata::Model model = strata::buildModel(c.raw);
    const strata::BoundaryRails rails(model, 0.0);
    std::vector<Vec2> ma, mb, ba, bb;
    for (std::size_t ci = 0; ci < rails.numberOfChains(); ++ci)
    {
      const auto& chain = rails.chain(static_cast<int>(ci));
      for (std::size_t i = 0; i < chain.numberOfSegments(); ++i)
      {
        ma.push_back(chain.points[i]);
        mb.push_back(chain.points[(i + 1) % chain.points.size()]);
      }
    }
    for (const auto& curve : r.boundary)
    {
      for (std::size_t i = 0; i + 1 < curve.points.size(); ++i)
      {
        ba.push_back(curve.points[i]);
        bb.push_back(curve.points[i + 1]);
      }
    }
    ASSERT_FALSE(ma.empty());
    ASSERT_FALSE(ba.empty());
    const strata::StripTree modelTree(ma, mb), meshTree(ba, bb);
    strata::StripTreeScratch scratch;
    const auto toCurves = [&](Vec2 x)
    { return std::sqrt(modelTree.nearest(x, scratch).distance2); };
    const auto toMesh = [&](Vec2 x) { return std::sqrt(meshTree.nearest(x, scratch).distance2); };
    double meshSide = 0.0, curveSide = 0.0, curveEnds = 0.0;
    for (const auto& curve : r.boundary)
    {
      for (std::size_t i = 0; i + 1 < curve.points.size(); ++i)
      {
        const Vec2 a = curve.points[i], b = curve.points[i + 1];
        meshSide = std::max(meshSide, toCurves(a));
        for (const double f : { 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875 })
        {
          meshSide = std::max(meshSide, toCurves(a + f * (b - a)));
        }
      }
      if (!curve.points.empty())
      {
        meshSide = std::max(meshSide, toCurves(curve.points.back()));
      }
    }
    const double finest = r.summary.finestEdgeLength;
    for (std::size_t s = 0; s < ma.size(); ++s)
    {
      const int m = static_cast<int>(std::min<double>(
        512.0, std::max(5.0, std::ceil(strata::norm(mb[s] - ma[s]) / (0.25 * finest)))));
      for (int j = 0; j <= m; ++j)
      {
        const double d = toMesh(ma[s] + (static_cast<double>(j) / m) * (mb[s] - ma[s]));
        curveSide = std::max(curveSide, d);
        curveEnds = j == 0 || j == m ? std::max(curveEnds, d) : curveEnds;
      }
    }
    for (std::size_t ci = 0; ci < rails.numberOfChains(); ++ci)
    {
      const auto& chain = rails.chain(static_cast<int>(ci));
      if (!chain.closed && !chain.points.empty())
      {
        curveSide = std::max(curveSide, toMesh(chain.points.back()));
        curveEnds = std::max(curveEnds, toMesh(chain.points.back()));
      }
    }
    EXPECT_NEAR(
      r.summary.maxBoundaryDeviation, std::max(meshSide, curveSide), 1e-12 * model.size());
    if (c.largestInside)
    {
      EXPECT_GT(curveSide, std::max(meshSide, 1.5 * curveEnds));
    }
  }
}

// lake_superior at MaxLevel 6 (the paper's count): made once (ThinLayerRetry off) it keeps a
// 25.6-degree triangle; by default that mesh misses MinimumAngle, so it is made again with
// the thin layer refinement, which meets it, and that one is kept (since the sixty-seventh
// session, as it misplaces 0.72% of the lake's area, at LocalMaxLevel 4 levels finer, 0.01%).
// A mesh that meets the bounds (the salt dome) is made once either way.
TEST(MesherTest, ThinLayerRetryMendsAMeshThatMissesTheBounds)
{
  const strata::RawPolylines lake =
    strata_test::readVtpAscii(strata_test::dataPath("lake_superior.vtp"));
  strata::MesherParams p;
  p.grid.maxLevel = 6;
  p.thinLayerRetry = false;
  const strata::MesherResult once = strata::triangulate(lake, p);
  EXPECT_LT(once.summary.minAngle, p.refinement.minimumAngle - 1.0);
  EXPECT_FALSE(once.summary.thinLayerMesh);
  p.thinLayerRetry = true;
  const strata::MesherResult retried = strata::triangulate(lake, p);
  EXPECT_TRUE(retried.summary.thinLayerMesh);
  EXPECT_GE(retried.summary.minAngle, p.refinement.minimumAngle - 0.05);
  EXPECT_LE(retried.summary.maxRegionAreaError, 0.005);
  const auto& stages = retried.summary.secondsPerStage;
  EXPECT_NE(std::find_if(stages.begin(),
              stages.end(),
              [](const std::pair<std::string, double>& s) { return s.first == "discarded run"; }),
    stages.end());
  const std::string all = allWarnings(retried);
  EXPECT_NE(all.find("the mesh without ThinLayerRefinement missed"), std::string::npos) << all;

  const strata::RawPolylines salt =
    strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp"));
  p.grid.maxLevel = -1;
  const strata::MesherResult saltDefault = strata::triangulate(salt, p);
  p.thinLayerRetry = false;
  const strata::MesherResult saltOnce = strata::triangulate(salt, p);
  EXPECT_EQ(saltDefault.points, saltOnce.points);
  EXPECT_EQ(saltDefault.triangles, saltOnce.triangles);
  EXPECT_FALSE(saltDefault.summary.thinLayerMesh);
  EXPECT_NE(saltDefault.summary.secondsPerStage.front().first, "discarded run");
}

// A region kept (half of its area or more) whose triangles' area is more than 10% off its
// model area is named in a warning with the difference: without the curve recovery, the
// countries' Monaco (8); none on the salt dome. Liechtenstein (7), within 10% net since the
// sixty-seventh session (-10% before), is named for its misplaced area (11%).
TEST(MesherTest, RegionAreasMoreThanTenPercentOffAreWarned)
{
  const auto warnings = [](const char* file)
  {
    strata::MesherParams p;
    p.curveRecovery = false;
    return allWarnings(
      strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath(file)), p));
  };
  const std::string countries = warnings("countries_westeurope.vtp");
  EXPECT_NE(countries.find("more than 10% off"), std::string::npos) << countries;
  EXPECT_NE(countries.find("(region id and difference): 8 (-"), std::string::npos) << countries;
  EXPECT_NE(countries.find("(region id and area lost plus added): 7 ("), std::string::npos)
    << countries;
  EXPECT_EQ(warnings("salt_dome.vtp").find("more than 10% off"), std::string::npos);
}

// A region lost is a hard miss, as a region cut is (ThinLayerRetry's choice): without the curve
// recovery, thin_layer's first mesh keeps 7% of its layer (12.9 degrees), the one with
// ThinLayerRefinement 83% in two pieces (21.8 degrees); both miss the angle and the area
// bounds, and the second is kept (from 2026-12-03 until a lost region counted, the first was).
TEST(MesherTest, AMeshThatLosesARegionIsNotKeptOverOneThatCutsIt)
{
  strata::MesherParams p;
  p.curveRecovery = false;
  const strata::MesherResult r =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("thin_layer.vtp")), p);
  EXPECT_TRUE(r.unresolvedRegions.empty());
  EXPECT_LT(r.summary.maxRegionAreaError, 0.5);
  EXPECT_TRUE(r.summary.thinLayerMesh);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("the second one is kept"), std::string::npos) << warnings;
}

// A wedge (region 1) of the given angle (degrees) from the middle of a 100 x 100 square's left
// side, between regions 0 (below) and 2 (above), Shared curves form.
namespace
{
strata::RawPolylines wedgeModel(double angle)
{
  const double d = 100.0 * std::tan(0.5 * angle * 3.14159265358979323846 / 180.0);
  strata::RawPolylines wedge;
  strata_test::addCurve(wedge, { { 0, 0 }, { 100, 0 } }, 0, -1);
  strata_test::addCurve(wedge, { { 100, 0 }, { 100, 50 - d } }, 0, -1);
  strata_test::addCurve(wedge, { { 0, 50 }, { 100, 50 - d } }, 1, 0);
  strata_test::addCurve(wedge, { { 100, 50 - d }, { 100, 50 + d } }, 1, -1);
  strata_test::addCurve(wedge, { { 0, 50 }, { 100, 50 + d } }, 2, 1);
  strata_test::addCurve(wedge, { { 100, 50 + d }, { 100, 100 } }, 2, -1);
  strata_test::addCurve(wedge, { { 100, 100 }, { 0, 100 } }, 2, -1);
  strata_test::addCurve(wedge, { { 0, 100 }, { 0, 50 } }, 2, -1);
  strata_test::addCurve(wedge, { { 0, 50 }, { 0, 0 } }, 0, -1);
  return wedge;
}
} // namespace

// The 10-degree wedge ends cleanly where it is thinner than the triangles (its tip goes to its
// neighbours): no triangle below 25 degrees at the 10-degree corner, none below 20 anywhere,
// the junction still has its vertex, and the wedge keeps its area but for the tip.
TEST(MesherTest, ASharpWedgeEndsCleanlyWithoutSmallAngles)
{
  const strata::MesherResult r = strata::triangulate(wedgeModel(10.0));
  ASSERT_GT(r.triangles.size(), 100u);
  EXPECT_GE(r.summary.minAngle, 20.0);
  EXPECT_EQ(r.summary.trianglesAtSharpCorners, 0u);
  bool junction = false;
  for (const Vec2& p : r.points)
  {
    junction = junction || p + r.origin == Vec2{ 0.0, 50.0 };
  }
  EXPECT_TRUE(junction);
  for (const auto& ra : r.regionAreas)
  {
    EXPECT_NEAR(ra.mesh, ra.model, 0.01 * ra.model) << "region " << ra.id;
  }
}

namespace
{
// The region of the triangle holding the point p (model coordinates); -1 outside the mesh.
int regionAt(const strata::MesherResult& r, Vec2 p)
{
  p = p - r.origin;
  int region = -1;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    const Vec2 a = r.points[r.triangles[t][0]], b = r.points[r.triangles[t][1]],
               c = r.points[r.triangles[t][2]];
    if (strata::orient2d(a, b, p) >= 0.0 && strata::orient2d(b, c, p) >= 0.0 &&
      strata::orient2d(c, a, p) >= 0.0)
    {
      region = r.regionId[t];
    }
  }
  return region;
}

// Along the axis of a wedge of `angle` degrees (its apex, a unit direction), from where it is
// 1.25 finest edges wide to `to` from the apex, every quarter finest edge lies in `region` (-1:
// outside every triangle).
void expectRegionAlongWedge(const strata::MesherResult& r,
  Vec2 apex,
  Vec2 direction,
  double angle,
  double to,
  int region)
{
  const double tangent = std::tan(0.5 * angle * 3.14159265358979323846 / 180.0);
  const double finest = r.summary.finestEdgeLength;
  const double from = 1.25 * finest / (2.0 * tangent);
  ASSERT_LT(from, to);
  for (double s = from; s < to; s += 0.25 * finest)
  {
    ASSERT_EQ(regionAt(r, apex + s * direction), region)
      << s << " from the apex, where the wedge is " << 2.0 * s * tangent / finest
      << " finest edges wide";
  }
}

void expectAreasWithinHalfAPercent(const strata::MesherResult& r)
{
  for (const auto& ra : r.regionAreas)
  {
    EXPECT_NEAR(ra.mesh, ra.model, 0.005 * ra.model) << "region " << ra.id;
  }
}
} // namespace

// A 24-degree wedge, whose tip the coarse mesh reaches with triangles a few finest edges
// across: the curve recovery's last pass cuts the tip where its third edge is one finest edge
// long, so the wedge ends where it is about one finest edge wide (three before), and every
// triangle keeps the bound.
TEST(MesherTest, ASharpWedgeEndsWhereItIsAboutOneFinestEdgeWide)
{
  const double angle = 24.0;
  const strata::MesherResult r = strata::triangulate(wedgeModel(angle));
  ASSERT_GT(r.triangles.size(), 100u);
  EXPECT_GE(r.summary.minAngle, 29.95);
  const Vec2 apex = Vec2{ 0.0, 50.0 } - r.origin;
  double reach = 1e300; // the wedge's nearest vertex to its apex
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    for (const int v : r.triangles[t])
    {
      reach = r.regionId[t] == 1 ? std::min(reach, strata::norm(r.points[v] - apex)) : reach;
    }
  }
  const double width = 2.0 * reach * std::tan(0.5 * angle * 3.14159265358979323846 / 180.0);
  EXPECT_LE(width, 1.25 * r.summary.finestEdgeLength);
  expectAreasWithinHalfAPercent(r);
}

// A 10-degree inlet of the exterior into a square (a coast's narrow bay, its apex no junction):
// the last pass extends the exterior's wedge to where it is about one finest edge wide (the
// compressed mesh closed it where it was 2.6 wide), with every triangle at 30 degrees and the
// area kept.
TEST(MesherTest, AnInletOfTheExteriorReachesWhereItIsAboutOneFinestEdgeWide)
{
  const double angle = 10.0, pi = 3.14159265358979323846;
  const double d = 70.0 * std::tan(0.5 * angle * pi / 180.0);
  strata::RawPolylines inlet;
  strata_test::addClosedLoop(inlet,
    { { 0, 0 },
      { 100, 0 },
      { 100, 50 - d },
      { 30, 50 },
      { 100, 50 + d },
      { 100, 100 },
      { 0, 100 } },
    0);
  const strata::MesherResult r = strata::triangulate(inlet);
  ASSERT_GT(r.triangles.size(), 100u);
  EXPECT_GE(r.summary.minAngle, 29.95);
  // The inlet's axis is outside every triangle from where the inlet is 1.25 finest edges wide.
  expectRegionAlongWedge(r, { 30.0, 50.0 }, { 1.0, 0.0 }, angle, 70.0, -1);
  expectAreasWithinHalfAPercent(r);
}

// A lens of one region inside another (a pinch-out with the same layer above and below) is
// extended like a spit: its region reaches where it is about one finest edge wide, and every
// triangle keeps MinimumAngle.
TEST(MesherTest, ALensInsideAnotherRegionReachesWhereItIsAboutOneFinestEdgeWide)
{
  const double angle = 10.0, pi = 3.14159265358979323846;
  const double d = 50.0 * std::tan(0.5 * angle * pi / 180.0);
  const std::vector<Vec2> lens = {
    { 20, 50 }, { 70, 50 - d }, { 80, 50 - d }, { 80, 50 + d }, { 70, 50 + d }
  };
  strata::RawPolylines model;
  strata_test::addClosedLoop(model, { { 0, 0 }, { 100, 0 }, { 100, 100 }, { 0, 100 } }, 0);
  strata_test::addClosedLoop(model, lens, 0);
  strata_test::addClosedLoop(model, lens, 1);
  const strata::MesherResult r = strata::triangulate(model);
  ASSERT_GT(r.triangles.size(), 100u);
  EXPECT_GE(r.summary.minAngle, 29.95);
  // The lens's axis is inside a triangle of region 1 from where the lens is 1.25 finest edges
  // wide.
  expectRegionAlongWedge(r, { 20.0, 50.0 }, { 1.0, 0.0 }, angle, 59.0, 1);
  expectAreasWithinHalfAPercent(r);
}

namespace
{
// A layer (region 1) pinching out at `angle` degrees at a junction, (20, 50): region 0 above it,
// region 2 below; its lower side runs to (100, 50 - d).
strata::RawPolylines pinchOutAtJunction(double angle, double& d)
{
  d = 80.0 * std::tan(angle * 3.14159265358979323846 / 180.0);
  strata::RawPolylines model;
  strata_test::addClosedLoop(
    model, { { 0, 50 }, { 20, 50 }, { 100, 50 }, { 100, 100 }, { 0, 100 } }, 0);
  strata_test::addClosedLoop(model, { { 20, 50 }, { 100, 50 - d }, { 100, 50 } }, 1);
  strata_test::addClosedLoop(
    model, { { 0, 0 }, { 100, 0 }, { 100, 50 - d }, { 20, 50 }, { 0, 50 } }, 2);
  return model;
}
} // namespace

// A layer pinching out at a junction (another region above it, a third below) is extended the
// same way: its region reaches where it is about one finest edge wide.
TEST(MesherTest, ALayerPinchingOutAtAJunctionReachesWhereItIsAboutOneFinestEdgeWide)
{
  const double angle = 10.0, pi = 3.14159265358979323846;
  double d = 0.0;
  const strata::MesherResult r = strata::triangulate(pinchOutAtJunction(angle, d));
  ASSERT_GT(r.triangles.size(), 100u);
  EXPECT_GE(r.summary.minAngle, 29.95);
  // Along the layer's axis, region 1 from where the layer is 1.25 finest edges wide.
  const double half = 0.5 * angle * pi / 180.0;
  expectRegionAlongWedge(r, { 20.0, 50.0 }, { std::cos(half), -std::sin(half) }, angle, 78.0, 1);
  expectAreasWithinHalfAPercent(r);
}

// The cut that ends an extended pinch-out runs slanted across the layer (from where it is one
// finest edge wide on one side to a finest edge nearer the apex on the other): its middle lies
// half the layer's width from the sides, as a cut straight across would, but the cut is longer
// than that width, so the boundary stays within half the local edge of the curves there
// (straight cuts beside triangles shorter than them made Marmousi's 0.59 local edges).
TEST(MesherTest, TheCutEndingAnExtendedPinchOutIsLongerThanTheLayerIsWide)
{
  double d = 0.0;
  const strata::MesherResult r = strata::triangulate(pinchOutAtJunction(10.0, d));
  ASSERT_GT(r.triangles.size(), 100u);
  // The layer's boundary edges off both its curves (the cut), with their middles' distances to
  // the two curves.
  const Vec2 apex = Vec2{ 20.0, 50.0 } - r.origin, top = Vec2{ 100.0, 50.0 } - r.origin,
             bottom = Vec2{ 100.0, 50.0 - d } - r.origin;
  std::map<std::pair<int, int>, std::vector<int>> faces;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = r.triangles[t][k], b = r.triangles[t][(k + 1) % 3];
      faces[{ std::min(a, b), std::max(a, b) }].push_back(static_cast<int>(t));
    }
  }
  const double tol = 1e-6 * r.summary.finestEdgeLength;
  std::size_t cuts = 0;
  for (const auto& [edge, tris] : faces)
  {
    if (tris.size() != 2 || (r.regionId[tris[0]] == 1) == (r.regionId[tris[1]] == 1))
    {
      continue;
    }
    const Vec2 a = r.points[edge.first], b = r.points[edge.second], m = 0.5 * (a + b);
    const double toTop = std::sqrt(strata::pointSegmentDistance2(m, apex, top));
    const double toBottom = std::sqrt(strata::pointSegmentDistance2(m, apex, bottom));
    if (toTop < tol || toBottom < tol)
    {
      continue; // along a curve
    }
    ++cuts;
    const double width = toTop + toBottom, length = strata::norm(b - a);
    EXPECT_LE(width, 1.1 * r.summary.finestEdgeLength);
    EXPECT_GE(length, 1.25 * width) << "a cut straight across the layer";
    EXPECT_LE(std::min(toTop, toBottom), 0.4 * length);
  }
  EXPECT_EQ(cuts, 1u);
  expectAreasWithinHalfAPercent(r);
}

// Where extending the pinch-outs among regions leaves a triangle below MinimumAngle (Marmousi at
// MaxLevel 7: a 20-degree tip left to a neighbour, 19.7 degrees), the last pass is made again
// without those near such a triangle and the better kept: the smallest angle stays at the bound.
TEST(MesherTest, ExtendedPinchOutsNeverLeaveATriangleBelowTheMinimumAngle)
{
  strata::MesherParams p;
  p.grid.maxLevel = 7;
  const strata::MesherResult r = strata::triangulate(
    strata_test::readVtpAscii(strata_test::dataPath("geology_marmousi.vtp")), p);
  EXPECT_GE(r.summary.minAngle, p.refinement.minimumAngle - 0.05);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.01);
}

// Marmousi's junctions of 3.8 to 20 degrees: with the refinement off (MinimumAngle 0) the
// triangles below 25 degrees whose smallest angle sits on such a corner are counted; with the
// defaults the wedges' tips are cut and none is left; a square has none.
TEST(MesherTest, TrianglesAtSharpInputCornersAreCounted)
{
  const strata::RawPolylines marmousi =
    strata_test::readVtpAscii(strata_test::dataPath("geology_marmousi.vtp"));
  strata::MesherParams off;
  off.refinement.minimumAngle = 0.0;
  const strata::MesherResult r = strata::triangulate(marmousi, off);
  const std::size_t below25 = static_cast<std::size_t>(
    std::count_if(r.minAngle.begin(), r.minAngle.end(), [](double a) { return a < 25.0; }));
  EXPECT_GE(r.summary.trianglesAtSharpCorners, 1u);
  EXPECT_LE(r.summary.trianglesAtSharpCorners, below25);
  EXPECT_EQ(strata::triangulate(marmousi).summary.trianglesAtSharpCorners, 0u);
  strata::RawPolylines square;
  strata_test::addClosedLoop(
    square, { { 0.0, 0.0 }, { 100.0, 0.0 }, { 100.0, 100.0 }, { 0.0, 100.0 } }, 0);
  EXPECT_EQ(strata::triangulate(square).summary.trianglesAtSharpCorners, 0u);
}

namespace
{
// Even-odd crossings.
bool insideOutline(const std::vector<Vec2>& polygon, Vec2 p)
{
  bool in = false;
  for (std::size_t j = 0, n = polygon.size(); j < n; ++j)
  {
    const Vec2 a = polygon[j], b = polygon[(j + 1) % n];
    in ^= (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
  }
  return in;
}
} // namespace

// KeepSharpCorners: every corner kept is meshed to its apex as rungs of its region: a vertex on
// the apex, the region's angle there the input's, its wedge's triangles no sharper than a
// quarter of that and no angle above 150 degrees; the areas stay within 0.5% and every triangle
// away from the kept corners keeps MinimumAngle. Off, the 1-degree pinch-out ends before its
// apex.
TEST(MesherTest, KeptSharpCornersReachTheirApexAsRungsOfTheirRegion)
{
  for (const char* file : { "pinch_out.vtp", "faulted_section.vtp" })
  {
    SCOPED_TRACE(file);
    const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
    strata::MesherParams keep;
    keep.keepSharpCorners = true;
    const strata::MesherResult r = strata::triangulate(raw, keep);
    ASSERT_GE(r.keptCorners.size(), 1u);
    EXPECT_GT(r.summary.keptCornerTriangles, 0u);
    // The wedges keep the input's angles; off them the mesh keeps MinimumAngle.
    EXPECT_LT(r.summary.minAngle, 25.0);
    EXPECT_EQ(r.summary.trianglesBelowMinimumAngle, 0u);
    EXPECT_GE(r.summary.minAngleUnforced, keep.refinement.minimumAngle - 0.05);
    EXPECT_EQ(r.summary.triangles, r.triangles.size());
    for (std::size_t t = 0; t < r.triangles.size(); ++t)
    {
      const auto& tri = r.triangles[t];
      ASSERT_GT(strata::orient2d(r.points[tri[0]], r.points[tri[1]], r.points[tri[2]]), 0.0);
    }
    const auto within = [](const strata::MesherResult::KeptCorner& k, Vec2 p)
    { return strata::norm2(p - k.apex) <= k.radius * k.radius * (1.0 + 1e-9); };
    for (const strata::MesherResult::KeptCorner& k : r.keptCorners)
    {
      SCOPED_TRACE("region " + std::to_string(k.region) + ", " + std::to_string(k.angle) + " deg");
      double angleAtApex = 0.0;
      for (std::size_t t = 0; t < r.triangles.size(); ++t)
      {
        const auto& tri = r.triangles[t];
        if (r.regionId[t] != k.region || !within(k, r.points[tri[0]]) ||
          !within(k, r.points[tri[1]]) || !within(k, r.points[tri[2]]) ||
          !insideOutline(
            k.outline, (1.0 / 3.0) * (r.points[tri[0]] + r.points[tri[1]] + r.points[tri[2]])))
        {
          continue;
        }
        EXPECT_GE(r.minAngle[t], 0.25 * k.angle - 1e-9);
        EXPECT_LE(r.maxAngle[t], 150.0 + 1e-9);
        const auto angles =
          strata::triangleAngles(r.points[tri[0]], r.points[tri[1]], r.points[tri[2]]);
        for (int i = 0; i < 3; ++i)
        {
          if (strata::norm(r.points[tri[i]] - k.apex) <= 1e-9 * k.radius)
          {
            angleAtApex += angles[i];
          }
        }
      }
      EXPECT_NEAR(angleAtApex, k.angle, 0.05 * k.angle) << "the region's angle at the apex";
    }
    for (std::size_t t = 0; t < r.triangles.size(); ++t)
    {
      bool near = false;
      for (const strata::MesherResult::KeptCorner& k : r.keptCorners)
      {
        for (int v : r.triangles[t])
        {
          near = near || strata::norm(r.points[v] - k.apex) <= 2.0 * k.radius;
        }
      }
      if (!near)
      {
        EXPECT_GE(r.minAngle[t], keep.refinement.minimumAngle - 1e-6) << "triangle " << t;
      }
    }
    expectAreasWithinHalfAPercent(r);
  }
  // Without the curve recovery it does nothing, and says so.
  strata::MesherParams noRecovery;
  noRecovery.keepSharpCorners = true;
  noRecovery.curveRecovery = false;
  const strata::MesherResult n = strata::triangulate(
    strata_test::readVtpAscii(strata_test::dataPath("pinch_out.vtp")), noRecovery);
  EXPECT_TRUE(n.keptCorners.empty());
  EXPECT_TRUE(std::any_of(n.warnings.begin(),
    n.warnings.end(),
    [](const std::string& w) { return w.find("KeepSharpCorners has no effect") == 0; }));
  // Off: no triangle of the pinching layer (region 1) within 5 of its apex at (600, 40).
  const strata::MesherResult off =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("pinch_out.vtp")));
  EXPECT_TRUE(off.keptCorners.empty());
  for (std::size_t t = 0; t < off.triangles.size(); ++t)
  {
    for (int v : off.triangles[t])
    {
      if (off.regionId[t] == 1)
      {
        EXPECT_GT(strata::norm(off.points[v] + off.origin - Vec2{ 600.0, 40.0 }), 5.0);
      }
    }
  }
}

namespace
{
// The model Data/`file` and its mesh made once (ThinLayerRetry off), with ThinLayerRefinement
// when `thinLayers`.
std::pair<strata::RawPolylines, strata::MesherResult> madeOnce(const char* file,
  bool thinLayers = false)
{
  strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
  strata::MesherParams once;
  once.thinLayerRetry = false;
  once.grid.thinLayerRefinement = thinLayers;
  strata::MesherResult r = strata::triangulate(raw, once);
  return { std::move(raw), std::move(r) };
}

// The model Data/`file` and its mesh with the default settings.
std::pair<strata::RawPolylines, strata::MesherResult> madeByDefault(const char* file)
{
  strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
  strata::MesherResult r = strata::triangulate(raw);
  return { std::move(raw), std::move(r) };
}
} // namespace

// Layers about a finest edge thick (thin_layered_section.vtp, LocalMaxLevel 14 automatic): the
// mesh made once loses a piece of region 4 where one layer ends in another (area 10.8% short),
// with every angle at 30 degrees. ThinLayerRetry makes it again 4 levels finer, which brings
// the area within issue 5's 0.5% (0.35%) but cuts region 4 in two where it is thinner than its
// finest triangles, so it makes that one again 2 levels finer, where the layer is whole, and
// keeps that mesh (every region within 0.05%, angles still 30 degrees), with KeepSharpCorners
// too; with the level set by the user the area miss stays.
TEST(MesherTest, ARegionOffItsAreaIsMadeAgainAtAFinerLevel)
{
  const auto [raw, r] = madeOnce("thin_layered_section.vtp");
  ASSERT_GT(r.summary.maxRegionAreaError, 0.02);
  EXPECT_GE(r.summary.minAngle, 25.0);

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_EQ(d.summary.localMaxLevel, r.summary.localMaxLevel + 6);
  EXPECT_TRUE(d.brokenRegions.empty());
  EXPECT_LE(d.summary.maxRegionAreaError, 0.0005);
  EXPECT_GE(d.summary.minAngle, 29.95);
  for (const auto& a : d.regionAreas)
  {
    EXPECT_NEAR(a.mesh, a.model, 0.005 * a.model) << "region " << a.id;
  }
  const std::string warnings = allWarnings(d);
  EXPECT_NE(warnings.find("had a region's area off by"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("the finer one is kept, but it cut 1 region(s) into more pieces"),
    std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("the third one is kept"), std::string::npos) << warnings;
  // The two meshes not kept are stages of the one kept.
  EXPECT_EQ(discardedLevelRuns(d), 2);

  strata::MesherParams keep;
  keep.keepSharpCorners = true;
  const strata::MesherResult k = strata::triangulate(raw, keep);
  EXPECT_EQ(k.summary.localMaxLevel, r.summary.localMaxLevel + 6);
  EXPECT_TRUE(k.brokenRegions.empty());
  EXPECT_LE(k.summary.maxRegionAreaError, 0.0005);
  EXPECT_GE(k.summary.minAngleUnforced, 29.95);
  EXPECT_NE(allWarnings(k).find("off the kept corners"), std::string::npos) << allWarnings(k);

  strata::MesherParams set;
  set.grid.localMaxLevel = r.summary.localMaxLevel;
  const strata::MesherResult s = strata::triangulate(raw, set);
  EXPECT_EQ(s.summary.localMaxLevel, r.summary.localMaxLevel);
  EXPECT_GT(s.summary.maxRegionAreaError, 0.005);
  EXPECT_EQ(allWarnings(s).find("made again at LocalMaxLevel"), std::string::npos);
}

// A faulted section whose layer pinches out between two others (pinch_tip_section.vtp, region
// 3 near (2.075, 0.318), LocalMaxLevel 15 automatic): the mesh made once gives the layer's last
// stretch, one to two finest edges thick, to its neighbour, its boundary 0.65 local edges off
// the curves. By default the thin layers refined around the miss mend it. With
// ThinLayerRefinement on, its mesh misses the same way, so the mesh is made again 4 levels
// finer, where the layer ends where it is about a finest edge thick, and that one is kept;
// with the level set by the user the miss stays. (Until 2026-12-04 spit_and_bay_lake.vtp
// showed this; since the compression's sleeping in a wave's tail, its mesh with
// ThinLayerRefinement meets the bound at once.)
TEST(MesherTest, ABoundaryTheThinLayersDoNotMendIsMadeAgainAtAFinerLevel)
{
  const auto [raw, r] = madeOnce("pinch_tip_section.vtp");
  ASSERT_GT(r.summary.maxRelativeDeviation, 0.55);
  EXPECT_GE(r.summary.minAngle, 29.95);

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_TRUE(d.summary.thinLayerMesh);
  EXPECT_EQ(d.summary.localMaxLevel, r.summary.localMaxLevel);
  EXPECT_LE(d.summary.maxRelativeDeviation, 0.5);

  strata::MesherParams thin;
  thin.grid.thinLayerRefinement = true;
  const strata::MesherResult t = strata::triangulate(raw, thin);
  EXPECT_EQ(t.summary.localMaxLevel, r.summary.localMaxLevel + 4);
  EXPECT_LE(t.summary.maxRelativeDeviation, 0.5);
  EXPECT_GE(t.summary.minAngle, 29.95);
  EXPECT_TRUE(t.brokenRegions.empty());
  EXPECT_LE(t.summary.maxRegionAreaError, 0.005);
  const std::string warnings = allWarnings(t);
  EXPECT_NE(warnings.find("had its boundary"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("the finer one is kept"), std::string::npos) << warnings;
  EXPECT_EQ(discardedLevelRuns(t), 1);

  strata::MesherParams set = thin;
  set.grid.localMaxLevel = r.summary.localMaxLevel;
  const strata::MesherResult s = strata::triangulate(raw, set);
  EXPECT_EQ(s.summary.localMaxLevel, r.summary.localMaxLevel);
  EXPECT_GT(s.summary.maxRelativeDeviation, 0.5);
  EXPECT_EQ(allWarnings(s).find("made again at LocalMaxLevel"), std::string::npos);
}

namespace
{
// The pieces of region `region` in the mesh: its triangles joined across shared edges, counted
// when their area is at least `floor` (the test's own count, from the triangles).
int piecesOf(const strata::MesherResult& r, int region, double floor)
{
  std::vector<int> parent(r.triangles.size());
  for (std::size_t t = 0; t < parent.size(); ++t)
  {
    parent[t] = static_cast<int>(t);
  }
  const auto find = [&](int t)
  {
    while (parent[t] != t)
    {
      t = parent[t] = parent[parent[t]];
    }
    return t;
  };
  std::map<std::pair<int, int>, int> firstAcross; // edge -> a triangle of the region on it
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    for (int k = 0; k < 3 && r.regionId[t] == region; ++k)
    {
      const int a = r.triangles[t][k], b = r.triangles[t][(k + 1) % 3];
      const auto [it, added] =
        firstAcross.emplace(std::make_pair(std::min(a, b), std::max(a, b)), static_cast<int>(t));
      if (!added)
      {
        parent[find(it->second)] = find(static_cast<int>(t));
      }
    }
  }
  std::map<int, double> area;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    if (r.regionId[t] == region)
    {
      const auto& tri = r.triangles[t];
      area[find(static_cast<int>(t))] +=
        0.5 * strata::orient2d(r.points[tri[0]], r.points[tri[1]], r.points[tri[2]]);
    }
  }
  return static_cast<int>(std::count_if(area.begin(),
    area.end(),
    [&](const std::pair<const int, double>& p) { return p.second >= floor; }));
}
} // namespace

// lost_layer_piece_section (a random faulted section): near where region 5, a layer about a
// finest edge thick, pinches out, the mesh made once gives a piece of it to its neighbour (and
// keeps a speck of it beyond): the boundary 0.6 - 0.7 local edges off its curve, while every
// angle is at 30 degrees and every area within 0.1%, so neither the angle nor the area bound
// sees it. The relative deviation does (above 0.5), so by default the mesh is made again with
// ThinLayerRefinement, first around the places it misses, and the one kept is within the
// bound. (Before the extensions of the pinch-outs looked past pieces of a layer cut off in its
// tip, the mesh made once also gave away 0.82 local edges of the layer where a fault cuts it.)
TEST(MesherTest, AMeshThatGivesAPieceOfALayerAwayIsMadeAgainWithTheThinLayerRefinement)
{
  const auto [raw, once] = madeOnce("lost_layer_piece_section.vtp");
  const strata::Model model = strata::buildModel(raw);
  EXPECT_GE(once.summary.minAngle, 29.95);
  EXPECT_LE(once.summary.maxRegionAreaError, 0.001);
  EXPECT_GT(boundaryDeviationOverLocalEdge(model, once), 0.55);
  EXPECT_GT(once.summary.maxRelativeDeviation, 0.6);
  EXPECT_GT(once.summary.relativeDeviationEdge, once.summary.finestEdgeLength);
  EXPECT_FALSE(once.summary.thinLayerMesh);

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_TRUE(d.summary.thinLayerMesh);
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, d), 0.5);
  EXPECT_LE(d.summary.maxRelativeDeviation, 0.5);
  EXPECT_GE(d.summary.minAngle, 29.95);
  EXPECT_LE(d.summary.maxRegionAreaError, 0.001);
  const std::string all = allWarnings(d);
  EXPECT_NE(all.find("the mesh without ThinLayerRefinement missed the angle, area or boundary "
                     "bound, or left a boundary vertex off the curves (smallest angle 30.0"),
    std::string::npos)
    << all;
  EXPECT_NE(
    all.find("a mesh with ThinLayerRefinement around the misses was made too"), std::string::npos)
    << all;
  ASSERT_FALSE(d.summary.secondsPerStage.empty());
  EXPECT_EQ(d.summary.secondsPerStage.front().first, "discarded run");
}

// cut_corner_section (a random layered section, 3 x 1.12, four regions): the compressed mesh
// ends the top layer's triangles 0.0019 (2.3 finest edges) short of the box's top-left
// corner, a right angle, with a chord across it. The region corners whose tip the mesh lost
// are rebuilt up to 90 degrees included (RefinementParams::wedgeCorners), so every corner of
// the box is a mesh vertex (as every junction is), and the boundary stays within half the
// local edge there (0.57 before).
TEST(MesherTest, TheCornersOfTheModelsBoxAreMeshVertices)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("cut_corner_section.vtp"));
  const strata::Model model = strata::buildModel(raw);
  const strata::MesherResult r = strata::triangulate(raw);
  const double top = 1.1214559078216553;
  for (const Vec2 c : { Vec2{ 0, 0 }, Vec2{ 3, 0 }, Vec2{ 3, top }, Vec2{ 0, top } })
  {
    double nearest = HUGE_VAL;
    for (const Vec2& x : r.points)
    {
      nearest = std::min(nearest, strata::norm(x + r.origin - c));
    }
    EXPECT_LE(nearest, 1e-9 * model.size()) << "corner (" << c.x << ", " << c.y << ")";
  }
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, r), 0.5);
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
}

// A lake's corner of 92 degrees (blunt_corner_lake.vtp, at (644.81, -763.95)) that the mesh
// cut 2 finest edges short of its apex: corners of its region up to 100 degrees whose tip is
// lost are rebuilt to the apex, as right angles are (a right angle drawn or digitised by hand).
TEST(MesherTest, ALakesCornerALittleWiderThanARightAngleIsAMeshVertex)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("blunt_corner_lake.vtp"));
  const strata::Model model = strata::buildModel(raw);
  const strata::MesherResult r = strata::triangulate(raw);
  const Vec2 corner{ 644.8117765598055, -763.9489459264131 };
  double nearest = HUGE_VAL;
  for (const Vec2& x : r.points)
  {
    nearest = std::min(nearest, strata::norm(x + r.origin - corner));
  }
  EXPECT_LE(nearest, 1e-9 * model.size());
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
}

// A layer the mesh cuts where it is about 1.3 finest edges thick (broken_layer_section.vtp,
// region 3, one piece in the model; LocalMaxLevel 14 automatic): the mesh made once has it in
// two pieces, and names it (brokenRegions, a warning with both counts). ThinLayerRetry makes
// the mesh again and keeps one where the layer is one piece: since 2026-12-06, when the
// boundary measure looks between its samples, it sees the cut as a boundary miss too (0.59
// local edges), and the mesh made again with ThinLayerRefinement around the misses at the
// same level keeps the layer whole (before, 4 levels finer: 17911 triangles against 14126).
// With the level set by the user the cut layer stays, named.
TEST(MesherTest, ALayerTheMeshCutsIsNamedAndMadeWholeAgain)
{
  const auto [raw, r] = madeOnce("broken_layer_section.vtp");
  const double floor = 4.0 * r.summary.finestEdgeLength * r.summary.finestEdgeLength;
  ASSERT_EQ(piecesOf(r, 3, floor), 2);
  EXPECT_EQ(r.brokenRegions, std::vector<int>{ 3 });
  const std::string warnings = allWarnings(r);
  EXPECT_NE(
    warnings.find("regions the mesh cuts into more pieces than the model has"), std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("): 3 (2/1);"), std::string::npos) << warnings;
  for (int region = 0; region < 7; ++region)
  {
    EXPECT_EQ(piecesOf(r, region, floor), region == 3 ? 2 : 1) << "region " << region;
  }

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_EQ(d.summary.localMaxLevel, r.summary.localMaxLevel);
  EXPECT_TRUE(d.summary.thinLayerMesh);
  EXPECT_TRUE(d.brokenRegions.empty());
  const double finerFloor = 4.0 * d.summary.finestEdgeLength * d.summary.finestEdgeLength;
  for (int region = 0; region < 7; ++region)
  {
    EXPECT_EQ(piecesOf(d, region, finerFloor), 1) << "region " << region;
  }
  EXPECT_GE(d.summary.minAngle, 29.95);
  EXPECT_LE(d.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(d.summary.maxRelativeDeviation, 0.5);
  const std::string dw = allWarnings(d);
  EXPECT_NE(dw.find("1 regions cut"), std::string::npos) << dw;
  EXPECT_NE(dw.find("0 regions cut"), std::string::npos) << dw;
  EXPECT_NE(dw.find("the second one is kept"), std::string::npos) << dw;

  strata::MesherParams set;
  set.grid.localMaxLevel = r.summary.localMaxLevel;
  const strata::MesherResult s = strata::triangulate(raw, set);
  EXPECT_EQ(s.brokenRegions, std::vector<int>{ 3 });
  EXPECT_EQ(allWarnings(s).find("made again at LocalMaxLevel"), std::string::npos);
}

// Of two meshes, ThinLayerRetry keeps the one that misses fewer of issue 5's hard bounds
// (25 degrees, 0.5% area, no region cut), whatever the angles above 25 degrees
// (stray_vertex_section.vtp with ThinLayerRefinement on, at LocalMaxLevel 20: the mesh with it
// at 25.7 degrees, every region whole; the one without at 30.0 degrees with a layer cut; the
// larger angle won before). (torn_layer_section.vtp at LocalMaxLevel 20 showed it with the
// area bound, 30 degrees and 2.4% lost against 28.8 within 0.1%, until the bold run near what
// the last cautious run leaves: its first mesh now keeps the layer's area, made once.)
TEST(MesherTest, AMeshWithinTheHardBoundsIsKeptOverOneWithALargerAngle)
{
  strata::MesherParams set;
  set.grid.thinLayerRefinement = true;
  const strata::MesherResult r = strata::triangulate(
    strata_test::readVtpAscii(strata_test::dataPath("stray_vertex_section.vtp")), set);
  ASSERT_GT(r.triangles.size(), 10000u);
  EXPECT_TRUE(r.brokenRegions.empty());
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_GE(r.summary.minAngle, 25.0);
  EXPECT_LT(r.summary.minAngle, 29.95); // (the other mesh's 30 did not win)
  EXPECT_TRUE(r.summary.thinLayerMesh);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("so a mesh without ThinLayerRefinement was made too (smallest angle "
                          "30.00 degrees, area error 0.01%, 1 regions cut"),
    std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("the first one is kept"), std::string::npos) << warnings;
}

// A region the third mesh of the finer levels still cuts gets a fourth mesh 2 levels finer
// again (torn_layer_section.vtp: its thin layer, 2.1 finest edges thick where it thins out at
// LocalMaxLevel 20, in 4 pieces there; whole at 22, at 30 degrees, with fewer triangles).
TEST(MesherTest, ALayerStillCutByTheThirdMeshIsMadeOnceMoreFiner)
{
  const strata::MesherResult r =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("torn_layer_section.vtp")));
  ASSERT_GT(r.triangles.size(), 10000u);
  EXPECT_TRUE(r.brokenRegions.empty());
  EXPECT_TRUE(r.unresolvedRegions.empty());
  EXPECT_EQ(r.summary.localMaxLevel, 22);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_GE(r.summary.minAngle, 29.9);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("the third one is kept, but it cut 1 region(s) into more pieces"),
    std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("the fourth one is kept"), std::string::npos) << warnings;
  EXPECT_EQ(discardedLevelRuns(r), 3);
}

// A triangle of a layer pokes a finest edge into the layer above (poked_triangle_loops.vtp),
// and the compression leaves the vertex at its tip 0.23 units off the curves: its move onto
// the curve would turn a triangle over. Since the fifty-fourth session it is merged into its
// neighbour on the curve before the refinement, so the mesh made once has every boundary
// vertex on a curve, within the bounds, and by default it is not made again (it was, with
// ThinLayerRefinement, which placed the vertex). Without the refinement (MinimumAngle 0) no
// vertex is merged: the vertex stays off, and that miss is one of those the mesh is made again
// for, its distance named among the first mesh's figures.
TEST(MesherTest, AVertexAtThePokedTipIsMergedOntoTheCurveAndAMeshLeavingOneOffIsMadeAgain)
{
  const auto [raw, o] = madeOnce("poked_triangle_loops.vtp");
  const double onCurve = 1e-9 * 1000.0;
  EXPECT_LE(o.summary.maxBoundaryVertexDistance, onCurve);
  EXPECT_GE(o.summary.minAngle, 29.95);
  EXPECT_LE(o.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(o.summary.maxRelativeDeviation, 0.5);
  EXPECT_EQ(allWarnings(o), "");

  const strata::MesherResult r = strata::triangulate(raw);
  EXPECT_FALSE(r.summary.thinLayerMesh);
  EXPECT_EQ(r.triangles, o.triangles);
  EXPECT_EQ(r.points, o.points);

  strata::MesherParams unrefined;
  unrefined.refinement.minimumAngle = 0.0;
  const strata::MesherResult u = strata::triangulate(raw, unrefined);
  EXPECT_GT(u.summary.maxBoundaryVertexDistance, 0.1);
  const std::string warnings = allWarnings(u);
  EXPECT_NE(
    warnings.find("left a boundary vertex off the curves (smallest angle"), std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("a boundary vertex 0.233657 model units off the curves), so a mesh with "
                          "ThinLayerRefinement was made too"),
    std::string::npos)
    << warnings;
}

// A region left with fewer pieces than the model has is a miss too (lost_wedge_tip_loops.vtp,
// LocalMaxLevel 16 automatic): made once, a stretch of a layer's wedge about 3.5 finest edges
// thick, beside a sliver narrower than the finest edge (whose curve points the boundary measure
// leaves out), goes to its neighbour and cuts off the wedge's tip; the rest of that piece of
// region 6 falls below the piece floor, so the mesh has one piece of it where the model has
// two, named in BrokenRegions. By default the mesh is made again 4 levels finer, where region 6
// keeps both pieces.
TEST(MesherTest, ARegionLeftWithFewerPiecesThanTheModelIsMadeAgainFiner)
{
  const auto [raw, r] = madeOnce("lost_wedge_tip_loops.vtp");
  ASSERT_EQ(r.brokenRegions, std::vector<int>{ 6 });
  EXPECT_NE(allWarnings(r).find("6 (1/2)"), std::string::npos) << allWarnings(r);

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_EQ(d.summary.localMaxLevel, r.summary.localMaxLevel + 4);
  EXPECT_TRUE(d.brokenRegions.empty());
  EXPECT_GE(d.summary.minAngle, 29.95);
  EXPECT_LE(d.summary.maxRegionAreaError, 0.005);
  EXPECT_NE(allWarnings(d).find("cut 1 region(s) into more pieces than the model has (or left "
                                "fewer)"),
    std::string::npos)
    << allWarnings(d);
}

namespace
{
// Every triangle at 30 degrees (none left below MinimumAngle), the largest angle at most 130,
// areas within 0.5%, the boundary within half the local edge, no region cut or lost.
void expectEveryTriangleAtThirtyWithinTheBounds(const strata::MesherResult& r)
{
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_EQ(r.summary.trianglesBelowMinimumAngle, 0u);
  EXPECT_LE(r.summary.maxAngle, 130.0);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_LE(r.summary.maxRegionMisplacedArea, 0.005);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_TRUE(r.brokenRegions.empty());
}

// The mesh of a Data model made by default, which ThinLayerRetry's ladder made again finer: at
// `level`, every triangle at 30 degrees within issue 5's bounds, each of `said` in its warnings
// and no triangle named below MinimumAngle. Returns the model.
strata::RawPolylines expectMadeAgainFinerAtThirty(const char* file,
  int level,
  std::initializer_list<const char*> said)
{
  auto [raw, r] = madeByDefault(file);
  expectEveryTriangleAtThirtyWithinTheBounds(r);
  EXPECT_GE(r.summary.minAngle, 30.0 - 1e-6);
  EXPECT_EQ(r.summary.localMaxLevel, level);
  expectWarningsSay(r, said);
  const std::string warnings = allWarnings(r);
  EXPECT_EQ(warnings.find("stay below MinimumAngle"), std::string::npos) << warnings;
  return std::move(raw);
}
} // namespace

// The last pass's cautious run may leave a triangle below MinimumAngle where a bolder
// insertion would mend it: a sliver at a lake's shore, whose boundary split the cautious run
// refuses (shore_sliver_lake.vtp, lake126 of random_lakes_countries.py 118 130: 27.3 degrees).
// A bold run near such triangles, on a copy kept when its smallest angle is larger, mends it.
TEST(MesherTest, ATriangleTheCautiousRunLeavesBelowTheBoundIsMendedByABoldRunNearIt)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("shore_sliver_lake.vtp"));
  const strata::MesherResult r = strata::triangulate(raw);
  expectEveryTriangleAtThirtyWithinTheBounds(r);
}

// Two junctions 0.20 finest edges apart, where a layer meets a fault (junction_pair_section.vtp,
// f104 of random_faulted_sections.py 104 105): their edge is shorter than any split may make,
// so the triangles beside it are only good when they are about as small. The refinement's
// floor is half that edge there (half the finest edge elsewhere): every triangle reaches
// 30 degrees (28.3 with the floor everywhere the same), with the other bounds.
TEST(MesherTest, TrianglesBesideTwoJunctionsCloseTogetherReachTheBound)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("junction_pair_section.vtp"));
  const strata::MesherResult r = strata::triangulate(raw);
  expectEveryTriangleAtThirtyWithinTheBounds(r);
}

// Sizes set in model units keep the boundary bound: a mesh that misses it is made again with
// ThinLayerRefinement around the misses, at the same finest edge (sized_lost_piece_loops.vtp at
// MaximumEdgeLength 20, MinimumEdgeLength 0.5: made once, a piece of a layer goes to its
// neighbour, 0.90 local edges; made again, 0.04). (A MaxLevel or LocalMaxLevel the user set
// is kept as set: that mesh is made once, the miss named in a warning.)
TEST(MesherTest, AMeshAtSizesInModelUnitsThatMissesTheBoundaryIsMadeAgain)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("sized_lost_piece_loops.vtp"));
  strata::MesherParams sized;
  sized.grid.maxEdgeLength = 20.0;
  sized.grid.minEdgeLength = 0.5;
  strata::MesherParams once = sized;
  once.thinLayerRetry = false;
  const strata::MesherResult o = strata::triangulate(raw, once);
  ASSERT_GT(o.summary.maxRelativeDeviation, 0.55);

  const strata::MesherResult r = strata::triangulate(raw, sized);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_LE(boundaryDeviationOverLocalEdge(strata::buildModel(raw), r), 0.5);
  EXPECT_TRUE(r.summary.thinLayerMesh);
  EXPECT_DOUBLE_EQ(r.summary.finestEdgeLength, o.summary.finestEdgeLength);
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("around the misses was made too"), std::string::npos) << warnings;
}

// A thin layer kept whole at the third level (stray_vertex_section.vtp, m110 of the fresh seeds
// of 2026-12-04, LocalMaxLevel 20 after the finer levels): the mesh without ThinLayerRefinement
// cuts region 5 into 3 pieces at 30 degrees; the one with it around the misses keeps it whole,
// with every boundary vertex on a curve, at 30 degrees and 0.40 local edges, and is kept.
// (Until the fifty-fourth session's merges that mesh left a vertex of the 4/5 boundary 3.2 units
// off its curve, at 25.5 degrees, a hard miss of issue 4's bound, and the mesh with the thin
// layer refinement everywhere was kept: whole, on the curves, at 25.7 degrees, the last of the
// unseen models below 30.)
TEST(MesherTest, AThinLayerAtTheThirdLevelIsKeptWholeOnTheCurvesAtThirtyDegrees)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("stray_vertex_section.vtp"));
  const strata::MesherResult r = strata::triangulate(raw);
  ASSERT_GT(r.triangles.size(), 10000u);
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * 27000.0);
  EXPECT_TRUE(r.brokenRegions.empty());
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("the third one is kept"), std::string::npos) << warnings;
  EXPECT_TRUE(r.summary.thinLayerMesh);
  EXPECT_NE(warnings.find("around the misses was made too"), std::string::npos) << warnings;
}

namespace
{
// Default settings on a lake: 30 degrees, areas within 0.5%, and the boundary within half the
// local edge by both the mesher's measure and this file's.
void expectLakeWithinTheBounds(const char* file)
{
  const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(file));
  const strata::MesherResult r = strata::triangulate(raw);
  ASSERT_GT(r.triangles.size(), 10000u);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_LE(boundaryDeviationOverLocalEdge(strata::buildModel(raw), r), 0.5);
  EXPECT_GE(r.summary.minAngle, 29.9);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
}
} // namespace

// An inlet beside bends of the shore is not a region narrower than the finest edge
// (island_inlet_lake.vtp: an island's inlet about 2-3 finest edges wide). The mesher's own
// measure left out the curve points where the disc of a finest edge's diameter touching the
// curve is cut by a curve, which the next segment does at any bend toward the disc: the mesh
// kept left the inlet out, 0.58 local edges by this measure (0.89 at its tip, narrower than
// the finest edge) while its own said 0.49. Now the disc is shrunk by 10% (a bend of less
// than about 25 degrees is not narrow) and a curve across within a finest edge counts too:
// the miss is seen (0.58 at the automatic LocalMaxLevel 22), the finer level and
// ThinLayerRefinement around the misses keep the inlet.
TEST(MesherTest, AnInletBesideABendOfTheShoreIsNotTakenForANarrowRegion)
{
  expectLakeWithinTheBounds("island_inlet_lake.vtp");
}

// A corner of a shore where a spur of land narrower than the finest edge starts
// (spur_corner_lake.vtp, lake125 of random_lakes_countries.py 125 126): the mesh made once cuts
// the spur off with one edge, 0.52 local edges from the curve at the corner by this file's
// measure, whose corner is the end of the segment before the spur (not beside a narrow
// region). The mesher sampled each segment from its start only, so it took the corner as the
// start of the spur's first segment and left it out (0.46). With each segment's end sampled
// as that segment's, the miss is seen and the mesh refined around it is kept.
TEST(MesherTest, TheCornerWhereANarrowSpurStartsIsMeasuredAsTheSegmentBeforeIt)
{
  expectLakeWithinTheBounds("spur_corner_lake.vtp");
}

// A wedge between a border and a section's long side, narrower than the finest edge near its
// tip, is a region narrower than the finest edge there (wedge_tip_countries.vtp, countries138
// of random_lakes_countries.py 130 142: a 21.8-degree wedge at a junction on a side 660 long,
// 29 k finest edges; the mesh leaves the tip out, 0.51 local edges 0.046 from the junction,
// where the wedge is 0.018 wide). The narrow-region test takes its point a hair inside the
// segment, at most 0.5% of the finest edge: 1e-4 of the side, as until 2026-12-05, tested the
// point 0.033 farther along, where the wedge is 0.031 wide, and counted the miss (0.51).
TEST(MesherTest, AWedgeTipBesideALongSideIsTestedWhereItIs)
{
  expectLakeWithinTheBounds("wedge_tip_countries.vtp");
}

// A boundary more than half a local edge off the curves after the thin layer meshes asks for
// the finer level (pinch_end_section.vtp, f137 of random_faulted_sections.py 137 138: the
// meshes at the automatic LocalMaxLevel 15 end a pinching-out layer where it is about a
// finest edge thick, just wider than the measure's exemption, 0.503 local edges). Until
// 2026-12-04 only a miss beyond 0.55 did, and that mesh was kept.
TEST(MesherTest, ABoundaryMissByAHairIsMadeAgainFiner)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("pinch_end_section.vtp"));
  const strata::MesherResult r = strata::triangulate(raw);
  expectEveryTriangleAtThirtyWithinTheBounds(r);
  EXPECT_LE(boundaryDeviationOverLocalEdge(strata::buildModel(raw), r), 0.5);
  EXPECT_EQ(r.summary.localMaxLevel, 19);
  EXPECT_NE(allWarnings(r).find("had its boundary 0.5028 local edges off the input curves"),
    std::string::npos)
    << allWarnings(r);
}

// A boundary edge that cuts off a bulge of an island deeper than 0.4 of the local edge (and a
// finest edge) is split at the bulge's farthest point, whatever the area (bulge_island_lake.vtp:
// an edge 17.6 long, the bulge 8.1 deep, triangles about 15 long beside it; the area bound,
// relative to the lake, never saw it: 0.52 local edges, under the finer level's bound then, 0.55).
TEST(MesherTest, AnIslandsBulgeCutOffByALongEdgeIsFollowed)
{
  expectLakeWithinTheBounds("bulge_island_lake.vtp");
}

// The last pass's finisher (a run bold only around the triangles left below MinimumAngle) can
// mend its zones and make a triangle below the angle to beat beside them: on
// beside_zone_lake.vtp (lake303 of random_lakes_countries.py 300 306) it mended two triangles
// of 28.3 and 28.8 degrees, large ones 0.009 units from the shore, and made one of 27.7
// degrees next to them, so it was not kept and the mesh kept 28.26 degrees (2026-12-06). It
// is made again, bold around that triangle too, and kept: every triangle at 30 degrees, the
// lake's area kept.
TEST(MesherTest, AFinisherThatMakesABadTriangleBesideItsZonesIsMadeAgainBoldThereToo)
{
  const auto [raw, r] = madeOnce("beside_zone_lake.vtp");
  EXPECT_EQ(r.summary.trianglesBelowMinimumAngle, 0u);
  ASSERT_FALSE(r.minAngle.empty());
  const double smallest = *std::min_element(r.minAngle.begin(), r.minAngle.end());
  EXPECT_GE(smallest, 30.0 - 1e-6);
  EXPECT_GE(r.summary.minAngle, 30.0 - 1e-6);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_EQ(allWarnings(r).find("stay below MinimumAngle"), std::string::npos) << allWarnings(r);
}

// The compression leaves 3 vertices of the approximated boundary off the curves on
// placed_later_section.vtp (f163 of random_faulted_sections.py 160 172), and the snaps and the
// refinement then place them: the mesh, made once or by default, has every boundary vertex on
// a curve, and no warning says otherwise.
TEST(MesherTest, BoundaryVerticesPlacedAfterTheCompressionAreNotWarnedOf)
{
  const auto [raw, once] = madeOnce("placed_later_section.vtp");
  const strata::MesherResult byDefault = strata::triangulate(raw);
  for (const strata::MesherResult* r : { &once, &byDefault })
  {
    EXPECT_GT(r->summary.triangles, 0u);
    EXPECT_LE(r->summary.maxBoundaryVertexDistance, 1e-9 * 25000.0);
    EXPECT_EQ(allWarnings(*r).find("could not be placed"), std::string::npos) << allWarnings(*r);
  }
}

// A vertex the compression pushed 2.1 model units past the section's bottom, beside a
// neighbour that arrived on it (overshoot_section.vtp, m508 of random_sections.py 500 524, at
// LocalMaxLevel 18, the level the default mesh is made again at): its snap onto the bottom
// would turn the thin triangle between the two over, so it stayed off the curves (2.14 units,
// with a warning). It is merged into that neighbour instead: made at that level once or by
// default, every vertex of the approximated boundary lies on a curve, with no warning of it,
// and the default mesh is within issue 5's bounds.
TEST(MesherTest, AVertexPushedPastACurveBesideOneOnItIsMergedIntoIt)
{
  const auto [raw, byDefault] = madeByDefault("overshoot_section.vtp");
  strata::MesherParams finer;
  finer.grid.localMaxLevel = 18;
  finer.thinLayerRetry = false;
  const strata::MesherResult once = strata::triangulate(raw, finer);
  for (const strata::MesherResult* r : { &once, &byDefault })
  {
    EXPECT_GT(r->summary.triangles, 0u);
    EXPECT_LE(r->summary.maxBoundaryVertexDistance, 1e-9 * 25000.0);
    const std::string warnings = allWarnings(*r);
    EXPECT_EQ(warnings.find("could not be placed"), std::string::npos) << warnings;
    EXPECT_EQ(warnings.find("a vertex of the approximated boundary lies"), std::string::npos)
      << warnings;
  }
  expectEveryTriangleAtThirtyWithinTheBounds(byDefault);
}

namespace
{
// A boundary miss the mesher once passed by, on Data/`file`: made with `once` (ThinLayerRetry
// off), the independent measure and the mesher's own both find the boundary more than `above`
// local edges off, with the miss's warning; with the default settings every triangle is at 30
// degrees within the bounds, and the boundary within half a local edge by the independent
// measure.
void expectTheMissSeenAndMetByDefault(const char* file, strata::MesherParams once, double above)
{
  const auto [raw, byDefault] = madeByDefault(file);
  const strata::Model model = strata::buildModel(raw);
  once.thinLayerRetry = false;
  const strata::MesherResult o = strata::triangulate(raw, once);
  ASSERT_GT(boundaryDeviationOverLocalEdge(model, o), above);
  EXPECT_GT(o.summary.maxRelativeDeviation, above);
  EXPECT_NE(allWarnings(o).find("more than half the local edge"), std::string::npos);

  expectEveryTriangleAtThirtyWithinTheBounds(byDefault);
  EXPECT_LE(boundaryDeviationOverLocalEdge(model, byDefault), 0.5);
}
} // namespace

// A peak of the boundary's deviation between two of the mesher's curve samples
// (kink_peak_section.vtp, f706 of random_faulted_sections.py 700 712). At LocalMaxLevel 16 with
// ThinLayerRefinement (the mesh kept by default until 2026-12-06) the distance from a layer's
// boundary to the mesh's rises to a kink where the next boundary edge becomes the nearest, whose
// local edge is 28% longer: 0.515 local edges just before it, by the quality table's measure,
// where the samples a quarter finest edge apart on either side gave 0.48 and 0.41, and the mesh
// was kept as within the bound. The peak is looked for between the samples: that mesh is a
// miss, with a warning, and the default settings make a mesh within the bound by either
// measure.
TEST(MesherTest, ABoundaryDeviationPeakBetweenTwoSamplesIsSeenAndTheMeshMadeAgain)
{
  strata::MesherParams once;
  once.grid.localMaxLevel = 16;
  once.grid.thinLayerRefinement = true;
  expectTheMissSeenAndMetByDefault("kink_peak_section.vtp", once, 0.5);
}

// A mesh boundary edge across a corner of the curves (corner_chord_lake.vtp, lake005 of
// random_lakes_countries.py 0 12): the first mesh made with the default settings has a shore
// edge 1.77 long whose point at 0.44 of it lies 0.53 local edges off the shore's corner, where
// the mesher's samples an eighth of the edge apart read 0.45 and 0.47 (the table's too), so
// that mesh was kept. The mesher looks between the samples of its boundary edges too: that
// mesh is a miss, with a warning, and the default settings make a mesh within the bound by
// either measure.
TEST(MesherTest, ABoundaryEdgeAcrossACornerOfTheCurvesIsSeenBetweenItsSamples)
{
  expectTheMissSeenAndMetByDefault("corner_chord_lake.vtp", strata::MesherParams(), 0.52);
}

// A curve point just beyond a region narrower than the finest edge (narrow_edge_section.vtp,
// f308 of random_faulted_sections.py 300 312): along its normal the other curve lies 1.00002
// finest edges away, so it is not left out, and the first mesh made with the default settings
// lies 0.5023 local edges off there. The mesher's ray, by sphere tracing, counted curves up
// to about 1e-3 finest edges farther, left the point out and kept that mesh; it now takes the
// ray's first crossing exactly: that mesh is a miss, with a warning, and the default settings
// make a mesh within the bound by either measure.
TEST(MesherTest, ACurvePointJustBeyondANarrowRegionIsNotLeftOut)
{
  expectTheMissSeenAndMetByDefault("narrow_edge_section.vtp", strata::MesherParams(), 0.5);
}

// Two free vertices closer than the refinement's floor inside a country
// (interior_pair_countries.vtp, countries159 of random_lakes_countries.py 154 166): their
// triangles stayed at 27.32 and 28.83 degrees, since no insertion may shorten their edges and a
// merge of either vertex into the other did not raise them. They meet at their edge's middle:
// with the default settings every triangle is at 30 degrees or more, with no warning (nor a
// thin layer mesh made too), and the countries' areas are kept.
TEST(MesherTest, TwoFreeVerticesTooCloseForTheRefinementMeetHalfWayInACountry)
{
  const auto [raw, r] = madeByDefault("interior_pair_countries.vtp");
  expectEveryTriangleAtThirtyWithinTheBounds(r);
  EXPECT_GE(r.summary.minAngle, 30.0 - 1e-6);
  EXPECT_EQ(allWarnings(r), "");
}

// A layer thinning to about a finest edge (thinning_layer_section.vtp, m320 of
// random_sections.py 312 324, LocalMaxLevel 14 automatic): the mesh kept there has two
// triangles below MinimumAngle (25.78 degrees), above issue 5's hard 25 but below its 30-degree
// goal, which no input corner forces. With the automatic sizes it is made again 4 levels finer
// and that mesh is kept: every triangle at 30 degrees, the areas and the boundary within issue
// 5's bounds, the retry named in a warning. With LocalMaxLevel 14 set by the user, the mesh
// is made at that level only, and its triangles below the angle are named.
TEST(MesherTest, AMeshBelowTheAngleGoalIsMadeAgainFinerWithTheAutomaticSizes)
{
  const strata::RawPolylines raw = expectMadeAgainFinerAtThirty("thinning_layer_section.vtp",
    18,
    { "the mesh at LocalMaxLevel 14 had triangles below 30 degrees (smallest 25.78), so it was "
      "made again at LocalMaxLevel 18",
      "the finer one is kept" });

  strata::MesherParams set;
  set.grid.localMaxLevel = 14;
  const strata::MesherResult once = strata::triangulate(raw, set);
  EXPECT_EQ(once.summary.localMaxLevel, 14);
  EXPECT_LT(once.summary.minAngle, 30.0 - 1.0);
  EXPECT_GT(once.summary.trianglesBelowMinimumAngle, 0u);
  EXPECT_NE(allWarnings(once).find("stay below MinimumAngle"), std::string::npos)
    << allWarnings(once);
}

// A layer narrower than the refinement's floor where it thins (narrow_layer_section.vtp, m1107
// of random_sections.py 1100 1130, LocalMaxLevel 14 automatic): the first mesh loses 3.8% of a
// region's area, and the mesh 4 levels finer, kept, mends the area but keeps a triangle at
// 27.00 degrees in region 2, whose boundary edge there is too short to split. Missing only the
// 30-degree goal, that mesh is made again 2 levels finer, and that one is kept: every triangle
// at 30 degrees, the areas and the boundary within issue 5's bounds, the three meshes named in
// one warning.
TEST(MesherTest, AFinerMeshStillBelowTheAngleGoalIsMadeTwoLevelsFinerAgain)
{
  expectMadeAgainFinerAtThirty("narrow_layer_section.vtp",
    20,
    { "so it was made again at LocalMaxLevel 18 (smallest 27.00 degrees",
      "the finer one is kept, but it had triangles below 30 degrees (smallest 27.00), so it was "
      "made again at LocalMaxLevel 20",
      "the third one is kept" });
}

// A region joined across a fault by a neck 0.05 units wide, an eighth of the finest edge at the
// automatic LocalMaxLevel 14 (fault_neck_section.vtp, f160 of random_faulted_sections.py 160
// 172): made once, the mesh cuts region 3 in two, and so does the mesh 4 levels finer, not kept
// then (no fewer regions cut). As the cut persists at the finer level, the ladder goes on,
// compared with the first mesh: 2 levels finer it is cut still, 2 more and it is whole, and that
// mesh is kept.
TEST(MesherTest, ARegionStillCutAtTheFinerLevelIsMadeFinerAgainUntilWhole)
{
  const auto [raw, once] = madeOnce("fault_neck_section.vtp");
  EXPECT_EQ(once.summary.localMaxLevel, 14);
  EXPECT_EQ(once.brokenRegions, std::vector<int>{ 3 });
  expectMadeAgainFinerAtThirty("fault_neck_section.vtp",
    22,
    { "the mesh at LocalMaxLevel 14 cut 1 region(s) into more pieces than the model has (or left "
      "fewer), so it was made again at LocalMaxLevel 18",
      "1 regions cut, boundary deviation 0.0303 local edges, 8049 triangles); the first one is "
      "kept, but as the finer one cut a region too, it was made again at LocalMaxLevel 20",
      "the first one is kept, but as the third one cut a region too, it was made again at "
      "LocalMaxLevel 22 (smallest 30.00 degrees, area error 0.01%, 0 regions cut",
      "the fourth one is kept" });
}

namespace
{
// The convex polygon `poly` (counter-clockwise) clipped to the half-plane left of the directed
// line a -> b (Sutherland-Hodgman).
std::vector<Vec2> clippedLeftOf(const std::vector<Vec2>& poly, Vec2 a, Vec2 b)
{
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    const Vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
    const double sp = strata::cross(b - a, p - a), sq = strata::cross(b - a, q - a);
    if (sp >= 0.0)
    {
      out.push_back(p);
    }
    if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0))
    {
      out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
  }
  return out;
}

double polygonArea(const std::vector<Vec2>& poly)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    sum += strata::cross(poly[i], poly[(i + 1) % poly.size()]);
  }
  return 0.5 * sum;
}

// A section 100 x 60 cut by zigzag curves (teeth 1.5 units up and down, 5 apart) around each of
// the heights `middles` (increasing), meshed by the paper's method on a grid coarser than its
// teeth (MaxLevel 8): region 0 below the first curve, region k between curves k - 1 and k.
// Returns the curves and the mesh.
std::pair<std::vector<std::vector<Vec2>>, strata::MesherResult> zigzagSection(
  std::initializer_list<double> middles)
{
  std::vector<std::vector<Vec2>> curves;
  for (double middle : middles)
  {
    curves.emplace_back();
    for (int i = 0; i <= 20; ++i)
    {
      curves.back().push_back({ 5.0 * i, middle + (i % 2 ? 1.5 : -1.5) });
    }
  }
  strata::RawPolylines raw;
  std::vector<Vec2> loop = { { 0, 0 }, { 100, 0 } };
  for (std::size_t k = 0; k <= curves.size(); ++k)
  {
    if (k < curves.size())
    {
      loop.insert(loop.end(), curves[k].rbegin(), curves[k].rend());
    }
    else
    {
      loop.insert(loop.end(), { { 100, 60 }, { 0, 60 } });
    }
    strata_test::addLoop(raw, loop, static_cast<int>(k));
    if (k < curves.size())
    {
      loop = curves[k];
    }
  }
  strata::MesherParams paper;
  paper.compression.optimize = false;
  paper.grid.maxLevel = 8;
  return { std::move(curves), strata::triangulate(raw, paper) };
}
} // namespace

// The Delaunay refinement's wedges (step 7') list the triangles near each corner a chunk of
// corners at a time (RefinementParams::wedgeChunk), from the mesh as it was and the triangles
// the extensions before made or changed: the mesh is the same, byte for byte, whatever the
// chunk. Marmousi (its last pass extends about 40 of its 180 wedges) meshed in one chunk, then
// in chunks of 1, 2 and 7 corners.
TEST(MesherTest, TheWedgesGiveTheSameMeshWhateverTheCornersListedAtOnce)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("geology_marmousi.vtp"));
  strata::MesherParams p;
  p.thinLayerRetry = false;
  const strata::MesherResult whole = strata::triangulate(raw, p);
  ASSERT_GT(whole.triangles.size(), 0u);
  for (const std::size_t chunk : { 1, 2, 7 })
  {
    p.refinement.wedgeChunk = chunk;
    const strata::MesherResult r = strata::triangulate(raw, p);
    EXPECT_EQ(r.points, whole.points) << "chunks of " << chunk;
    EXPECT_EQ(r.triangles, whole.triangles) << "chunks of " << chunk;
    EXPECT_EQ(r.regionId, whole.regionId) << "chunks of " << chunk;
  }
}

// RegionArea::misplaced (and Summary::maxRegionMisplacedArea) is the symmetric difference of a
// region's triangles and its model region. A section 100 x 60 split by a zigzag curve (teeth
// 1.5 units up and down, 5 apart) is meshed by the paper's method on a grid coarser than its
// teeth: the mesh's boundary cuts across the peaks, where region 0 loses to region 1, and the
// valleys, where it gains. The misplaced areas agree with the exact figures, every triangle
// clipped against the region below the curve tooth by tooth; the net area errors hide most of
// them.
TEST(MesherTest, TheMisplacedAreaIsTheSymmetricDifferenceOfTheMeshAndTheModel)
{
  const auto [curves, r] = zigzagSection({ 30.0 });
  const std::vector<Vec2>& zigzag = curves.front();
  ASSERT_EQ(r.regionAreas.size(), 2u);

  // The exact areas: each triangle's part below the curve, tooth by tooth.
  double modelBelow = 0.0;
  for (std::size_t i = 0; i + 1 < zigzag.size(); ++i)
  {
    modelBelow += 0.5 * (zigzag[i + 1].x - zigzag[i].x) * (zigzag[i].y + zigzag[i + 1].y);
  }
  const double model[2] = { modelBelow, 6000.0 - modelBelow };
  double mesh[2] = { 0.0, 0.0 }, common[2] = { 0.0, 0.0 };
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    const std::vector<Vec2> tri = { r.points[r.triangles[t][0]] + r.origin,
      r.points[r.triangles[t][1]] + r.origin,
      r.points[r.triangles[t][2]] + r.origin };
    double inside = 0.0; // below the curve
    for (std::size_t i = 0; i + 1 < zigzag.size(); ++i)
    {
      const double x0 = zigzag[i].x, x1 = zigzag[i + 1].x;
      std::vector<Vec2> piece = clippedLeftOf(tri, { x0, 1.0 }, { x0, 0.0 });
      piece = clippedLeftOf(piece, { x1, 0.0 }, { x1, 1.0 });
      piece = clippedLeftOf(piece, zigzag[i + 1], zigzag[i]);
      inside += polygonArea(piece);
    }
    const int region = r.regionId[t];
    ASSERT_TRUE(region == 0 || region == 1);
    mesh[region] += polygonArea(tri);
    common[region] += region == 0 ? inside : polygonArea(tri) - inside;
  }
  double largest = 0.0;
  for (const strata::MesherResult::RegionArea& ra : r.regionAreas)
  {
    const int k = ra.id;
    const double exact = mesh[k] + model[k] - 2.0 * common[k];
    EXPECT_NEAR(ra.model, model[k], 1e-9 * model[k]);
    EXPECT_NEAR(ra.mesh, mesh[k], 1e-9 * model[k]);
    EXPECT_GT(exact, 0.002 * model[k]) << "region " << k; // the mesh cuts across teeth
    EXPECT_NEAR(ra.misplaced, exact, 0.01 * exact) << "region " << k;
    EXPECT_LT(std::fabs(ra.mesh - ra.model), 0.5 * exact) << "region " << k;
    largest = std::max(largest, exact / model[k]);
  }
  EXPECT_NEAR(r.summary.maxRegionMisplacedArea, largest, 0.01 * largest);
  EXPECT_GE(r.summary.maxRegionMisplacedArea, r.summary.maxRegionAreaError);
}

// A layer's tip about a finest edge thick at the automatic LocalMaxLevel 14
// (pinchout_tip_section.vtp, f1403 of random_faulted_sections.py 1400 1424). The mesh with the
// thin layer refinement, kept over the one without (0.54% net), loses the tip, 0.54% of region
// 1's area, and adds 0.10% elsewhere: 0.44% net, within issue 5's 0.5%, but 0.63% misplaced,
// as the independent checker measures it. The misplaced area is a miss too, so the mesh is made
// again 4 levels finer, and that one is kept: 0.10% misplaced.
TEST(MesherTest, ARegionWhoseLossAndGainCancelOutIsMadeFinerForItsMisplacedArea)
{
  const auto [raw, first] = madeOnce("pinchout_tip_section.vtp", true);
  EXPECT_EQ(first.summary.localMaxLevel, 14);
  EXPECT_LE(first.summary.maxRegionAreaError, 0.005);
  EXPECT_GT(first.summary.maxRegionMisplacedArea, 0.006);

  expectMadeAgainFinerAtThirty("pinchout_tip_section.vtp",
    18,
    { "the mesh at LocalMaxLevel 14 had 0.63% of a region's area misplaced (0.44% net), so it "
      "was made again at LocalMaxLevel 18",
      "the finer one is kept" });
}

// A region whose triangles cover its model area within 10% but leave more than 10% of it out of
// place is named in a warning, with the area lost plus added (the net difference's warning does
// not see it). A layer 3 units thick between two zigzag curves (teeth 1.5 units up and down, 5
// apart) across a section 100 x 60, meshed by the paper's method on a grid coarser than its teeth.
TEST(MesherTest, ARegionWhoseTrianglesLieOutOfPlaceIsNamedEvenWhenItsAreaIsRight)
{
  const strata::MesherResult r = zigzagSection({ 30.0, 33.0 }).second;
  ASSERT_EQ(r.regionAreas.size(), 3u);
  const strata::MesherResult::RegionArea& thin = r.regionAreas[1];
  ASSERT_EQ(thin.id, 1);
  EXPECT_LE(std::fabs(thin.mesh - thin.model), 0.1 * thin.model);
  EXPECT_GT(thin.misplaced, 0.1 * thin.model);
  const std::string warnings = allWarnings(r);
  char expected[64];
  std::snprintf(expected,
    sizeof(expected),
    "(region id and area lost plus added): 1 (%d%%)",
    static_cast<int>(std::lround(100.0 * thin.misplaced / thin.model)));
  EXPECT_NE(warnings.find(expected), std::string::npos) << expected << "\n" << warnings;
  EXPECT_EQ(warnings.find("more than 10% off their model area"), std::string::npos) << warnings;
}

// A layer 0.003 thick (3e-6 of the section's width, 1/130 of the finest edge) ending at both
// sides of a section 1000 x 100 (vanishing_layer_section.vtp): its two junctions at each side are
// far closer than the finest edge, and the compression left a vertex 4.3 units outside the
// section that neither a snap nor a merge could place, with three triangles tagged with the
// layers beside it (one at 26.8 degrees). After the refinement it goes with its triangles into
// the exterior, where their centroids lie: every triangle inside the section, every boundary
// vertex on a curve, 30 degrees. The layer itself is lost, and named.
TEST(MesherTest, AVertexLeftOutsideTheModelGoesWithItsTrianglesIntoTheExterior)
{
  const auto [raw, r] = madeByDefault("vanishing_layer_section.vtp");
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    const auto& tri = r.triangles[t];
    const Vec2 g =
      (1.0 / 3.0) * (r.points[tri[0]] + r.points[tri[1]] + r.points[tri[2]]) + r.origin;
    ASSERT_TRUE(g.x > 0.0 && g.x < 1000.0 && g.y > 0.0 && g.y < 100.0)
      << "triangle " << t << " at (" << g.x << ", " << g.y << ")";
  }
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * 1000.0);
  EXPECT_GE(r.summary.minAngle, 30.0 - 0.05);
  ASSERT_EQ(r.unresolvedRegions.size(), 1u);
  EXPECT_EQ(r.unresolvedRegions.front(), 1);
  const std::string warnings = allWarnings(r);
  EXPECT_EQ(warnings.find("could not be placed on a curve"), std::string::npos) << warnings;
}

// Ten layers pinching out at one point of a section's base, 0.66 to 3.07 degrees apart
// (fan_apex_section.vtp, fan002 of random_junction_models.py 0 8). At LocalMaxLevel 18 the mesh
// made once has a triangle whose smallest angle sits on the apex, a sharp input corner that
// forces it, and triangles near the apex that no corner forces, down to 15.88 degrees. Those
// still miss the angle, and the finer levels go on: the mesh 2 levels finer is kept for its
// larger smallest angle off the corners (18.96 degrees), with its boundary within half a local
// edge (0.35). Until 2026-12-07 a triangle at a sharp corner hid the mesh's other angle misses
// from ThinLayerRetry, and the mesh at 18 was kept. Since 2026-12-07's sixty-third session the
// mesh at 18 without ThinLayerRefinement is seen to be more than a local edge off (1.03; the
// mesher said 0.88 before), so the one with it (10.54 degrees) stands for that level and is not
// kept over the mesh at 14 (14.45 degrees), which still misses the angle: the next level is made
// all the same.
TEST(MesherTest, ATriangleAtASharpCornerDoesNotHideTheAngleMissesAwayFromIt)
{
  const auto [raw, r] = madeByDefault("fan_apex_section.vtp");
  EXPECT_EQ(r.summary.localMaxLevel, 20);
  EXPECT_GT(r.summary.minAngleUnforced, 18.0);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.5);
  EXPECT_LE(r.summary.maxRegionMisplacedArea, 0.005);
  expectWarningsSay(r,
    { "at LocalMaxLevel 18 (smallest 10.54 degrees off the sharp input corners,",
      "; the first one is kept, but it had triangles below 25 degrees (smallest 14.45), so it was "
      "made again at LocalMaxLevel 20",
      "the third one is kept" });
}

// Nine horizons fanning out from one point of a section's base (fanned_pinch_outs_section.vtp,
// fan047 of random_junction_models.py 24 48). At LocalMaxLevel 20 the mesh made without
// ThinLayerRefinement gives a piece of a layer about 6 finest edges wide near the apex to its
// neighbour: its boundary lies 2.31 local edges off the curves, beyond issue 4's bound of one
// local edge, for a smallest angle of 22.15 degrees; the mesh with ThinLayerRefinement keeps the
// piece (0.51 local edges) at 19.39 degrees. Both are below 25 degrees, and since 2026-12-07 a
// boundary more than a local edge off is a hard miss too: the second mesh is kept (until then
// the first was, for its larger smallest angle).
TEST(MesherTest, ALargerSmallestAngleDoesNotBuyAPieceOfALayerLost)
{
  const auto [raw, r] = madeByDefault("fanned_pinch_outs_section.vtp");
  EXPECT_EQ(r.summary.localMaxLevel, 20);
  EXPECT_TRUE(r.summary.thinLayerMesh);
  EXPECT_LE(r.summary.maxRelativeDeviation, 1.0);
  EXPECT_GT(r.summary.minAngleUnforced, 19.0);
  EXPECT_LE(r.summary.maxRegionMisplacedArea, 0.005);
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * 1.2);
  expectWarningsSay(r,
    { "the mesh without ThinLayerRefinement missed the angle, area or boundary bound",
      "boundary deviation 2.3050 local edges), so a mesh with ThinLayerRefinement was made too",
      "; the second one is kept" });
}

// A disc cut into 11 sectors at its centre, six of them 1.8 to 4.2 degrees wide
// (eleven_sector_pie.vtp, pie007 of random_junction_models.py 7 8). At LocalMaxLevel 17 the mesh
// made once loses pieces of the narrow sectors near the centre: its boundary lies 1.27 local
// edges off the curves by the mesher's measure, 1.38 by the quality table's. Until 2026-12-07's
// sixty-third session the mesher said 0.91: between two curve samples its search stopped at the
// first one above half a local edge, so above 0.5 its figure was the samples' largest. It now
// goes on while a point between may be beyond one local edge (issue 4's bound, a hard bound of
// ThinLayerRetry).
TEST(MesherTest, TheBoundaryFigureTellsABoundaryMoreThanALocalEdgeOff)
{
  const auto [raw, once] = madeOnce("eleven_sector_pie.vtp");
  EXPECT_EQ(once.summary.localMaxLevel, 17);
  EXPECT_GT(once.summary.maxRelativeDeviation, 1.2);
  EXPECT_LT(once.summary.maxRelativeDeviation, 1.4);
  const std::string warnings = allWarnings(once);
  EXPECT_NE(warnings.find("the mesh's boundary lies 1.2"), std::string::npos) << warnings;
}

// The same disc by default: the mesh at LocalMaxLevel 17 (the one with ThinLayerRefinement
// around the misses, 0.98 local edges off) still misses half a local edge; the mesh 4 levels
// finer (0.89) is not kept, its smallest angle smaller (26.92 against 28.45 degrees). Since
// 2026-12-07's sixty-third session the kept mesh still missing a bound leads on to the next
// level all the same (2 levels finer again), and that one is kept: 0.003 local edges, 29.24
// degrees. Until then a finer mesh not kept ended the levels.
TEST(MesherTest, AFinerMeshNotKeptDoesNotEndTheLevelsWhileTheKeptOneMisses)
{
  const auto [raw, r] = madeByDefault("eleven_sector_pie.vtp");
  expectKeptLevelMeetsTheBounds(raw, r, 23, 29.0);
  expectWarningsSay(r,
    { "the mesh at LocalMaxLevel 17 had its boundary",
      "so it was made again at LocalMaxLevel 21 (",
      "; the first one is kept, but it had its boundary",
      "so it was made again at LocalMaxLevel 23 (",
      "; the third one is kept" });
}

// Eight horizons fanning out from one point of a section's base (eight_horizon_fan_section.vtp,
// fan005 of random_junction_models.py 5 6). The mesh at LocalMaxLevel 18 (26.39 degrees) has its
// boundary 1.27 local edges off near the fan's point, beyond issue 4's bound; the one 2 levels
// finer is still 1.13 off (26.06 degrees) and not kept. Since 2026-12-07's sixty-third session a
// kept mesh still beyond that bound after this step leads to one level more, 2 levels finer
// again: at 22 the boundary is within 0.001 local edges, at 25.27 degrees, and that mesh, which
// misses none of the hard bounds, is kept. Until then the mesh at 18 was.
TEST(MesherTest, ABoundaryStillMoreThanALocalEdgeOffLeadsToOneLevelMore)
{
  const auto [raw, r] = madeByDefault("eight_horizon_fan_section.vtp");
  expectKeptLevelMeetsTheBounds(raw, r, 22, 25.0);
  expectWarningsSay(r,
    { "so it was made again at LocalMaxLevel 20 (",
      "; the second one is kept, but it had its boundary 1.2721 local edges off",
      "so it was made again at LocalMaxLevel 22 (",
      "; the fourth one is kept" });
}

// A body with eleven teeth 0.056 wide (2.6 finest edges) in a box (astride_teeth_comb.vtp,
// comb603 of random_junction_models.py 603 604). The grid's vertical lines run inside the teeth,
// so that no grid triangle holds both sides of one: the mesh made once cuts a tooth (1.15 local
// edges off). Until the sixty-seventh session the thin layer refinement did not see the teeth
// either (a layer had to cross a triangle), its mesh cut one too (1.92 local edges off), and so
// did the meshes 4, 6 and 8 levels finer (10.8-13.1 degrees): the first was kept. It now refines
// beside a layer as well: that mesh keeps every tooth whole, within 0.02 local edges, at 30
// degrees, and no finer level is made.
TEST(MesherTest, ACombsTeethAstrideTheGridLinesAreKeptWhole)
{
  const auto [raw, r] = madeByDefault("astride_teeth_comb.vtp");
  EXPECT_TRUE(r.summary.thinLayerMesh);
  EXPECT_TRUE(r.brokenRegions.empty()) << allWarnings(r);
  EXPECT_LE(r.summary.maxRelativeDeviation, 0.1);
  EXPECT_GE(r.summary.minAngle, 30.0 - 0.05);
  EXPECT_LE(r.summary.maxRegionMisplacedArea, 0.005);
  EXPECT_LE(r.summary.maxBoundaryVertexDistance, 1e-9 * strata::buildModel(raw).size());
  EXPECT_EQ(discardedLevelRuns(r), 0) << allWarnings(r);
  expectWarningsSay(r,
    { "1 regions cut, boundary deviation 1.1523 local edges), so a mesh with ThinLayerRefinement "
      "was made too",
      "; the second one is kept" });
}

// Layers a finest edge thick where they end in each other (aliased_layers_section.vtp,
// LocalMaxLevel 14 automatic): the mesh made once keeps triangles below 25 degrees that no input
// corner forces (7.9 degrees). They are counted (those whose smallest angle sits on a model
// corner sharper than 25 degrees apart, in TrianglesAtSharpCorners), and a warning names the
// worst one's angle, region and place (its centroid, input coordinates). ThinLayerRetry (default)
// makes the mesh again with LocalMaxLevel 4 levels finer and keeps it (28.3 degrees: one triangle
// below 30, named); a LocalMaxLevel the user set is kept as set.
TEST(MesherTest, TrianglesLeftBelowTheBoundAreNamedAndAFinerLevelMendsThem)
{
  const auto [raw, r] = madeOnce("aliased_layers_section.vtp");
  const strata::MesherParams once;
  ASSERT_LT(r.summary.minAngle, 25.0);
  std::size_t below = 0, worst = 0;
  for (std::size_t t = 0; t < r.minAngle.size(); ++t)
  {
    below += r.minAngle[t] < once.refinement.minimumAngle - 0.05;
    worst = r.minAngle[t] < r.minAngle[worst] ? t : worst;
  }
  // (Every triangle at a sharp corner is below 25 degrees, so among them.)
  ASSERT_LE(r.summary.trianglesAtSharpCorners, below);
  below -= r.summary.trianglesAtSharpCorners;
  EXPECT_GT(below, 0u);
  EXPECT_EQ(r.summary.trianglesBelowMinimumAngle, below);
  const std::string warnings = allWarnings(r);
  const auto& tri = r.triangles[worst];
  const Vec2 g = (1.0 / 3.0) * (r.points[tri[0]] + r.points[tri[1]] + r.points[tri[2]]) + r.origin;
  char expected[160];
  std::snprintf(expected,
    sizeof(expected),
    "%zu triangles stay below MinimumAngle (30 degrees) with no input corner forcing them: the "
    "smallest angle, %.2f degrees, is in region %d at (%.9g, %.9g)",
    below,
    r.minAngle[worst],
    r.regionId[worst],
    g.x,
    g.y);
  EXPECT_NE(warnings.find(expected), std::string::npos) << expected << "\n" << warnings;

  const strata::MesherResult d = strata::triangulate(raw);
  EXPECT_EQ(d.summary.localMaxLevel, r.summary.localMaxLevel + 4);
  EXPECT_GE(d.summary.minAngle, 28.0);
  std::size_t dBelow = 0;
  for (double angle : d.minAngle)
  {
    dBelow += angle < 29.95;
  }
  EXPECT_EQ(d.summary.trianglesBelowMinimumAngle, dBelow);
  EXPECT_LT(dBelow, below);
  EXPECT_NE(allWarnings(d).find("had triangles below 25 degrees"), std::string::npos)
    << allWarnings(d);
  EXPECT_NE(allWarnings(d).find("the finer one is kept"), std::string::npos) << allWarnings(d);

  strata::MesherParams set;
  set.grid.localMaxLevel = r.summary.localMaxLevel;
  const strata::MesherResult s = strata::triangulate(raw, set);
  EXPECT_EQ(s.summary.localMaxLevel, r.summary.localMaxLevel);
  EXPECT_EQ(allWarnings(s).find("made again at LocalMaxLevel"), std::string::npos);

  // A mesh that meets the bound says nothing of the kind.
  const strata::MesherResult salt =
    strata::triangulate(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")));
  EXPECT_EQ(salt.summary.trianglesBelowMinimumAngle, 0u);
  EXPECT_EQ(allWarnings(salt).find("stay below MinimumAngle"), std::string::npos);
}

// Above 30 degrees Delaunay refinement may cascade into worse triangles than it leaves toward
// 30: on interior_pair_countries.vtp, MinimumAngle 31 leaves the mesh at 22.37 degrees (where
// 30 gives 30.00), below issue 5's 25 (geology_marmousi.vtp at 32 was left at 24.22 until the
// fifty-fourth session's merges). A mesh that misses a bound of the meshes at 30 degrees is
// then made again with the refinement toward 30 and kept when it misses fewer: the default's
// mesh, its triangles below 31 counted and named, the choice in a warning. Where the bound
// asked for is reached within the bounds (lake_superior.vtp at 32 degrees), the mesh is made
// once.
TEST(MesherTest, AnAngleAboveThirtyIsNotBoughtWithTrianglesWorseThanThirtyGives)
{
  const auto [raw, byDefault] = madeByDefault("interior_pair_countries.vtp");
  strata::MesherParams p;
  p.refinement.minimumAngle = 31.0;
  const strata::MesherResult r = strata::triangulate(raw, p);
  ASSERT_GT(r.summary.triangles, 0u);
  EXPECT_GE(r.summary.minAngle, 29.95);
  EXPECT_LE(r.summary.maxAngle, 130.0);
  EXPECT_LE(r.summary.maxRegionAreaError, 0.005);
  EXPECT_EQ(r.triangles, byDefault.triangles);
  EXPECT_EQ(r.points, byDefault.points);
  EXPECT_EQ(r.regionId, byDefault.regionId);
  EXPECT_EQ(byDefault.summary.trianglesBelowMinimumAngle, 0u);
  EXPECT_GT(r.summary.trianglesBelowMinimumAngle, 0u);
  const std::string warnings = allWarnings(r);
  EXPECT_NE(warnings.find("stay below MinimumAngle (31 degrees)"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("the mesh refined toward MinimumAngle (31 degrees) missed a bound that "
                          "a mesh refined toward 30 degrees is held to (smallest angle 22.37 "
                          "degrees"),
    std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("so it was made again refined toward 30 degrees (smallest angle 30.00 "
                          "degrees"),
    std::string::npos)
    << warnings;
  EXPECT_NE(warnings.find("the second one is kept (above 30 degrees"), std::string::npos)
    << warnings;
  EXPECT_TRUE(std::any_of(r.summary.secondsPerStage.begin(),
    r.summary.secondsPerStage.end(),
    [](const auto& s) { return s.first == "discarded angle run"; }));

  const strata::RawPolylines lake =
    strata_test::readVtpAscii(strata_test::dataPath("lake_superior.vtp"));
  strata::MesherParams p32;
  p32.refinement.minimumAngle = 32.0;
  const strata::MesherResult reached = strata::triangulate(lake, p32);
  EXPECT_GE(reached.summary.minAngle, 32.0 - 0.05);
  EXPECT_EQ(allWarnings(reached).find("made again refined toward"), std::string::npos)
    << allWarnings(reached);
}

// The choice between the mesh toward a MinimumAngle above 30 and the one made again toward 30,
// on the figures of the meshes met in the sweeps: each bound of the meshes at 30 counts once
// (the region bounds and the boundary only with the automatic sizes); the mesh toward 30 is
// kept when it misses fewer (Marmousi at 32 until the fifty-fourth session's merges), or as
// many with a larger smallest angle, or as many with as large an angle and a smaller area
// error (m215 of random_sections.py 204 216 at 32: both cut a layer, 29.81% of its area lost
// toward 32, 1.50% toward 30), never when it has no triangle; the mesh asked for is kept
// otherwise (m313 of random_sections.py 312 324 at 33).
TEST(MesherTest, AboveThirtyTheMeshTowardThirtyIsKeptWhenItMissesFewerBoundsOrLosesLessArea)
{
  const double offCurve = 1e-9;
  const auto mesh = [](double angle, double areaError, int cut, double deviation)
  {
    strata::MesherResult r;
    r.summary.triangles = 1000;
    r.summary.minAngle = angle;
    r.summary.minAngleUnforced = angle;
    r.summary.maxRegionAreaError = areaError;
    r.summary.maxRelativeDeviation = deviation;
    r.summary.maxBoundaryVertexDistance = 0.0;
    for (int i = 0; i < cut; ++i)
    {
      r.brokenRegions.push_back(i);
    }
    return r;
  };
  using strata::boundsMissedAtThirty;
  using strata::keepsTheMeshTowardThirty;
  EXPECT_EQ(boundsMissedAtThirty(mesh(32.0, 0.001, 0, 0.3), true, offCurve), 0);
  EXPECT_EQ(boundsMissedAtThirty(mesh(29.96, 0.001, 0, 0.3), true, offCurve), 0);
  EXPECT_EQ(boundsMissedAtThirty(mesh(29.9, 0.001, 0, 0.3), true, offCurve), 1);
  EXPECT_EQ(boundsMissedAtThirty(mesh(24.22, 0.0002, 0, 1.33), true, offCurve), 2);
  EXPECT_EQ(boundsMissedAtThirty(mesh(32.0, 0.2981, 1, 0.99), true, offCurve), 3);
  EXPECT_EQ(boundsMissedAtThirty(mesh(32.0, 0.2981, 1, 0.99), false, offCurve), 1);
  strata::MesherResult off = mesh(32.0, 0.001, 0, 0.3);
  off.summary.maxBoundaryVertexDistance = 1e-6;
  EXPECT_EQ(boundsMissedAtThirty(off, false, offCurve), 1);
  strata::MesherResult lost = mesh(32.0, 0.001, 0, 0.3);
  lost.unresolvedRegions.push_back(3);
  EXPECT_EQ(boundsMissedAtThirty(lost, true, offCurve), 1);
  EXPECT_EQ(boundsMissedAtThirty(lost, false, offCurve), 0);

  // Marmousi at 32: the angle and the boundary missed toward 32, nothing toward 30.
  EXPECT_TRUE(keepsTheMeshTowardThirty(
    mesh(24.22, 0.0002, 0, 1.33), mesh(30.0, 0.0002, 0, 0.45), true, offCurve));
  // m215 at 32: as many misses, the angles tied up to 30, the area decides.
  EXPECT_TRUE(keepsTheMeshTowardThirty(
    mesh(32.0, 0.2981, 1, 0.99), mesh(30.0, 0.0150, 1, 0.96), true, offCurve));
  // m313 at 33: as many misses, the angles tied, a larger area error toward 30.
  EXPECT_FALSE(keepsTheMeshTowardThirty(
    mesh(33.0, 0.0007, 1, 0.61), mesh(30.0, 0.0013, 1, 0.60), true, offCurve));
  // As many misses, a larger angle toward 30 (by more than 0.05 degrees) whatever the area.
  EXPECT_TRUE(
    keepsTheMeshTowardThirty(mesh(26.0, 0.001, 0, 0.3), mesh(28.0, 0.002, 0, 0.3), true, offCurve));
  EXPECT_FALSE(keepsTheMeshTowardThirty(
    mesh(26.0, 0.001, 0, 0.3), mesh(26.04, 0.002, 0, 0.3), true, offCurve));
  // More misses toward 30 (the area, a region cut, the boundary against the angle and the
  // area): the mesh asked for stays, whatever the angles; with the sizes the user set, the cut
  // and the boundary are no misses, and the mesh toward 30 misses fewer.
  EXPECT_FALSE(
    keepsTheMeshTowardThirty(mesh(26.0, 0.01, 0, 0.3), mesh(30.0, 0.01, 1, 0.9), true, offCurve));
  EXPECT_TRUE(
    keepsTheMeshTowardThirty(mesh(26.0, 0.01, 0, 0.3), mesh(30.0, 0.01, 1, 0.9), false, offCurve));
  strata::MesherResult empty = mesh(30.0, 0.0, 0, 0.0);
  empty.summary.triangles = 0;
  EXPECT_FALSE(keepsTheMeshTowardThirty(mesh(24.0, 0.001, 0, 0.3), empty, true, offCurve));
}
