// Tests of the compression (paper Section 6): rails, restrain, junctions, flips, push
// criteria, and the invariants of a compressed grid.
#include "Compression.h"
#include "Errors.h"
#include "Quality.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>

namespace
{
using strata::Vec2;

// A closed loop of region 0 (Loops form).
strata::RawPolylines loop(const strata::LargeVector<Vec2>& points)
{
  strata::RawPolylines raw;
  raw.points.assign(points.begin(), points.end());
  raw.offsets = { 0, static_cast<std::int64_t>(points.size()) + 1 };
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    raw.connectivity.push_back(static_cast<std::int64_t>(i));
  }
  raw.connectivity.push_back(0);
  raw.regionId = { 0 };
  raw.form = strata::ModelForm::Loops;
  return raw;
}

strata::RawPolylines square(double side)
{
  return loop({ { 0, 0 }, { side, 0 }, { side, side }, { 0, side } });
}

// An irregular polygon (a "blob") with 40 vertices.
strata::RawPolylines blob()
{
  strata::LargeVector<Vec2> p;
  for (int i = 0; i < 40; ++i)
  {
    const double a = 2.0 * 3.14159265358979323846 * i / 40.0;
    const double r = 10.0 + 2.0 * std::sin(3.0 * a) + std::cos(7.0 * a);
    p.push_back({ r * std::cos(a), r * std::sin(a) });
  }
  return loop(p);
}

// Model -> field -> grid -> classification, ready for compress().
struct Pipeline
{
  std::unique_ptr<strata::Model> model;
  std::unique_ptr<strata::DistanceField> field;
  strata::TriangleMesh mesh;
  strata::Classification cls;

  Pipeline(const strata::RawPolylines& raw, int maxLevel)
  {
    this->model = std::make_unique<strata::Model>(strata::buildModel(raw));
    this->field = std::make_unique<strata::DistanceField>(*this->model);
    strata::Grid48Params gp;
    gp.maxLevel = maxLevel;
    this->mesh = strata::Grid48::build(*this->model, *this->field, gp).extract();
    this->cls = strata::classify(this->mesh, *this->model, *this->field);
  }

  strata::CompressionResult run(const strata::CompressionParams& p = {}) const
  {
    return strata::compress(this->mesh, this->cls, *this->model, *this->field, p);
  }

  double boundaryDistance(Vec2 p) const
  {
    static thread_local strata::StripTreeScratch scratch;
    const strata::BoundaryRails rails(*this->model, 0.0);
    double d = 0.0;
    rails.closest(p, scratch, &d);
    return d;
  }
};

std::size_t nonPositive(const strata::CompressionResult& r)
{
  std::size_t n = 0;
  for (const auto& t : r.triangles)
  {
    n += !(strata::orient2d(r.points[t[0]], r.points[t[1]], r.points[t[2]]) > 0.0);
  }
  return n;
}
} // namespace

TEST(CompressionTest, RailsOfASquareAreOneClosedChainWithFeatureCorners)
{
  const strata::Model m = strata::buildModel(square(10.0));
  const strata::BoundaryRails rails(m, 140.0);
  ASSERT_EQ(rails.numberOfChains(), 1u);
  const strata::BoundaryRails::Chain& c = rails.chain(0);
  EXPECT_TRUE(c.closed);
  EXPECT_EQ(c.points.size(), 4u);
  EXPECT_EQ(c.left == 0 || c.right == 0, true);
  EXPECT_EQ(c.left == -1 || c.right == -1, true);
  for (std::uint8_t f : c.feature)
  {
    EXPECT_EQ(f, 1); // 90 degree corners are sharper than 140
  }
  const strata::BoundaryRails none(m, 0.0);
  for (std::uint8_t f : none.chain(0).feature)
  {
    EXPECT_EQ(f, 0);
  }
}

