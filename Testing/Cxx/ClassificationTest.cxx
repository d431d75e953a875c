// Tests of the classification of grid vertices, edges and faces against brute force (distance
// to every segment, even-odd over every ring, every segment against every edge).
#include "Classification.h"

#include "CoreTestUtilities.h"
#include "DistanceField.h"
#include "Errors.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace
{

using strata::Classification;
using strata::Grid48;
using strata::Grid48Params;
using strata::TriangleMesh;
using strata::Vec2;

using Loaded = strata_test::LoadedModel;

const Loaded& load(const std::string& name)
{
  return strata_test::loadModelAndField(name);
}

TriangleMesh gridMesh(const Loaded& m, int maxLevel, int localMaxLevel)
{
  Grid48Params p;
  p.maxLevel = maxLevel;
  p.localMaxLevel = localMaxLevel;
  return Grid48::build(m.model, *m.field, p).extract();
}

// Brute force over the model: all distinct segments, all rings of every region.
class BruteForce
{
public:
  explicit BruteForce(const strata::Model& model)
    : Model(model)
  {
    std::map<std::pair<int, int>, bool> seen;
    for (const strata::Curve& c : model.curves)
    {
      const std::size_t n = c.nodes.size();
      for (std::size_t i = 0; i + (c.closed ? 0 : 1) < n; ++i)
      {
        const int u = c.nodes[i], w = c.nodes[(i + 1) % n];
        if (u != w && seen.emplace(std::minmax(u, w), true).second)
        {
          this->A.push_back(model.nodes[u]);
          this->B.push_back(model.nodes[w]);
        }
      }
    }
    // Buckets over the bounds, only to keep the edge checks fast; every segment goes into
    // every bucket of its bounding box.
    this->Box = model.bounds;
    for (std::size_t s = 0; s < this->A.size(); ++s)
    {
      int x0, y0, x1, y1;
      this->range(std::min(this->A[s].x, this->B[s].x),
        std::min(this->A[s].y, this->B[s].y),
        std::max(this->A[s].x, this->B[s].x),
        std::max(this->A[s].y, this->B[s].y),
        x0,
        y0,
        x1,
        y1);
      for (int y = y0; y <= y1; ++y)
      {
        for (int x = x0; x <= x1; ++x)
        {
          this->Buckets[y * kBuckets + x].push_back(static_cast<int>(s));
        }
      }
    }
  }

  double distance(Vec2 p) const
  {
    return std::sqrt(strata_test::bruteForceDistance2(this->A, this->B, p));
  }

  // Region by the even-odd rule over each region's rings (-1 for none); the models are
  // partitions, so a point off the boundary is in at most one.
  int region(Vec2 p, int* count = nullptr) const
  {
    int found = -1;
    int inside = 0;
    for (const strata::Region& r : this->Model.regions)
    {
      bool odd = false;
      for (const strata::Ring& ring : r.rings)
      {
        const std::size_t n = ring.points.size();
        for (std::size_t i = 0; i < n; ++i)
        {
          const Vec2 a = ring.points[i], b = ring.points[(i + 1) % n];
          if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
          {
            odd = !odd;
          }
        }
      }
      if (odd)
      {
        found = r.id;
        ++inside;
      }
    }
    if (count)
    {
      *count = inside;
    }
    return found;
  }

  // Whether a segment comes within tol of segment pq (closed).
  bool near(Vec2 p, Vec2 q, double tol) const
  {
    int x0, y0, x1, y1;
    this->range(std::min(p.x, q.x) - tol,
      std::min(p.y, q.y) - tol,
      std::max(p.x, q.x) + tol,
      std::max(p.y, q.y) + tol,
      x0,
      y0,
      x1,
      y1);
    for (int y = y0; y <= y1; ++y)
    {
      for (int x = x0; x <= x1; ++x)
      {
        for (const int s : this->Buckets[y * kBuckets + x])
        {
          if (segmentDistance(p, q, this->A[s], this->B[s]) <= tol)
          {
            return true;
          }
        }
      }
    }
    return false;
  }

private:
  static constexpr int kBuckets = 128;

  static double segmentDistance(Vec2 a, Vec2 b, Vec2 c, Vec2 d)
  {
    return std::sqrt(strata::segmentSegmentDistance2(a, b, c, d));
  }

  void range(double xa, double ya, double xb, double yb, int& x0, int& y0, int& x1, int& y1) const
  {
    auto cell = [&](double v, double lo, double w)
    {
      const double f = w > 0 ? (v - lo) / w * kBuckets : 0.0;
      return static_cast<int>(std::clamp(std::floor(f), 0.0, kBuckets - 1.0));
    };
    x0 = cell(xa, this->Box.min.x, this->Box.width());
    x1 = cell(xb, this->Box.min.x, this->Box.width());
    y0 = cell(ya, this->Box.min.y, this->Box.height());
    y1 = cell(yb, this->Box.min.y, this->Box.height());
  }

  const strata::Model& Model;
  std::vector<Vec2> A, B;
  strata::Box2 Box;
  std::vector<int> Buckets[kBuckets * kBuckets];
};

void expectVerticesAgreeWithBruteForce(const std::string& name, int maxLevel, int localMaxLevel)
{
  SCOPED_TRACE(name);
  const Loaded& m = load(name);
  const TriangleMesh mesh = gridMesh(m, maxLevel, localMaxLevel);
  const Classification c = strata::classify(mesh, m.model, *m.field);
  const BruteForce brute(m.model);
  strata::DistanceField::Scratch scratch;
  ASSERT_EQ(c.vertexClass.size(), mesh.points.size());
  ASSERT_EQ(c.vertexRegion.size(), mesh.points.size());
  int interior = 0;
  int exterior = 0;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const Vec2 p = mesh.points[i];
    const double d = brute.distance(p);
    if (d <= c.boundaryTolerance)
    {
      EXPECT_EQ(c.vertexClass[i], strata::VertexBoundary) << "point " << i;
      EXPECT_EQ(c.vertexRegion[i], m.field->query(p, scratch).region) << "point " << i;
      continue;
    }
    int count = 0;
    const int region = brute.region(p, &count);
    ASSERT_LE(count, 1) << "point " << i << " is in two regions: not a partition";
    ASSERT_EQ(c.vertexClass[i], region >= 0 ? strata::VertexInterior : strata::VertexExterior)
      << "point " << i << " (" << p.x << ", " << p.y << ") at distance " << d;
    ASSERT_EQ(c.vertexRegion[i], region) << "point " << i << " (" << p.x << ", " << p.y << ")";
    (region >= 0 ? interior : exterior) += 1;
  }
  EXPECT_GT(interior, 0);
  // Few queries: one per component of covered edges and per boundary point.
  EXPECT_LT(c.regionQueries, mesh.points.size() / 10 + mesh.triangles.size() / 10);
}

