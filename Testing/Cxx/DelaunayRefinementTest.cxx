// Tests of the constrained Delaunay refinement (core unit DelaunayRefinement): invariants on
// small meshes built by hand (regions kept, areas conserved, no inverted triangle, the angle
// bound reached, boundary edges kept), its floors, and its preconditions.
#include "DelaunayRefinement.h"
#include "ArcIndex.h"
#include "CallTables.h"
#include "Errors.h"
#include "Quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

using strata::RefinementParams;
using strata::RefinementResult;
using strata::RegionMesh;
using strata::Vec2;

namespace
{
constexpr double kPi = 3.14159265358979323846;

// Rows of points at the given heights, columns every dx over [0, length]; the quads between
// two rows are split into two triangles (diagonals alternating) and take the region of their
// band (band i lies between rows i and i + 1).
RegionMesh bands(const std::vector<double>& rows, double length, double dx)
{
  RegionMesh m;
  const int nx = static_cast<int>(std::lround(length / dx)) + 1;
  for (double y : rows)
  {
    for (int i = 0; i < nx; ++i)
    {
      m.points.push_back({ i * dx, y });
    }
  }
  for (std::size_t r = 0; r + 1 < rows.size(); ++r)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      const int a = static_cast<int>(r) * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      if (i % 2 == 0)
      {
        m.triangles.push_back({ a, b, c });
        m.triangles.push_back({ a, c, d });
      }
      else
      {
        m.triangles.push_back({ a, b, d });
        m.triangles.push_back({ b, c, d });
      }
      m.region.insert(m.region.end(), 2, static_cast<int>(r));
      m.level.insert(m.level.end(), 2, 0);
    }
  }
  return m;
}

// Straight boundaries: every boundary edge is split at its middle.
bool middle(Vec2 a, Vec2 b, int, int, Vec2& at)
{
  at = 0.5 * (a + b);
  return true;
}

double area(const RegionMesh& m, std::size_t t)
{
  const auto& tri = m.triangles[t];
  return 0.5 * strata::orient2d(m.points[tri[0]], m.points[tri[1]], m.points[tri[2]]);
}

double smallestAngle(const RegionMesh& m, std::size_t t)
{
  const auto& tri = m.triangles[t];
  const auto angles = strata::triangleAngles(m.points[tri[0]], m.points[tri[1]], m.points[tri[2]]);
  return std::min({ angles[0], angles[1], angles[2] });
}

double meshMinimumAngle(const RegionMesh& m)
{
  double worst = 180.0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    worst = std::min(worst, smallestAngle(m, t));
  }
  return worst;
}

std::map<int, double> regionAreas(const RegionMesh& m)
{
  std::map<int, double> a;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    a[m.region[t]] += area(m, t);
  }
  return a;
}

// Directed edges of the mesh: each at most once (a consistently oriented manifold).
std::map<std::pair<int, int>, std::size_t> directedEdges(const RegionMesh& m)
{
  std::map<std::pair<int, int>, std::size_t> edges;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::pair<int, int> e(m.triangles[t][k], m.triangles[t][(k + 1) % 3]);
      EXPECT_EQ(edges.count(e), 0u) << "edge " << e.first << "-" << e.second << " twice";
      edges[e] = t;
    }
  }
  return edges;
}

// Unconstrained edges (same region on both sides) that are not Delaunay: the opposite vertex
// of the other triangle inside the circumcircle (in-circle determinant above 1e-9 of the
// squared edge length squared).
std::size_t notDelaunayEdges(const RegionMesh& m)
{
  std::size_t count = 0;
  const auto edges = directedEdges(m);
  for (const auto& [e, t] : edges)
  {
    const auto back = edges.find({ e.second, e.first });
    if (back == edges.end() || m.region[back->second] != m.region[t])
    {
      continue;
    }
    const auto& tri = m.triangles[t];
    const auto& other = m.triangles[back->second];
    const Vec2 q = m.points[other[0] + other[1] + other[2] - e.first - e.second];
    const Vec2 a = m.points[tri[0]], b = m.points[tri[1]], c = m.points[tri[2]];
    const Vec2 ad = a - q, bd = b - q, cd = c - q;
    const double det = strata::norm2(ad) * strata::cross(bd, cd) +
      strata::norm2(bd) * strata::cross(cd, ad) + strata::norm2(cd) * strata::cross(ad, bd);
    count += det > 1e-9 * std::pow(strata::norm2(b - a), 2);
  }
  return count;
}

// Region boundary edges (undirected, as point pairs) of the mesh.
std::set<std::pair<int, int>> boundaryEdges(const RegionMesh& m)
{
  const auto edges = directedEdges(m);
  std::set<std::pair<int, int>> out;
  for (const auto& [e, t] : edges)
  {
    const auto back = edges.find({ e.second, e.first });
    if (back == edges.end() || m.region[back->second] != m.region[t])
    {
      out.insert({ std::min(e.first, e.second), std::max(e.first, e.second) });
    }
  }
  return out;
}

// A 10-degree spike of region 1 (0, 0), (10, 0), (10, 10 tan 10 degrees) between region 0
// above and region `below` beneath, and a second piece of region 1 of area secondArea (a
// right triangle) away from it.
RegionMesh spike10(double secondArea, int below)
{
  const double tip = 10.0 * std::tan(10.0 * kPi / 180.0);
  RegionMesh m;
  m.points = { { 0, 0 }, { 10, 0 }, { 10, tip }, { 0, 10 }, { 10, 10 }, { 5, -10 } };
  m.triangles = { { 0, 1, 2 }, { 0, 2, 4 }, { 0, 4, 3 }, { 0, 5, 1 } };
  m.region = { 1, 0, 0, below };
  const double side = std::sqrt(2.0 * secondArea); // a right triangle of that area
  m.points.insert(m.points.end(), { { 20, 0 }, { 20 + side, 0 }, { 20, side } });
  m.triangles.push_back({ 6, 7, 8 });
  m.region.push_back(1);
  m.level.assign(m.triangles.size(), 0);
  return m;
}

void expectValid(const RegionMesh& m)
{
  ASSERT_EQ(m.region.size(), m.triangles.size());
  ASSERT_EQ(m.level.size(), m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    EXPECT_GT(area(m, t), 0.0) << "triangle " << t << " is not counter-clockwise";
  }
  directedEdges(m);
}
} // namespace

// A layer 1 thick between two 10 thick ones, meshed with 10-long strip triangles (5.7
// degrees): refined to 30 degrees everywhere, each triangle in its band, each band's area kept.
TEST(DelaunayRefinementTest, AThinStripBetweenTwoLayersReachesTheAngleBound)
{
  RegionMesh m = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
  const double before = meshMinimumAngle(m);
  ASSERT_LT(before, 6.0);
  const RefinementResult r = strata::refineDelaunay(m, middle);
  expectValid(m);
  EXPECT_EQ(r.badTrianglesLeft, 0u);
  EXPECT_FALSE(r.budgetReached);
  EXPECT_GT(r.boundaryVertices, 0u);
  EXPECT_GE(meshMinimumAngle(m), 30.0 - 1e-9);
  const std::map<int, double> a = regionAreas(m);
  EXPECT_NEAR(a.at(0), 1000.0, 1e-9);
  EXPECT_NEAR(a.at(1), 100.0, 1e-9);
  EXPECT_NEAR(a.at(2), 1000.0, 1e-9);
  const double lo[3] = { -10.0, 0.0, 1.0 }, hi[3] = { 0.0, 1.0, 11.0 };
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    for (int v : m.triangles[t])
    {
      EXPECT_GE(m.points[v].y, lo[m.region[t]] - 1e-12) << "triangle " << t;
      EXPECT_LE(m.points[v].y, hi[m.region[t]] + 1e-12) << "triangle " << t;
    }
  }
}

// MaximumEdgeLength: two bands of 20-long right triangles (good angles, nothing for the angle
// refinement) get every region edge longer than 6 split, the boundary ones on their curve
// (middle), with the angle bound kept, each band's area kept and every vertex of the
// boundary between the bands on its line.
TEST(DelaunayRefinementTest, RegionEdgesLongerThanTheMaximumEdgeLengthAreSplit)
{
  RegionMesh m = bands({ 0.0, 20.0, 40.0 }, 100.0, 20.0);
  RefinementParams p;
  p.maximumEdgeLength = 6.0;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.sizeVertices, 0u);
  double longest = 0.0;
  for (const auto& tri : m.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      longest = std::max(longest, strata::norm(m.points[tri[(k + 1) % 3]] - m.points[tri[k]]));
    }
  }
  EXPECT_LE(longest, 6.0);
  EXPECT_GE(meshMinimumAngle(m), 30.0 - 1e-9);
  const std::map<int, double> a = regionAreas(m);
  EXPECT_NEAR(a.at(0), 2000.0, 1e-9);
  EXPECT_NEAR(a.at(1), 2000.0, 1e-9);
  for (const auto& [u, v] : boundaryEdges(m))
  {
    for (const int w : { u, v })
    {
      const Vec2 q = m.points[w];
      EXPECT_TRUE(q.y == 0.0 || q.y == 20.0 || q.y == 40.0 || q.x == 0.0 || q.x == 100.0)
        << q.x << " " << q.y;
    }
  }
  // Without it nothing is split: the bands are already good.
  RegionMesh same = bands({ 0.0, 20.0, 40.0 }, 100.0, 20.0);
  const RefinementResult none = strata::refineDelaunay(same, middle);
  EXPECT_EQ(none.sizeVertices, 0u);
  EXPECT_EQ(same.triangles.size(), 20u);
}

namespace
{
// The curve recovery of the tests below, on lostBand()'s bands (curves y = 0 and y = 3): curve
// points found strictly inside a triangle by `margin` of its longest edge (0: by rounding);
// with `asked`, the centroids' answers asked all at once too (regionsNear, counted there).
RefinementParams bandRecovery(double margin, std::size_t* asked)
{
  RefinementParams p;
  p.regionAt = [](Vec2 q) { return q.y < 0.0 ? 0 : (q.y < 3.0 ? 1 : 2); };
  p.curvePoint = [margin](Vec2 a, Vec2 b, Vec2 c, Vec2& at)
  {
    const Vec2 g = (1.0 / 3.0) * (a + b + c);
    const double longest =
      std::sqrt(std::max({ strata::norm2(b - a), strata::norm2(c - b), strata::norm2(a - c) }));
    for (double line : { 0.0, 3.0 })
    {
      at = { g.x, line };
      bool inside = true;
      for (const auto& [u, v] : { std::pair<Vec2, Vec2>(a, b), { b, c }, { c, a } })
      {
        inside = inside && strata::orient2d(u, v, at) > margin * longest * strata::norm(v - u);
      }
      if (inside)
      {
        return true;
      }
    }
    return false;
  };
  if (!asked)
  {
    return p;
  }
  p.curveDistance = [](Vec2 q, double) { return std::min(std::fabs(q.y), std::fabs(q.y - 3.0)); };
  const auto regionAt = p.regionAt;
  const auto curveDistance = p.curveDistance;
  p.regionsNear = [=](const Vec2* x, const double* within, std::size_t n, int* region)
  {
    *asked += n;
    for (std::size_t i = 0; i < n; ++i)
    {
      region[i] =
        curveDistance(x[i], within[i]) < within[i] ? regionAt(x[i]) : strata::kNoCurveNear;
    }
  };
  return p;
}

RegionMesh lostBand()
{
  RegionMesh m = bands({ -10.0, 3.0, 13.0 }, 100.0, 10.0);
  for (int& r : m.region)
  {
    r = r == 0 ? 0 : 2;
  }
  return m;
}
} // namespace