TEST(CompressionTest, RailsOfSharedCurvesEndAtJunctions)
{
  const strata::Model m =
    strata::buildModel(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")));
  const strata::BoundaryRails rails(m, 140.0);
  strata::LargeVector<int> isJunction(m.nodes.size(), 0);
  for (int j : m.junctions)
  {
    isJunction[j] = 1;
  }
  for (std::size_t ci = 0; ci < rails.numberOfChains(); ++ci)
  {
    const strata::BoundaryRails::Chain& c = rails.chain(static_cast<int>(ci));
    EXPECT_NE(c.left, c.right);
    for (std::size_t i = 0; i < c.nodes.size(); ++i)
    {
      const bool end = !c.closed && (i == 0 || i + 1 == c.nodes.size());
      EXPECT_EQ(isJunction[c.nodes[i]] == 1, end) << "chain " << ci << " point " << i;
    }
  }
}

TEST(CompressionTest, EveryChainPointOfANodeIsFoundAtThatNode)
{
  // salt_dome: junctions on three or more chains, curve vertices on one, closed chains.
  const strata::Model m =
    strata::buildModel(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")));
  const strata::BoundaryRails rails(m, 140.0);
  std::vector<std::size_t> onChains(m.nodes.size(), 0);
  for (std::size_t ci = 0; ci < rails.numberOfChains(); ++ci)
  {
    for (const int node : rails.chain(static_cast<int>(ci)).nodes)
    {
      ++onChains[node];
    }
  }
  std::size_t junctionLocations = 0;
  for (std::size_t node = 0; node < m.nodes.size(); ++node)
  {
    const auto locations = rails.locationsOfNode(static_cast<int>(node));
    ASSERT_EQ(locations.size(), onChains[node]) << "node " << node;
    for (const strata::BoundaryRails::Location& l : locations)
    {
      const int point = rails.pointAt(l);
      ASSERT_GE(point, 0) << "node " << node;
      EXPECT_EQ(rails.chain(l.chain).nodes[point], static_cast<int>(node));
      EXPECT_EQ(strata::norm(rails.position(l) - m.nodes[node]), 0.0);
    }
    junctionLocations += locations.size() > 1 ? locations.size() : 0;
  }
  EXPECT_GE(junctionLocations, 3u * m.junctions.size());
  EXPECT_TRUE(rails.locationsOfNode(-1).empty());
  EXPECT_TRUE(rails.locationsOfNode(static_cast<int>(m.nodes.size())).empty());
}

TEST(CompressionTest, ClosestRailPointIsExact)
{
  const strata::Model m = strata::buildModel(blob());
  const strata::BoundaryRails rails(m, 140.0);
  strata::StripTreeScratch scratch;
  const strata::Ring& ring = m.regions[0].rings[0];
  for (int k = 0; k < 200; ++k)
  {
    const Vec2 p{ -15.0 + 0.15 * k, 7.0 * std::sin(0.37 * k) };
    double d = 0.0;
    const strata::BoundaryRails::Location l = rails.closest(p, scratch, &d);
    double brute = HUGE_VAL;
    for (std::size_t i = 0; i < ring.points.size(); ++i)
    {
      brute = std::min(brute,
        std::sqrt(strata::pointSegmentDistance2(
          p, ring.points[i], ring.points[(i + 1) % ring.points.size()])));
    }
    EXPECT_NEAR(d, brute, 1e-12);
    EXPECT_NEAR(strata::norm(rails.position(l) - p), brute, 1e-9);
  }
}

TEST(CompressionTest, SlidingFollowsThePolylineAndStopsAtFeatures)
{
  const strata::Model m = strata::buildModel(square(10.0));
  const strata::BoundaryRails rails(m, 140.0);
  strata::StripTreeScratch scratch;
  // Local coordinates: the square is [-5, 5]^2.
  const strata::BoundaryRails::Location start = rails.closest({ 0.0, -6.0 }, scratch);
  const Vec2 p0 = rails.position(start);
  EXPECT_NEAR(p0.x, 0.0, 1e-12);
  EXPECT_NEAR(p0.y, -5.0, 1e-12);
  // Two units along the side: still on it, two units away.
  const strata::BoundaryRails::Slide a = rails.slide(start, 2.0);
  EXPECT_FALSE(a.stopped);
  EXPECT_NEAR(strata::norm(rails.position(a.location) - p0), 2.0, 1e-12);
  // Twenty units: stops at the corner (a feature), which it does not pass.
  const strata::BoundaryRails::Slide b = rails.slide(start, 20.0);
  EXPECT_TRUE(b.stopped);
  EXPECT_NEAR(strata::norm(rails.position(b.location) - p0), 5.0, 1e-12);
  EXPECT_GE(rails.pointAt(b.location), 0);
  // Without features the slide goes round the corner and stays on the boundary.
  const strata::BoundaryRails smooth(m, 0.0);
  const strata::BoundaryRails::Slide c = smooth.slide(smooth.closest({ 0.0, -6.0 }, scratch), 7.0);
  EXPECT_FALSE(c.stopped);
  double d = 0.0;
  smooth.closest(smooth.position(c.location), scratch, &d);
  EXPECT_NEAR(d, 0.0, 1e-12);
}

TEST(CompressionTest, RestrainTestRefusesInversionAndCollapse)
{
  // Vertex 0 above the edge 1-2.
  const strata::LargeVector<Vec2> p = { { 0.5, 1.0 }, { 1.0, 0.0 }, { 0.0, 0.0 } };
  const strata::LargeVector<std::array<int, 3>> t = { { 0, 2, 1 } }; // counter-clockwise
  const int star[1] = { 0 };
  EXPECT_TRUE(strata::restrainAccepts(p, t, star, 1, 0, { 0.7, 0.5 }));
  EXPECT_FALSE(strata::restrainAccepts(p, t, star, 1, 0, { 0.5, -0.1 })); // crosses the edge
  EXPECT_FALSE(strata::restrainAccepts(p, t, star, 1, 0, { 3.0, 0.0 }));  // flat
  const double minTwice[1] = { 0.2 };                                     // 20% of twice 0.5
  EXPECT_FALSE(strata::restrainAccepts(p, t, star, 1, 0, { 0.5, 0.1 }, minTwice));
  EXPECT_TRUE(strata::restrainAccepts(p, t, star, 1, 0, { 0.5, 0.3 }, minTwice));
  // Already below the threshold: moves that do not shrink it further are allowed.
  const strata::LargeVector<Vec2> low = { { 0.5, 0.1 }, { 1.0, 0.0 }, { 0.0, 0.0 } };
  EXPECT_TRUE(strata::restrainAccepts(low, t, star, 1, 0, { 0.4, 0.12 }, minTwice));
  EXPECT_FALSE(strata::restrainAccepts(low, t, star, 1, 0, { 0.4, 0.05 }, minTwice));
}

TEST(CompressionTest, FlipsRemoveDegenerateTriangles)
{
  // A square split by its diagonal 0-2, the upper half fanned from a vertex pushed almost
  // onto that diagonal: triangle 0-2-4 is a sliver; flipping its longest edge (the diagonal)
  // removes every angle below 10 degrees.
  const strata::LargeVector<Vec2> p = { { 0, 0 }, { 2, 0 }, { 2, 2 }, { 0, 2 }, { 1.0, 1.001 } };
  strata::LargeVector<std::array<int, 3>> t = {
    { 0, 1, 2 }, { 0, 2, 4 }, { 0, 4, 3 }, { 4, 2, 3 }
  };
  ASSERT_LT(strata::summarizeQuality(p, t).minAngle, 1.0);
  const std::size_t flips = strata::flipDegenerateTriangles(p, t);
  EXPECT_GE(flips, 1u);
  const strata::QualitySummary s = strata::summarizeQuality(p, t);
  EXPECT_GT(s.minAngle, 10.0);
  EXPECT_EQ(s.inverted + s.degenerate, 0u);
  EXPECT_NEAR(s.totalArea, 4.0, 1e-12); // still covers the square
}

TEST(CompressionTest, CompressionNeverInvertsATriangle)
{
  const Pipeline pipe(blob(), 9);
  for (strata::PushCriterion c : { strata::PushCriterion::AllCandidates,
         strata::PushCriterion::OneSide,
         strata::PushCriterion::Closest })
  {
    for (strata::SpringConfiguration s :
      { strata::SpringConfiguration::EdgeOnly, strata::SpringConfiguration::EdgeAndProjection })
    {
      for (bool optimize : { false, true })
      {
        strata::CompressionParams p;
        p.pushCriterion = c;
        p.springConfiguration = s;
        p.optimize = optimize;
        const strata::CompressionResult r = pipe.run(p);
        EXPECT_EQ(nonPositive(r), 0u);
        EXPECT_EQ(r.degenerateTriangles, 0u);
        EXPECT_GT(r.arrivedVertices, 0u);
      }
    }
  }
}

TEST(CompressionTest, PushCriteriaPickDifferentVertices)
{
  const Pipeline pipe(blob(), 9);
  strata::CompressionParams p;
  p.maxIterations = 0; // only the initial choice
  p.pushCriterion = strata::PushCriterion::AllCandidates;
  const std::size_t all = pipe.run(p).pushedVertices;
  p.pushCriterion = strata::PushCriterion::OneSide;
  const std::size_t oneSide = pipe.run(p).pushedVertices;
  p.pushCriterion = strata::PushCriterion::Closest;
  const std::size_t closest = pipe.run(p).pushedVertices;
  EXPECT_GT(all, oneSide);
  EXPECT_GT(all, closest);
  EXPECT_GT(oneSide, 0u);
  EXPECT_GT(closest, 0u);
}

TEST(CompressionTest, RailVerticesStayOnTheirCurve)
{
  for (const char* name : { "lake_superior.vtp", "salt_dome.vtp" })
  {
    const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath(name)), 9);
    const double tolerance = 1e-9 * pipe.model->size();
    for (bool optimize : { false, true })
    {
      strata::CompressionParams p;
      p.optimize = optimize;
      const strata::CompressionResult r = pipe.run(p);
      std::size_t onCurve = 0;
      for (std::size_t i = 0; i < r.points.size(); ++i)
      {
        if (r.vertexState[i] == strata::VertexOnCurve || r.vertexState[i] == strata::VertexPinned)
        {
          ++onCurve;
          EXPECT_LE(pipe.boundaryDistance(r.points[i]), tolerance) << name << " vertex " << i;
        }
      }
      EXPECT_GT(onCurve, 100u);
    }
  }
}