TEST(ClassificationTest, vertices_agree_with_brute_force_on_salt_dome)
{
  expectVerticesAgreeWithBruteForce("salt_dome.vtp", 14, 18);
}

TEST(ClassificationTest, vertices_agree_with_brute_force_on_gulf_section)
{
  expectVerticesAgreeWithBruteForce("gulf_section.vtp", 13, 16);
}

TEST(ClassificationTest, vertices_agree_with_brute_force_on_loops_and_holes)
{
  expectVerticesAgreeWithBruteForce("gulf_section_loops.vtp", 11, 13);
  expectVerticesAgreeWithBruteForce("nested_holes.vtp", 10, 14);
  expectVerticesAgreeWithBruteForce("touching_loops.vtp", 10, 14);
  expectVerticesAgreeWithBruteForce("lake_superior.vtp", 11, 14);
}

// knownDistances: every point's distance is given, so that the disk test decides most edges.
void expectEdgesAgreeWithBruteForce(const std::string& name,
  int maxLevel,
  int localMaxLevel,
  bool knownDistances = false)
{
  SCOPED_TRACE(name + (knownDistances ? " with known distances" : ""));
  const Loaded& m = load(name);
  TriangleMesh mesh = gridMesh(m, maxLevel, localMaxLevel);
  if (knownDistances)
  {
    strata::DistanceField::Scratch scratch;
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
    {
      mesh.pointBoundaryDistance[i] = m.field->boundaryDistance(mesh.points[i], scratch);
    }
  }
  const Classification c = strata::classify(mesh, m.model, *m.field);
  const BruteForce brute(m.model);
  const std::size_t ne = c.edges.size();
  ASSERT_EQ(c.edgeClass.size(), ne);
  ASSERT_EQ(c.edgeRegion.size(), ne);
  // Unique, sorted, (a < b); Euler's formula for a disk: E = V + F - 1.
  EXPECT_EQ(ne, mesh.points.size() + mesh.triangles.size() - 1);
  EXPECT_TRUE(std::is_sorted(c.edges.begin(), c.edges.end()));
  EXPECT_TRUE(std::adjacent_find(c.edges.begin(), c.edges.end()) == c.edges.end());
  int counts[3] = { 0, 0, 0 };
  for (std::size_t e = 0; e < ne; ++e)
  {
    const int a = c.edges[e][0], b = c.edges[e][1];
    ASSERT_LT(a, b);
    const bool crossed = brute.near(mesh.points[a], mesh.points[b], c.boundaryTolerance);
    ++counts[c.edgeClass[e]];
    if (crossed)
    {
      ASSERT_EQ(c.edgeClass[e], strata::EdgeIntersection) << "edge " << a << "-" << b;
      // The region rule: the first interior end point, else the first end point in a region.
      const int expected = c.vertexClass[a] == strata::VertexInterior ? c.vertexRegion[a]
        : c.vertexClass[b] == strata::VertexInterior                  ? c.vertexRegion[b]
        : c.vertexRegion[a] >= 0                                      ? c.vertexRegion[a]
                                                                      : c.vertexRegion[b];
      EXPECT_EQ(c.edgeRegion[e], expected) << "edge " << a << "-" << b;
      continue;
    }
    // Not crossed: same class and region at both ends, and the edge's class and region.
    ASSERT_NE(c.edgeClass[e], strata::EdgeIntersection) << "edge " << a << "-" << b;
    ASSERT_EQ(c.vertexClass[a], c.vertexClass[b]) << "edge " << a << "-" << b;
    ASSERT_EQ(c.vertexRegion[a], c.vertexRegion[b]) << "edge " << a << "-" << b;
    ASSERT_NE(c.vertexClass[a], strata::VertexBoundary);
    EXPECT_EQ(c.edgeClass[e], c.vertexRegion[a] >= 0 ? strata::EdgeInterior : strata::EdgeExterior);
    EXPECT_EQ(c.edgeRegion[e], c.vertexRegion[a]);
  }
  EXPECT_GT(counts[strata::EdgeInterior], 0);
  EXPECT_GT(counts[strata::EdgeIntersection], 0);
}

