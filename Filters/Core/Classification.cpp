// StrataMesh core: classification of a mesh against the model (paper Section 5).
//
// Definitions (tol = the boundary tolerance)
// -------------------------------------------
// - A point is a boundary vertex when a boundary segment is within tol of it.
// - An edge is an intersection edge when a boundary segment is within tol of it (closed): it
//   crosses or touches a boundary. This covers "an end point on the boundary", "end points in
//   different regions" (any path between two regions meets a boundary) and a thin region
//   crossed between two end points of one region.
// - Every other edge lies in one region (or in the exterior) together with its end points.
//
// How, without brute force and with few distance queries
// ------------------------------------------------------
// 1. Unique edges from the triangles in a compressed row layout keyed by the smaller end
//    point (O(n), no hashing).
// 2. Points: when the grid already computed a point's distance to the boundary with the strip
//    tree (TriangleMesh::pointBoundaryDistance), d <= tol decides; otherwise the boundary
//    index (BoundaryIndex, a uniform grid of the model's segments) answers "is a segment
//    within tol" exactly, from the one or few cells around the point.
// 3. Edges: the disk argument first: the open disk of radius d around a point holds no
//    boundary, so when both ends have known distances and (d(a) - tol) + (d(b) - tol) > |ab|,
//    the shrunken disks cover the edge and every point of it is farther than tol from any
//    boundary: not an intersection edge. Otherwise the boundary index tests the segments in
//    the cells under the edge's box (exact segment/segment distance).
// 4. Regions: the region is constant along any path that meets no boundary, so a union-find
//    over the edges that are not intersection edges gives components of points of one region
//    each (in practice one per connected piece of a region, plus a few pockets), and one
//    DistanceField::query per component, at any of its points, labels them all. Boundary
//    points are queried one by one: their region is the side query() reports (the region
//    when the point is on or inside it, -1 on the exterior side). This assumes regions that
//    do not overlap (a partition, as FORMAT.md describes; where Loops regions overlap, query()
//    picks the region with the largest signed distance, which may vary within a component).
// 5. Faces: the region of the barycentre g: that of a corner v that is not a boundary vertex
//    when the segment v-g stays farther than tol from the boundary (the disk of a known
//    distance, or the index), else a query at g.
// The edge and face tests need no distance query at all; the queries are one per component,
// one per boundary point and one per face whose barycentre is not connected to a corner.
// Steps 2, 3's tests and 5 are independent per item: on large meshes each block's two halves
// run at once (Parallel.h), each with its own index and scratch (the same results).
#include "Classification.h"

#include "Errors.h"
#include "Parallel.h"
#include "Rows.h"
#include "UnionFind.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