// The optimization collapses vertices squeezed against a neighbour (the worst slivers): the
// two faces of the edge disappear, nothing inverts, the collapsed vertex is left unused, and
// the smallest angle is better than without the optimization's later rounds.
TEST(CompressionTest, SqueezedVerticesAreCollapsedWithoutInvertingFaces)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("geology_marmousi.vtp")), 9);
  const strata::CompressionResult r = pipe.run();
  ASSERT_GT(r.collapsedVertices, 0u);
  EXPECT_EQ(nonPositive(r), 0u);
  EXPECT_EQ(r.degenerateTriangles, 0u);
  strata::LargeVector<int> uses(r.points.size(), 0);
  for (const auto& t : r.triangles)
  {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    for (int v : t)
    {
      ++uses[v];
    }
  }
  std::size_t unused = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i)
  {
    unused += uses[i] == 0 && r.vertexState[i] != strata::VertexUntouched;
  }
  EXPECT_GE(unused, r.collapsedVertices);
  // Each undirected edge in at most two faces, in opposite directions.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : r.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::pair<int, int> edge(t[k], t[(k + 1) % 3]);
      EXPECT_EQ(++directed[edge], 1);
    }
  }
}

TEST(CompressionTest, JunctionVerticesLieExactlyOnJunctions)
{
  for (const char* name : { "salt_dome.vtp", "pinch_out.vtp", "countries_westeurope.vtp" })
  {
    const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath(name)), 9);
    ASSERT_FALSE(pipe.model->junctions.empty());
    const strata::CompressionResult r = pipe.run();
    for (int j : pipe.model->junctions)
    {
      const Vec2 q = pipe.model->nodes[j];
      int count = 0;
      for (std::size_t i = 0; i < r.points.size(); ++i)
      {
        if (r.points[i] == q)
        {
          ++count;
          EXPECT_EQ(r.vertexState[i], strata::VertexPinned);
        }
      }
      EXPECT_EQ(count, 1) << name << " junction node " << j;
    }
    EXPECT_EQ(r.junctionVertices, pipe.model->junctions.size());
  }
}