TEST(ClassificationTest, edges_agree_with_brute_force_on_salt_dome)
{
  expectEdgesAgreeWithBruteForce("salt_dome.vtp", 14, 18);
  expectEdgesAgreeWithBruteForce("salt_dome.vtp", 14, 18, true);
}

TEST(ClassificationTest, edges_agree_with_brute_force_on_gulf_section)
{
  expectEdgesAgreeWithBruteForce("gulf_section.vtp", 14, 18);
  expectEdgesAgreeWithBruteForce("gulf_section.vtp", 14, 18, true);
  expectEdgesAgreeWithBruteForce("thin_layer.vtp", 10, 16, true);
  expectEdgesAgreeWithBruteForce("pinch_out.vtp", 10, 16, true);
}

TEST(ClassificationTest, faces_get_the_region_of_their_barycentre)
{
  for (const std::string name : { "salt_dome.vtp", "gulf_section.vtp", "countries_westeurope.vtp" })
  {
    const Loaded& m = load(name);
    const TriangleMesh mesh = gridMesh(m, 12, 16);
    const Classification c = strata::classify(mesh, m.model, *m.field);
    ASSERT_EQ(c.cellRegion.size(), mesh.triangles.size());
    strata::DistanceField::Scratch scratch;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    {
      const auto& tri = mesh.triangles[t];
      const Vec2 g =
        (1.0 / 3.0) * (mesh.points[tri[0]] + mesh.points[tri[1]] + mesh.points[tri[2]]);
      ASSERT_EQ(c.cellRegion[t], m.field->query(g, scratch).region) << name << " face " << t;
    }
  }
}