// Curve recovery: the model has a layer (region 1) between y = 0 and y = 3 that the mesh lost
// (it tags everything below y = 3 region 0, as a compression that put its boundary vertices
// on the layer's upper curve would). Points of the curve y = 0 inserted where it crosses
// triangles bring the layer back: region 1 gets its area, region 0 loses it, no triangle
// inverts, and every vertex on a region boundary lies on a curve (y = 0, y = 3 or the border).
TEST(DelaunayRefinementTest, CurveRecoveryBringsBackALayerTheMeshLost)
{
  RegionMesh m = lostBand();
  RefinementParams p = bandRecovery(0.1, nullptr);
  const auto onLine = [](double v, double line) { return std::fabs(v - line) <= 1e-9; };
  p.onCurve = [&](Vec2 q)
  {
    return onLine(q.y, 0.0) || onLine(q.y, 3.0) || onLine(q.y, -10.0) || onLine(q.y, 13.0) ||
      onLine(q.x, 0.0) || onLine(q.x, 100.0);
  };
  // The probes asked all at once (curvePoints, as the mesher does on two threads) give the
  // same mesh as one at a time.
  RegionMesh batched = m;
  RefinementParams q = p;
  std::size_t asked = 0;
  q.curvePoints = [&](const Vec2* corners, std::size_t n, char* found, Vec2* at)
  {
    asked += n;
    for (std::size_t i = 0; i < n; ++i)
    {
      found[i] = p.curvePoint(corners[3 * i], corners[3 * i + 1], corners[3 * i + 2], at[i]);
    }
  };
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  const RefinementResult rb = strata::refineDelaunay(batched, middle, q);
  EXPECT_GT(asked, 0u);
  EXPECT_EQ(rb.curveVertices, r.curveVertices);
  EXPECT_EQ(batched.triangles, m.triangles);
  EXPECT_EQ(batched.points, m.points);
  EXPECT_EQ(batched.region, m.region);
  expectValid(m);
  EXPECT_GT(r.curveVertices, 0u);
  const std::map<int, double> a = regionAreas(m);
  ASSERT_EQ(a.count(1), 1u);
  EXPECT_NEAR(a.at(1), 300.0, 15.0);
  EXPECT_NEAR(a.at(0), 1000.0, 15.0);
  EXPECT_NEAR(a.at(0) + a.at(1) + a.at(2), 2300.0, 1e-9);
  const auto edges = directedEdges(m);
  for (const auto& [e, t] : edges)
  {
    const auto back = edges.find({ e.second, e.first });
    if (back == edges.end() || m.region[back->second] != m.region[t])
    {
      EXPECT_TRUE(p.onCurve(m.points[e.first]) && p.onCurve(m.points[e.second]))
        << "boundary edge " << e.first << "-" << e.second << " leaves the curves";
    }
  }
}

// The centroids' answers a caller already has (KnownCentroidRegions, as the mesher has them)
// are taken for the triangles whose corners lie where they were asked about: the same mesh as
// asking again, with fewer questions; answers about another mesh (every point moved, every
// answer wrong) are not taken; the arrays are taken, not copied; a known triangle with a point
// id out of range, or an answer missing, is rejected.
TEST(DelaunayRefinementTest, KnownCentroidAnswersAreTakenOnlyForTheTrianglesAskedAbout)
{
  const RegionMesh m = lostBand();
  std::size_t asked = 0;
  const RefinementParams p = bandRecovery(0.1, &asked);
  strata::KnownCentroidRegions answers{ m.triangles, m.points, {} };
  for (const auto& tri : m.triangles)
  {
    const Vec2 a = m.points[tri[0]], b = m.points[tri[1]], c = m.points[tri[2]];
    const Vec2 g = (1.0 / 3.0) * (a + b + c);
    const double reach =
      std::sqrt(std::max({ strata::norm2(b - a), strata::norm2(c - b), strata::norm2(a - c) }));
    int answer = 0;
    p.regionsNear(&g, &reach, 1, &answer);
    answers.region.push_back(answer);
  }
  RegionMesh plain = m, given = m, other = m;
  asked = 0;
  const RefinementResult r = strata::refineDelaunay(plain, middle, p);
  const std::size_t askedPlain = asked;
  asked = 0;
  strata::KnownCentroidRegions known = answers;
  const RefinementResult rg =
    strata::refineDelaunay(given, middle, p, strata::ProgressReporter(), &known);
  EXPECT_GT(r.curveVertices, 0u);
  EXPECT_LT(asked, askedPlain);
  EXPECT_EQ(rg.curveVertices, r.curveVertices);
  EXPECT_EQ(given.triangles, plain.triangles);
  EXPECT_EQ(given.points, plain.points);
  EXPECT_EQ(given.region, plain.region);
  EXPECT_TRUE(known.triangles.empty() && known.points.empty()) << "taken, not copied";
  strata::KnownCentroidRegions moved = answers;
  for (Vec2& x : moved.points)
  {
    x.x += 0.25;
  }
  std::fill(moved.region.begin(), moved.region.end(), 7);
  asked = 0;
  strata::refineDelaunay(other, middle, p, strata::ProgressReporter(), &moved);
  EXPECT_EQ(asked, askedPlain);
  EXPECT_EQ(other.triangles, plain.triangles);
  EXPECT_EQ(other.points, plain.points);
  EXPECT_EQ(other.region, plain.region);
  strata::KnownCentroidRegions outOfRange = answers, missing = answers;
  outOfRange.triangles[0][1] = static_cast<int>(outOfRange.points.size());
  missing.region.pop_back();
  RegionMesh bad = m;
  EXPECT_THROW(strata::refineDelaunay(bad, middle, p, strata::ProgressReporter(), &outOfRange),
    strata::ParameterError);
  EXPECT_THROW(strata::refineDelaunay(bad, middle, p, strata::ProgressReporter(), &missing),
    strata::ParameterError);
}

// Curve points inside their triangle by rounding only (as the contract allows) leave slivers
// whose area rounds to zero: they stay as they are (no circumcentre to insert), never a
// non-finite point in the mesh; the mesh stays valid and the same from run to run.
TEST(DelaunayRefinementTest, SliversOfNoAreaByRoundingNeverBringANonFinitePoint)
{
  std::size_t asked = 0;
  const RefinementParams p = bandRecovery(0.0, &asked);
  RegionMesh m = lostBand(), again = lostBand();
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  strata::refineDelaunay(again, middle, p);
  EXPECT_GT(r.curveVertices, 0u);
  for (const Vec2& x : m.points)
  {
    ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y)) << x.x << " " << x.y;
  }
  expectValid(m);
  EXPECT_EQ(again.points, m.points);
  EXPECT_EQ(again.triangles, m.triangles);
}

// Smoothing after the refinement (here no vertex can be inserted: the floor is longer than
// every edge). A 10 x 10 square cut by the curve y = 5 (region 0 below, 1 above), all its
// triangles around the vertex v = (9, 5) on that curve: with a curveSlide along y = 5, v
// slides toward the middle, stays on the curve, and the smallest angle grows with both areas
// kept; without curveSlide v stays where it is. The same square as one region, v free, is
// moved toward the centroid of its neighbours.
TEST(DelaunayRefinementTest, SmoothingSlidesBoundaryVerticesOnTheirCurveAndMovesFreeOnes)
{
  const auto square = [](int upper)
  {
    RegionMesh m;
    m.points = { { 9, 5 }, { 0, 0 }, { 10, 0 }, { 10, 5 }, { 10, 10 }, { 0, 10 }, { 0, 5 } };
    m.triangles = { { 0, 6, 1 }, { 0, 1, 2 }, { 0, 2, 3 }, { 0, 3, 4 }, { 0, 4, 5 }, { 0, 5, 6 } };
    m.region = { 0, 0, 0, upper, upper, upper };
    m.level.assign(6, 0);
    return m;
  };
  RefinementParams p;
  // Nothing inserted, nothing split: even the floor beside the short boundary edge (9, 5) -
  // (10, 5), a twentieth of minimumEdgeLength there, lies above every edge.
  p.minimumEdgeLength = 1000.0;
  p.curveDistance = [](Vec2 q, double)
  {
    return std::min({ std::fabs(q.y - 5.0),
      std::fabs(q.y),
      std::fabs(q.y - 10.0),
      std::fabs(q.x),
      std::fabs(q.x - 10.0) });
  };
  p.curveSlide = [](Vec2 from, Vec2 toward, int left, int right, Vec2& at)
  {
    if (from.y != 5.0 || std::min(left, right) != 0 || std::max(left, right) != 1)
    {
      return false;
    }
    at = { std::clamp(toward.x, 0.5, 9.5), 5.0 };
    return true;
  };
  RegionMesh two = square(1);
  const double before = meshMinimumAngle(two);
  const RefinementResult slid = strata::refineDelaunay(two, middle, p);
  expectValid(two);
  EXPECT_EQ(slid.interiorVertices + slid.boundaryVertices, 0u);
  EXPECT_GT(slid.smoothingMoves, 0u);
  EXPECT_EQ(two.points[0].y, 5.0);
  EXPECT_LT(two.points[0].x, 9.0);
  EXPECT_GT(meshMinimumAngle(two), before + 5.0);
  const std::map<int, double> a = regionAreas(two);
  EXPECT_NEAR(a.at(0), 50.0, 1e-9);
  EXPECT_NEAR(a.at(1), 50.0, 1e-9);

  RefinementParams fixed = p;
  fixed.curveSlide = nullptr;
  RegionMesh stays = square(1);
  EXPECT_EQ(strata::refineDelaunay(stays, middle, fixed).smoothingMoves, 0u);
  EXPECT_EQ(stays.points[0], (Vec2{ 9, 5 }));

  RegionMesh one = square(0);
  const RefinementResult moved = strata::refineDelaunay(one, middle, fixed);
  expectValid(one);
  EXPECT_GT(moved.smoothingMoves, 0u);
  EXPECT_LT(strata::norm(one.points[0] - Vec2{ 5, 5 }), strata::norm(Vec2{ 9, 5 } - Vec2{ 5, 5 }));
  EXPECT_GT(meshMinimumAngle(one), before + 5.0);
  EXPECT_NEAR(regionAreas(one).at(0), 100.0, 1e-9);
}

// With the curve recovery's regionAt and onCurve, a region's 10-degree spike (a triangle whose
// corner lies between two region boundary edges) takes its neighbour's region: no corner of a
// region is left below the bound, the total area is kept; a region made of that triangle alone
// keeps it (no region disappears).
TEST(DelaunayRefinementTest, SharpRegionCornersInSmallTrianglesAreDissolved)
{
  const double tip = 10.0 * std::tan(10.0 * kPi / 180.0);
  const auto spike = [&](bool second)
  {
    RegionMesh m;
    m.points = { { 0, 0 }, { 10, 0 }, { 10, tip }, { 0, 10 }, { 10, 10 } };
    m.triangles = { { 0, 1, 2 }, { 0, 2, 4 }, { 0, 4, 3 } };
    m.region = { 1, 0, 0 };
    if (second) // a second piece of region 1, away from the spike
    {
      m.points.insert(m.points.end(), { { 20, 0 }, { 30, 0 }, { 25, 8 } });
      m.triangles.push_back({ 5, 6, 7 });
      m.region.push_back(1);
    }
    m.level.assign(m.triangles.size(), 0);
    return m;
  };
  RefinementParams p;
  p.minimumEdgeLength = 1.0;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [&](Vec2 q)
  {
    return q.x >= 20.0 || (q.y < q.x * tip / 10.0) ? 1 : 0; // the tags the mesh has
  };
  // No curvePoint: no recovery (nor its second pass, whose retag would give the spike's
  // pieces back to region 1), only the dissolving.
  RegionMesh m = spike(true);
  const double total = regionAreas(m).at(0) + regionAreas(m).at(1);
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.dissolvedCorners, 0u);
  EXPECT_EQ(r.badTrianglesAtCorners, 0u);
  const std::map<int, double> a = regionAreas(m);
  EXPECT_NEAR(a.at(0) + a.at(1), total, 1e-9);
  EXPECT_NEAR(a.at(1), 40.0, 1e-9); // the second piece only

  RegionMesh alone = spike(false);
  const RefinementResult kept = strata::refineDelaunay(alone, middle, p);
  EXPECT_EQ(kept.dissolvedCorners, 0u);
  EXPECT_NEAR(regionAreas(alone).at(1), 5.0 * tip, 1e-9);
}