TEST(CompressionTest, RegionBoundaryVerticesEndOnCurves)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")), 10);
  const strata::CompressionResult r = pipe.run();
  EXPECT_EQ(r.offCurveBoundaryVertices, 0u);
}

TEST(CompressionTest, WithoutIterationsTheMeshIsStillValid)
{
  const Pipeline pipe(blob(), 8);
  strata::CompressionParams p;
  p.maxIterations = 0;
  const strata::CompressionResult r = pipe.run(p);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(nonPositive(r), 0u);
}

TEST(CompressionTest, RejectsParametersOutOfRangeNamingThem)
{
  const Pipeline pipe(square(10.0), 6);
  const auto message = [&](const strata::CompressionParams& p)
  {
    try
    {
      pipe.run(p);
    }
    catch (const strata::ParameterError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  strata::CompressionParams p;
  p.timeStep = 0.0;
  EXPECT_NE(message(p).find("TimeStep"), std::string::npos);
  p = {};
  p.pushVelocity = -1.0;
  EXPECT_NE(message(p).find("PushVelocity"), std::string::npos);
  p = {};
  p.featureAngle = 200.0;
  EXPECT_NE(message(p).find("FeatureAngle"), std::string::npos);
  p = {};
  p.maxIterations = -1;
  EXPECT_NE(message(p).find("MaxIterations"), std::string::npos);
  p = {};
  p.springStiffness = 0.0;
  EXPECT_NE(message(p).find("SpringStiffness"), std::string::npos);
  p = {};
  p.damping = -0.1;
  EXPECT_NE(message(p).find("Damping"), std::string::npos);
  p = {};
  p.pushCriterion = static_cast<strata::PushCriterion>(7);
  EXPECT_NE(message(p).find("PushCriterion"), std::string::npos);
  p = {};
  p.springConfiguration = static_cast<strata::SpringConfiguration>(3);
  EXPECT_NE(message(p).find("SpringConfiguration"), std::string::npos);
  p = {};
  p.boundaryTolerance = -0.5;
  EXPECT_NE(message(p).find("BoundaryTolerance"), std::string::npos);
}

// Boundary refinement splits boundary edges onto their curve: each split adds one vertex,
// on the curve, and two triangles; no triangle inverts; off (0) it splits nothing.
TEST(CompressionTest, BoundaryRefinementInsertsVerticesOnTheCurves)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("lake_superior.vtp")), 9);
  const double tolerance = 1e-9 * pipe.model->size();
  const strata::CompressionResult r = pipe.run();
  ASSERT_GT(r.boundarySplits, 0u);
  EXPECT_EQ(r.firstInsertedPoint, pipe.mesh.points.size());
  // Each boundary split and each angle-refinement split adds one vertex and two faces; each
  // collapse removes two faces (the vertex stays, unused).
  EXPECT_EQ(r.points.size(), r.firstInsertedPoint + r.boundarySplits + r.angleVertices);
  EXPECT_EQ(r.triangles.size() + 2 * r.collapsedVertices,
    pipe.mesh.triangles.size() + 2 * (r.boundarySplits + r.angleVertices));
  EXPECT_EQ(r.triangleRegion.size(), r.triangles.size());
  EXPECT_EQ(r.vertexState.size(), r.points.size());
  EXPECT_EQ(nonPositive(r), 0u);
  strata::LargeVector<std::uint8_t> used(r.points.size(), 0);
  for (const auto& t : r.triangles)
  {
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  std::size_t onCurve = 0, free = 0;
  for (std::size_t i = r.firstInsertedPoint; i < r.points.size(); ++i)
  {
    if (r.vertexState[i] == strata::VertexFree || !used[i])
    {
      ++free;
      continue;
    }
    ++onCurve;
    EXPECT_TRUE(
      r.vertexState[i] == strata::VertexOnCurve || r.vertexState[i] == strata::VertexPinned);
    EXPECT_LE(pipe.boundaryDistance(r.points[i]), tolerance) << "inserted vertex " << i;
  }
  // Angle refinement may split boundary edges too (on the curve), so at least the boundary
  // refinement's vertices are on curves; the free ones are angle refinement's.
  EXPECT_GE(onCurve, r.boundarySplits);
  EXPECT_LE(free, r.angleVertices);
  // Where the curve runs beyond the opposite face (an inlet deeper than a triangle), that
  // face's free vertex is moved onto the curve instead: the countries' coasts have such inlets.
  const Pipeline coasts(
    strata_test::readVtpAscii(strata_test::dataPath("countries_westeurope.vtp")), 10);
  const strata::CompressionResult rc = coasts.run();
  EXPECT_GT(rc.bulgeVertices, 0u);
  EXPECT_EQ(nonPositive(rc), 0u);
  for (std::size_t i = 0; i < rc.points.size(); ++i)
  {
    if (rc.vertexState[i] == strata::VertexOnCurve || rc.vertexState[i] == strata::VertexPinned)
    {
      EXPECT_LE(coasts.boundaryDistance(rc.points[i]), 1e-9 * coasts.model->size()) << i;
    }
  }
  strata::CompressionParams off;
  off.boundaryTolerance = 0.0;
  const strata::CompressionResult r0 = pipe.run(off);
  EXPECT_EQ(r0.boundarySplits, 0u);
  EXPECT_EQ(r0.bulgeVertices, 0u);
  EXPECT_EQ(r0.points.size(), pipe.mesh.points.size() + r0.angleVertices);
}

