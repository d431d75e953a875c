// Tests of the adaptive 4-8 grid: invariants of the mesh (conforming, tiling, exact angles,
// levels of neighbours), the multi-resolution hierarchy (nested conforming levels), the
// refinement criteria against independent brute-force checks, resuming, parameters.
#include "Grid48.h"

#include "CoreTestUtilities.h"
#include "DistanceField.h"
#include "Errors.h"
#include "GridSession.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace
{

using strata::Box2;
using strata::Grid48;
using strata::Grid48Params;
using strata::TriangleMesh;
using strata::Vec2;

using Loaded = strata_test::LoadedModel;

const Loaded& load(const std::string& name)
{
  return strata_test::loadModelAndField(name);
}

// Every model in Data/ but the 5872-point Lake Superior (only the defaults test uses it).
const std::vector<std::string>& allModels()
{
  static const std::vector<std::string> models = { "countries_westeurope.vtp",
    "countries_westeurope_loops.vtp",
    "geology_marmousi.vtp",
    "guitar.vtp",
    "gulf_section.vtp",
    "gulf_section_loops.vtp",
    "lake_superior.vtp",
    "nested_holes.vtp",
    "pinch_out.vtp",
    "salt_dome.vtp",
    "salt_dome_loops.vtp",
    "thin_layer.vtp",
    "touching_loops.vtp" };
  return models;
}

// Small explicit levels keep the brute-force checks fast: maxLevel 12, localMaxLevel 15.
Grid48Params smallParams()
{
  Grid48Params p;
  p.maxLevel = 12;
  p.localMaxLevel = 15;
  return p;
}

using Lattice = std::array<std::int64_t, 2>;

Lattice lattice(const Grid48& grid, const TriangleMesh& mesh, int point)
{
  const auto l = grid.vertexLattice(mesh.pointVertex[point]);
  return { static_cast<std::int64_t>(l[0]), static_cast<std::int64_t>(l[1]) };
}

double area(const TriangleMesh& mesh, int t)
{
  const auto& tri = mesh.triangles[t];
  return 0.5 * strata::orient2d(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
}

std::uint64_t edgeKey(int a, int b)
{
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) |
    static_cast<std::uint32_t>(std::max(a, b));
}

// Conforming, tiling, exact angles, neighbour levels; every failure names the triangle.
void expectValidMesh(const Grid48& grid, const TriangleMesh& mesh, const std::string& what)
{
  SCOPED_TRACE(what);
  const std::size_t nt = mesh.triangles.size();
  ASSERT_EQ(mesh.triangleLevel.size(), nt);
  ASSERT_EQ(mesh.triangleNode.size(), nt);
  ASSERT_EQ(mesh.pointVertex.size(), mesh.points.size());
  ASSERT_EQ(mesh.pointLevel.size(), mesh.points.size());
  const std::int64_t n = std::int64_t(1) << 31;

  // Exact right isosceles triangles, counter-clockwise, right angle first; and in doubles.
  double total = 0.0;
  for (std::size_t t = 0; t < nt; ++t)
  {
    const auto& tri = mesh.triangles[t];
    const Lattice a = lattice(grid, mesh, tri[0]);
    const Lattice b = lattice(grid, mesh, tri[1]);
    const Lattice c = lattice(grid, mesh, tri[2]);
    const std::int64_t e1x = b[0] - a[0], e1y = b[1] - a[1];
    const std::int64_t e2x = c[0] - a[0], e2y = c[1] - a[1];
    ASSERT_EQ(e1x * e2x + e1y * e2y, 0) << "triangle " << t << " has no exact right angle";
    ASSERT_EQ(e1x * e1x + e1y * e1y, e2x * e2x + e2y * e2y) << "triangle " << t;
    ASSERT_GT(static_cast<__int128>(e1x) * e2y - static_cast<__int128>(e1y) * e2x, 0)
      << "triangle " << t << " is not counter-clockwise";
    // The legs of level l are side / 2^((l + 1) / 2) long (half-diagonals at even levels).
    const int level = mesh.triangleLevel[t];
    const double leg = grid.hypotenuseLength(level) / std::sqrt(2.0);
    const Vec2 pa = mesh.points[tri[0]], pb = mesh.points[tri[1]], pc = mesh.points[tri[2]];
    const double l1 = strata::norm(pb - pa), l2 = strata::norm(pc - pa);
    EXPECT_NEAR(l1 / leg, 1.0, 1e-12) << "triangle " << t << " level " << level;
    EXPECT_NEAR(l2 / leg, 1.0, 1e-12) << "triangle " << t;
    EXPECT_NEAR(strata::dot(pb - pa, pc - pa) / (l1 * l2), 0.0, 1e-12) << "angle at the apex";
    const double cos45 = strata::dot(pa - pb, pc - pb) / (l1 * strata::norm(pc - pb));
    EXPECT_NEAR(cos45, std::sqrt(0.5), 1e-12) << "triangle " << t;
    total += area(mesh, static_cast<int>(t));
  }
  EXPECT_NEAR(total / (grid.side() * grid.side()), 1.0, 1e-12) << "the triangles do not tile";

  // Each edge in two triangles, or in one on the square's border; levels differ by <= 1.
  std::unordered_map<std::uint64_t, std::pair<int, int>> edges; // key -> (count, a level)
  edges.reserve(2 * nt);
  for (std::size_t t = 0; t < nt; ++t)
  {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      auto& e = edges[edgeKey(tri[k], tri[(k + 1) % 3])];
      if (e.first == 1)
      {
        EXPECT_LE(std::abs(e.second - mesh.triangleLevel[t]), 1)
          << "neighbours of levels " << e.second << " and " << mesh.triangleLevel[t];
      }
      ++e.first;
      e.second = mesh.triangleLevel[t];
    }
  }
  for (const auto& [key, e] : edges)
  {
    const Lattice a = lattice(grid, mesh, static_cast<int>(key >> 32));
    const Lattice b = lattice(grid, mesh, static_cast<int>(key & 0xffffffffu));
    const bool border =
      (a[0] == b[0] && (a[0] == 0 || a[0] == n)) || (a[1] == b[1] && (a[1] == 0 || a[1] == n));
    ASSERT_EQ(e.first, border ? 1 : 2) << "edge (" << a[0] << "," << a[1] << ")-(" << b[0] << ","
                                       << b[1] << ") is in " << e.first << " triangles";
  }

  // No vertex inside an edge (hanging vertex): buckets of points, exact lattice tests.
  const int buckets = 256;
  std::unordered_map<std::int64_t, std::vector<int>> bucket;
  auto bucketOf = [&](std::int64_t x)
  { return std::min<std::int64_t>(buckets - 1, x * buckets / n); };
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const Lattice p = lattice(grid, mesh, static_cast<int>(i));
    bucket[bucketOf(p[0]) * buckets + bucketOf(p[1])].push_back(static_cast<int>(i));
  }
  for (const auto& [key, e] : edges)
  {
    const Lattice a = lattice(grid, mesh, static_cast<int>(key >> 32));
    const Lattice b = lattice(grid, mesh, static_cast<int>(key & 0xffffffffu));
    for (std::int64_t bx = bucketOf(std::min(a[0], b[0])); bx <= bucketOf(std::max(a[0], b[0]));
         ++bx)
    {
      for (std::int64_t by = bucketOf(std::min(a[1], b[1])); by <= bucketOf(std::max(a[1], b[1]));
           ++by)
      {
        const auto it = bucket.find(bx * buckets + by);
        if (it == bucket.end())
        {
          continue;
        }
        for (const int q : it->second)
        {
          const Lattice p = lattice(grid, mesh, q);
          if (p == a || p == b)
          {
            continue;
          }
          const __int128 cr = static_cast<__int128>(b[0] - a[0]) * (p[1] - a[1]) -
            static_cast<__int128>(b[1] - a[1]) * (p[0] - a[0]);
          const __int128 dt = static_cast<__int128>(p[0] - a[0]) * (b[0] - a[0]) +
            static_cast<__int128>(p[1] - a[1]) * (b[1] - a[1]);
          const __int128 len2 = static_cast<__int128>(b[0] - a[0]) * (b[0] - a[0]) +
            static_cast<__int128>(b[1] - a[1]) * (b[1] - a[1]);
          ASSERT_FALSE(cr == 0 && dt > 0 && dt < len2)
            << "point (" << p[0] << "," << p[1] << ") hangs on an edge";
        }
      }
    }
  }

  // One vertex per lattice point.
  std::set<Lattice> distinct;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    distinct.insert(lattice(grid, mesh, static_cast<int>(i)));
  }
  EXPECT_EQ(distinct.size(), mesh.points.size()) << "two vertices share a lattice point";
}

// The grid's own neighbour links between leaves are symmetric and match shared edges.
void expectConsistentNeighbours(const Grid48& grid)
{
  for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
  {
    if (!grid.isLeaf(t))
    {
      continue;
    }
    const auto& v = grid.nodeVertices(t);
    const auto& nb = grid.nodeNeighbours(t);
    // Edge k is opposite... (v1, v2), (v2, v0), (v0, v1).
    const int ends[3][2] = { { v[1], v[2] }, { v[2], v[0] }, { v[0], v[1] } };
    for (int k = 0; k < 3; ++k)
    {
      if (nb[k] < 0)
      {
        continue;
      }
      ASSERT_TRUE(grid.isLeaf(nb[k])) << "leaf " << t << " links to inner node " << nb[k];
      const auto& w = grid.nodeVertices(nb[k]);
      const std::set<int> mine = { ends[k][0], ends[k][1] };
      int shared = 0;
      for (int j = 0; j < 3; ++j)
      {
        shared += mine.count(w[j]) ? 1 : 0;
      }
      ASSERT_EQ(shared, 2) << "leaf " << t << " and its neighbour " << nb[k] << " share no edge";
      const auto& back = grid.nodeNeighbours(nb[k]);
      ASSERT_TRUE(back[0] == t || back[1] == t || back[2] == t) << "link is not symmetric";
    }
  }
}