// A region's 20-degree spike between two triangles of one other region, (0, 0) (10, -1.76)
// (10, 1.76), where the model's region (a strip 3.5 wide whose end is a 60-degree wedge with its
// apex at (0, 0)) is wider than the mesh: the spike is the mesh's doing. When sharpModelCorner
// says the model has no sharp corner there, the spike is not given away: its sides are split on
// the model's curves until the region reaches the bound with its apex kept. When it says the
// model has one (a real wedge), the spike is given away as before.
TEST(DelaunayRefinementTest, ASpikeOfTheMeshNotOfTheModelIsWidenedNotGivenAway)
{
  const double h = 10.0 * std::tan(10.0 * kPi / 180.0);
  const double bend = h / std::tan(30.0 * kPi / 180.0); // where the wedge meets the strip
  const auto spike = [&]()
  {
    RegionMesh m;
    m.points = { { 0, 0 },
      { 10, -h },
      { 10, h },
      { 20, -h },
      { 20, h },
      { 0, -10 },
      { 20, -10 },
      { 20, 10 },
      { 0, 10 } };
    m.triangles = { { 0, 1, 2 },
      { 1, 3, 4 },
      { 1, 4, 2 },
      { 0, 5, 1 },
      { 5, 6, 1 },
      { 1, 6, 3 },
      { 0, 2, 8 },
      { 2, 7, 8 },
      { 2, 4, 7 } };
    m.region = { 1, 1, 1, 0, 0, 0, 0, 0, 0 };
    m.level.assign(m.triangles.size(), 0);
    return m;
  };
  // The model's curves: region 1's outline and the frame.
  const std::vector<std::array<Vec2, 2>> curves = { { Vec2{ 0, 0 }, Vec2{ bend, h } },
    { Vec2{ bend, h }, Vec2{ 20, h } },
    { Vec2{ 0, 0 }, Vec2{ bend, -h } },
    { Vec2{ bend, -h }, Vec2{ 20, -h } },
    { Vec2{ 0, -10 }, Vec2{ 20, -10 } },
    { Vec2{ 20, -10 }, Vec2{ 20, 10 } },
    { Vec2{ 20, 10 }, Vec2{ 0, 10 } },
    { Vec2{ 0, 10 }, Vec2{ 0, -10 } } };
  const auto nearest = [&](Vec2 q)
  {
    Vec2 best = q;
    double d = 1e300;
    for (const auto& c : curves)
    {
      const Vec2 e = c[1] - c[0];
      const double t = std::clamp(strata::dot(q - c[0], e) / strata::norm2(e), 0.0, 1.0);
      const Vec2 x = c[0] + t * e;
      if (strata::norm(x - q) < d)
      {
        d = strata::norm(x - q);
        best = x;
      }
    }
    return best;
  };
  const strata::BoundarySplitter onModel = [&](Vec2 a, Vec2 b, int, int, Vec2& at)
  {
    at = nearest(0.5 * (a + b));
    return true;
  };
  RefinementParams p;
  p.minimumEdgeLength = 1.0;
  p.onCurve = [&](Vec2 q) { return strata::norm(nearest(q) - q) < 1e-9; };
  p.regionAt = [&](Vec2 q)
  { return q.x >= 0.0 && std::fabs(q.y) < std::min(h, q.x * std::tan(30.0 * kPi / 180.0)); };
  const auto atApex = [](const RegionMesh& m)
  {
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
    {
      const auto& tri = m.triangles[t];
      if (m.region[t] == 1 && std::count(tri.begin(), tri.end(), 0) == 1)
      {
        return true;
      }
    }
    return false;
  };
  const auto regionMinimumAngle = [](const RegionMesh& m, int region)
  {
    double smallest = 180.0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
    {
      smallest = m.region[t] == region ? std::min(smallest, smallestAngle(m, t)) : smallest;
    }
    return smallest;
  };

  RefinementParams widen = p;
  widen.sharpModelCorner = [](int, Vec2, double) { return false; };
  RegionMesh m = spike();
  const double before = regionAreas(m).at(1);
  const RefinementResult r = strata::refineDelaunay(m, onModel, widen);
  expectValid(m);
  EXPECT_EQ(r.dissolvedCorners, 0u);
  EXPECT_TRUE(atApex(m));
  EXPECT_GT(regionAreas(m).at(1), before); // toward the model's wedge
  EXPECT_GE(regionMinimumAngle(m, 1), 30.0);
  EXPECT_EQ(r.badTrianglesAtCorners, 0u);

  RefinementParams real = p;
  real.sharpModelCorner = [](int region, Vec2 q, double radius)
  { return region == 1 && strata::norm(q) <= radius; };
  RegionMesh given = spike();
  const RefinementResult g = strata::refineDelaunay(given, onModel, real);
  expectValid(given);
  EXPECT_GT(g.dissolvedCorners, 0u);
  EXPECT_FALSE(atApex(given));
}

// The spike of the test above with minimumEdgeLength 0.5: 10 long, more than the 16 edges of
// 0.5 up to which corners are dissolved, with a triangle below it, (0, 0) (5, -10) (10, 0).
// It is dissolved all the same when its area is at most 0.05% of its region's (a second piece
// of region 1 of area 20000 makes it 0.04%), and kept when it is a larger share (second piece
// of area 40: 18%), or when the triangle below is a second piece of region 0, which the spike
// would join to the first (a wedge's tip between two fault blocks).
TEST(DelaunayRefinementTest, ASharpCornerInALongerTriangleIsDissolvedWhenItIsASmallShare)
{
  const double tip = 10.0 * std::tan(10.0 * kPi / 180.0);
  RefinementParams p;
  p.minimumEdgeLength = 0.5;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [](Vec2) { return 0; }; // (no curvePoint: no recovery, only the dissolving)

  RegionMesh small = spike10(20000.0, 2);
  const RefinementResult r = strata::refineDelaunay(small, middle, p);
  expectValid(small);
  EXPECT_GT(r.dissolvedCorners, 0u);
  EXPECT_NEAR(regionAreas(small).at(1), 20000.0, 1e-6); // the second piece only

  RegionMesh large = spike10(40.0, 2);
  EXPECT_EQ(strata::refineDelaunay(large, middle, p).dissolvedCorners, 0u);
  EXPECT_NEAR(regionAreas(large).at(1), 40.0 + 5.0 * tip, 1e-9);

  RegionMesh pieces = spike10(20000.0, 0);
  EXPECT_EQ(strata::refineDelaunay(pieces, middle, p).dissolvedCorners, 0u);
  EXPECT_NEAR(regionAreas(pieces).at(1), 20000.0 + 5.0 * tip, 1e-6);
}

// A 10-degree region corner in a triangle 10 long (100 minimumEdgeLength), too large a share
// of its region (0.4%) to be given away whole: its tip is cut off on the corner's two curves
// (a small share: 0.003%) and given to a neighbour. Region 1 no longer reaches the corner
// and keeps all but the tip; with minimumEdgeLength 0.5 (the triangle is still longer than 16
// of them) the tip would be 4.3 long, no small share: no cut, and the corner stays.
TEST(DelaunayRefinementTest, ASharpCornerInALargeTriangleHasItsTipCut)
{
  const double tip = 10.0 * std::tan(10.0 * kPi / 180.0);
  RegionMesh m = spike10(2000.0, 2); // region 1: the wedge and a second piece of area 2000
  RefinementParams p;
  p.minimumEdgeLength = 0.1;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [](Vec2) { return 0; }; // (no curvePoint: no recovery, only 2c)
  const RegionMesh before = m;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.dissolvedCorners, 0u);
  EXPECT_GE(r.boundaryVertices, 2u);
  const double wedge = 2000.0 + 5.0 * tip;
  EXPECT_LT(regionAreas(m).at(1), wedge);
  EXPECT_GT(regionAreas(m).at(1), wedge * (1.0 - 5e-4));
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    for (const int v : m.triangles[t])
    {
      EXPECT_FALSE(m.region[t] == 1 && v == 0) << "triangle " << t << " still has the corner";
    }
  }
  p.minimumEdgeLength = 0.5;
  RegionMesh kept = before;
  strata::refineDelaunay(kept, middle, p);
  EXPECT_NEAR(regionAreas(kept).at(1), wedge, 1e-9);
}

namespace
{
// A 20 x 20 square around region 1's corner with apex (10, 0) and sides to (0, +-h), whose
// region 1 ends at x = 6 (the chord (6, +-0.4 h)): the tip and the rest take region `other`.
RegionMesh cornerCutAt6(double h, int other)
{
  const double y6 = 0.4 * h;
  RegionMesh m;
  m.points = { { 0, -10 },
    { 20, -10 },
    { 20, 10 },
    { 0, 10 },
    { 0, -h },
    { 0, h },
    { 6, -y6 },
    { 6, y6 },
    { 10, 0 } };
  m.triangles = { { 4, 6, 7 },
    { 4, 7, 5 },
    { 0, 1, 8 },
    { 1, 2, 8 },
    { 2, 3, 8 },
    { 3, 5, 7 },
    { 3, 7, 8 },
    { 7, 6, 8 },
    { 0, 8, 6 },
    { 0, 6, 4 } };
  m.region = { 1, 1, other, other, other, other, other, other, other, other };
  m.level.assign(m.triangles.size(), 0);
  return m;
}

// Whether q lies on a side of cornerCutAt6's corner.
bool onCornerSide(Vec2 q, double h)
{
  return q.x >= 0.0 && q.x <= 10.0 && std::fabs(std::fabs(q.y) - (10.0 - q.x) * h / 10.0) < 1e-9;
}

// The refinement of cornerCutAt6(h, other) with its corner (apex (10, 0), `angle` degrees,
// sides to (0, +-h)) in RefinementParams::wedgeCorners: region 1 inside the corner, `other`
// around it (the box's sides are curves when it is a region).
RefinementParams cornerParams(double h, double angle, int other, double minimumEdgeLength)
{
  RefinementParams p;
  p.minimumEdgeLength = minimumEdgeLength;
  p.onCurve = [h, other](Vec2 q)
  {
    return onCornerSide(q, h) || std::fabs(q.x) < 1e-9 ||
      (other >= 0 && (std::fabs(q.x - 20.0) < 1e-9 || std::fabs(std::fabs(q.y) - 10.0) < 1e-9));
  };
  p.regionAt = [h, other](Vec2 q)
  { return q.x > 0.0 && q.x < 10.0 && std::fabs(q.y) < (10.0 - q.x) * h / 10.0 ? 1 : other; };
  strata::SharpCorner corner;
  corner.apex = { 10, 0 };
  corner.region = 1;
  corner.angle = angle;
  corner.first = { { 10, 0 }, { 0, h } };
  corner.second = { { 10, 0 }, { 0, -h } };
  p.wedgeCorners = { corner };
  return p;
}

} // namespace

// A 45-degree corner of region 1 (apex (10, 0), sides to (0, +-4.14)) whose tip the mesh gave
// to region 0 (region 1 ends at x = 6, four finest edges from the apex): with the corner in
// RefinementParams::wedgeCorners, the last pass rebuilds the tip as rungs of region 1 (step
// 7'), so region 1 reaches its apex again with its whole area; without it the tip stays lost.
TEST(DelaunayRefinementTest, ALostTipOfARegionCornerIsRebuiltToItsApex)
{
  const double h = 10.0 * std::tan(22.5 * kPi / 180.0), y6 = 0.4 * h;
  const RegionMesh lost = cornerCutAt6(h, 0);
  const RefinementParams p = cornerParams(h, 45.0, 0, 1.0);
  RefinementParams none = p;
  none.wedgeCorners.clear();
  RegionMesh without = lost;
  const RefinementResult before = strata::refineDelaunay(without, middle, none);
  EXPECT_NEAR(regionAreas(without).at(1), 10.0 * h - 4.0 * y6, 1e-9);

  RegionMesh m = lost;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(r.extendedWedges, 1u);
  EXPECT_NEAR(regionAreas(m).at(1), 10.0 * h, 1e-9);
  EXPECT_NEAR(regionAreas(m).at(0), 400.0 - 10.0 * h, 1e-9);
  bool apex = false;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    for (const int v : m.triangles[t])
    {
      apex = apex || (m.region[t] == 1 && m.points[v] == Vec2{ 10, 0 });
    }
  }
  EXPECT_TRUE(apex);
  // The rungs and the triangles beside them are refined as any others.
  EXPECT_LE(r.badTrianglesLeft, before.badTrianglesLeft);
}

// The same lost tip where the finest edge is 2.6 long: region 1 ends 4.33 along its sides from
// the apex, 1.67 finest edges, and the corner is one finest edge wide at 1.31 of them. That
// end lies more than a quarter of that width beyond (kRestoredMargin), though not a half, so
// the tip is rebuilt (a spit's tip lost 1.4 finest edges from its apex, in a random lake, was
// 0.53 local edges from the mesh with a margin of a half).
TEST(DelaunayRefinementTest, ATipLostLittleMoreThanWhereItIsOneFinestEdgeWideIsRebuilt)
{
  const double h = 10.0 * std::tan(22.5 * kPi / 180.0);
  RegionMesh m = cornerCutAt6(h, 0);
  const RefinementParams p = cornerParams(h, 45.0, 0, 2.6);
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(r.extendedWedges, 1u);
  EXPECT_NEAR(regionAreas(m).at(1), 10.0 * h, 1e-9);
}