TEST(CompressionTest, RejectsAClassificationOfAnotherMesh)
{
  const Pipeline a(square(10.0), 6);
  const Pipeline b(square(10.0), 8);
  EXPECT_THROW(strata::compress(a.mesh, b.cls, *a.model, *a.field), strata::ParameterError);
}

// Whether two point lists are the same, bit for bit.
::testing::AssertionResult samePoints(const strata::LargeVector<Vec2>& a,
  const strata::LargeVector<Vec2>& b)
{
  if (a.size() != b.size())
  {
    return ::testing::AssertionFailure() << a.size() << " points against " << b.size();
  }
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (!(a[i].x == b[i].x && a[i].y == b[i].y))
    {
      return ::testing::AssertionFailure() << "point " << i << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

// Whether two compressions gave the same mesh: triangles, points (bit for bit), regions, levels
// and vertex states.
void expectSameMesh(const strata::CompressionResult& r, const strata::CompressionResult& lent)
{
  ASSERT_EQ(r.triangles, lent.triangles);
  EXPECT_TRUE(samePoints(r.points, lent.points));
  EXPECT_EQ(r.triangleRegion, lent.triangleRegion);
  EXPECT_EQ(r.triangleLevel, lent.triangleLevel);
  EXPECT_EQ(r.vertexState, lent.vertexState);
}

// A classification handed over (compress(Classification&&)) gives the same mesh as one lent,
// and is left with its vertex arrays only: its face regions and edges went during the run.
TEST(CompressionTest, AHandedOverClassificationGivesTheSameMeshAndLetsItsEdgesGo)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")), 10);
  const strata::CompressionResult lent = pipe.run();
  strata::Classification handed = pipe.cls;
  ASSERT_FALSE(handed.edges.empty());
  const strata::CompressionResult r =
    strata::compress(pipe.mesh, std::move(handed), *pipe.model, *pipe.field);
  // (Read after the move on purpose: compress() documents what it leaves.)
  EXPECT_TRUE(handed.edges.empty()); // NOLINT(bugprone-use-after-move)
  EXPECT_TRUE(handed.edgeClass.empty());
  EXPECT_TRUE(handed.cellRegion.empty());
  EXPECT_EQ(handed.vertexRegion, pipe.cls.vertexRegion);
  EXPECT_EQ(handed.vertexClass, pipe.cls.vertexClass);
  expectSameMesh(r, lent);
  EXPECT_EQ(nonPositive(r), 0u);
}

// A grid handed over too (compressHandedOver) gives the same mesh, and is left with its points
// only: its triangles, levels and distances went once the sub-mesh was built. At level 10 part
// of the salt dome's grid lies outside the simulated zone, whose triangles the result keeps.
// Also for a mesh without levels or known distances (not a Grid48's).
TEST(CompressionTest, AHandedOverGridGivesTheSameMeshAndKeepsOnlyItsPoints)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp")), 10);
  for (const bool bare : { false, true })
  {
    strata::TriangleMesh mesh = pipe.mesh;
    if (bare)
    {
      mesh.triangleLevel.clear();
      mesh.pointBoundaryDistance.clear();
    }
    for (const bool optimize : { false, true })
    {
      SCOPED_TRACE(std::string(bare ? "a bare mesh, " : "the grid's mesh, ") +
        (optimize ? "with the optimization" : "without the optimization"));
      strata::CompressionParams params;
      params.optimize = optimize;
      const strata::CompressionResult lent =
        strata::compress(mesh, pipe.cls, *pipe.model, *pipe.field, params);
      strata::TriangleMesh grid = mesh;
      const strata::CompressionResult r = strata::compressHandedOver(
        grid, strata::Classification(pipe.cls), *pipe.model, *pipe.field, params);
      EXPECT_TRUE(grid.triangles.empty());
      EXPECT_TRUE(grid.triangleLevel.empty());
      EXPECT_TRUE(grid.pointBoundaryDistance.empty());
      EXPECT_TRUE(samePoints(grid.points, mesh.points));
      // Some grid triangles were outside the zone and are in the result as the grid had them.
      std::size_t kept = 0;
      for (std::size_t t = 0; t < mesh.triangles.size() && t < r.triangles.size(); ++t)
      {
        kept += r.triangles[t] == mesh.triangles[t] &&
          r.vertexState[r.triangles[t][0]] == strata::VertexUntouched;
      }
      EXPECT_GT(kept, 0u);
      expectSameMesh(r, lent);
      EXPECT_EQ(r.warnings, lent.warnings);
    }
  }
}