// Every extracted level is valid and nested: each coarse triangle is exactly the union of the
// finest triangles below it (by the hierarchy and by area).
void expectNestedLevels(const Grid48& grid, const TriangleMesh& finest, const std::string& what)
{
  for (int level = 0; level <= grid.maxLeafLevel(); ++level)
  {
    const TriangleMesh coarse = grid.extract(level);
    expectValidMesh(grid, coarse, what + ", level " + std::to_string(level));
    if (::testing::Test::HasFatalFailure())
    {
      return;
    }
    std::unordered_map<int, double> coarseArea;
    for (std::size_t t = 0; t < coarse.triangles.size(); ++t)
    {
      const int node = coarse.triangleNode[t];
      EXPECT_TRUE(
        coarse.triangleLevel[t] == level || (grid.isLeaf(node) && coarse.triangleLevel[t] < level));
      coarseArea[node] = area(coarse, static_cast<int>(t));
    }
    std::unordered_map<int, double> covered;
    for (std::size_t t = 0; t < finest.triangles.size(); ++t)
    {
      int node = finest.triangleNode[t];
      while (grid.nodeLevel(node) > level)
      {
        node = grid.nodeParent(node);
      }
      ASSERT_TRUE(coarseArea.count(node))
        << "finest triangle " << t << " has no ancestor at level " << level;
      covered[node] += area(finest, static_cast<int>(t));
    }
    ASSERT_EQ(covered.size(), coarseArea.size());
    for (const auto& [node, a] : coarseArea)
    {
      EXPECT_NEAR(covered[node] / a, 1.0, 1e-12) << "node " << node << " at level " << level;
    }
  }
}

// Polyline vertices in the closed triangle abc.
int verticesIn(const std::vector<Vec2>& sortedByX, Vec2 a, Vec2 b, Vec2 c)
{
  const double x0 = std::min({ a.x, b.x, c.x }), x1 = std::max({ a.x, b.x, c.x });
  auto it = std::lower_bound(
    sortedByX.begin(), sortedByX.end(), x0, [](const Vec2& p, double x) { return p.x < x; });
  int count = 0;
  for (; it != sortedByX.end() && it->x <= x1; ++it)
  {
    const Vec2 p = *it;
    if (strata::orient2d(a, b, p) >= 0 && strata::orient2d(b, c, p) >= 0 &&
      strata::orient2d(c, a, p) >= 0)
    {
      ++count;
    }
  }
  return count;
}

TEST(Grid48Test, level0_is_four_right_triangles_around_the_centre)
{
  const Grid48 grid(Box2{ { 0, 0 }, { 10, 4 } });
  EXPECT_EQ(grid.numberOfLeaves(), 4u);
  EXPECT_EQ(grid.numberOfVertices(), 5u);
  EXPECT_DOUBLE_EQ(grid.side(), 11.0); // larger side 10 plus 5 % on each side
  EXPECT_DOUBLE_EQ(grid.origin().x, -0.5);
  EXPECT_DOUBLE_EQ(grid.origin().y, 2.0 - 5.5);
  const TriangleMesh mesh = grid.extract();
  ASSERT_EQ(mesh.triangles.size(), 4u);
  for (const auto& tri : mesh.triangles)
  {
    EXPECT_EQ(mesh.points[tri[0]], (Vec2{ 5.0, 2.0 })); // the centre is every right angle
  }
  expectValidMesh(grid, mesh, "level 0");
}

TEST(Grid48Test, refinement_with_any_criterion_is_conforming_and_nested)
{
  // Hand-made criteria: refine towards a point, along a circle, and at random.
  Grid48 grid(Box2{ { -1, -1 }, { 1, 1 } }, 0.0);
  auto nearPoint = [](const Grid48& g, int node)
  {
    const auto& v = g.nodeVertices(node);
    const Vec2 a = g.vertexPosition(v[0]), b = g.vertexPosition(v[1]), c = g.vertexPosition(v[2]);
    const Vec2 p{ 0.3, -0.2 };
    return strata::orient2d(a, b, p) >= 0 && strata::orient2d(b, c, p) >= 0 &&
      strata::orient2d(c, a, p) >= 0;
  };
  grid.refineWhere(nearPoint, 24);
  EXPECT_EQ(grid.maxLeafLevel(), 24);
  TriangleMesh mesh = grid.extract();
  expectValidMesh(grid, mesh, "point");
  expectConsistentNeighbours(grid);
  expectNestedLevels(grid, mesh, "point");

  auto circle = [](const Grid48& g, int node)
  {
    const auto& v = g.nodeVertices(node);
    int inside = 0;
    for (int k = 0; k < 3; ++k)
    {
      inside += strata::norm(g.vertexPosition(v[k])) < 0.7 ? 1 : 0;
    }
    return inside != 0 && inside != 3;
  };
  grid.refineWhere(circle, 14);
  std::uint32_t state = 12345;
  auto random = [&state](const Grid48&, int)
  {
    state = state * 1664525u + 1013904223u;
    return (state >> 28) == 0; // one in 16
  };
  grid.refineWhere(random, 18);
  mesh = grid.extract();
  expectValidMesh(grid, mesh, "circle and random");
  expectConsistentNeighbours(grid);
  expectNestedLevels(grid, mesh, "circle and random");
  EXPECT_EQ(grid.numberOfLeaves(), mesh.triangles.size());
}

TEST(Grid48Test, refinement_is_conforming_on_every_model)
{
  for (const std::string& name : allModels())
  {
    const Loaded& m = load(name);
    const Grid48 grid = Grid48::build(m.model, *m.field, smallParams());
    const TriangleMesh mesh = grid.extract();
    expectValidMesh(grid, mesh, name);
    expectConsistentNeighbours(grid);
    ASSERT_FALSE(HasFatalFailure()) << name;
  }
}

TEST(Grid48Test, default_parameters_give_a_valid_grid_on_every_model)
{
  std::vector<std::string> models = allModels();
  models.push_back("lake_superior_full.vtp");
  for (const std::string& name : models)
  {
    const Loaded& m = load(name);
    const Grid48 grid = Grid48::build(m.model, *m.field);
    const Grid48Params& p = grid.params();
    EXPECT_GE(p.maxLevel, 10) << name;
    EXPECT_LE(p.maxLevel, 20) << name;
    EXPECT_EQ(p.localMaxLevel, p.maxLevel + 4) << name;
    EXPECT_DOUBLE_EQ(p.tolerance, 1e-3 * grid.hypotenuseLength(p.maxLevel)) << name;
    EXPECT_EQ(p.junctionMaxLevel, p.localMaxLevel + 8) << name;
    // Beyond localMaxLevel only to separate close junctions.
    EXPECT_LE(grid.maxLeafLevel(), p.junctionMaxLevel) << name;
    EXPECT_GT(grid.numberOfLeaves(), 1000u) << name;
    EXPECT_LT(grid.numberOfLeaves(), 200000u) << name;
    const TriangleMesh mesh = grid.extract();
    expectValidMesh(grid, mesh, name);
    ASSERT_FALSE(HasFatalFailure()) << name;
  }
}

TEST(Grid48Test, extracted_levels_are_conforming_and_nested)
{
  for (const std::string name : { "salt_dome.vtp", "pinch_out.vtp", "countries_westeurope.vtp" })
  {
    const Loaded& m = load(name);
    Grid48Params p;
    p.maxLevel = 10;
    p.localMaxLevel = 14;
    const Grid48 grid = Grid48::build(m.model, *m.field, p);
    expectNestedLevels(grid, grid.extract(), name);
    ASSERT_FALSE(HasFatalFailure()) << name;
    EXPECT_EQ(grid.extract(grid.maxLeafLevel()).triangles.size(), grid.numberOfLeaves());
    EXPECT_EQ(grid.extract(-1).triangles.size(), grid.numberOfLeaves());
    EXPECT_EQ(grid.extract(0).triangles.size(), 4u);
  }
}

TEST(Grid48Test, global_criterion_leaves_no_splittable_leaf_below_max_level)
{
  for (const std::string& name : allModels())
  {
    const Loaded& m = load(name);
    Grid48Params p = smallParams();
    p.localRefinement = false;
    p.thinRegionRefinement = false;
    p.junctionRefinement = false;
    for (const double tolerance : { 0.0, 0.02 })
    {
      p.tolerance = tolerance * m.model.size();
      const Grid48 grid = Grid48::build(m.model, *m.field, p);
      const double tol = grid.params().tolerance;
      strata::DistanceField::Scratch scratch;
      int checked = 0;
      for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
      {
        const int level = grid.nodeLevel(t);
        const double h = grid.hypotenuseLength(level);
        const auto& v = grid.nodeVertices(t);
        const Vec2 q = 0.5 * (grid.vertexPosition(v[1]) + grid.vertexPosition(v[2]));
        const double d = m.field->boundaryDistance(q, scratch);
        const bool wants = level < p.maxLevel && d > tol && h > d;
        if (grid.isLeaf(t))
        {
          ASSERT_FALSE(wants) << name << ": leaf " << t << " of level " << level << " h " << h
                              << " d " << d;
          ++checked;
        }
      }
      EXPECT_EQ(checked, static_cast<int>(grid.numberOfLeaves()));
      // Without local refinement nothing is finer than maxLevel.
      EXPECT_LE(grid.maxLeafLevel(), p.maxLevel) << name;
    }
  }
}