namespace strata
{

Classification classify(const TriangleMesh& mesh,
  const Model& model,
  const DistanceField& field,
  const ClassificationParams& params,
  const ProgressReporter& progress)
{
  if (!(params.boundaryTolerance >= 0.0) || !std::isfinite(params.boundaryTolerance))
  {
    throw ParameterError("classify: BoundaryTolerance " + std::to_string(params.boundaryTolerance) +
      " is not a finite value >= 0 (0: automatic)");
  }
  const std::size_t np = mesh.points.size();
  const std::size_t nt = mesh.triangles.size();
  const bool known = mesh.pointBoundaryDistance.size() == np;
  if (!mesh.pointBoundaryDistance.empty() && !known)
  {
    throw ParameterError("classify: the mesh has " + std::to_string(np) + " points but " +
      std::to_string(mesh.pointBoundaryDistance.size()) + " known distances");
  }
  double shortest2 = HUGE_VAL;
  for (std::size_t t = 0; t < nt; ++t)
  {
    const std::array<int, 3>& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] < 0 || static_cast<std::size_t>(tri[k]) >= np)
      {
        throw ParameterError("classify: triangle " + std::to_string(t) + " refers to point " +
          std::to_string(tri[k]) + ", not in [0, " + std::to_string(np) + ")");
      }
    }
    for (int k = 0; k < 3; ++k)
    {
      shortest2 = std::min(shortest2, norm2(mesh.points[tri[k]] - mesh.points[tri[(k + 1) % 3]]));
    }
  }

  Classification c;
  c.boundaryTolerance = params.boundaryTolerance;
  if (c.boundaryTolerance == 0.0 && nt > 0)
  {
    c.boundaryTolerance = 1e-6 * std::sqrt(shortest2);
  }
  const double tol = c.boundaryTolerance;
  progress.report(0.0, "classifying the grid");
  // The points', edges' and faces' tests run in two halves at once on large meshes
  // (Parallel.h), each half with its own index (its queries keep stamps), scratch and count.
  struct alignas(64) Part
  {
    explicit Part(const Model& model)
      : index(model)
    {
    }
    BoundaryIndex index;
    DistanceField::Scratch scratch;
    std::size_t queries = 0;
  };
  std::optional<Part> parts[2];
  parts[0].emplace(model);
  auto regionOf = [&](Vec2 p, Part& part)
  {
    ++part.queries;
    return field.region(p, part.scratch);
  };
  // work(i, part) for i in [0, n), progress from `from` to `to` between blocks.
  const auto sweep = [&](std::size_t n, double from, double to, auto&& work)
  {
    if (n >= kTwoThreadItems && !parts[1])
    {
      parts[1].emplace(model);
    }
    blockwise(
      n,
      kTwoThreadBlock,
      kTwoThreadItems,
      [&](std::size_t begin, std::size_t end, int which)
      {
        for (std::size_t i = begin; i < end; ++i)
        {
          work(i, *parts[which]);
        }
      },
      [&](std::size_t done) {
        progress.report(from + (to - from) * static_cast<double>(done) / n, "classifying the grid");
      });
  };
  // Distance known from the grid, or NaN.
  auto knownDistance = [&](int i)
  { return known ? mesh.pointBoundaryDistance[i] : std::numeric_limits<double>::quiet_NaN(); };

  // 1. Unique edges: rows of the smaller end point.
  LargeVector<int> rowStart;
  {
    LargeVector<int> other;
    groupIntoRows(np,
      rowStart,
      other,
      [&](auto&& emit)
      {
        for (const std::array<int, 3>& tri : mesh.triangles)
        {
          for (int k = 0; k < 3; ++k)
          {
            const int a = tri[k];
            const int b = tri[(k + 1) % 3];
            emit(std::min(a, b), std::max(a, b));
          }
        }
      });
    c.edges.reserve(other.size() / 2 + np);
    for (std::size_t i = 0; i < np; ++i)
    {
      const auto begin = other.begin() + rowStart[i];
      const auto end = other.begin() + rowStart[i + 1];
      std::sort(begin, end);
      for (auto it = begin; it != end; ++it)
      {
        if (it == begin || *it != *(it - 1))
        {
          c.edges.push_back({ static_cast<int>(i), *it });
        }
      }
    }
  }
  LargeVector<int>().swap(rowStart);
  const std::size_t ne = c.edges.size();
  progress.report(0.1, "classifying the grid");

  // 2. Boundary points.
  c.vertexClass.assign(np, VertexExterior);
  sweep(np,
    0.1,
    0.2,
    [&](std::size_t i, Part& part)
    {
      const double d = knownDistance(static_cast<int>(i));
      const bool boundary = std::isnan(d) ? part.index.nearPoint(mesh.points[i], tol) : d <= tol;
      if (boundary)
      {
        c.vertexClass[i] = VertexBoundary;
      }
    });

  // 3. Edges (the tests first); union of the end points of the others.
  c.edgeClass.assign(ne, EdgeExterior);
  sweep(ne,
    0.2,
    0.5,
    [&](std::size_t e, Part& part)
    {
      const int a = c.edges[e][0];
      const int b = c.edges[e][1];
      bool intersection = c.vertexClass[a] == VertexBoundary || c.vertexClass[b] == VertexBoundary;
      if (!intersection)
      {
        const Vec2 pa = mesh.points[a];
        const Vec2 pb = mesh.points[b];
        const double da = knownDistance(a);
        const double db = knownDistance(b);
        // NaN compares false: unknown distances fall through to the index.
        if (!((da - tol) + (db - tol) > norm(pb - pa)))
        {
          intersection = part.index.nearSegment(pa, pb, tol);
        }
      }
      if (intersection)
      {
        c.edgeClass[e] = EdgeIntersection;
      }
    });
  LargeVector<int> parent(np);
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t e = 0; e < ne; ++e)
  {
    if (e % 65536 == 0)
    {
      progress.report(0.5 + 0.1 * static_cast<double>(e) / ne, "classifying the grid");
    }
    if (c.edgeClass[e] != EdgeIntersection)
    {
      const int ra = rootOf(parent, c.edges[e][0]);
      const int rb = rootOf(parent, c.edges[e][1]);
      if (ra != rb)
      {
        parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    }
  }

  // 4. Regions: one query per component, one per boundary point.
  c.vertexRegion.assign(np, -1);
  for (std::size_t i = 0; i < np; ++i)
  {
    if (i % 16384 == 0)
    {
      progress.report(0.6 + 0.1 * static_cast<double>(i) / np, "classifying the grid");
    }
    if (c.vertexClass[i] == VertexBoundary)
    {
      c.vertexRegion[i] = regionOf(mesh.points[i], *parts[0]);
      continue;
    }
    const int root = rootOf(parent, static_cast<int>(i));
    if (root == static_cast<int>(i))
    {
      c.vertexRegion[i] = regionOf(mesh.points[i], *parts[0]);
    }
    else
    {
      c.vertexRegion[i] = c.vertexRegion[root]; // roots are the smallest index: done already
    }
    c.vertexClass[i] = c.vertexRegion[i] >= 0 ? VertexInterior : VertexExterior;
  }
  LargeVector<int>().swap(parent);

  c.edgeRegion.assign(ne, -1);
  for (std::size_t e = 0; e < ne; ++e)
  {
    const int a = c.edges[e][0];
    const int b = c.edges[e][1];
    const int ra = c.vertexRegion[a];
    if (c.edgeClass[e] != EdgeIntersection)
    {
      c.edgeClass[e] = ra >= 0 ? EdgeInterior : EdgeExterior;
      c.edgeRegion[e] = ra;
      continue;
    }
    const int rb = c.vertexRegion[b];
    if (c.vertexClass[a] == VertexInterior)
    {
      c.edgeRegion[e] = ra;
    }
    else if (c.vertexClass[b] == VertexInterior)
    {
      c.edgeRegion[e] = rb;
    }
    else
    {
      c.edgeRegion[e] = ra >= 0 ? ra : rb;
    }
  }

  // 5. Faces: region of the barycentre.
  c.cellRegion.assign(nt, -1);
  sweep(nt,
    0.7,
    1.0,
    [&](std::size_t t, Part& part)
    {
      const std::array<int, 3>& tri = mesh.triangles[t];
      const Vec2 g =
        (1.0 / 3.0) * (mesh.points[tri[0]] + mesh.points[tri[1]] + mesh.points[tri[2]]);
      int region = -2;
      for (int k = 0; k < 3 && region == -2; ++k)
      {
        const int v = tri[k];
        if (c.vertexClass[v] != VertexBoundary && knownDistance(v) - tol > norm(g - mesh.points[v]))
        {
          region = c.vertexRegion[v];
        }
      }
      for (int k = 0; k < 3 && region == -2; ++k)
      {
        const int v = tri[k];
        if (c.vertexClass[v] != VertexBoundary && !part.index.nearSegment(mesh.points[v], g, tol))
        {
          region = c.vertexRegion[v];
        }
      }
      c.cellRegion[t] = region == -2 ? regionOf(g, part) : region;
    });
  for (const std::optional<Part>& part : parts)
  {
    c.regionQueries += part ? part->queries : 0;
  }
  progress.report(1.0, "classifying the grid");
  return c;
}

} // namespace strata