TEST(CompressionTest, AbortStopsTheSimulation)
{
  const Pipeline pipe(blob(), 9);
  int calls = 0;
  const strata::ProgressReporter progress([&](double, const char*) { return ++calls < 5; });
  EXPECT_THROW(
    strata::compress(pipe.mesh, pipe.cls, *pipe.model, *pipe.field, {}, progress), strata::Aborted);
  EXPECT_EQ(calls, 5);
}

// An abort at any of the set-up's progress reports (the sub-mesh's arrays, the spring system's
// blocks, the states, the pushes' targets) stops the compression with Aborted and leaves
// nothing behind: a run afterwards gives the same mesh as one before.
TEST(CompressionTest, AnAbortAnywhereInTheSetUpStopsItCleanly)
{
  const Pipeline pipe(blob(), 16);
  const strata::CompressionResult before = pipe.run();
  int setUpReports = 0; // (the set-up reports at 0; the simulation from 0.1 on)
  const strata::ProgressReporter count(
    [&](double fraction, const char*)
    {
      setUpReports += fraction < 0.1;
      return true;
    });
  strata::compress(pipe.mesh, pipe.cls, *pipe.model, *pipe.field, {}, count);
  ASSERT_GE(setUpReports, 8);
  for (int k = 1; k <= setUpReports; ++k)
  {
    int calls = 0;
    const strata::ProgressReporter stop([&](double, const char*) { return ++calls < k; });
    EXPECT_THROW(
      strata::compress(pipe.mesh, pipe.cls, *pipe.model, *pipe.field, {}, stop), strata::Aborted);
    EXPECT_EQ(calls, k);
  }
  const strata::CompressionResult after = pipe.run();
  EXPECT_EQ(after.points, before.points);
  EXPECT_EQ(after.triangles, before.triangles);
  EXPECT_EQ(after.triangleRegion, before.triangleRegion);
}