TEST(ClassificationTest, classification_is_consistent_on_every_model)
{
  for (const std::string name : { "countries_westeurope.vtp",
         "countries_westeurope_loops.vtp",
         "geology_marmousi.vtp",
         "guitar.vtp",
         "gulf_section_loops.vtp",
         "lake_superior.vtp",
         "nested_holes.vtp",
         "pinch_out.vtp",
         "salt_dome_loops.vtp",
         "thin_layer.vtp",
         "touching_loops.vtp" })
  {
    const Loaded& m = load(name);
    const TriangleMesh mesh = gridMesh(m, 12, 15);
    const Classification c = strata::classify(mesh, m.model, *m.field);
    int betweenRegions = 0;
    for (std::size_t e = 0; e < c.edges.size(); ++e)
    {
      const int a = c.edges[e][0], b = c.edges[e][1];
      if (c.edgeClass[e] != strata::EdgeIntersection)
      {
        ASSERT_EQ(c.vertexRegion[a], c.vertexRegion[b]) << name;
        ASSERT_NE(c.vertexClass[a], strata::VertexBoundary) << name;
        ASSERT_EQ(c.edgeRegion[e], c.vertexRegion[a]) << name;
      }
      else if (c.vertexRegion[a] != c.vertexRegion[b])
      {
        ++betweenRegions;
      }
    }
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
    {
      ASSERT_EQ(c.vertexClass[i] == strata::VertexInterior,
        c.vertexRegion[i] >= 0 && c.vertexClass[i] != strata::VertexBoundary)
        << name << " point " << i;
    }
    EXPECT_GT(betweenRegions, 0) << name << ": no edge between two regions";
    // Every region big enough to hold a vertex of the grid (all but Monaco and Liechtenstein
    // at these levels) has some.
    std::vector<int> ids(c.vertexRegion.begin(), c.vertexRegion.end());
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    EXPECT_GE(ids.size(), std::min<std::size_t>(m.model.regions.size() + 1, 3)) << name;
  }
}

// A 4 x 4 square region 0 with a thin slab 0.02 thick cut out of it as region 1 (Loops form:
// the slab's loop is a hole of region 0 and the outline of region 1).
strata::Model slabModel()
{
  strata::RawPolylines raw;
  raw.form = strata::ModelForm::Loops;
  raw.offsets.push_back(0);
  const std::vector<Vec2> slab = { { -1, 0.01 }, { 1, 0.01 }, { 1, 0.03 }, { -1, 0.03 } };
  strata_test::addClosedLoop(raw, { { -2, -2 }, { 2, -2 }, { 2, 2 }, { -2, 2 } }, 0);
  strata_test::addClosedLoop(raw, slab, 0);
  strata_test::addClosedLoop(raw, slab, 1);
  return strata::buildModel(raw);
}

TEST(ClassificationTest, an_edge_across_a_thin_region_is_an_intersection_edge)
{
  const strata::Model model = slabModel();
  const strata::DistanceField field(model);
  TriangleMesh mesh;
  // Two triangles: the shared edge (0,-0.5)-(0,0.5) crosses the slab; the others do not
  // (the last point is outside the square).
  mesh.points = { { 0, -0.5 }, { 0.5, -0.4 }, { 0, 0.5 }, { -3, 0 } };
  mesh.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  const Classification c = strata::classify(mesh, model, field);
  ASSERT_EQ(c.edges.size(), 5u);
  EXPECT_EQ(c.vertexClass, (strata::LargeVector<std::int8_t>{ 2, 2, 2, 0 }));
  EXPECT_EQ(c.vertexRegion, (strata::LargeVector<int>{ 0, 0, 0, -1 }));
  for (std::size_t e = 0; e < c.edges.size(); ++e)
  {
    const auto& ab = c.edges[e];
    if (ab == std::array<int, 2>{ 0, 2 })
    {
      EXPECT_EQ(c.edgeClass[e], strata::EdgeIntersection); // both ends in region 0
      EXPECT_EQ(c.edgeRegion[e], 0);
    }
    else if (ab == std::array<int, 2>{ 0, 1 })
    {
      EXPECT_EQ(c.edgeClass[e], strata::EdgeInterior);
      EXPECT_EQ(c.edgeRegion[e], 0);
    }
    else if (ab == std::array<int, 2>{ 1, 2 })
    {
      EXPECT_EQ(c.edgeClass[e], strata::EdgeIntersection); // crosses the slab's end
    }
    else
    {
      EXPECT_EQ(c.edgeClass[e], strata::EdgeIntersection); // to the exterior point
      EXPECT_EQ(c.edgeRegion[e], 0);
    }
  }
  EXPECT_EQ(c.cellRegion, (strata::LargeVector<int>{ 0, 0 }));
}