TEST(Grid48Test, local_criterion_leaves_no_two_polygon_vertices_in_a_triangle)
{
  for (const std::string& name : allModels())
  {
    const Loaded& m = load(name);
    const Grid48Params p = smallParams();
    const Grid48 grid = Grid48::build(m.model, *m.field, p);
    std::vector<Vec2> nodes = m.model.nodes;
    std::sort(nodes.begin(), nodes.end(), [](const Vec2& a, const Vec2& b) { return a.x < b.x; });
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      if (!grid.isLeaf(t) || grid.nodeLevel(t) >= p.localMaxLevel)
      {
        continue;
      }
      const auto& v = grid.nodeVertices(t);
      const int count = verticesIn(
        nodes, grid.vertexPosition(v[0]), grid.vertexPosition(v[1]), grid.vertexPosition(v[2]));
      ASSERT_LE(count, 1) << name << ": leaf " << t << " of level " << grid.nodeLevel(t);
    }
  }
}

// Boundary curves as the test sees them: distinct segments chained through nodes of degree 2.
struct TestCurves
{
  std::vector<Vec2> a, b;
  std::vector<int> curve;
};

TestCurves curvesOf(const strata::Model& model)
{
  std::map<std::pair<int, int>, int> segments;
  std::vector<std::pair<int, int>> ends;
  for (const strata::Curve& c : model.curves)
  {
    const std::size_t n = c.nodes.size();
    for (std::size_t i = 0; i + (c.closed ? 0 : 1) < n; ++i)
    {
      const int u = c.nodes[i], w = c.nodes[(i + 1) % n];
      if (u != w && segments.emplace(std::minmax(u, w), static_cast<int>(ends.size())).second)
      {
        ends.push_back({ u, w });
      }
    }
  }
  std::vector<int> degree(model.nodes.size(), 0);
  for (const auto& e : ends)
  {
    ++degree[e.first];
    ++degree[e.second];
  }
  // Union the two segments at every node of degree 2.
  std::vector<int> parent(ends.size());
  for (std::size_t i = 0; i < parent.size(); ++i)
  {
    parent[i] = static_cast<int>(i);
  }
  auto find = [&](int i)
  {
    while (parent[i] != i)
    {
      i = parent[i] = parent[parent[i]];
    }
    return i;
  };
  std::vector<int> firstAt(model.nodes.size(), -1);
  for (std::size_t s = 0; s < ends.size(); ++s)
  {
    for (const int node : { ends[s].first, ends[s].second })
    {
      if (degree[node] != 2)
      {
        continue;
      }
      if (firstAt[node] < 0)
      {
        firstAt[node] = static_cast<int>(s);
      }
      else
      {
        parent[find(static_cast<int>(s))] = find(firstAt[node]);
      }
    }
  }
  TestCurves out;
  for (std::size_t s = 0; s < ends.size(); ++s)
  {
    out.a.push_back(model.nodes[ends[s].first]);
    out.b.push_back(model.nodes[ends[s].second]);
    out.curve.push_back(find(static_cast<int>(s)));
  }
  return out;
}

bool segmentMeetsTriangle(Vec2 p, Vec2 q, Vec2 a, Vec2 b, Vec2 c)
{
  auto inside = [&](Vec2 x)
  {
    return strata::orient2d(a, b, x) >= 0 && strata::orient2d(b, c, x) >= 0 &&
      strata::orient2d(c, a, x) >= 0;
  };
  if (inside(p) || inside(q))
  {
    return true;
  }
  auto crosses = [](Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2)
  {
    if (std::max(p1.x, p2.x) < std::min(q1.x, q2.x) ||
      std::max(q1.x, q2.x) < std::min(p1.x, p2.x) || std::max(p1.y, p2.y) < std::min(q1.y, q2.y) ||
      std::max(q1.y, q2.y) < std::min(p1.y, p2.y))
    {
      return false;
    }
    const double o1 = strata::orient2d(p1, p2, q1), o2 = strata::orient2d(p1, p2, q2);
    const double o3 = strata::orient2d(q1, q2, p1), o4 = strata::orient2d(q1, q2, p2);
    return ((o1 >= 0 && o2 <= 0) || (o1 <= 0 && o2 >= 0)) &&
      ((o3 >= 0 && o4 <= 0) || (o3 <= 0 && o4 >= 0));
  };
  return crosses(p, q, a, b) || crosses(p, q, b, c) || crosses(p, q, c, a);
}

TEST(Grid48Test, local_criterion_leaves_no_triangle_crossed_by_two_curves)
{
  for (const std::string name : { "salt_dome.vtp",
         "salt_dome_loops.vtp",
         "pinch_out.vtp",
         "thin_layer.vtp",
         "geology_marmousi.vtp",
         "countries_westeurope_loops.vtp" })
  {
    const Loaded& m = load(name);
    const Grid48Params p = smallParams();
    const Grid48 grid = Grid48::build(m.model, *m.field, p);
    const TestCurves curves = curvesOf(m.model);
    int crossedByOne = 0;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      if (!grid.isLeaf(t) || grid.nodeLevel(t) >= p.localMaxLevel)
      {
        continue;
      }
      const auto& v = grid.nodeVertices(t);
      const Vec2 a = grid.vertexPosition(v[0]), b = grid.vertexPosition(v[1]),
                 c = grid.vertexPosition(v[2]);
      std::set<int> hit;
      for (std::size_t s = 0; s < curves.a.size(); ++s)
      {
        if (segmentMeetsTriangle(curves.a[s], curves.b[s], a, b, c))
        {
          hit.insert(curves.curve[s]);
        }
      }
      ASSERT_LE(hit.size(), 1u) << name << ": leaf " << t << " of level " << grid.nodeLevel(t);
      crossedByOne += hit.size() == 1 ? 1 : 0;
    }
    EXPECT_GT(crossedByOne, 0) << name;
  }
}

TEST(Grid48Test, thin_region_refinement_resolves_a_thin_lens_bounded_by_one_curve)
{
  // One closed curve: a lens 0.02 thick and 2 long in a 4 x 4 square region (Loops form: the
  // lens is region 1's loop and region 0's hole).
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  strata_test::addClosedLoop(raw, { { -2, -2 }, { 2, -2 }, { 2, 2 }, { -2, 2 } }, 0);
  const std::vector<Vec2> lens{ { -1, 0.011 }, { 1, 0.011 }, { 1, 0.031 }, { -1, 0.031 } };
  strata_test::addClosedLoop(raw, lens, 0);
  strata_test::addClosedLoop(raw, lens, 1);
  const strata::Model model = strata::buildModel(raw);
  const strata::DistanceField field(model);
  Grid48Params p;
  p.maxLevel = 6;
  p.localMaxLevel = 20;
  p.thinRegionRefinement = false;
  const Grid48 without = Grid48::build(model, field, p);
  p.thinRegionRefinement = true;
  const Grid48 with = Grid48::build(model, field, p);
  EXPECT_GT(with.numberOfLeaves(), without.numberOfLeaves());
  // With the rule, no leaf below localMaxLevel holds both long sides of the lens.
  for (int t = 0; t < static_cast<int>(with.numberOfNodes()); ++t)
  {
    if (!with.isLeaf(t) || with.nodeLevel(t) >= p.localMaxLevel)
    {
      continue;
    }
    const auto& v = with.nodeVertices(t);
    const Vec2 a = with.vertexPosition(v[0]), b = with.vertexPosition(v[1]),
               c = with.vertexPosition(v[2]);
    EXPECT_FALSE(segmentMeetsTriangle({ -0.9, 0.011 }, { 0.9, 0.011 }, a, b, c) &&
      segmentMeetsTriangle({ -0.9, 0.031 }, { 0.9, 0.031 }, a, b, c))
      << "leaf " << t << " of level " << with.nodeLevel(t);
  }
  expectValidMesh(with, with.extract(), "lens");
}

// A 4 x 4 square cut by two horizontal layers (Loops form): A, from y = -1 to -0.98, is 0.02
// thick (about three finest legs of the junction level 18), B, from 1 to 1.004, 0.004 (below
// the finest leg, about 0.0061). Both are far thinner than the legs of localMaxLevel 10 (about
// 0.097).
strata::RawPolylines twoThinLayers()
{
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  const auto band = [&](double y0, double y1, int region) {
    strata_test::addClosedLoop(raw, { { -2, y0 }, { 2, y0 }, { 2, y1 }, { -2, y1 } }, region);
  };
  band(-2, -1.0, 0);
  band(-1.0, -0.98, 1);
  band(-0.98, 1.0, 2);
  band(1.0, 1.004, 3);
  band(1.004, 2, 4);
  return raw;
}