// A 10-degree spit of region 1 into the exterior (apex (10, 0), sides to (0, +-0.87)) that the
// mesh ends at x = 6, where it is 2.8 finest edges wide: with the corner in
// RefinementParams::wedgeCorners, the last pass extends it (step 7') to where it is one finest
// edge wide (1.43 from the apex) on one side and to a finest edge nearer the apex on the other
// (a slanted cut), the tip beyond left to the exterior; without it the spit stays short.
TEST(DelaunayRefinementTest, AShortSpitIsExtendedToWhereItIsOneFinestEdgeWide)
{
  const double h = 10.0 * std::tan(5.0 * kPi / 180.0);
  const RegionMesh lost = cornerCutAt6(h, -1);
  const RefinementParams p = cornerParams(h, 10.0, -1, 0.25);
  RefinementParams none = p;
  none.wedgeCorners.clear();
  const auto reach = [](const RegionMesh& m)
  {
    double x = 0.0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
    {
      for (const int v : m.triangles[t])
      {
        x = m.region[t] == 1 ? std::max(x, m.points[v].x) : x;
      }
    }
    return x;
  };
  RegionMesh without = lost;
  const RefinementResult before = strata::refineDelaunay(without, middle, none);
  EXPECT_NEAR(reach(without), 6.0, 1e-9);

  RegionMesh m = lost;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(r.extendedWedges, 1u);
  const double d0 = p.minimumEdgeLength / (2.0 * std::sin(5.0 * kPi / 180.0));
  const double d1 = d0 - p.minimumEdgeLength;
  EXPECT_NEAR(reach(m), 10.0 - d1 * std::cos(5.0 * kPi / 180.0), 1e-6);
  // Its area: the spit's but for the tip beyond the cut (the apex and the cut's ends).
  EXPECT_NEAR(regionAreas(m).at(1), 10.0 * h - 0.5 * d0 * d1 * std::sin(10.0 * kPi / 180.0), 1e-9);
  EXPECT_LE(r.badTrianglesLeft, before.badTrianglesLeft);
}

// Step 7' lists the triangles near each wedge corner a chunk of corners at a time
// (RefinementParams::wedgeChunk): from the mesh as it was and what the extensions before made
// or changed. The spit of AShortSpitIsExtendedToWhereItIsOneFinestEdgeWide listed three times,
// and the lost tip of ALostTipOfARegionCornerIsRebuiltToItsApex twice: the first of each is
// extended, the others find it done; in chunks of one corner (each listed after the extensions
// before it), two or the default, the same mesh and the same count.
TEST(DelaunayRefinementTest, WedgesListedInChunksSeeTheExtensionsBeforeThem)
{
  const auto check = [](const RegionMesh& lost, RefinementParams p, int copies)
  {
    p.wedgeCorners.assign(static_cast<std::size_t>(copies), p.wedgeCorners.front());
    RegionMesh whole = lost;
    const RefinementResult r = strata::refineDelaunay(whole, middle, p);
    expectValid(whole);
    EXPECT_EQ(r.extendedWedges, 1u);
    for (const std::size_t chunk : { 1, 2 })
    {
      p.wedgeChunk = chunk;
      RegionMesh m = lost;
      const RefinementResult rc = strata::refineDelaunay(m, middle, p);
      EXPECT_EQ(rc.extendedWedges, r.extendedWedges) << "chunks of " << chunk;
      EXPECT_EQ(m.points, whole.points) << "chunks of " << chunk;
      EXPECT_EQ(m.triangles, whole.triangles) << "chunks of " << chunk;
      EXPECT_EQ(m.region, whole.region) << "chunks of " << chunk;
    }
  };
  const double spit = 10.0 * std::tan(5.0 * kPi / 180.0);
  check(cornerCutAt6(spit, -1), cornerParams(spit, 10.0, -1, 0.25), 3);
  const double tip = 10.0 * std::tan(22.5 * kPi / 180.0);
  check(cornerCutAt6(tip, 0), cornerParams(tip, 45.0, 0, 1.0), 2);
}

// The spit of AShortSpitIsExtendedToWhereItIsOneFinestEdgeWide, but with a piece of region 1
// left inside the tip, cut off from the spit by exterior triangles: a quad from x = 7 to 8.5,
// just short of the cut (x = 8.57 on one side, 8.82 on the other) by less than the rungs'
// spacing. The piece is no end of the spit's body: the last pass still extends the spit from
// x = 6 to the cut (whose far end takes the quad's corner at x = 8.5 on its side), and region
// 1 is then one piece.
TEST(DelaunayRefinementTest, APieceOfASpitLeftInItsTipDoesNotStopTheExtension)
{
  const double h = 10.0 * std::tan(5.0 * kPi / 180.0);
  RegionMesh m = cornerCutAt6(h, -1);
  // Points 9 - 12 on the sides at x = 7 and 8.5; the tip triangle (7, 6, 8) and the two
  // triangles beside its sides are split at them.
  m.points.insert(
    m.points.end(), { { 7, -0.3 * h }, { 7, 0.3 * h }, { 8.5, -0.15 * h }, { 8.5, 0.15 * h } });
  m.triangles = { { 4, 6, 7 },
    { 4, 7, 5 },
    { 0, 1, 8 },
    { 1, 2, 8 },
    { 2, 3, 8 },
    { 3, 5, 7 },
    { 3, 7, 10 },
    { 3, 10, 12 },
    { 3, 12, 8 },
    { 7, 6, 9 },
    { 7, 9, 10 },
    { 10, 9, 11 },
    { 10, 11, 12 },
    { 12, 11, 8 },
    { 0, 8, 11 },
    { 0, 11, 9 },
    { 0, 9, 6 },
    { 0, 6, 4 } };
  m.region.assign(m.triangles.size(), -1);
  m.region[0] = m.region[1] = m.region[11] = m.region[12] = 1;
  m.level.assign(m.triangles.size(), 0);
  expectValid(m);
  const RefinementParams p = cornerParams(h, 10.0, -1, 0.25);
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(r.extendedWedges, 1u);
  // The cut's far end (d0, x = 8.58) is at the piece's corner on that side (x = 8.5, within
  // half a finest edge of it); its nearer end d1 as computed.
  const double d0 = p.minimumEdgeLength / (2.0 * std::sin(5.0 * kPi / 180.0));
  const double d1 = d0 - p.minimumEdgeLength;
  const double corner = 1.5 / std::cos(5.0 * kPi / 180.0);
  ASSERT_LT(corner - d0, 0.5 * p.minimumEdgeLength);
  EXPECT_NEAR(
    regionAreas(m).at(1), 10.0 * h - 0.5 * corner * d1 * std::sin(10.0 * kPi / 180.0), 1e-9);
  // One piece: every triangle of region 1 reached from the first across region 1's edges.
  std::map<std::pair<int, int>, int> edge;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      edge[{ m.triangles[t][k], m.triangles[t][(k + 1) % 3] }] = static_cast<int>(t);
    }
  }
  std::vector<int> stack, seen(m.triangles.size(), 0);
  for (std::size_t t = 0; t < m.triangles.size() && stack.empty(); ++t)
  {
    if (m.region[t] == 1)
    {
      stack.push_back(static_cast<int>(t));
      seen[t] = 1;
    }
  }
  while (!stack.empty())
  {
    const int t = stack.back();
    stack.pop_back();
    for (int k = 0; k < 3; ++k)
    {
      const auto it = edge.find({ m.triangles[t][(k + 1) % 3], m.triangles[t][k] });
      if (it != edge.end() && m.region[it->second] == 1 && !seen[it->second])
      {
        seen[it->second] = 1;
        stack.push_back(it->second);
      }
    }
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    EXPECT_TRUE(m.region[t] != 1 || seen[t]) << "triangle " << t << " of region 1 is cut off";
  }
}

// A speck, a region triangle with no neighbour of its own region and an inradius below
// minimumEdgeLength, goes to a neighbouring region whatever its size (beyond the mesh's outer
// border only when no region beside it raises its angle): the 10 x 1 triangle (40, 0),
// (50, 0), (50, 1) of region 2 on the border of the strip of region 0 (longer than the 16 edges of
// minimumEdgeLength 0.5 up to which corners are dissolved); region 2 keeps its other piece, a
// 10 x 10 triangle in region 1. With minimumEdgeLength 0.01 it is no speck (its inradius is
// 0.45) and too long and too large to go whole: it stays, but for the tip of its 5.7-degree
// corner, cut off on its curves (a small share of region 2).
TEST(DelaunayRefinementTest, SpecksOfARegionGoToTheirNeighbours)
{
  RefinementParams p;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [](Vec2 q) { return q.y < 1.0 ? 0 : 1; };
  const auto speck = []()
  {
    RegionMesh m = bands({ 0.0, 1.0, 11.0 }, 100.0, 10.0);
    m.region[8] = 2;  // (40, 0), (50, 0), (50, 1)
    m.region[30] = 2; // in region 1
    return m;
  };
  p.minimumEdgeLength = 0.5;
  RegionMesh m = speck();
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.dissolvedCorners, 0u);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    const auto& tri = m.triangles[t];
    const double y = (m.points[tri[0]].y + m.points[tri[1]].y + m.points[tri[2]].y) / 3.0;
    EXPECT_TRUE(m.region[t] != 2 || y > 1.0) << "triangle " << t; // only the other piece
  }
  const std::map<int, double> a = regionAreas(m);
  // The strip with the speck's 5: a region beside it takes it rather than the exterior
  // beyond the mesh's outer border (y = 0), which stays where it was.
  EXPECT_NEAR(a.at(0), 100.0, 1e-9);
  EXPECT_NEAR(a.at(1), 950.0, 1e-9);
  EXPECT_NEAR(a.at(2), 50.0, 1e-9);

  p.minimumEdgeLength = 0.01;
  RegionMesh kept = speck();
  strata::refineDelaunay(kept, middle, p);
  expectValid(kept);
  EXPECT_LT(regionAreas(kept).at(2), 55.0 - 1e-6);
  EXPECT_GT(regionAreas(kept).at(2), 55.0 * (1.0 - 5e-4));

  // A 2-degree spike of region 1, 100 long, hanging from one triangle of its region: with one
  // neighbour of its region it is a speck only below half minimumEdgeLength (inradius 1.7 <
  // 2.5 with minimumEdgeLength 5, though longer than the corners of 16 x 5; with 2 it is
  // neither and stays).
  const double rise = 100.0 * std::tan(2.0 * kPi / 180.0);
  const auto spike = [&]()
  {
    RegionMesh m;
    m.points = {
      { 0, 0 }, { 100, 0 }, { 100, rise }, { 0, 100 }, { 100, 100 }, { 150, 0.5 * rise }
    };
    m.triangles = { { 0, 1, 2 }, { 1, 5, 2 }, { 0, 2, 4 }, { 0, 4, 3 } };
    m.region = { 1, 1, 0, 0 };
    m.level.assign(4, 0);
    return m;
  };
  const double base = 25.0 * rise, wedge = 50.0 * rise;
  p.regionAt = [&](Vec2 q) { return q.x > 100.0 || q.y < q.x * rise / 100.0 ? 1 : 0; };
  p.minimumEdgeLength = 5.0;
  RegionMesh gone = spike();
  strata::refineDelaunay(gone, middle, p);
  expectValid(gone);
  EXPECT_NEAR(regionAreas(gone).at(1), base, 1e-9);
  p.minimumEdgeLength = 2.0;
  RegionMesh stays = spike();
  strata::refineDelaunay(stays, middle, p);
  EXPECT_NEAR(regionAreas(stays).at(1), base + wedge, 1e-9);
}