// Section 5 on a mesh large enough for the face classification's two threads (from 65536
// vertices of the sub-mesh): every face takes the region its corners off the curves agree
// on, else the region of its barycentre.
TEST(CompressionTest, FacesOfALargeMeshTakeTheirCornersOrBarycentresRegion)
{
  const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath("gulf_section.vtp")), 19);
  strata::CompressionParams params;
  params.optimize = false; // (the regions as the classification left them)
  const strata::CompressionResult r = pipe.run(params);
  ASSERT_GE(r.simulatedVertices, 65536u);
  strata::DistanceField::Scratch scratch;
  std::size_t byCorners = 0, byBarycentre = 0;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    const auto& tri = r.triangles[t];
    int agreed = -2; // none yet; -3: they differ
    for (const int v : tri)
    {
      if (r.vertexState[v] == strata::VertexOnCurve || r.vertexState[v] == strata::VertexPinned)
      {
        continue;
      }
      const int region = pipe.field->region(r.points[v], scratch);
      agreed = agreed == -2 || agreed == region ? region : -3;
    }
    const Vec2 g = (1.0 / 3.0) * (r.points[tri[0]] + r.points[tri[1]] + r.points[tri[2]]);
    const int expected = agreed >= -1 ? agreed : pipe.field->region(g, scratch);
    (agreed >= -1 ? byCorners : byBarycentre) += 1;
    ASSERT_EQ(r.triangleRegion[t], expected) << "triangle " << t;
  }
  EXPECT_GT(byCorners, 0u);
  EXPECT_GT(byBarycentre, 0u);
}