// The grid of twoThinLayers() at maxLevel 6 and localMaxLevel 10, with `thin` as
// thinLayerRefinement and the given zones.
Grid48 twoThinLayersGrid(const strata::Model& model,
  const strata::DistanceField& field,
  bool thin,
  std::vector<Grid48Params::Zone> zones = {})
{
  Grid48Params p;
  p.maxLevel = 6;
  p.localMaxLevel = 10;
  p.thinLayerRefinement = thin;
  p.thinLayerZones = std::move(zones);
  return Grid48::build(model, field, p);
}

// The centroid of node t of the grid.
Vec2 nodeCentroid(const Grid48& grid, int t)
{
  const auto& v = grid.nodeVertices(t);
  return (1.0 / 3.0) *
    (grid.vertexPosition(v[0]) + grid.vertexPosition(v[1]) + grid.vertexPosition(v[2]));
}

TEST(Grid48Test, thin_layer_refinement_gives_a_layer_cells_as_wide_as_it_and_no_finer)
{
  const double a0 = -1.0, a1 = -0.98, b0 = 1.0, b1 = 1.004;
  const strata::Model model = strata::buildModel(twoThinLayers());
  const strata::DistanceField field(model);
  const Grid48 without = twoThinLayersGrid(model, field, false);
  const Grid48 with = twoThinLayersGrid(model, field, true);
  const Grid48Params& p = with.params();
  ASSERT_EQ(with.params().junctionMaxLevel, 18);
  const double finestLeg = with.hypotenuseLength(18) / std::sqrt(2.0);
  ASSERT_GT(a1 - a0, finestLeg);
  ASSERT_LT(b1 - b0, finestLeg);
  // Away from the border's junctions: the leaves that both sides of a layer cross (their
  // largest leg and finest level), and the leaves finer than localMaxLevel near a layer.
  struct Crossing
  {
    int leaves = 0;
    double largestLeg = 0.0;
    int finestLevel = 0;
    int fineNear = 0;
  };
  const auto crossing = [&](const Grid48& grid, double y0, double y1)
  {
    Crossing r;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      if (!grid.isLeaf(t))
      {
        continue;
      }
      const auto& v = grid.nodeVertices(t);
      const Vec2 a = grid.vertexPosition(v[0]), b = grid.vertexPosition(v[1]),
                 c = grid.vertexPosition(v[2]);
      const Vec2 g = (1.0 / 3.0) * (a + b + c);
      if (std::fabs(g.x) > 1.5)
      {
        continue;
      }
      if (std::fabs(g.y - 0.5 * (y0 + y1)) < 0.2 && grid.nodeLevel(t) > p.localMaxLevel)
      {
        ++r.fineNear;
      }
      if (segmentMeetsTriangle({ -2, y0 }, { 2, y0 }, a, b, c) &&
        segmentMeetsTriangle({ -2, y1 }, { 2, y1 }, a, b, c))
      {
        ++r.leaves;
        r.largestLeg =
          std::max(r.largestLeg, grid.hypotenuseLength(grid.nodeLevel(t)) / std::sqrt(2.0));
        r.finestLevel = std::max(r.finestLevel, grid.nodeLevel(t));
      }
    }
    return r;
  };
  // Without the option the layer A lies in cells far wider than it is thick, and nothing near
  // it is finer than localMaxLevel ...
  const Crossing aWithout = crossing(without, a0, a1);
  EXPECT_GT(aWithout.leaves, 0);
  EXPECT_GT(aWithout.largestLeg, 3.0 * (a1 - a0));
  EXPECT_EQ(aWithout.fineNear, 0);
  // ... with it, the cells near A are refined beyond localMaxLevel, and a cell holding both
  // sides of A is at most as wide as A is thick.
  const Crossing aWith = crossing(with, a0, a1);
  EXPECT_GT(aWith.fineNear, 0);
  EXPECT_LE(aWith.largestLeg, (a1 - a0) * (1.0 + 1e-9));
  EXPECT_LE(with.maxLeafLevel(), with.params().junctionMaxLevel);
  // B, thinner than the finest leg, is left to the local criterion (up to localMaxLevel).
  const Crossing bWith = crossing(with, b0, b1);
  EXPECT_GT(bWith.leaves, 0);
  EXPECT_LE(bWith.finestLevel, p.localMaxLevel);
  EXPECT_EQ(bWith.fineNear, 0);
  expectValidMesh(with, with.extract(), "thin layers");
}

// Thin layer zones: the refinement beyond localMaxLevel only around them (the places a mesh
// lost a piece of a layer); a zone away from any thin layer changes nothing.
TEST(Grid48Test, thin_layer_zones_keep_the_thin_layer_refinement_around_them)
{
  const strata::Model model = strata::buildModel(twoThinLayers());
  const strata::DistanceField field(model);
  const Grid48 without = twoThinLayersGrid(model, field, false);
  const Grid48 everywhere = twoThinLayersGrid(model, field, true);
  const Vec2 centre{ -1.0, -0.99 };
  const Grid48 zoned = twoThinLayersGrid(model, field, true, { { centre, 0.25 } });
  const int localMaxLevel = zoned.params().localMaxLevel;
  // The leaves finer than localMaxLevel along layer A, near the zone or away from it.
  const auto fine = [&](const Grid48& grid, bool nearZone)
  {
    int n = 0;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      const Vec2 g = nodeCentroid(grid, t);
      n += grid.isLeaf(t) && grid.nodeLevel(t) > localMaxLevel && std::fabs(g.y + 0.99) < 0.2 &&
        (std::fabs(g.x + 1.0) < 0.3) == nearZone && std::fabs(g.x) < 1.5;
    }
    return n;
  };
  ASSERT_GT(fine(everywhere, true), 0);
  ASSERT_GT(fine(everywhere, false), 0);
  EXPECT_EQ(fine(without, true), 0);
  EXPECT_GT(fine(zoned, true), 0);
  // Beyond the zone, widened by a few hypotenuses of localMaxLevel: as without the option.
  for (int t = 0; t < static_cast<int>(zoned.numberOfNodes()); ++t)
  {
    if (zoned.isLeaf(t) && zoned.nodeLevel(t) > localMaxLevel)
    {
      EXPECT_LT(strata::norm(nodeCentroid(zoned, t) - centre),
        0.25 + 3.0 * zoned.hypotenuseLength(localMaxLevel))
        << "leaf " << t;
    }
  }
  EXPECT_LT(zoned.numberOfNodes(), everywhere.numberOfNodes());
  expectValidMesh(zoned, zoned.extract(), "thin layer zone");

  const Grid48 away = twoThinLayersGrid(model, field, true, { { { 0.0, 0.0 }, 0.1 } });
  EXPECT_EQ(away.numberOfNodes(), without.numberOfNodes());
  EXPECT_THROW(twoThinLayersGrid(model, field, true, { { { 0.0, 0.0 }, std::nan("") } }),
    strata::ParameterError);
}

// A 4 x 4 square with a vertical tooth 0.02 wide astride the grid's line x = 0 (from -0.008 to
// 0.012, from the bottom to y = 1.5; the domain's centre is a vertex of every level from 2):
// every grid edge along x = 0 lies inside the tooth, so that no triangle beside it holds both of
// its sides (comb603 of random_junction_models.py, whose mesh cut such a tooth).
TEST(Grid48Test, thin_layer_refinement_finds_a_tooth_astride_the_grid_edges)
{
  const double x0 = -0.008, x1 = 0.012, top = 1.5;
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  strata_test::addClosedLoop(raw,
    { { -2, -2 },
      { x0, -2 },
      { x0, top },
      { x1, top },
      { x1, -2 },
      { 2, -2 },
      { 2, 2 },
      { -2, 2 } },
    0);
  strata_test::addClosedLoop(raw, { { x0, -2 }, { x1, -2 }, { x1, top }, { x0, top } }, 1);
  const strata::Model model = strata::buildModel(raw);
  const strata::DistanceField field(model);
  const Grid48 without = twoThinLayersGrid(model, field, false);
  const Grid48 with = twoThinLayersGrid(model, field, true);
  const double finestLeg = with.hypotenuseLength(with.params().junctionMaxLevel) / std::sqrt(2.0);
  ASSERT_GT(x1 - x0, finestLeg);
  // Away from the tooth's ends: the leaves crossed by a side of it (their largest leg), and
  // those crossed by both.
  struct Crossing
  {
    int leaves = 0;
    int both = 0;
    double largestLeg = 0.0;
  };
  const auto crossing = [&](const Grid48& grid)
  {
    Crossing r;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      const Vec2 g = nodeCentroid(grid, t);
      if (!grid.isLeaf(t) || g.y < -1.5 || g.y > 1.0)
      {
        continue;
      }
      const auto& v = grid.nodeVertices(t);
      const Vec2 a = grid.vertexPosition(v[0]), b = grid.vertexPosition(v[1]),
                 c = grid.vertexPosition(v[2]);
      const bool left = segmentMeetsTriangle({ x0, -2 }, { x0, top }, a, b, c);
      const bool right = segmentMeetsTriangle({ x1, -2 }, { x1, top }, a, b, c);
      if (left || right)
      {
        ++r.leaves;
        r.both += left && right;
        r.largestLeg =
          std::max(r.largestLeg, grid.hypotenuseLength(grid.nodeLevel(t)) / std::sqrt(2.0));
      }
    }
    return r;
  };
  // Without the option the tooth lies in cells far wider than it is, none holding both sides.
  const Crossing before = crossing(without);
  ASSERT_GT(before.leaves, 0);
  EXPECT_EQ(before.both, 0);
  EXPECT_GT(before.largestLeg, 3.0 * (x1 - x0));
  // With it, every cell either side of the tooth crosses is at most as wide as the tooth.
  const Crossing after = crossing(with);
  EXPECT_GT(after.leaves, before.leaves);
  EXPECT_LE(after.largestLeg, (x1 - x0) * (1.0 + 1e-9));
  EXPECT_LE(with.maxLeafLevel(), with.params().junctionMaxLevel);
  expectValidMesh(with, with.extract(), "tooth astride the grid's edges");
}