// A speck at the mesh's outer border goes to the region beside it, not beyond the border: the
// tip of region 1 where its curve meets the border (x = 0) at 24.9 degrees, one triangle
// (0, 0), (1.3, 2.8), (0, 3) with an inradius below half minimumEdgeLength 1.2, hanging from its
// region, is given to region 0 below the curve, and the mesh still covers the whole polygon
// (it went to the exterior before, leaving a notch in the border; m110 of
// random_sections.py 100 112).
TEST(DelaunayRefinementTest, ASpeckAtTheOuterBorderGoesToARegionNotBeyondTheBorder)
{
  // The model's polygon (0, -3) (4, -3) (4, 5) (0, 6), region 1 above the curve, and exterior
  // triangles (region -1, as the compressed grid has them) left of x = 0.
  RegionMesh m;
  m.points = { { 0, 0 },
    { 0, 3 },
    { 1.3, 2.8 },
    { 0, 6 },
    { 4, 5 },
    { 4, -3 },
    { 0, -3 },
    { -2, -3 },
    { -2, 6 } };
  m.triangles = { { 0, 2, 1 },
    { 1, 2, 3 },
    { 2, 4, 3 },
    { 0, 6, 5 },
    { 0, 5, 2 },
    { 5, 4, 2 },
    { 7, 6, 0 },
    { 7, 0, 8 },
    { 8, 0, 1 },
    { 8, 1, 3 } };
  m.region = { 1, 1, 1, 0, 0, 0, -1, -1, -1, -1 };
  m.level.assign(m.triangles.size(), 0);
  const double whole = 34.0, exterior = 18.0, below = 34.0 - 9.65;
  ASSERT_NEAR(regionAreas(m).at(0) + regionAreas(m).at(1), whole, 1e-9);
  ASSERT_NEAR(regionAreas(m).at(0), below, 1e-9);
  ASSERT_NEAR(regionAreas(m).at(-1), exterior, 1e-9);
  // Region 1 lies above the curve (0, 0) - (1.3, 2.8) - (4, 5).
  const auto above = [](Vec2 q)
  {
    const double y = q.x < 1.3 ? 2.8 / 1.3 * q.x : 2.8 + (q.x - 1.3) * 2.2 / 2.7;
    return q.y > y;
  };
  RefinementParams p;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [&](Vec2 q) { return above(q) ? 1 : 0; };
  p.minimumEdgeLength = 1.2;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.dissolvedCorners, 0u);
  const std::map<int, double> a = regionAreas(m);
  EXPECT_NEAR(a.at(-1), exterior, 1e-9) << "a triangle went beyond the border";
  EXPECT_NEAR(a.at(0) + a.at(1), whole, 1e-9);
  EXPECT_GT(a.at(0), below + 1e-6); // region 0 took the tip
}

// A piece of region 1 thinner than half minimumEdgeLength everywhere (a 0.02-thick strip
// between regions 0 and 2, cut off from the region's large piece above: 0.02% of its area)
// goes whole to one neighbour; with a finest edge below its thickness it stays.
TEST(DelaunayRefinementTest, AThinPieceOfARegionGoesWholeToANeighbour)
{
  const auto strip = []()
  {
    RegionMesh m = bands({ 0.0, 10.0, 10.02, 20.0, 120.0 }, 100.0, 5.0);
    std::replace(m.region.begin(), m.region.end(), 3, 1); // the large piece of region 1
    return m;
  };
  RefinementParams p;
  p.onCurve = [](Vec2) { return true; };
  p.regionAt = [](Vec2 q) { return q.y < 10.0 ? 0 : (q.y < 10.02 ? 1 : (q.y < 20.0 ? 2 : 1)); };
  p.minimumEdgeLength = 1.0;
  RegionMesh m = strip();
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GE(r.dissolvedCorners, 40u); // the strip's 40 triangles
  std::set<int> took;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    const auto& tri = m.triangles[t];
    const double y = (m.points[tri[0]].y + m.points[tri[1]].y + m.points[tri[2]].y) / 3.0;
    if (y > 10.0 && y < 10.02)
    {
      EXPECT_NE(m.region[t], 1) << "triangle " << t;
      took.insert(m.region[t]);
    }
  }
  EXPECT_EQ(took.size(), 1u) << "the strip goes to one neighbour";
  const std::map<int, double> a = regionAreas(m);
  EXPECT_NEAR(a.at(1), 10000.0, 1e-6);
  EXPECT_NEAR(a.at(0) + a.at(2), 1000.0 + 998.0 + 2.0, 1e-6);

  p.minimumEdgeLength = 0.01;
  RegionMesh kept = strip();
  strata::refineDelaunay(kept, middle, p);
  expectValid(kept);
  EXPECT_NEAR(regionAreas(kept).at(1), 10002.0, 1e-6);
}

// With no angle to reach the mesh is only flipped to constrained Delaunay: no vertex added,
// the region boundary edges (here the line x = 50 between two regions, and the border) are the
// same, no edge inside a region has its opposite vertex inside the other circumcircle, and the
// smallest angle does not decrease.
TEST(DelaunayRefinementTest, FlipsToConstrainedDelaunayKeepingRegionBoundaries)
{
  RegionMesh m = bands({ 0.0, 10.0, 20.0, 30.0, 40.0, 50.0 }, 100.0, 10.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0);
  for (Vec2& p : m.points)
  {
    const bool border = p.x == 0.0 || p.x == 100.0 || p.y == 0.0 || p.y == 50.0;
    if (!border && p.x != 50.0)
    {
      p = p + Vec2{ jitter(rng), jitter(rng) };
    }
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
  {
    const auto& tri = m.triangles[t];
    m.region[t] = (m.points[tri[0]].x + m.points[tri[1]].x + m.points[tri[2]].x) / 3.0 < 50.0;
  }
  const std::size_t points = m.points.size();
  const std::set<std::pair<int, int>> boundary = boundaryEdges(m);
  const double before = meshMinimumAngle(m);
  RefinementParams p;
  p.minimumAngle = 0.0;
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_GT(r.delaunayFlips, 0u);
  EXPECT_EQ(m.points.size(), points);
  EXPECT_EQ(boundaryEdges(m), boundary);
  EXPECT_GE(meshMinimumAngle(m), before);
  EXPECT_EQ(notDelaunayEdges(m), 0u);
}

// A region that is a single 10-degree wedge: its smallest angle lies between two boundary
// edges, so no insertion can widen it; it is left and counted, and the refinement ends.
TEST(DelaunayRefinementTest, ACornerSharperThanTheBoundIsLeftAndCounted)
{
  RegionMesh m;
  const double a = 10.0 * kPi / 180.0;
  m.points = { { 0.0, 0.0 }, { 10.0, 0.0 }, { 10.0 * std::cos(a), 10.0 * std::sin(a) } };
  m.triangles = { { 0, 1, 2 } };
  m.region = { 0 };
  m.level = { 3 };
  const RefinementResult r = strata::refineDelaunay(m, middle);
  expectValid(m);
  EXPECT_EQ(r.badTrianglesLeft, 1u);
  EXPECT_EQ(r.badTrianglesAtCorners, 1u);
  EXPECT_EQ(r.interiorVertices, 0u);
}

// Exterior triangles (region < 0) are never refined; a floor longer than every edge stops
// all insertions; a splitter that refuses keeps every boundary edge whole.
TEST(DelaunayRefinementTest, FloorsExteriorAndRefusedSplitsStopTheRefinement)
{
  {
    RegionMesh m = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
    for (int& r : m.region)
    {
      r = r == 1 ? -1 : r;
    }
    const RefinementResult r = strata::refineDelaunay(m, middle);
    expectValid(m);
    EXPECT_EQ(r.badTrianglesLeft, 0u); // the strip is exterior: nothing is bad
    EXPECT_EQ(r.interiorVertices + r.boundaryVertices, 0u);
  }
  {
    RegionMesh m = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
    RefinementParams p;
    p.minimumEdgeLength = 100.0;
    const RefinementResult r = strata::refineDelaunay(m, middle, p);
    expectValid(m);
    EXPECT_EQ(r.interiorVertices + r.boundaryVertices, 0u);
    EXPECT_GT(r.badTrianglesLeft, 0u);
  }
  {
    RegionMesh m = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
    const std::set<std::pair<int, int>> boundary = boundaryEdges(m);
    const std::map<int, double> before = regionAreas(m);
    const RefinementResult r =
      strata::refineDelaunay(m, [](Vec2, Vec2, int, int, Vec2&) { return false; });
    expectValid(m);
    EXPECT_EQ(r.boundaryVertices, 0u);
    EXPECT_EQ(boundaryEdges(m), boundary);
    for (const auto& [region, a] : regionAreas(m))
    {
      EXPECT_NEAR(a, before.at(region), 1e-9) << "region " << region;
    }
    EXPECT_GE(meshMinimumAngle(m), 5.0); // flips only: never below the 5.7-degree start
  }
}

// The refinement goes down to half minimumEdgeLength: the strip's triangles, whose shortest
// edges (its height, 1) are below minimumEdgeLength 1.5 but above half of it, are refined to
// the bound; with minimumEdgeLength 3 (half of it above the height) they are left.
TEST(DelaunayRefinementTest, TrianglesDownToHalfTheMinimumEdgeLengthAreRefined)
{
  RefinementParams p;
  p.minimumEdgeLength = 1.5;
  RegionMesh m = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
  const RefinementResult fine = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(fine.badTrianglesLeft, 0u);
  EXPECT_GE(meshMinimumAngle(m), 30.0 - 1e-9);
  p.minimumEdgeLength = 3.0;
  RegionMesh coarse = bands({ -10.0, 0.0, 1.0, 11.0 }, 100.0, 10.0);
  const RefinementResult left = strata::refineDelaunay(coarse, middle, p);
  expectValid(coarse);
  EXPECT_GT(left.badTrianglesLeft, 0u);
  EXPECT_LT(meshMinimumAngle(coarse), 30.0);
}

// A square [0, 10]^2 cut in two regions by the line y = 5, on which two vertices lie `gap`
// apart at (5, 5) and (5 + gap, 5) (two junctions close together), each region a fan of four
// triangles: the two beside the short edge are slivers.
RegionMesh shortBoundaryEdge(double gap)
{
  RegionMesh m;
  m.points = {
    { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 }, { 0, 5 }, { 5, 5 }, { 5 + gap, 5 }, { 10, 5 }
  };
  m.triangles = { { 0, 1, 6 },
    { 1, 7, 6 },
    { 0, 6, 5 },
    { 0, 5, 4 },
    { 4, 5, 3 },
    { 5, 6, 3 },
    { 6, 2, 3 },
    { 6, 7, 2 } };
  m.region = { 0, 0, 0, 0, 1, 1, 1, 1 };
  m.level.assign(m.triangles.size(), 0);
  return m;
}

// Beside a region boundary edge shorter than 0.4 minimumEdgeLength that the refinement may not
// split (two junctions 0.3 apart, minimumEdgeLength 2: half of it, the floor elsewhere, is
// above the slivers' shortest edges), the triangles are refined down to half that edge: every
// triangle reaches the bound, and the short edge stays. An edge shorter than a tenth of the
// floor (0.02) gets triangles down to a twentieth of minimumEdgeLength only: the slivers beside
// it are left, and the refinement ends well within its budget.
TEST(DelaunayRefinementTest, BesideAShortBoundaryEdgeTrianglesAreRefinedDownToIt)
{
  RefinementParams p;
  p.minimumEdgeLength = 2.0;
  RegionMesh m = shortBoundaryEdge(0.3);
  const std::map<int, double> before = regionAreas(m);
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(r.badTrianglesLeft, 0u);
  EXPECT_GE(meshMinimumAngle(m), 30.0 - 1e-9);
  EXPECT_EQ(boundaryEdges(m).count({ 5, 6 }), 1u);
  for (const auto& [region, a] : regionAreas(m))
  {
    EXPECT_NEAR(a, before.at(region), 1e-9) << "region " << region;
  }
  // Away from it the floor holds: no edge shorter than half minimumEdgeLength farther than 3
  // from the short edge.
  for (const auto& tri : m.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const Vec2 a = m.points[tri[k]], b = m.points[tri[(k + 1) % 3]];
      if (strata::norm(0.5 * (a + b) - Vec2{ 5.15, 5.0 }) > 3.0)
      {
        EXPECT_GE(strata::norm(b - a), 0.5 * p.minimumEdgeLength - 1e-9);
      }
    }
  }

  RegionMesh tiny = shortBoundaryEdge(0.02);
  const RefinementResult left = strata::refineDelaunay(tiny, middle, p);
  expectValid(tiny);
  EXPECT_GT(left.badTrianglesLeft, 0u);
  EXPECT_FALSE(left.budgetReached);
  EXPECT_LT(left.interiorVertices + left.boundaryVertices, 1000u);
}