TEST(ClassificationTest, boundary_tolerance_decides_boundary_vertices)
{
  const strata::Model model = slabModel();
  const strata::DistanceField field(model);
  TriangleMesh mesh;
  // On the slab's lower side, 1e-4 above it (inside the slab), and two far points.
  mesh.points = { { 0, 0.01 }, { 0.5, 0.0101 }, { 0.5, -1 }, { -0.5, -1 } };
  mesh.triangles = { { 3, 2, 1 }, { 3, 1, 0 } };
  Classification c = strata::classify(mesh, model, field);
  strata::DistanceField::Scratch scratch;
  EXPECT_EQ(c.vertexClass[0], strata::VertexBoundary);
  EXPECT_EQ(c.vertexRegion[0], field.query(mesh.points[0], scratch).region);
  EXPECT_EQ(c.vertexClass[1], strata::VertexInterior);
  EXPECT_EQ(c.vertexRegion[1], 1);
  strata::ClassificationParams params;
  params.boundaryTolerance = 2e-4;
  c = strata::classify(mesh, model, field, params);
  EXPECT_DOUBLE_EQ(c.boundaryTolerance, 2e-4);
  EXPECT_EQ(c.vertexClass[1], strata::VertexBoundary);
  EXPECT_EQ(c.vertexRegion[1], 1);
  EXPECT_EQ(c.vertexClass[2], strata::VertexInterior);
}

TEST(ClassificationTest, known_distances_do_not_change_the_result)
{
  const Loaded& m = load("salt_dome.vtp");
  TriangleMesh mesh = gridMesh(m, 13, 17);
  const Classification a = strata::classify(mesh, m.model, *m.field);
  mesh.pointBoundaryDistance.clear();
  const Classification b = strata::classify(mesh, m.model, *m.field);
  EXPECT_EQ(a.vertexClass, b.vertexClass);
  EXPECT_EQ(a.vertexRegion, b.vertexRegion);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.edgeClass, b.edgeClass);
  EXPECT_EQ(a.edgeRegion, b.edgeRegion);
  EXPECT_EQ(a.cellRegion, b.cellRegion);
}

TEST(ClassificationTest, bad_parameters_and_meshes_throw)
{
  const Loaded& m = load("pinch_out.vtp");
  TriangleMesh mesh;
  mesh.points = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
  mesh.triangles = { { 0, 1, 2 } };
  strata::ClassificationParams p;
  p.boundaryTolerance = -1;
  EXPECT_THROW(strata::classify(mesh, m.model, *m.field, p), strata::ParameterError);
  p.boundaryTolerance = HUGE_VAL;
  EXPECT_THROW(strata::classify(mesh, m.model, *m.field, p), strata::ParameterError);
  mesh.triangles = { { 0, 1, 3 } };
  EXPECT_THROW(strata::classify(mesh, m.model, *m.field), strata::ParameterError);
  mesh.triangles = { { 0, 1, 2 } };
  mesh.pointBoundaryDistance = { 1.0 };
  EXPECT_THROW(strata::classify(mesh, m.model, *m.field), strata::ParameterError);
  // An empty mesh is fine.
  const Classification empty = strata::classify(TriangleMesh(), m.model, *m.field);
  EXPECT_TRUE(empty.edges.empty());
}

TEST(ClassificationTest, progress_is_reported_and_abort_throws)
{
  const Loaded& m = load("gulf_section.vtp");
  const TriangleMesh mesh = gridMesh(m, 14, 18);
  std::vector<double> fractions;
  strata::classify(mesh,
    m.model,
    *m.field,
    {},
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
  int calls = 0;
  EXPECT_THROW(strata::classify(mesh,
                 m.model,
                 *m.field,
                 {},
                 strata::ProgressReporter([&](double, const char*) { return ++calls < 4; })),
    strata::Aborted);
}

} // namespace