// BoundaryIndex::thinLayer beside a triangle: a box 4 x 2 with a tooth (region 1) from its left
// side along y = 0 (one curve from (0, 0) round the tooth back to the side), and triangles that
// its lower side crosses but its upper side does not meet; then two curves instead.
TEST(Grid48Test, a_curve_come_back_beside_a_triangle_is_a_thin_layer_two_curves_are_not)
{
  // The index of the model and whether thinLayer holds for the triangle abc (input
  // coordinates; the index's are the model's local ones).
  struct Indexed
  {
    strata::Model model;
    strata::BoundaryIndex index;
    bool thinLayer(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest)
    {
      const Vec2 o = this->model.origin;
      return this->index.thinLayer(a - o, b - o, c - o, thinnest, thickest);
    }
  };
  // The tooth's lower side from (0, 0) to (3.8, 0), its upper one from (3.8, right) to (0, left).
  const auto indexed = [](double right, double left)
  {
    strata::RawPolylines raw;
    raw.form = strata::ModelForm::Loops;
    raw.offsets.push_back(0);
    strata_test::addClosedLoop(raw,
      { { 0, -1 },
        { 4, -1 },
        { 4, 1 },
        { 0, 1 },
        { 0, left },
        { 3.8, right },
        { 3.8, 0 },
        { 0, 0 } },
      0);
    strata_test::addClosedLoop(raw, { { 0, 0 }, { 3.8, 0 }, { 3.8, right }, { 0, left } }, 1);
    strata::Model model = strata::buildModel(raw);
    strata::BoundaryIndex index(model);
    return Indexed{ std::move(model), std::move(index) };
  };
  const Vec2 a{ 1.8, -0.2 }, b{ 2.2, -0.2 }, c{ 2.0, 0.01 };
  // A tooth 0.02 thick beside the triangle: a layer between the bounds, not outside them.
  Indexed tooth = indexed(0.02, 0.02);
  EXPECT_TRUE(tooth.thinLayer(a, b, c, 0.001, 0.1));
  EXPECT_FALSE(tooth.thinLayer(a, b, c, 0.001, 0.015));
  EXPECT_FALSE(tooth.thinLayer(a, b, c, 0.03, 0.1));
  // Its end within `thickest` of the triangle joins its sides: no layer beside it there.
  EXPECT_FALSE(tooth.thinLayer({ 3.6, -0.2 }, { 4.0, -0.2 }, { 3.8, 0.01 }, 0.001, 0.1));
  // A tooth 0.3 thick, farther from the triangle than `thickest`.
  EXPECT_FALSE(indexed(0.3, 0.3).thinLayer(a, b, c, 0.001, 0.25));
  // A tooth widening to the left, its upper side 0.18 to 0.31 away along the part of y = 0
  // inside a flat triangle: a layer thinner than 0.35 there, not one thinner than 0.25 (it is
  // that close at one end only).
  Indexed widening = indexed(0.02, 0.5);
  const Vec2 fa{ 1.0, -0.01 }, fb{ 3.0, -0.01 }, fc{ 2.0, 0.01 };
  EXPECT_TRUE(widening.thinLayer(fa, fb, fc, 0.001, 0.35));
  EXPECT_FALSE(widening.thinLayer(fa, fb, fc, 0.001, 0.25));
  // A layer 0.02 thick between two curves across the box (ending on its sides): left to the
  // triangles that both cross.
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  strata_test::addClosedLoop(raw, { { 0, -1 }, { 4, -1 }, { 4, 0 }, { 0, 0 } }, 0);
  strata_test::addClosedLoop(raw, { { 0, 0 }, { 4, 0 }, { 4, 0.02 }, { 0, 0.02 } }, 1);
  strata_test::addClosedLoop(raw, { { 0, 0.02 }, { 4, 0.02 }, { 4, 1 }, { 0, 1 } }, 2);
  strata::Model model = strata::buildModel(raw);
  strata::BoundaryIndex index(model);
  Indexed layer{ std::move(model), std::move(index) };
  EXPECT_FALSE(layer.thinLayer(a, b, c, 0.001, 0.1));
  EXPECT_TRUE(layer.thinLayer(a, b, { 2.0, 0.3 }, 0.001, 0.1));
  // A square island 1 wide (a closed curve with no junction: its run of segments starts at
  // one of its corners) and a small triangle beside each corner, across one side: the curve
  // turning there is one strand, through the curve's start too.
  strata::RawPolylines islandRaw;
  islandRaw.form = strata::ModelForm::Loops;
  islandRaw.offsets.push_back(0);
  const std::vector<Vec2> square{ { 1, -0.5 }, { 2, -0.5 }, { 2, 0.5 }, { 1, 0.5 } };
  strata_test::addClosedLoop(islandRaw, { { 0, -1 }, { 4, -1 }, { 4, 1 }, { 0, 1 } }, 0);
  strata_test::addClosedLoop(islandRaw, square, 0);
  strata_test::addClosedLoop(islandRaw, square, 1);
  strata::Model islandModel = strata::buildModel(islandRaw);
  strata::BoundaryIndex islandIndex(islandModel);
  Indexed island{ std::move(islandModel), std::move(islandIndex) };
  for (const double x : { 1.03, 1.92 })
  {
    for (const double y : { -0.5, 0.5 })
    {
      EXPECT_FALSE(island.thinLayer(
        { x, y - 0.02 }, { x + 0.05, y - 0.02 }, { x + 0.025, y + 0.02 }, 0.001, 0.1))
        << "beside the corner near (" << x << ", " << y << ")";
    }
  }
}

TEST(Grid48Test, close_junctions_end_up_in_different_triangles)
{
  // gulf_section has junction pairs 0.7 m, 3.7 m and 10.9 m apart, among 60-180 m edges at
  // MaxLevel 10: each pair shares a triangle of localMaxLevel without the junction rule.
  const Loaded& m = load("gulf_section.vtp");
  std::vector<Vec2> junctions;
  for (int id : m.model.junctions)
  {
    junctions.push_back(m.model.nodes[id]);
  }
  std::sort(
    junctions.begin(), junctions.end(), [](const Vec2& a, const Vec2& b) { return a.x < b.x; });
  auto crowdedLeaves = [&](const Grid48& grid, int belowLevel)
  {
    int crowded = 0;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      if (!grid.isLeaf(t) || grid.nodeLevel(t) >= belowLevel)
      {
        continue;
      }
      const auto& v = grid.nodeVertices(t);
      if (verticesIn(junctions,
            grid.vertexPosition(v[0]),
            grid.vertexPosition(v[1]),
            grid.vertexPosition(v[2])) >= 2)
      {
        ++crowded;
      }
    }
    return crowded;
  };
  Grid48Params p;
  p.maxLevel = 10;
  p.junctionRefinement = false;
  const Grid48 without = Grid48::build(m.model, *m.field, p);
  EXPECT_EQ(without.params().junctionMaxLevel, 22); // localMaxLevel 14 + 8
  EXPECT_GT(crowdedLeaves(without, Grid48::MaxSupportedLevel + 1), 0);
  p.junctionRefinement = true;
  const Grid48 with = Grid48::build(m.model, *m.field, p);
  const int cap = with.params().junctionMaxLevel;
  EXPECT_EQ(crowdedLeaves(with, cap), 0);
  EXPECT_GT(with.maxLeafLevel(), with.params().localMaxLevel);
  EXPECT_LE(with.maxLeafLevel(), cap);
  // Cheap: a few hundred more leaves, not a refinement of the whole boundary.
  EXPECT_GT(with.numberOfLeaves(), without.numberOfLeaves());
  EXPECT_LT(with.numberOfLeaves(), without.numberOfLeaves() + 1000);
  expectValidMesh(with, with.extract(), "junctions");
  // Two junctions 1e-4 apart in a unit square, with and without the local rule: separated
  // up to the cap, never beyond it.
  // Four regions whose borders meet at two triple junctions j0 and j1 1e-4 apart.
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  const Vec2 j0{ 0.3, 0.5 }, j1{ 0.3001, 0.5 };
  strata_test::addClosedLoop(raw, { { 0, 0 }, { 0.3, 0 }, j0, { 0, 0.5 } }, 1);
  strata_test::addClosedLoop(raw, { { 0.3, 0 }, { 1, 0 }, { 1, 0.5 }, j1, j0 }, 2);
  strata_test::addClosedLoop(raw, { { 0, 0.5 }, j0, j1, { 0.3001, 1 }, { 0, 1 } }, 0);
  strata_test::addClosedLoop(raw, { j1, { 1, 0.5 }, { 1, 1 }, { 0.3001, 1 } }, 3);
  const strata::Model small = strata::buildModel(raw);
  const strata::DistanceField field(small);
  std::vector<Vec2> pair; // local coordinates
  for (int id : small.junctions)
  {
    pair.push_back(small.nodes[id]);
  }
  ASSERT_EQ(pair.size(), 6u); // j0, j1 and where the borders meet the square
  std::sort(pair.begin(), pair.end(), [](const Vec2& a, const Vec2& b) { return a.x < b.x; });
  for (bool local : { true, false })
  {
    Grid48Params q;
    q.maxLevel = 6;
    q.localMaxLevel = 10;
    q.localRefinement = local;
    q.junctionMaxLevel = 40;
    const Grid48 grid = Grid48::build(small, field, q);
    int crowded = 0;
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      const auto& v = grid.nodeVertices(t);
      crowded += grid.isLeaf(t) &&
        verticesIn(
          pair, grid.vertexPosition(v[0]), grid.vertexPosition(v[1]), grid.vertexPosition(v[2])) >=
          2;
    }
    EXPECT_EQ(crowded, 0) << "local " << local;
    EXPECT_GT(grid.maxLeafLevel(), 20) << "local " << local;
    EXPECT_LE(grid.maxLeafLevel(), 40) << "local " << local;
    expectValidMesh(grid, grid.extract(), "junction pair");
  }
}