// With stopPoint (the mesher's: junctions, curve ends, feature points), the local floor is
// only beside a short region boundary edge between two such points: the same two junctions
// 0.3 apart are refined down to it, but when one end is an ordinary curve point the floor
// stays half minimumEdgeLength there and the slivers beside the edge are left.
TEST(DelaunayRefinementTest, TheLocalFloorIsOnlyBetweenTwoStopPointsWhenTheyAreGiven)
{
  const auto at = [](Vec2 q, Vec2 x) { return strata::norm(q - x) < 1e-12; };
  RefinementParams p;
  p.minimumEdgeLength = 2.0;
  p.stopPoint = [&](Vec2 q) { return at(q, { 5.0, 5.0 }) || at(q, { 5.3, 5.0 }); };
  RegionMesh junctions = shortBoundaryEdge(0.3);
  const RefinementResult r = strata::refineDelaunay(junctions, middle, p);
  expectValid(junctions);
  EXPECT_EQ(r.badTrianglesLeft, 0u);
  EXPECT_GE(meshMinimumAngle(junctions), 30.0 - 1e-9);

  p.stopPoint = [&](Vec2 q) { return at(q, { 5.0, 5.0 }); };
  RegionMesh one = shortBoundaryEdge(0.3);
  const RefinementResult left = strata::refineDelaunay(one, middle, p);
  expectValid(one);
  EXPECT_GT(left.badTrianglesLeft, 0u);
  EXPECT_LT(meshMinimumAngle(one), 30.0);
}

// Curve fidelity (RefinementParams::curveDeviation): a region boundary edge that cuts off
// more than 0.05% of its smaller region's area from its curve is split at the curve's point
// farthest from it, so that the regions get their curve areas (a square halved by the curve
// (5, 0) - (5 + bulge, 5) - (5, 10), meshed with the straight edge x = 5); an edge that cuts
// off less is kept, and a refused edge is left alone.
TEST(DelaunayRefinementTest, BoundaryEdgesThatCutOffTheirCurveAreSplitOnIt)
{
  for (const double bulge : { 1.0, 0.001 })
  {
    RegionMesh m;
    m.points = { { 0, 0 }, { 5, 0 }, { 10, 0 }, { 10, 10 }, { 5, 10 }, { 0, 10 } };
    m.triangles = { { 0, 1, 4 }, { 0, 4, 5 }, { 1, 2, 3 }, { 1, 3, 4 } };
    m.region = { 0, 0, 1, 1 };
    m.level = { 0, 0, 0, 0 };
    RefinementParams p;
    p.minimumEdgeLength = 1.0;
    const Vec2 tip{ 5.0 + bulge, 5.0 };
    int asked = 0;
    p.curveDeviation = [&](Vec2 a, Vec2 b, int left, int right, double& area, Vec2& at)
    {
      ++asked;
      const bool whole = a.x == 5.0 && b.x == 5.0 && std::min(a.y, b.y) == 0.0 &&
        std::max(a.y, b.y) == 10.0 && std::min(left, right) == 0 && std::max(left, right) == 1;
      if (!whole)
      {
        return false; // the outer border, or a half already on the curve
      }
      area = 5.0 * bulge;
      at = tip;
      return true;
    };
    const RefinementResult r = strata::refineDelaunay(m, middle, p);
    expectValid(m);
    const bool split = bulge == 1.0; // 5 against 0.05% x 45; 0.005 against 0.05% x 50
    EXPECT_GT(asked, 0);
    EXPECT_EQ(r.fidelitySplits, split ? 1u : 0u) << bulge;
    EXPECT_EQ(std::count(m.points.begin(), m.points.end(), tip), split ? 1 : 0) << bulge;
    const auto areas = regionAreas(m);
    EXPECT_NEAR(areas.at(0), split ? 55.0 : 50.0, 1e-9) << bulge;
    EXPECT_NEAR(areas.at(1), split ? 45.0 : 50.0, 1e-9) << bulge;
  }
}

// Curve fidelity where no split fits: the curve (6, 0) - (3, 5) - (6, 10) has a corner at
// (3, 5) that the boundary edge x = 6 cuts off, and the free vertex (3.1, 5) of region 0 sits
// beside the corner, off the curve (as the compression leaves one by a model corner), so the
// split at the corner would turn a triangle, and the triangle (6, 0) - (6, 10) - (4.1, 5) has
// a corner off the curves for a retag. The vertex is moved onto the corner, and the triangle
// takes the region at its centroid: both regions get their curve areas (45 and 55).
TEST(DelaunayRefinementTest, AFreeVertexBesideACutCornerIsMovedOntoIt)
{
  RegionMesh m;
  m.points = { { 0, 0 }, { 6, 0 }, { 10, 0 }, { 10, 10 }, { 6, 10 }, { 0, 10 }, { 3.1, 5 } };
  m.triangles = { { 0, 1, 6 }, { 1, 4, 6 }, { 4, 5, 6 }, { 5, 0, 6 }, { 1, 2, 3 }, { 1, 3, 4 } };
  m.region = { 0, 0, 0, 0, 1, 1 };
  m.level = { 0, 0, 0, 0, 0, 0 };
  const Vec2 corner{ 3, 5 };
  const auto curveX = [](double y) { return y <= 5.0 ? 6.0 - 0.6 * y : 3.0 + 0.6 * (y - 5.0); };
  RefinementParams p;
  p.minimumEdgeLength = 1.0;
  p.regionAt = [&](Vec2 q) { return q.x > curveX(q.y) ? 1 : 0; };
  p.onCurve = [&](Vec2 q)
  { return q.y >= 0.0 && q.y <= 10.0 && std::abs(q.x - curveX(q.y)) < 1e-9; };
  p.curveDeviation = [&](Vec2 a, Vec2 b, int left, int right, double& area, Vec2& at)
  {
    const bool chord = a.x == 6.0 && b.x == 6.0 && std::min(a.y, b.y) == 0.0 &&
      std::max(a.y, b.y) == 10.0 && std::min(left, right) == 0 && std::max(left, right) == 1;
    if (!chord)
    {
      return false; // the outer border, or the two sides of the corner
    }
    area = 15.0;
    at = corner;
    return true;
  };
  strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_EQ(std::count(m.points.begin(), m.points.end(), corner), 1);
  const auto areas = regionAreas(m);
  EXPECT_NEAR(areas.at(0), 45.0, 1e-9);
  EXPECT_NEAR(areas.at(1), 55.0, 1e-9);
}

// Curve fidelity at a model corner (RefinementParams::modelCorner): a square [0, 10]^2 (one
// region, its sides the outer border) meshed with a chord across its corner (0, 10), as the
// compression leaves one by a box's corner. A chord whose corner lies far from it (from
// (0, 5) to (5, 10): 3.5, half its length) is split at the corner; one that ends near the
// corner (from (0, 9.6) to (4, 10): the corner 0.4 from its end, too near for a split) has
// that end slid onto the corner along its side. Either way the corner is a mesh vertex and
// the region has the square's area. The callback reports no area cut off (as for a box's
// corner in a region thousands of times larger), so the area rule alone splits nothing; the
// far chord's corner lies more than 0.4 of the local edge (and a finest edge) from it, so
// without modelCorner it is split there all the same (issue 5's boundary bound), the near
// one is not.
TEST(DelaunayRefinementTest, AChordAcrossAModelCornerGetsAVertexOnTheCorner)
{
  const Vec2 corner{ 0, 10 };
  const std::array<Vec2, 4> corners = { Vec2{ 0, 0 }, Vec2{ 10, 0 }, Vec2{ 10, 10 }, corner };
  const auto onSide = [](Vec2 q, int side) // 0 bottom, 1 right, 2 top, 3 left
  {
    const double along = side % 2 == 0 ? q.x : q.y, across = side % 2 == 0 ? q.y : q.x;
    const double at = side == 0 || side == 3 ? 0.0 : 10.0;
    return std::abs(across - at) < 1e-9 && along >= -1e-9 && along <= 10.0 + 1e-9;
  };
  const auto sideOf = [&](Vec2 q)
  {
    for (int side = 0; side < 4; ++side)
    {
      if (onSide(q, side))
      {
        return side;
      }
    }
    return -1;
  };
  RefinementParams p;
  p.minimumEdgeLength = 1.0;
  p.onCurve = [&](Vec2 q) { return sideOf(q) >= 0; };
  p.curveDistance = [](Vec2 q, double) {
    return std::min({ std::abs(q.x), std::abs(10.0 - q.x), std::abs(q.y), std::abs(10.0 - q.y) });
  };
  // Along a side toward `toward`, stopping at the square's corners (none moves).
  p.curveSlide = [&](Vec2 from, Vec2 toward, int, int, Vec2& at)
  {
    const int side = sideOf(from);
    if (side < 0 || std::find(corners.begin(), corners.end(), from) != corners.end())
    {
      return false;
    }
    at = side % 2 == 0 ? Vec2{ std::clamp(toward.x, 0.0, 10.0), from.y }
                       : Vec2{ from.x, std::clamp(toward.y, 0.0, 10.0) };
    return true;
  };
  // An edge between two adjacent sides stands for the stretch through their corner.
  p.curveDeviation = [&](Vec2 a, Vec2 b, int, int, double& area, Vec2& at)
  {
    for (const Vec2 c : corners)
    {
      if (sideOf(a) >= 0 && sideOf(b) >= 0 && sideOf(a) != sideOf(b) && !(a == c) && !(b == c) &&
        (a.x == c.x || a.y == c.y) && (b.x == c.x || b.y == c.y))
      {
        area = 0.0;
        at = c;
        return true;
      }
    }
    return false;
  };
  p.modelCorner = [&](Vec2 q)
  { return std::find(corners.begin(), corners.end(), q) != corners.end(); };
  for (const auto& [from, to] :
    { std::pair<Vec2, Vec2>{ { 0, 5 }, { 5, 10 } }, { { 0, 9.6 }, { 4, 10 } } })
  {
    RegionMesh m;
    // The pentagon without the corner, fanned around (4, 4).
    m.points = { { 0, 0 }, { 10, 0 }, { 10, 10 }, to, from, { 4, 4 } };
    m.triangles = { { 0, 1, 5 }, { 1, 2, 5 }, { 2, 3, 5 }, { 3, 4, 5 }, { 4, 0, 5 } };
    m.region = { 0, 0, 0, 0, 0 };
    m.level = { 0, 0, 0, 0, 0 };
    RefinementParams without = p;
    without.modelCorner = nullptr;
    RegionMesh cut = m;
    strata::refineDelaunay(cut, middle, without);
    EXPECT_EQ(std::count(cut.points.begin(), cut.points.end(), corner), from.y == 5 ? 1 : 0);
    strata::refineDelaunay(m, middle, p);
    expectValid(m);
    EXPECT_EQ(std::count(m.points.begin(), m.points.end(), corner), 1)
      << "chord from (" << from.x << ", " << from.y << ")";
    EXPECT_NEAR(regionAreas(m).at(0), 100.0, 1e-9);
  }
}

// Curve fidelity adds up (RefinementParams::curveAreaBudget 0.25%, as the mesher sets with the
// automatic sizes): a thin layer (band 1, 20 long, 1 thick, between two 10-thick bands) whose
// boundary edges each cut off 0.04% of its area, under the per-edge 0.05%, but 0.8% in all
// (20 edges), has them split too. With only 5 such edges (0.2% in all), or without the budget
// (the default), none is.
TEST(DelaunayRefinementTest, BoundaryEdgesOfALayerThatCutOffTooMuchInAllAreSplit)
{
  for (const auto& [reach, budget] : { std::pair{ 20.0, 2.5e-3 }, { 10.0, 2.5e-3 }, { 20.0, 0.0 } })
  {
    RegionMesh m = bands({ 0.0, 10.0, 11.0, 21.0 }, 20.0, 2.0);
    RefinementParams p;
    p.minimumEdgeLength = 1.0;
    p.curveAreaBudget = budget;
    const double cut = 4e-4 * 20.0; // of band 1's area, per edge
    int asked = 0;
    p.curveDeviation = [&](Vec2 a, Vec2 b, int left, int right, double& area, Vec2& at)
    {
      ++asked;
      const bool row = a.y == b.y && (a.y == 10.0 || a.y == 11.0);
      const bool layer = std::min(left, right) >= 0 && (left == 1 || right == 1);
      if (!row || !layer || std::abs(b.x - a.x) < 1.5 || std::max(a.x, b.x) > reach ||
        (reach < 20.0 && a.y == 11.0))
      {
        return false; // the outer border, a half already split, or beyond the reach
      }
      area = cut;
      at = 0.5 * (a + b);
      return true;
    };
    const RefinementResult r = strata::refineDelaunay(m, middle, p);
    expectValid(m);
    EXPECT_GT(asked, 0);
    EXPECT_EQ(r.fidelitySplits, reach == 20.0 && budget > 0.0 ? 20u : 0u) << reach << " " << budget;
    // The splits are on the rows: the areas stay.
    const auto areas = regionAreas(m);
    EXPECT_NEAR(areas.at(0), 200.0, 1e-9);
    EXPECT_NEAR(areas.at(1), 20.0, 1e-9);
    EXPECT_NEAR(areas.at(2), 200.0, 1e-9);
  }
}