// A large mesh's simulation is split in two halves on two threads (SpringParams::splitSprings);
// forced on small meshes, the compressed mesh keeps every invariant of the serial one and
// about the same numbers.
TEST(CompressionTest, ASplitSimulationKeepsTheInvariants)
{
  for (const char* name : { "salt_dome.vtp", "lake_superior.vtp" })
  {
    SCOPED_TRACE(name);
    const Pipeline pipe(strata_test::readVtpAscii(strata_test::dataPath(name)), 10);
    strata::CompressionParams serialParams, splitParams;
    splitParams.splitSprings = 0;
    for (const bool optimize : { false, true })
    {
      serialParams.optimize = splitParams.optimize = optimize;
      const strata::CompressionResult serial = pipe.run(serialParams);
      const strata::CompressionResult r = pipe.run(splitParams);
      EXPECT_EQ(nonPositive(r), 0u);
      EXPECT_EQ(r.degenerateTriangles, 0u);
      EXPECT_EQ(r.junctionVertices, pipe.model->junctions.size());
      const double tolerance = 1e-9 * pipe.model->size();
      for (std::size_t i = 0; i < r.points.size(); ++i)
      {
        if (r.vertexState[i] == strata::VertexOnCurve || r.vertexState[i] == strata::VertexPinned)
        {
          EXPECT_LE(pipe.boundaryDistance(r.points[i]), tolerance) << "vertex " << i;
        }
      }
      EXPECT_NEAR(static_cast<double>(r.arrivedVertices),
        static_cast<double>(serial.arrivedVertices),
        0.02 * static_cast<double>(serial.arrivedVertices));
      EXPECT_NEAR(static_cast<double>(r.triangles.size()),
        static_cast<double>(serial.triangles.size()),
        0.02 * static_cast<double>(serial.triangles.size()));
    }
  }
}

// The triangles a collapse removed (all corners the vertex kept) leave the result with their
// levels and regions; the others keep their order, and the points stay.
TEST(CompressionTest, CollapsedTrianglesAreDroppedWithTheirLevelsAndRegions)
{
  strata::CompressionResult r;
  r.points = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 1, 1 } };
  r.triangles = { { 0, 1, 2 }, { 3, 3, 3 }, { 1, 3, 2 }, { 2, 2, 2 } };
  r.triangleLevel = { 5, 6, 7, 8 };
  r.triangleRegion = { 0, 1, 2, 3 };
  EXPECT_EQ(strata::dropCollapsedTriangles(r), 2u);
  const strata::LargeVector<std::array<int, 3>> kept = { { 0, 1, 2 }, { 1, 3, 2 } };
  EXPECT_EQ(r.triangles, kept);
  EXPECT_EQ(r.triangleLevel, (strata::LargeVector<int>{ 5, 7 }));
  EXPECT_EQ(r.triangleRegion, (strata::LargeVector<int>{ 0, 2 }));
  EXPECT_EQ(r.points.size(), 4u);
  EXPECT_EQ(strata::dropCollapsedTriangles(r), 0u);
  EXPECT_EQ(r.triangles, kept);
}