TEST(Grid48Test, the_junctions_ending_a_thin_strip_are_not_separated)
{
  // thin_layer's 1-unit layer ends on the model's border in two junctions 1 apart at each
  // end; the layer goes on, thinner than its triangles, so (d) leaves the pair alone (it cost
  // 7 degrees of minimum angle there, see Grid48.cpp). A strip wider apart further away (the
  // fault throws of gulf_section) is still separated: close_junctions_end_up_in_different_...
  const Loaded& m = load("thin_layer.vtp");
  const Grid48 grid = Grid48::build(m.model, *m.field);
  EXPECT_EQ(grid.params().junctionMaxLevel, grid.params().localMaxLevel + 8);
  EXPECT_LE(grid.maxLeafLevel(), grid.params().localMaxLevel);
  EXPECT_EQ(grid.statistics().featureTests, 0u);
}

TEST(Grid48Test, both_forms_of_a_model_refine_alike)
{
  for (const auto& [shared, loops] :
    { std::pair<std::string, std::string>{ "salt_dome.vtp", "salt_dome_loops.vtp" },
      { "gulf_section.vtp", "gulf_section_loops.vtp" },
      { "countries_westeurope.vtp", "countries_westeurope_loops.vtp" } })
  {
    const Loaded& a = load(shared);
    const Loaded& b = load(loops);
    const Grid48 ga = Grid48::build(a.model, *a.field, smallParams());
    const Grid48 gb = Grid48::build(b.model, *b.field, smallParams());
    EXPECT_EQ(ga.numberOfLeaves(), gb.numberOfLeaves()) << shared;
  }
}