// A sharp corner between two unconstrained edges at a junction (what a wedge's tip given to
// its neighbour leaves: the same region on both sides of the edges) is no region corner: the
// refinement widens it (16 degrees before, at least 30 after) from beyond its long edge. No
// boundary edge may be split, so only interior insertions can do it.
TEST(DelaunayRefinementTest, ASharpCornerBetweenUnconstrainedEdgesIsWidened)
{
  // Point 0 is the corner: 1 and 2 lie on its edges (16 degrees apart), 3 beyond the short
  // edge 1-2 (triangle 1-3-2 is region 1), 4 and 5 close to it (triangle 4-5-0 is region 2, so
  // point 0 is a junction), then rings 25 and 50 from it (a Delaunay triangulation).
  RegionMesh m;
  m.points = { { 0.0, 0.0 },
    { 13.0, 0.0 },
    { 17.0 * std::cos(16.0 * kPi / 180.0), 17.0 * std::sin(16.0 * kPi / 180.0) },
    { 19.0, -2.0 },
    { 4.0 * std::cos(150.0 * kPi / 180.0), 4.0 * std::sin(150.0 * kPi / 180.0) },
    { 4.0 * std::cos(230.0 * kPi / 180.0), 4.0 * std::sin(230.0 * kPi / 180.0) } };
  for (const auto& [radius, first] : { std::pair<double, double>(25.0, 15.0), { 50.0, 0.0 } })
  {
    for (int k = 0; k < 12; ++k)
    {
      const double angle = (first + 30.0 * k) * kPi / 180.0;
      m.points.push_back({ radius * std::cos(angle), radius * std::sin(angle) });
    }
  }
  m.triangles = { { 11, 23, 24 },
    { 23, 11, 10 },
    { 29, 17, 16 },
    { 17, 29, 18 },
    { 25, 26, 13 },
    { 28, 29, 16 },
    { 15, 28, 16 },
    { 28, 15, 27 },
    { 22, 23, 10 },
    { 11, 4, 10 },
    { 8, 4, 0 },
    { 12, 25, 13 },
    { 25, 12, 24 },
    { 12, 11, 24 },
    { 12, 4, 11 },
    { 6, 19, 7 },
    { 19, 6, 18 },
    { 6, 17, 18 },
    { 19, 20, 7 },
    { 20, 8, 7 },
    { 8, 20, 21 },
    { 15, 14, 27 },
    { 26, 14, 13 },
    { 14, 26, 27 },
    { 9, 8, 21 },
    { 9, 22, 10 },
    { 22, 9, 21 },
    { 4, 9, 10 },
    { 9, 4, 8 },
    { 5, 12, 13 },
    { 12, 5, 4 },
    { 4, 5, 0 },
    { 14, 5, 13 },
    { 5, 14, 15 },
    { 5, 15, 16 },
    { 5, 1, 0 },
    { 1, 5, 16 },
    { 17, 3, 16 },
    { 3, 1, 16 },
    { 6, 3, 17 },
    { 3, 2, 1 },
    { 2, 3, 6 },
    { 2, 6, 7 },
    { 1, 2, 0 },
    { 2, 8, 0 },
    { 8, 2, 7 } };
  m.region = { 2,
    2,
    0,
    0,
    2,
    0,
    0,
    0,
    0,
    0,
    0,
    2,
    2,
    2,
    2,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    2,
    2,
    2,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    0,
    1,
    0,
    0,
    0,
    0,
    0 };
  m.level.assign(m.triangles.size(), 0);
  const auto smallestAt = [](const RegionMesh& mesh, int v)
  {
    double smallest = 180.0;
    for (const auto& t : mesh.triangles)
    {
      for (int k = 0; k < 3; ++k)
      {
        if (t[k] == v)
        {
          smallest = std::min(smallest,
            strata::triangleAngles(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]])[k]);
        }
      }
    }
    return smallest;
  };
  ASSERT_NEAR(smallestAt(m, 0), 16.0, 1e-5);
  const auto never = [](Vec2, Vec2, int, int, Vec2&) { return false; };
  const RefinementResult result = strata::refineDelaunay(m, never);
  expectValid(m);
  EXPECT_GT(result.interiorVertices, 0u);
  EXPECT_GE(smallestAt(m, 0), 30.0);
}

// The insertion budget caps the work: 1000 vertices (budget 0 x triangles + 1000) on a strip
// that needs more.
// A boundary vertex 0.3 from its neighbour on a straight curve between two bands (the
// triangles on that edge have 4-degree apexes, and the edge is too short for the refinement):
// the short edge is collapsed, the vertex merged into its neighbour, and the bands' 45-degree
// triangles come back, each band's area kept, every boundary edge still on the curves. Where
// the curve's vertices may not move (feature points), nothing is collapsed.
TEST(DelaunayRefinementTest, AnEdgeTooShortForTheRefinementIsCollapsed)
{
  const auto build = []()
  {
    RegionMesh m = bands({ -4.0, 0.0, 4.0 }, 16.0, 4.0);
    const int p = 7, q = 8; // (8, 0) and (12, 0)
    const int w = static_cast<int>(m.points.size());
    m.points.push_back({ 8.3, 0.0 });
    const std::size_t nt = m.triangles.size();
    for (std::size_t t = 0; t < nt; ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const int a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
        if ((a == p && b == q) || (a == q && b == p))
        {
          const int c = m.triangles[t][(k + 2) % 3];
          m.triangles[t] = { a, w, c };
          m.triangles.push_back({ w, b, c });
          m.region.push_back(m.region[t]);
          m.level.push_back(m.level[t]);
          break;
        }
      }
    }
    return m;
  };
  const auto onBox = [](Vec2 p)
  {
    return std::fabs(p.x) < 1e-9 || std::fabs(p.x - 16.0) < 1e-9 ||
      std::fabs(std::fabs(p.y) - 4.0) < 1e-9;
  };
  RefinementParams params;
  params.minimumAngle = 30.0;
  params.minimumEdgeLength = 2.0; // the floor: edges below 1 are not refined
  params.onCurve = [&](Vec2 p) { return std::fabs(p.y) < 1e-9 || onBox(p); };
  params.curveDistance = [&](Vec2 p, double)
  {
    return std::min(
      { std::fabs(p.y), std::fabs(p.x), std::fabs(16.0 - p.x), 4.0 - std::fabs(p.y) });
  };
  params.curveSlide = [](Vec2 from, Vec2 toward, int left, int right, Vec2& at)
  {
    if (!(std::fabs(from.y) < 1e-9) || std::min(left, right) != 0 || std::max(left, right) != 1)
    {
      return false;
    }
    at = { std::clamp(toward.x, 0.0, 16.0), 0.0 };
    return true;
  };

  RegionMesh m = build();
  const auto before = regionAreas(m);
  ASSERT_LT(meshMinimumAngle(m), 5.0);
  EXPECT_EQ(strata::collapseShortEdges(m, params), 1u);
  expectValid(m);
  EXPECT_NEAR(meshMinimumAngle(m), 45.0, 1e-9);
  const auto after = regionAreas(m);
  ASSERT_EQ(after.size(), before.size());
  for (const auto& [r, a] : before)
  {
    EXPECT_NEAR(after.at(r), a, 1e-9) << "region " << r;
  }
  for (const auto& [a, b] : boundaryEdges(m))
  {
    EXPECT_TRUE(params.onCurve(m.points[a]) && params.onCurve(m.points[b]))
      << "boundary edge " << a << "-" << b << " off the curves";
  }

  RegionMesh fixed = build();
  params.curveSlide = [](Vec2, Vec2, int, int, Vec2&) { return false; };
  EXPECT_EQ(strata::collapseShortEdges(fixed, params), 0u);
  EXPECT_EQ(fixed.triangles.size(), build().triangles.size());
}

// Two free vertices 0.3 apart at the centre of a regular hexagon of radius 2 (its rim on the
// curves), each joined to half the rim: the two triangles on their short edge have 7.4-degree
// apexes, and the edge is too short for the refinement. Merging either vertex into the other
// leaves a fan around a point 0.15 off the centre; both vertices are free, so they meet at
// the edge's middle instead, the hexagon's centre: six equilateral triangles.
TEST(DelaunayRefinementTest, TwoFreeVerticesTooCloseForTheRefinementMeetHalfWay)
{
  RegionMesh m;
  for (int i = 0; i < 6; ++i)
  {
    const double a = i * kPi / 3.0;
    m.points.push_back({ 2.0 * std::cos(a), 2.0 * std::sin(a) });
  }
  const int c1 = 6, c2 = 7; // the left and the right one
  m.points.push_back({ -0.15, 0.0 });
  m.points.push_back({ 0.15, 0.0 });
  m.triangles = { { c2, 5, 0 },
    { c2, 0, 1 },
    { c1, c2, 1 },
    { c1, 1, 2 },
    { c1, 2, 3 },
    { c1, 3, 4 },
    { c2, c1, 4 },
    { c2, 4, 5 } };
  m.region.assign(m.triangles.size(), 0);
  m.level.assign(m.triangles.size(), 0);
  const auto onRim = [](Vec2 p) { return std::fabs(strata::norm(p) - 2.0) < 1e-3; };
  RefinementParams params;
  params.minimumAngle = 30.0;
  params.minimumEdgeLength = 2.0; // the floor: edges below 1 are not refined
  params.onCurve = onRim;
  params.curveDistance = [](Vec2 p, double) { return std::fabs(strata::norm(p) - 2.0); };
  params.curveSlide = [](Vec2, Vec2, int, int, Vec2&) { return false; };
  expectValid(m);
  ASSERT_LT(meshMinimumAngle(m), 10.0);
  const double area = regionAreas(m).at(0);

  EXPECT_EQ(strata::collapseShortEdges(m, params), 1u);
  expectValid(m);
  EXPECT_EQ(m.triangles.size(), 6u);
  EXPECT_NEAR(meshMinimumAngle(m), 60.0, 1e-9);
  EXPECT_NEAR(regionAreas(m).at(0), area, 1e-12);
  for (const auto& t : m.triangles)
  {
    for (const int v : t)
    {
      EXPECT_TRUE(v < 6 || strata::norm(m.points[v]) < 1e-15)
        << "vertex " << v << " off the centre";
    }
  }
}

TEST(DelaunayRefinementTest, TheInsertionBudgetCapsTheVerticesInserted)
{
  RegionMesh m = bands({ -10.0, 0.0, 0.1, 10.1 }, 2000.0, 10.0);
  RefinementParams p;
  p.insertionBudget = 0.0;
  const std::size_t points = m.points.size();
  const RefinementResult r = strata::refineDelaunay(m, middle, p);
  expectValid(m);
  EXPECT_TRUE(r.budgetReached);
  EXPECT_LE(m.points.size() - points, 1000u); // the mesh kept comes from one run
  EXPECT_GT(r.badTrianglesLeft, 0u);
}

TEST(DelaunayRefinementTest, AbortIsHonoured)
{
  RegionMesh m = bands({ -10.0, 0.0, 0.5, 10.5 }, 2000.0, 10.0);
  int calls = 0;
  const strata::ProgressReporter progress(
    [&](double fraction, const char*)
    {
      EXPECT_GE(fraction, 0.0);
      EXPECT_LE(fraction, 1.0);
      return ++calls < 3;
    });
  EXPECT_THROW(strata::refineDelaunay(m, middle, {}, progress), strata::Aborted);
}