// The leaves as sorted lattice triangles, to compare grids exactly.
std::vector<std::array<std::uint32_t, 6>> leafSet(const Grid48& grid)
{
  std::vector<std::array<std::uint32_t, 6>> out;
  for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
  {
    if (grid.isLeaf(t))
    {
      const auto& v = grid.nodeVertices(t);
      std::array<std::uint32_t, 6> key;
      for (int k = 0; k < 3; ++k)
      {
        key[2 * k] = grid.vertexLattice(v[k])[0];
        key[2 * k + 1] = grid.vertexLattice(v[k])[1];
      }
      out.push_back(key);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Grid48Test, resumed_refinement_equals_building_from_scratch)
{
  for (const std::string name :
    { "salt_dome.vtp", "countries_westeurope.vtp", "guitar.vtp", "thin_layer.vtp" })
  {
    const Loaded& m = load(name);
    Grid48Params coarse;
    coarse.maxLevel = 10;
    coarse.localMaxLevel = 12;
    Grid48 resumed = Grid48::build(m.model, *m.field, coarse);
    const std::size_t before = resumed.numberOfLeaves();
    Grid48Params fine;
    fine.maxLevel = 13;
    fine.localMaxLevel = 16;
    resumed.refine(m.model, *m.field, fine);
    const Grid48 scratch = Grid48::build(m.model, *m.field, fine);
    EXPECT_GT(resumed.numberOfLeaves(), before) << name;
    EXPECT_EQ(resumed.numberOfLeaves(), scratch.numberOfLeaves()) << name;
    EXPECT_TRUE(leafSet(resumed) == leafSet(scratch)) << name;
    expectValidMesh(resumed, resumed.extract(), name + " resumed");
    expectConsistentNeighbours(resumed);
    // Refining again with the same parameters changes nothing.
    resumed.refine(m.model, *m.field, fine);
    EXPECT_EQ(resumed.numberOfLeaves(), scratch.numberOfLeaves()) << name;
  }
}

TEST(Grid48Test, grid_meshes_carry_levels_and_known_distances)
{
  const Loaded& m = load("salt_dome.vtp");
  const Grid48 grid = Grid48::build(m.model, *m.field, smallParams());
  const TriangleMesh mesh = grid.extract();
  ASSERT_EQ(mesh.pointBoundaryDistance.size(), mesh.points.size());
  strata::DistanceField::Scratch scratch;
  int known = 0;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const double d = mesh.pointBoundaryDistance[i];
    if (!std::isnan(d))
    {
      EXPECT_DOUBLE_EQ(d, m.field->boundaryDistance(mesh.points[i], scratch));
      ++known;
    }
    EXPECT_EQ(mesh.pointLevel[i], grid.vertexLevel(mesh.pointVertex[i]));
  }
  EXPECT_GT(known, 0);
  // A vertex created by splitting a level-l triangle first appears at level l + 1, as the
  // right angle of the two children.
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
  {
    EXPECT_EQ(mesh.pointLevel[mesh.triangles[t][0]], mesh.triangleLevel[t]);
  }
}

TEST(Grid48Test, memory_per_leaf_is_below_200_bytes)
{
  const Loaded& m = load("gulf_section.vtp");
  Grid48Params p;
  p.maxLevel = 18;
  p.localMaxLevel = 22;
  const Grid48 grid = Grid48::build(m.model, *m.field, p);
  ASSERT_GT(grid.numberOfLeaves(), 100000u);
  const double perLeaf = static_cast<double>(grid.memoryBytes()) / grid.numberOfLeaves();
  EXPECT_LT(perLeaf, 200.0);
  EXPECT_GT(perLeaf, 50.0); // sanity: the hierarchy is in there
}

TEST(Grid48Test, empty_model_gives_the_level0_square)
{
  strata::RawPolylines raw;
  raw.offsets.push_back(0);
  raw.form = strata::ModelForm::Loops;
  const strata::Model model = strata::buildModel(raw);
  const strata::DistanceField field(model);
  const Grid48 grid = Grid48::build(model, field);
  EXPECT_EQ(grid.numberOfLeaves(), 4u);
  expectValidMesh(grid, grid.extract(), "empty");
}

TEST(Grid48Test, parameters_out_of_range_throw)
{
  const Loaded& m = load("pinch_out.vtp");
  auto build = [&](Grid48Params p) { return Grid48::build(m.model, *m.field, p); };
  Grid48Params p;
  p.maxLevel = 61;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.maxLevel = -2;
  EXPECT_THROW(build(p), strata::ParameterError);
  p = {};
  p.maxLevel = 12;
  p.localMaxLevel = 11;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.localMaxLevel = 61;
  EXPECT_THROW(build(p), strata::ParameterError);
  p = {};
  p.tolerance = -1.0;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.tolerance = std::nan("");
  EXPECT_THROW(build(p), strata::ParameterError);
  p = {};
  p.margin = -0.1;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.margin = 2.0;
  EXPECT_THROW(build(p), strata::ParameterError);
  p = {};
  p.maxLevel = 12;
  p.localMaxLevel = 14;
  p.junctionMaxLevel = 13;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.junctionMaxLevel = 61;
  EXPECT_THROW(build(p), strata::ParameterError);
  p = {};
  p.featurePointAngle = -1.0;
  EXPECT_THROW(build(p), strata::ParameterError);
  p.featurePointAngle = 181.0;
  EXPECT_THROW(build(p), strata::ParameterError);
  EXPECT_THROW(Grid48(Box2{ { 0, 0 }, { 1, 1 } }).extract(-2), strata::ParameterError);
  // The model must fit in the grid's domain to resume.
  const Loaded& other = load("gulf_section.vtp");
  Grid48 small = build({});
  EXPECT_THROW(small.refine(other.model, *other.field, {}), strata::ParameterError);
  // Explicit localMaxLevel == maxLevel: no local refinement at all.
  p = {};
  p.maxLevel = 12;
  p.localMaxLevel = 12;
  EXPECT_LE(build(p).maxLeafLevel(), 12);
}

// The longest and shortest hypotenuse among the leaves.
std::pair<double, double> leafHypotenuseRange(const Grid48& grid)
{
  double longest = 0.0, shortest = HUGE_VAL;
  for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
  {
    if (grid.isLeaf(t))
    {
      const auto& v = grid.nodeVertices(t);
      const double h = std::hypot(grid.vertexPosition(v[1]).x - grid.vertexPosition(v[2]).x,
        grid.vertexPosition(v[1]).y - grid.vertexPosition(v[2]).y);
      longest = std::max(longest, h);
      shortest = std::min(shortest, h);
    }
  }
  return { longest, shortest };
}

TEST(Grid48Test, edge_lengths_in_model_units_choose_the_levels)
{
  for (const std::string name : { "gulf_section.vtp", "salt_dome.vtp", "thin_layer.vtp" })
  {
    const Loaded& m = load(name);
    const Grid48 automatic = Grid48::build(m.model, *m.field);
    const double side = automatic.side();
    // MaximumEdgeLength: every leaf's hypotenuse (its longest edge) is at most that long,
    // far from the boundary too; the level overrides the automatic one.
    for (const double fraction : { 0.3, 0.07, 0.011 })
    {
      Grid48Params p;
      p.maxEdgeLength = fraction * side;
      const Grid48 grid = Grid48::build(m.model, *m.field, p);
      const Grid48Params& r = grid.params();
      const int level = r.minLevel;
      EXPECT_LE(grid.hypotenuseLength(level), p.maxEdgeLength) << name;
      EXPECT_GT(grid.hypotenuseLength(level - 1), p.maxEdgeLength) << name; // the coarsest
      EXPECT_EQ(r.maxLevel, level) << name;
      EXPECT_EQ(r.localMaxLevel, level + 4) << name;
      EXPECT_LE(leafHypotenuseRange(grid).first, p.maxEdgeLength) << name << " " << fraction;
      expectValidMesh(grid, grid.extract(), name);
      // A MaxLevel set finer than the length's level wins; a coarser one is raised to it.
      p.maxLevel = level + 3;
      EXPECT_EQ(Grid48::resolveParams(m.model, p).maxLevel, level + 3) << name;
      EXPECT_EQ(Grid48::resolveParams(m.model, p).minLevel, level) << name;
      p.maxLevel = level > 0 ? level - 1 : 0;
      p.localMaxLevel = p.maxLevel;
      const Grid48Params raised = Grid48::resolveParams(m.model, p);
      EXPECT_EQ(raised.maxLevel, level) << name;
      EXPECT_EQ(raised.localMaxLevel, level) << name; // raised to MaxLevel, no local levels
      EXPECT_EQ(raised.junctionMaxLevel, level) << name;
    }
    // MinimumEdgeLength caps every level, set or automatic: no leaf's hypotenuse is shorter.
    const double shortest = leafHypotenuseRange(automatic).second;
    for (const double factor : { 2.0, 16.0, 100.0 })
    {
      Grid48Params p;
      p.minEdgeLength = factor * shortest;
      p.localMaxLevel = -1;
      const Grid48 grid = Grid48::build(m.model, *m.field, p);
      const Grid48Params& r = grid.params();
      EXPECT_GE(grid.hypotenuseLength(r.junctionMaxLevel), p.minEdgeLength) << name;
      EXPECT_LT(grid.hypotenuseLength(r.junctionMaxLevel + 1), p.minEdgeLength) << name;
      EXPECT_LE(r.maxLevel, r.localMaxLevel);
      EXPECT_LE(r.localMaxLevel, r.junctionMaxLevel);
      EXPECT_LE(r.maxLevel, automatic.params().maxLevel) << name;
      EXPECT_GE(leafHypotenuseRange(grid).second, p.minEdgeLength * (1 - 1e-9))
        << name << " " << factor;
      EXPECT_LT(grid.numberOfLeaves(), automatic.numberOfLeaves()) << name;
      expectValidMesh(grid, grid.extract(), name);
      p.maxLevel = 40; // a level set finer than the cap is lowered (the coarser wins)
      p.localMaxLevel = 44;
      EXPECT_EQ(Grid48::resolveParams(m.model, p).localMaxLevel, r.junctionMaxLevel) << name;
      EXPECT_EQ(Grid48::resolveParams(m.model, p).maxLevel, r.junctionMaxLevel) << name;
    }
    // Both: every hypotenuse in [minimum, maximum], and when the two are within a factor
    // sqrt(2) of each other the maximum wins (hypotenuses above minimum / sqrt(2)).
    for (const double ratio : { 4.0, 1.2, 1.0 })
    {
      Grid48Params p;
      p.maxEdgeLength = 0.05 * side;
      p.minEdgeLength = p.maxEdgeLength / ratio;
      const Grid48 grid = Grid48::build(m.model, *m.field, p);
      const auto range = leafHypotenuseRange(grid);
      EXPECT_LE(range.first, p.maxEdgeLength) << name << " " << ratio;
      EXPECT_GT(range.second, p.minEdgeLength / std::sqrt(2.0)) << name << " " << ratio;
      expectValidMesh(grid, grid.extract(), name);
    }
  }
  // Out of range, naming the parameter.
  const Loaded& m = load("pinch_out.vtp");
  const double side = Grid48::build(m.model, *m.field).side();
  auto message = [&](const Grid48Params& p) -> std::string
  {
    try
    {
      Grid48::resolveParams(m.model, p);
    }
    catch (const strata::ParameterError& e)
    {
      return e.what();
    }
    return "";
  };
  for (const double bad : { -1.0, std::nan(""), HUGE_VAL })
  {
    Grid48Params p;
    p.maxEdgeLength = bad;
    EXPECT_NE(message(p).find("MaximumEdgeLength"), std::string::npos);
    p = {};
    p.minEdgeLength = bad;
    EXPECT_NE(message(p).find("MinimumEdgeLength"), std::string::npos);
  }
  Grid48Params p;
  p.maxEdgeLength = 1e-3 * side; // level 20 (4 M triangles) is still allowed
  EXPECT_EQ(message(p), "");
  p.maxEdgeLength = side / 4096.0; // level 24: too many triangles
  EXPECT_NE(message(p).find("MaximumEdgeLength"), std::string::npos);
  p.maxEdgeLength = 1.0;
  p.minEdgeLength = 2.0;
  EXPECT_NE(message(p).find("MinimumEdgeLength"), std::string::npos);
  p = {};
  p.minLevel = 23;
  p.maxLevel = 30;
  EXPECT_NE(message(p).find("MinLevel"), std::string::npos);
  p.minLevel = 31;
  p.maxLevel = 30;
  EXPECT_NE(message(p).find("MinLevel"), std::string::npos);
  // A minEdgeLength longer than the whole domain keeps level 0.
  p = {};
  p.minEdgeLength = 10.0 * side;
  EXPECT_EQ(Grid48::build(m.model, *m.field, p).numberOfLeaves(), 4u);
}

TEST(Grid48Test, progress_is_reported_and_abort_leaves_a_valid_grid)
{
  const Loaded& m = load("gulf_section.vtp");
  Grid48Params p;
  p.maxLevel = 16;
  p.localMaxLevel = 20;
  std::vector<double> fractions;
  const Grid48 grid = Grid48::build(m.model,
    *m.field,
    p,
    strata::ProgressReporter(
      [&](double f, const char*)
      {
        fractions.push_back(f);
        return true;
      }));
  ASSERT_GE(fractions.size(), 3u);
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));

  Grid48 partial = Grid48::build(m.model, *m.field, { 8, 8, 0.0, true, true, 0.05 });
  int calls = 0;
  EXPECT_THROW(partial.refine(m.model,
                 *m.field,
                 p,
                 strata::ProgressReporter([&](double, const char*) { return ++calls < 3; })),
    strata::Aborted);
  EXPECT_LT(partial.numberOfLeaves(), grid.numberOfLeaves());
  expectValidMesh(partial, partial.extract(), "aborted");
  expectConsistentNeighbours(partial);
  // Resuming after the abort reaches the same grid.
  partial.refine(m.model, *m.field, p);
  EXPECT_TRUE(leafSet(partial) == leafSet(grid));
}

} // namespace

// The target edge length field (Grid48Params::targetEdgeLength, criterion (f)).

// Edge-adjacent leaves of the finest mesh: the largest ratio of their hypotenuses.
double worstNeighbourRatio(const TriangleMesh& mesh)
{
  std::unordered_map<std::uint64_t, int> firstFace;
  double worst = 1.0;
  auto hypotenuse = [&](int t)
  {
    const auto& tri = mesh.triangles[t];
    return strata::norm(mesh.points[tri[1]] - mesh.points[tri[2]]);
  };
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t)
  {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      const auto [it, inserted] = firstFace.emplace(edgeKey(tri[k], tri[(k + 1) % 3]), t);
      if (!inserted)
      {
        const double a = hypotenuse(t);
        const double b = hypotenuse(it->second);
        worst = std::max(worst, std::max(a, b) / std::min(a, b));
      }
    }
  }
  return worst;
}

// The smallest target at the corners and the centroid of leaf t (input coordinates).
double smallestSampledTarget(const Grid48& grid,
  int t,
  Vec2 origin,
  const std::function<double(Vec2)>& field)
{
  const auto& v = grid.nodeVertices(t);
  double smallest = HUGE_VAL;
  Vec2 centroid{ 0.0, 0.0 };
  for (const int k : v)
  {
    smallest = std::min(smallest, field(grid.vertexPosition(k) + origin));
    centroid = centroid + grid.vertexPosition(k);
  }
  return std::min(smallest, field((1.0 / 3.0) * centroid + origin));
}

TEST(Grid48Test, target_edge_length_field_refines_a_disc_coarsens_elsewhere_and_is_graded)
{
  for (const std::string name : { "salt_dome.vtp", "gulf_section.vtp" })
  {
    SCOPED_TRACE(name);
    const Loaded& m = load(name);
    const Grid48 automatic = Grid48::build(m.model, *m.field);
    const double side = automatic.side();
    const int autoLevel = automatic.params().maxLevel;
    // Small edges (two levels finer than the automatic MaxLevel) in a disc around the centre
    // of the model, large ones (side / 8) elsewhere; input coordinates, as the adapters give.
    const Vec2 centre = m.model.bounds.center() + m.model.origin;
    const double radius = 0.1 * side;
    const double small = automatic.hypotenuseLength(autoLevel + 2);
    const double large = side / 8.0;
    const auto field = [&](Vec2 p) { return strata::norm(p - centre) < radius ? small : large; };
    Grid48Params p;
    p.targetEdgeLength = field;
    const Grid48 grid = Grid48::build(m.model, *m.field, p);
    const Grid48Params& r = grid.params();
    // The field coarsens MaxLevel to the level of its largest value: side / 2^(6 / 2).
    EXPECT_EQ(r.maxLevel, 6);
    EXPECT_EQ(r.localMaxLevel, 10);
    EXPECT_EQ(r.targetMaxLevel, autoLevel + 8); // the floor follows the usual levels
    expectValidMesh(grid, grid.extract(), name);
    expectConsistentNeighbours(grid);

    std::size_t inside = 0, insideAuto = 0, outside = 0, outsideAuto = 0;
    const auto count = [&](const Grid48& g, std::size_t& in, std::size_t& out)
    {
      for (int t = 0; t < static_cast<int>(g.numberOfNodes()); ++t)
      {
        if (!g.isLeaf(t))
        {
          continue;
        }
        const Vec2 c = nodeCentroid(g, t) + m.model.origin;
        const double d = strata::norm(c - centre);
        (d < radius ? in : out) += d < radius || d > radius + 2.0 * large ? 1 : 0;
      }
    };
    count(grid, inside, outside);
    count(automatic, insideAuto, outsideAuto);
    EXPECT_GT(inside, 2 * insideAuto) << inside << " vs " << insideAuto;
    EXPECT_LT(outside, outsideAuto) << outside << " vs " << outsideAuto;
    std::cout << name << ": inside the disc " << inside << " leaves (" << insideAuto
              << " without the field), far outside " << outside << " (" << outsideAuto << "); all "
              << grid.numberOfLeaves() << " (" << automatic.numberOfLeaves() << ")\n";

    // Every leaf above the floor is no longer than the smallest target sampled on it, and
    // a leaf inside the disc is no longer than the small target.
    for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
    {
      if (!grid.isLeaf(t) || grid.nodeLevel(t) >= r.targetMaxLevel)
      {
        continue;
      }
      const double h = grid.hypotenuseLength(grid.nodeLevel(t));
      EXPECT_LE(h, smallestSampledTarget(grid, t, m.model.origin, field) * (1 + 1e-9)) << t;
      const auto& v = grid.nodeVertices(t);
      bool allInside = true;
      for (const int k : v)
      {
        allInside &= strata::norm(grid.vertexPosition(k) + m.model.origin - centre) < radius;
      }
      if (allInside)
      {
        EXPECT_LE(h, small * (1 + 1e-9)) << t;
      }
    }
    // Grading: edge-adjacent leaves' longest edges within a factor sqrt(2) (<= 2 asked).
    EXPECT_LE(worstNeighbourRatio(grid.extract()), std::sqrt(2.0) * (1 + 1e-9));
    // A MaxLevel set is kept (the field refines, but does not coarsen it).
    p.maxLevel = autoLevel;
    EXPECT_EQ(Grid48::resolveParams(m.model, p).maxLevel, autoLevel);
  }
}

TEST(Grid48Test, target_edge_length_floor_bounds_the_refinement)
{
  const Loaded& m = load("salt_dome.vtp");
  const Grid48 automatic = Grid48::build(m.model, *m.field);
  const double side = automatic.side();
  const Vec2 centre = m.model.bounds.center() + m.model.origin;
  const double radius = 0.05 * side;
  // 1e-9 in a disc: refined down to the floor, LocalMaxLevel + 4, and not beyond.
  Grid48Params p;
  p.targetEdgeLength = [&](Vec2 q)
  { return strata::norm(q - centre) < radius ? 1e-9 : std::nan(""); };
  const Grid48 grid = Grid48::build(m.model, *m.field, p);
  const Grid48Params& r = grid.params();
  EXPECT_EQ(r.maxLevel, automatic.params().maxLevel); // no finite large value: no coarsening
  EXPECT_EQ(r.targetMaxLevel, r.localMaxLevel + 4);
  const double floor = grid.hypotenuseLength(r.targetMaxLevel);
  // The disc's area in floor triangles (h^2 / 4 each), plus the graded transition ring.
  const double discTriangles = 3.14159265 * radius * radius / (0.25 * floor * floor);
  EXPECT_GT(static_cast<double>(grid.numberOfLeaves()), discTriangles);
  EXPECT_LT(static_cast<double>(grid.numberOfLeaves()),
    static_cast<double>(automatic.numberOfLeaves()) + 1.3 * discTriangles);
  // Inside the disc every leaf reached the floor; only the boundary criteria (junctions,
  // up to JunctionMaxLevel) go finer, as without the field.
  std::size_t finer = 0, finerAuto = 0;
  for (int t = 0; t < static_cast<int>(grid.numberOfNodes()); ++t)
  {
    if (!grid.isLeaf(t))
    {
      continue;
    }
    finer += grid.nodeLevel(t) > r.targetMaxLevel ? 1 : 0;
    bool allInside = true;
    for (const int k : grid.nodeVertices(t))
    {
      allInside &= strata::norm(grid.vertexPosition(k) + m.model.origin - centre) < radius;
    }
    if (allInside)
    {
      EXPECT_GE(grid.nodeLevel(t), r.targetMaxLevel) << t;
    }
  }
  for (int t = 0; t < static_cast<int>(automatic.numberOfNodes()); ++t)
  {
    finerAuto += automatic.isLeaf(t) && automatic.nodeLevel(t) > r.targetMaxLevel ? 1 : 0;
  }
  EXPECT_LE(finer, finerAuto + 64);
  expectValidMesh(grid, grid.extract(), "floor");
  // MinimumEdgeLength is the floor when set: no hypotenuse is shorter.
  p.minEdgeLength = 4.0 * floor;
  const Grid48 capped = Grid48::build(m.model, *m.field, p);
  EXPECT_GE(leafHypotenuseRange(capped).second, p.minEdgeLength * (1 - 1e-9));
  EXPECT_LE(leafHypotenuseRange(capped).second, 2.0 * p.minEdgeLength);
  EXPECT_LT(capped.numberOfLeaves(), grid.numberOfLeaves() / 4)
    << capped.numberOfLeaves() << " vs " << grid.numberOfLeaves();
}

TEST(Grid48Test, target_edge_length_without_wishes_changes_nothing_and_bad_values_throw)
{
  const Loaded& m = load("pinch_out.vtp");
  const Grid48 automatic = Grid48::build(m.model, *m.field);
  Grid48Params p;
  p.targetEdgeLength = [](Vec2 q) { return q.x < 0.0 ? HUGE_VAL : std::nan(""); };
  const Grid48 none = Grid48::build(m.model, *m.field, p);
  EXPECT_TRUE(leafSet(none) == leafSet(automatic));
  for (const double bad : { 0.0, -2.5, -HUGE_VAL })
  {
    p.targetEdgeLength = [bad](Vec2) { return bad; };
    try
    {
      Grid48::build(m.model, *m.field, p);
      ADD_FAILURE() << "no error for " << bad;
    }
    catch (const strata::ParameterError& e)
    {
      EXPECT_NE(std::string(e.what()).find("target edge length"), std::string::npos) << e.what();
    }
  }
  p = {};
  p.targetEdgeLength = [](Vec2) { return 1.0; };
  p.maxLevel = 10;
  p.localMaxLevel = 12;
  p.targetMaxLevel = 11; // below LocalMaxLevel
  EXPECT_THROW(Grid48::resolveParams(m.model, p), strata::ParameterError);
}

TEST(Grid48Test, a_session_resumes_only_with_the_same_target_field)
{
  const strata::RawPolylines raw =
    strata_test::readVtpAscii(strata_test::dataPath("salt_dome.vtp"));
  strata::GridSession session(raw);
  const strata::Model& model = session.model();
  const Vec2 centre = model.bounds.center() + model.origin;
  double radius = 50.0;
  Grid48Params p;
  p.maxLevel = 10;
  p.targetEdgeLength = [&](Vec2 q) { return strata::norm(q - centre) < radius ? 5.0 : HUGE_VAL; };
  p.targetEdgeLengthId = 1;
  EXPECT_FALSE(session.refine(p));
  const std::size_t first = session.grid().numberOfLeaves();
  EXPECT_TRUE(session.refine(p)); // same field: resumed, nothing to do
  EXPECT_EQ(session.grid().numberOfLeaves(), first);
  radius = 25.0; // the field changed: a new id rebuilds, coarser where the disc shrank
  p.targetEdgeLengthId = 2;
  EXPECT_FALSE(session.refine(p));
  EXPECT_LT(session.grid().numberOfLeaves(), first);
  EXPECT_TRUE(leafSet(session.grid()) == leafSet(Grid48::build(model, session.field(), p)));
  p.targetEdgeLengthId = 0; // unknown field: always rebuilt
  EXPECT_FALSE(session.refine(p));
  p.targetEdgeLength = nullptr; // field removed: rebuilt, as without it
  EXPECT_FALSE(session.refine(p));
  EXPECT_TRUE(leafSet(session.grid()) == leafSet(Grid48::build(model, session.field(), p)));
}