TEST(DelaunayRefinementTest, MalformedMeshesAndParametersAreRejected)
{
  const auto message = [](RegionMesh m, RefinementParams p)
  {
    try
    {
      strata::refineDelaunay(m, middle, p);
    }
    catch (const strata::ParameterError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  const RegionMesh good = bands({ 0.0, 1.0, 2.0 }, 4.0, 1.0);
  RefinementParams p;
  // (Delaunay refinement is known to end up to about 33 degrees: 34 is refused.)
  p.minimumAngle = strata::kLargestMinimumAngle;
  EXPECT_EQ(message(good, p), "");
  p.minimumAngle = 34.0;
  EXPECT_NE(message(good, p).find("MinimumAngle = 34"), std::string::npos);
  p = {};
  p.insertionBudget = -1.0;
  EXPECT_NE(message(good, p).find("budget"), std::string::npos);
  p = {};
  p.curveAreaBudget = 2.0;
  EXPECT_NE(message(good, p).find("curve area budget"), std::string::npos);
  p = {};
  p.wedgeChunk = 0;
  EXPECT_NE(message(good, p).find("wedge chunk 0"), std::string::npos);
  p = {};
  p.maximumEdgeLength = std::nan("");
  EXPECT_NE(message(good, p).find("maximum edge length nan"), std::string::npos);
  RegionMesh m = good;
  m.region.pop_back();
  EXPECT_NE(message(m, {}).find("regions"), std::string::npos);
  m = good;
  m.triangles[0][1] = 999;
  EXPECT_NE(message(m, {}).find("point 999"), std::string::npos);
  m = good;
  m.triangles.push_back(m.triangles[0]); // the same triangle twice: edges on one side twice
  m.region.push_back(0);
  m.level.push_back(0);
  EXPECT_NE(message(m, {}).find("more than two triangles"), std::string::npos);
}

// From 65536 triangles the whole-mesh sweeps (neighbours, the Delaunay flips' first test, the
// bad triangles, the smallest angle) run in blocks, each block's halves on two threads: the
// mesh still ends constrained Delaunay, a malformed mesh names the first point at fault, and
// an abort between blocks is honoured (no thread left running).
TEST(DelaunayRefinementTest, LargeMeshesAreSweptOnTwoThreadsWithTheSerialOutcome)
{
  RegionMesh m = bands({ 0.0, 1.0, 2.0, 3.0 }, 12000.0, 1.0);
  ASSERT_GE(m.triangles.size(), 65536u);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (Vec2& p : m.points)
  {
    if (p.y > 0.0 && p.y < 3.0 && p.y != 1.0 && p.x > 0.0 && p.x < 12000.0)
    {
      p = p + Vec2{ jitter(rng), jitter(rng) };
    }
  }
  const std::set<std::pair<int, int>> boundary = boundaryEdges(m);
  RefinementParams p;
  p.minimumAngle = 0.0;
  RegionMesh flipped = m;
  const RefinementResult r = strata::refineDelaunay(flipped, middle, p);
  expectValid(flipped);
  EXPECT_GT(r.delaunayFlips, 0u);
  EXPECT_EQ(boundaryEdges(flipped), boundary);
  EXPECT_EQ(notDelaunayEdges(flipped), 0u);

  // A triangle twice, near the end (the second half): the message names its lowest corner.
  RegionMesh twice = m;
  const std::array<int, 3> copy = twice.triangles[twice.triangles.size() - 5];
  twice.triangles.push_back(copy);
  twice.region.push_back(twice.region.back());
  twice.level.push_back(0);
  const int lowest = std::min({ copy[0], copy[1], copy[2] });
  try
  {
    strata::refineDelaunay(twice, middle, p);
    ADD_FAILURE() << "a triangle twice was accepted";
  }
  catch (const strata::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find("the edge from point " + std::to_string(lowest) + " "),
      std::string::npos)
      << e.what();
  }

  int calls = 0;
  const strata::ProgressReporter progress([&](double, const char*) { return ++calls < 2; });
  RegionMesh aborted = m;
  EXPECT_THROW(strata::refineDelaunay(aborted, middle, {}, progress), strata::Aborted);
}

TEST(DelaunayRefinementTest, PointStarsListEachPointsTrianglesInOrderAndOnlyTheFlaggedOnes)
{
  // A fan of four triangles around point 4 (the centre of a square), and a fifth beside it.
  strata::LargeVector<std::array<int, 3>> triangles;
  for (const std::array<int, 3>& t : std::vector<std::array<int, 3>>{
         { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 }, { 1, 5, 2 } })
  {
    triangles.push_back(t);
  }
  const std::size_t np = 6;
  const auto starOf = [](const strata::PointStars& s, int v)
  { return std::vector<int>(s.items.begin() + s.start[v], s.items.begin() + s.start[v + 1]); };

  const strata::PointStars all = strata::pointStars(np, triangles);
  ASSERT_EQ(all.start.size(), np + 1);
  EXPECT_EQ(starOf(all, 4), (std::vector<int>{ 0, 1, 2, 3 }));
  EXPECT_EQ(starOf(all, 1), (std::vector<int>{ 0, 1, 4 }));
  EXPECT_EQ(starOf(all, 5), (std::vector<int>{ 4 }));
  EXPECT_EQ(all.items.size(), 3 * triangles.size());

  std::vector<char> only(np, 0);
  only[1] = only[5] = 1;
  const strata::PointStars some = strata::pointStars(np, triangles, &only);
  ASSERT_EQ(some.start.size(), np + 1);
  for (int v = 0; v < static_cast<int>(np); ++v)
  {
    EXPECT_EQ(starOf(some, v), only[v] ? starOf(all, v) : std::vector<int>()) << "point " << v;
  }
  EXPECT_EQ(some.items.size(), 4u);
}

TEST(DelaunayRefinementTest, PointStarsTickEveryBlockOfTrianglesInBothPassesWithTheSameStars)
{
  // A strip of 2.5 blocks' triangles: the tick (a progress report) runs every kStarsTick
  // triangles of the count and of the placing, and the stars are those made without it.
  strata::LargeVector<std::array<int, 3>> triangles;
  const int n = static_cast<int>(5 * strata::kStarsTick / 2);
  for (int t = 0; t < n; ++t)
  {
    triangles.push_back(t % 2 == 0 ? std::array<int, 3>{ t / 2, t / 2 + 1, t / 2 + n }
                                   : std::array<int, 3>{ t / 2 + 1, t / 2 + n + 1, t / 2 + n });
  }
  const std::size_t np = static_cast<std::size_t>(2 * n + 2);
  int ticks = 0;
  const strata::PointStars ticked =
    strata::pointStars(np, triangles, nullptr, [&ticks] { ++ticks; });
  EXPECT_EQ(ticks, 4); // two in each pass
  const strata::PointStars plain = strata::pointStars(np, triangles);
  EXPECT_EQ(ticked.start, plain.start);
  EXPECT_EQ(ticked.items, plain.items);
  // A tick that throws (an abort) ends the call with its exception.
  EXPECT_THROW(
    strata::pointStars(np, triangles, nullptr, [] { throw strata::Aborted(); }), strata::Aborted);
}

// PlaceTable (CallTables.h): a call of 5000 keys drawn at random (some share a slot, and
// probe past it), then a call of three, then one of 48 keys drawn at random in its 128 slots:
// each call finds the places of its own keys, and none of the keys of the calls before.
TEST(DelaunayRefinementTest, APlaceTableGivesThePlacesOfItsCallsKeysOnly)
{
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> draw(0, 1 << 30);
  const auto distinct = [&](std::size_t n)
  {
    std::set<int> keys;
    while (keys.size() < n)
    {
      keys.insert(draw(rng));
    }
    std::vector<int> list(keys.begin(), keys.end());
    std::shuffle(list.begin(), list.end(), rng);
    return list;
  };
  strata::PlaceTable table;
  // A call of `keys`, each at its place in the list; then each is found there.
  const auto call = [&table](const std::vector<int>& keys)
  {
    table.begin(keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i)
    {
      table.insert(keys[i], static_cast<int>(i));
    }
    std::size_t found = 0;
    for (std::size_t i = 0; i < keys.size(); ++i)
    {
      found += table.find(keys[i]) == static_cast<int>(i);
    }
    return found;
  };
  const std::vector<int> first = distinct(5000);
  EXPECT_EQ(call(first), first.size());
  const std::set<int> firstKeys(first.begin(), first.end());
  for (int i = 0; i < 5000; ++i)
  {
    const int other = draw(rng);
    ASSERT_TRUE(firstKeys.count(other) > 0 || table.find(other) == -1) << other;
  }
  table.begin(3);
  table.insert(first[7], 2);
  table.insert(42, 0);
  EXPECT_EQ(table.find(first[7]), 2);
  EXPECT_EQ(table.find(42), 0);
  EXPECT_EQ(table.find(first[0]), -1); // (the first call's)
  EXPECT_EQ(table.find(first[4999]), -1);
  const std::vector<int> third = distinct(48);
  EXPECT_EQ(call(third), third.size());
  ASSERT_EQ(std::count(third.begin(), third.end(), first[7]), 0);
  EXPECT_EQ(table.find(first[7]), -1); // (the second call's)
}

// VertexMemo (CallTables.h): a vertex's values are worked out once per call, again in the next
// call, and again after another vertex of the call took its slot (the index kMemoSlots apart):
// each vertex always gets its own values.
TEST(DelaunayRefinementTest, AVertexMemoGivesEachVertexItsOwnValuesWorkedOutOncePerCall)
{
  strata::VertexMemo memo;
  int worked = 0;
  const auto of = [&worked](int v)
  {
    return [&worked, v](std::array<double, 2>& values)
    {
      ++worked;
      values = { static_cast<double>(v), -static_cast<double>(v) };
    };
  };
  const int v = 5, w = 5 + static_cast<int>(strata::VertexMemo::kMemoSlots); // (one slot)
  memo.begin();
  EXPECT_EQ(memo.get(v, of(v))[0], 5.0);
  EXPECT_EQ(memo.get(v, of(v))[1], -5.0);
  EXPECT_EQ(worked, 1);
  EXPECT_EQ(memo.get(w, of(w))[0], static_cast<double>(w));
  EXPECT_EQ(worked, 2);
  EXPECT_EQ(memo.get(v, of(v))[0], 5.0);
  EXPECT_EQ(worked, 3);
  EXPECT_EQ(memo.get(6, of(6))[1], -6.0);
  EXPECT_EQ(worked, 4);
  memo.begin();
  EXPECT_EQ(memo.get(v, of(v))[0], 5.0);
  EXPECT_EQ(worked, 5);
}

TEST(DelaunayRefinementTest, AnArcIndexGivesTheArcsOfAWalkAlongTheLine)
{
  // Zigzag polylines (a picked horizon's jitter), along x and along y, asked at their points,
  // at points on their segments (where two segments meet, or the line comes back near itself),
  // and beside them: the index gives what arcAlong's walk gives, value for value.
  std::mt19937 random(7);
  std::normal_distribution<double> jitter(0.0, 1.5);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  for (const bool vertical : { false, true })
  {
    std::vector<Vec2> line;
    for (int i = 0; i < 2000; ++i)
    {
      const double a = 0.5 * i + 3000.0, b = jitter(random) + 1e5;
      line.push_back(vertical ? Vec2{ b, a } : Vec2{ a, b });
    }
    for (int k = 0; k < 40; ++k) // and a stretch doubling back along itself
    {
      line.push_back(line[line.size() - 2 - 2 * k]);
    }
    const double tol = 1e-9 * 1e5;
    strata::ArcIndex index(line);
    std::vector<Vec2> asked;
    for (std::size_t j = 0; j + 1 < line.size(); ++j)
    {
      const double u = along(random);
      asked.push_back(line[j]);
      asked.push_back(line[j] + u * (line[j + 1] - line[j]));
      asked.push_back(line[j] + u * (line[j + 1] - line[j]) + Vec2{ 3 * tol, -2 * tol });
      asked.push_back(line[j] + Vec2{ jitter(random), jitter(random) });
    }
    int found = 0;
    for (const Vec2& p : asked)
    {
      const double walked = strata::arcAlong(line, p, tol);
      EXPECT_EQ(index.arc(p, tol), walked) << "at (" << p.x << ", " << p.y << ")";
      found += walked >= 0.0;
    }
    // (Most of the points on the line are found, most beside it not: both kinds were asked.)
    EXPECT_GT(found, static_cast<int>(asked.size()) / 3);
    EXPECT_LT(found, static_cast<int>(asked.size()) * 3 / 4);
  }
}
