// StrataMesh core: physical compression of the classified 4-8 grid onto the model's
// boundaries (paper Section 6), face classification (Section 5) and a quality pass.
//
// The algorithm
// -------------
// 0. Rails. The model's boundary becomes chains of segments between junctions (nodes where
//    the number of boundary segments is not two); closed chains have none. Chain points whose
//    angle is below featureAngle are features. One strip tree over all segments gives the
//    exact closest boundary point of any point (segment + parameter).
// 1. Candidates and push criterion (6.3). Candidates are the end points of intersection
//    edges. AllCandidates pushes both ends of each; OneSide the exterior end of an edge between
//    a region and the exterior, the end in the region of larger id between two regions, the
//    closer end when both ends lie in one region (a thin feature crosses the edge); Closest
//    the end closer to the boundary. Vertices the classification found on a boundary are
//    pushed too (they arrive in one step). A pushed vertex's target is its closest boundary
//    point; it moves straight toward it at pushVelocity, ignoring all forces.
// 2. Junctions (6.4). Each junction gets exactly one vertex: the nearest candidate whose move
//    onto the junction keeps its triangles valid is snapped there before the simulation and
//    pinned; if none can move, the nearest one is pushed toward the junction and pinned on
//    arrival. A junction or feature point takes one vertex: other targets within 0.3 h of a
//    taken point, or within h / 4 of another target on the same chain, are moved half an edge
//    length along the chain (h = local edge length).
// 3. Simulated zone. Vertices within activeRings edge rings of a candidate or junction vertex
//    are simulated (never the domain border), numbered in Z-order of their positions (memory
//    locality; a large step's two halves meet on a short seam, see SpringSystem.cpp); the
//    triangles around them form a sub-mesh with flat local arrays (triangles, neighbours
//    across each edge, spring edge ids, a CSR vertex -> triangles table, which the
//    simulation's flips update from the stars of the flipped triangles' vertices only:
//    updateStars); every other vertex keeps its grid position.
// 4. Simulation (6.1, 6.2). A SpringSystem on the sub-mesh with rest lengths from the grid:
//    simulated vertices are free particles, pushed and arrived ones are driven, the halo is
//    fixed. Every step: forces; free particles by semi-implicit Euler; one push step per
//    pushed vertex; once every push is over, arrived vertices slide on their rail (6.4): they
//    move along the chain by the tangential component of their force (a first-order step,
//    dt^2 F_t / m), the move follows the polyline, a bend where the force turns back holds
//    the vertex, and passing over a feature point stops it there for good. Every move of any
//    kind passes the restrain test (6.3): each triangle around the vertex must stay
//    counter-clockwise with at least 2% of its rest area (or not shrink if it already is
//    below), so no triangle ever inverts and the mesh stays an embedding. Degeneracy (6.5): every
//    flipInterval steps, triangles below 10% of their rest area or with an angle under 10 degrees
//    get their longest edge flipped when the flip is valid and improves the pair's smallest angle;
//    a push blocked for 10 steps has the edges that block it flipped when valid (typically a chord
//    between two vertices already on a curve that bulges beyond it); blocked for 20 steps it aims
//    half an edge length aside (at most 3 times). A push is over when it arrived or used its time
//    (distance / speed + 20 steps). When the push phase ends, the deformed mesh is checked again
//    (up to 4 waves): an edge between two free vertices that now crosses a boundary (ends in
//    different regions) gets an end pushed by the same criterion, and the free corner of a face
//    whose other two corners are on curves is pushed when the face's barycentre lies in another
//    region (the curve bulges into the face, or a region too thin to hold a vertex runs
//    through it). Sleeping: every 10 steps, particles that moved less than 0.03 h (and are
//    not pushed) and whose neighbours did too stop being integrated, and springs touching
//    only sleeping particles are skipped; in a wave's tail (at most 0.1% of the simulated
//    vertices still pushed) the test runs at every step, with that one step's move, as the
//    refresh right after a wave does, and keeps two rings of edges awake around each vertex
//    still pushed. The loop stops after maxIterations,
//    or when every push is over and fewer than 0.5% of the simulated vertices move, or nothing
//    moved by 1e-3 h in 10 steps.
// 5. Faces (Section 5). A face crossing a boundary takes the region of its barycentre
//    (DistanceField::query). A face "crosses" when its corners do not settle it: corners off
//    the curves lie inside regions, so a face whose off-curve corners all lie in one region
//    takes that region, and only faces with every corner on a curve, or corners in different
//    regions, use the barycentre. Hence an edge between faces of different regions joins two
//    vertices on curves, except next to a face with corners in different regions. Faces
//    outside the simulated zone keep the region of their corners.
// 6. Optimization (beyond the paper, optional): Optimization.cpp, which explains it.
#include "Compression.h"
#include "Compressor.h"

#include "Errors.h"
#include "Parallel.h"
#include "Quality.h"
#include "Rows.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <utility>

namespace strata
{

namespace
{

void checkRange(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    throw ParameterError(
      std::string("Compression: ") + name + " " + std::to_string(value) + " is not in " + range);
  }
}

// 0b0a0b0a... from the low 16 bits of v: the bits spread for a Morton (Z-order) key.
std::uint32_t spreadBits(std::uint32_t v)
{
  v &= 0xffffu;
  v = (v | (v << 8)) & 0x00ff00ffu;
  v = (v | (v << 4)) & 0x0f0f0f0fu;
  v = (v | (v << 2)) & 0x33333333u;
  return (v | (v << 1)) & 0x55555555u;
}

// Sorts the point ids in Z-order over their bounding box (ties by id), so that ids close in
// the list are close in the plane: the simulation's arrays are then read nearly in order, and
// the halves of a split step (SpringSystem) meet along a short seam.
void sortSpatially(LargeVector<int>& ids, const LargeVector<Vec2>& points)
{
  if (ids.empty())
  {
    return;
  }
  Vec2 lo = points[ids[0]], hi = lo;
  for (const int i : ids)
  {
    lo = { std::min(lo.x, points[i].x), std::min(lo.y, points[i].y) };
    hi = { std::max(hi.x, points[i].x), std::max(hi.y, points[i].y) };
  }
  const double sx = hi.x > lo.x ? 65535.0 / (hi.x - lo.x) : 0.0;
  const double sy = hi.y > lo.y ? 65535.0 / (hi.y - lo.y) : 0.0;
  LargeVector<std::pair<std::uint32_t, int>> keyed;
  keyed.reserve(ids.size());
  for (const int i : ids)
  {
    const auto cx = static_cast<std::uint32_t>((points[i].x - lo.x) * sx);
    const auto cy = static_cast<std::uint32_t>((points[i].y - lo.y) * sy);
    keyed.emplace_back(spreadBits(cx) | (spreadBits(cy) << 1), i);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    ids[k] = keyed[k].second;
  }
}

} // namespace

using namespace detail;

void validate(const CompressionParams& p)
{
  checkRange(p.springConfiguration == SpringConfiguration::EdgeOnly ||
      p.springConfiguration == SpringConfiguration::EdgeAndProjection,
    "SpringConfiguration",
    static_cast<double>(static_cast<int>(p.springConfiguration)),
    "{0 (edge only), 1 (edge and projection)}");
  checkRange(p.springStiffness > 0.0 && p.springStiffness <= 1e3,
    "SpringStiffness",
    p.springStiffness,
    "(0, 1e3]");
  checkRange(p.damping >= 0.0 && p.damping <= 1e3, "Damping", p.damping, "[0, 1e3]");
  checkRange(p.timeStep > 0.0 && p.timeStep <= 1.0, "TimeStep", p.timeStep, "(0, 1]");
  checkRange(p.maxIterations >= 0 && p.maxIterations <= 1000000,
    "MaxIterations",
    p.maxIterations,
    "[0, 1e6]");
  checkRange(p.pushCriterion == PushCriterion::AllCandidates ||
      p.pushCriterion == PushCriterion::OneSide || p.pushCriterion == PushCriterion::Closest,
    "PushCriterion",
    static_cast<double>(static_cast<int>(p.pushCriterion)),
    "{0 (all candidates), 1 (one side), 2 (closest)}");
  checkRange(
    p.pushVelocity > 0.0 && p.pushVelocity <= 10.0, "PushVelocity", p.pushVelocity, "(0, 10]");
  checkRange(
    p.featureAngle >= 0.0 && p.featureAngle <= 180.0, "FeatureAngle", p.featureAngle, "[0, 180]");
  checkRange(
    p.flipInterval >= 1 && p.flipInterval <= 1000000, "FlipInterval", p.flipInterval, "[1, 1e6]");
  checkRange(p.activeRings >= 1 && p.activeRings <= 16, "ActiveRings", p.activeRings, "[1, 16]");
  checkRange(p.optimizationPasses >= 0 && p.optimizationPasses <= 100,
    "OptimizationPasses",
    p.optimizationPasses,
    "[0, 100]");
  checkRange(p.boundaryTolerance >= 0.0 && p.boundaryTolerance <= 10.0,
    "BoundaryTolerance",
    p.boundaryTolerance,
    "[0, 10]");
}

//------------------------------------------------------------------------------
// Rails.
BoundaryRails::BoundaryRails(const Model& model, double featureAngle)
{
  // Distinct segments by node pair (lo < hi) with the regions left and right of lo -> hi.
  struct Seg
  {
    int lo, hi, left, right;
  };
  std::vector<Seg> raw;
  for (const Region& region : model.regions)
  {
    for (const Ring& ring : region.rings)
    {
      const std::size_t n = ring.nodes.size();
      for (std::size_t i = 0; i < n; ++i)
      {
        const int u = ring.nodes[i], v = ring.nodes[(i + 1) % n];
        if (u == v)
        {
          continue;
        }
        // The region lies left of u -> v.
        if (u < v)
        {
          raw.push_back({ u, v, region.id, -2 });
        }
        else
        {
          raw.push_back({ v, u, -2, region.id });
        }
      }
    }
  }
  std::sort(raw.begin(),
    raw.end(),
    [](const Seg& a, const Seg& b) { return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi; });
  std::vector<Seg> segs;
  for (const Seg& s : raw)
  {
    if (!segs.empty() && segs.back().lo == s.lo && segs.back().hi == s.hi)
    {
      if (s.left != -2)
      {
        segs.back().left = s.left;
      }
      if (s.right != -2)
      {
        segs.back().right = s.right;
      }
    }
    else
    {
      segs.push_back(s);
    }
  }
  for (Seg& s : segs)
  {
    s.left = s.left == -2 ? -1 : s.left;
    s.right = s.right == -2 ? -1 : s.right;
  }

  // Node -> incident segments.
  const std::size_t nn = model.nodes.size();
  std::vector<int> start, incident;
  groupIntoRows(nn,
    start,
    incident,
    [&](auto&& emit)
    {
      for (std::size_t s = 0; s < segs.size(); ++s)
      {
        emit(segs[s].lo, static_cast<int>(s));
        emit(segs[s].hi, static_cast<int>(s));
      }
    });
  auto degree = [&](int node) { return start[node + 1] - start[node]; };
  std::vector<std::uint8_t> used(segs.size(), 0);

  // Walks from `node` along segment s until a node of degree != 2 (or back to the start).
  auto walk = [&](int node, int s)
  {
    Chain c;
    const int first = node;
    c.nodes.push_back(node);
    const Seg& s0 = segs[s];
    c.left = node == s0.lo ? s0.left : s0.right;
    c.right = node == s0.lo ? s0.right : s0.left;
    while (true)
    {
      used[s] = 1;
      const int next = segs[s].lo == node ? segs[s].hi : segs[s].lo;
      if (next == first)
      {
        c.closed = true;
        break;
      }
      c.nodes.push_back(next);
      node = next;
      if (degree(node) != 2)
      {
        break;
      }
      int following = -1;
      for (int k = start[node]; k < start[node + 1]; ++k)
      {
        if (!used[incident[k]])
        {
          following = incident[k];
        }
      }
      if (following < 0)
      {
        break;
      }
      s = following;
    }
    return c;
  };
  for (std::size_t node = 0; node < nn; ++node)
  {
    if (degree(static_cast<int>(node)) == 2)
    {
      continue;
    }
    for (int k = start[node]; k < start[node + 1]; ++k)
    {
      if (!used[incident[k]])
      {
        this->Chains.push_back(walk(static_cast<int>(node), incident[k]));
      }
    }
  }
  for (std::size_t s = 0; s < segs.size(); ++s)
  {
    if (!used[s])
    {
      this->Chains.push_back(walk(segs[s].lo, static_cast<int>(s)));
    }
  }

  // Geometry, features, tree.
  const double cosLimit = std::cos(featureAngle * 3.14159265358979323846 / 180.0);
  std::vector<Vec2> a, b;
  for (std::size_t ci = 0; ci < this->Chains.size(); ++ci)
  {
    Chain& c = this->Chains[ci];
    const std::size_t n = c.nodes.size();
    c.points.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      c.points[i] = model.nodes[c.nodes[i]];
    }
    c.feature.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!c.closed && (i == 0 || i + 1 == n))
      {
        c.feature[i] = 1; // chain ends: junctions or dangling ends
        continue;
      }
      const Vec2 p = c.points[i];
      const Vec2 u = c.points[(i + n - 1) % n] - p;
      const Vec2 v = c.points[(i + 1) % n] - p;
      // angle(u, v) < featureAngle  <=>  cos(angle) > cos(featureAngle)
      const double cosAngle = dot(u, v) / (norm(u) * norm(v));
      if (featureAngle > 0.0 && cosAngle > cosLimit)
      {
        c.feature[i] = 1;
      }
    }
    for (std::size_t k = 0; k < c.numberOfSegments(); ++k)
    {
      a.push_back(c.points[k]);
      b.push_back(c.points[(k + 1) % n]);
      this->SegmentOf.push_back({ static_cast<int>(ci), static_cast<int>(k) });
    }
  }
  this->Tree = StripTree(std::move(a), std::move(b));

  // Each node's chain points, chain by chain and point by point: locationsOfNode() is asked
  // about every curve vertex at a chain point, so it must not scan the chains (ten horizons of
  // 2000 points each: the optimization stage 2.15 -> 0.72 s).
  groupIntoRows(nn,
    this->NodeStart,
    this->NodeLocations,
    [&](auto&& emit)
    {
      for (std::size_t ci = 0; ci < this->Chains.size(); ++ci)
      {
        const Chain& c = this->Chains[ci];
        for (std::size_t i = 0; i < c.nodes.size(); ++i)
        {
          const bool last = i == c.numberOfSegments(); // (an open chain's end)
          emit(static_cast<std::size_t>(c.nodes[i]),
            Location{ static_cast<int>(ci), static_cast<int>(last ? i - 1 : i), last ? 1.0 : 0.0 });
        }
      }
    });
}

BoundaryRails::Location BoundaryRails::closest(Vec2 p,
  StripTreeScratch& scratch,
  double* distance,
  double maxDistance) const
{
  const NearestSegment s = this->Tree.nearest(p, scratch, maxDistance);
  const Location l = s.segment >= 0 ? this->location(s.segment, s.t) : Location{};
  if (distance)
  {
    *distance = std::sqrt(s.distance2);
  }
  return l;
}

SegmentGrid BoundaryRails::segmentGrid(double cellSize, std::size_t maxCells) const
{
  std::vector<Vec2> a, b;
  for (const Chain& c : this->Chains)
  {
    for (std::size_t k = 0; k < c.numberOfSegments(); ++k)
    {
      a.push_back(c.points[k]);
      b.push_back(c.points[(k + 1) % c.points.size()]);
    }
  }
  return SegmentGrid(std::move(a), std::move(b), cellSize, maxCells);
}

BoundaryRails::Location BoundaryRails::location(int segment, double t) const
{
  return { this->SegmentOf[segment][0], this->SegmentOf[segment][1], t };
}

Vec2 BoundaryRails::position(const Location& l) const
{
  const Chain& c = this->Chains[l.chain];
  const Vec2 a = c.points[l.segment];
  const Vec2 b = c.points[(l.segment + 1) % c.points.size()];
  if (l.t == 0.0)
  {
    return a;
  }
  if (l.t == 1.0)
  {
    return b;
  }
  return a + l.t * (b - a);
}

Vec2 BoundaryRails::tangent(const Location& l) const
{
  const Chain& c = this->Chains[l.chain];
  const Vec2 d = c.points[(l.segment + 1) % c.points.size()] - c.points[l.segment];
  const double len = norm(d);
  return len > 0.0 ? (1.0 / len) * d : Vec2{ 1.0, 0.0 };
}

int BoundaryRails::pointAt(const Location& l) const
{
  if (l.t == 0.0)
  {
    return l.segment;
  }
  if (l.t == 1.0)
  {
    return static_cast<int>((l.segment + 1) % this->Chains[l.chain].points.size());
  }
  return -1;
}

bool BoundaryRails::isStop(int chain, int point) const
{
  return this->Chains[chain].feature[point] != 0;
}

std::vector<BoundaryRails::Location> BoundaryRails::locationsOfNode(int node) const
{
  if (node < 0 || static_cast<std::size_t>(node) + 1 >= this->NodeStart.size())
  {
    return {};
  }
  return std::vector<Location>(this->NodeLocations.begin() + this->NodeStart[node],
    this->NodeLocations.begin() + this->NodeStart[node + 1]);
}

BoundaryRails::Slide BoundaryRails::slide(const Location& from, double s) const
{
  Slide out;
  out.location = from;
  const Chain& c = this->Chains[from.chain];
  const int np = static_cast<int>(c.points.size());
  const int ns = static_cast<int>(c.numberOfSegments());
  Location& l = out.location;
  // Leaving the chain point the location is at: step onto the segment in the direction of
  // motion (that point is not passed over, so it does not stop the slide).
  if (s > 0.0 && l.t == 1.0 && (c.closed || l.segment + 1 < ns))
  {
    l.segment = (l.segment + 1) % ns;
    l.t = 0.0;
  }
  else if (s < 0.0 && l.t == 0.0 && (c.closed || l.segment > 0))
  {
    l.segment = (l.segment + ns - 1) % ns;
    l.t = 1.0;
  }
  // Each turn consumes a segment; a closed chain without stops could be walked around for
  // ever with a huge s, so bound the turns.
  for (int turn = 0; turn <= 2 * ns + 2 && s != 0.0; ++turn)
  {
    const Vec2 a = c.points[l.segment];
    const Vec2 b = c.points[(l.segment + 1) % np];
    const double len = norm(b - a);
    if (s > 0.0)
    {
      const double avail = (1.0 - l.t) * len;
      if (s < avail)
      {
        l.t += s / len;
        return out;
      }
      s -= avail;
      l.t = 1.0;
      const int end = (l.segment + 1) % np;
      if (this->isStop(from.chain, end) || (!c.closed && l.segment + 1 >= ns))
      {
        out.stopped = true;
        return out;
      }
      l.segment = (l.segment + 1) % ns;
      l.t = 0.0;
    }
    else
    {
      const double avail = l.t * len;
      if (-s < avail)
      {
        l.t += s / len;
        return out;
      }
      s += avail;
      l.t = 0.0;
      if (this->isStop(from.chain, l.segment) || (!c.closed && l.segment == 0))
      {
        out.stopped = true;
        return out;
      }
      l.segment = (l.segment + ns - 1) % ns;
      l.t = 1.0;
    }
  }
  return out;
}

//------------------------------------------------------------------------------
bool restrainAccepts(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles,
  const int* star,
  int starSize,
  int i,
  Vec2 to,
  const double* minTwiceArea,
  double minFraction)
{
  for (int s = 0; s < starSize; ++s)
  {
    const int t = star[s];
    const std::array<int, 3>& tri = triangles[t];
    const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
    const Vec2 a = points[tri[(k + 1) % 3]];
    const Vec2 b = points[tri[(k + 2) % 3]];
    // Two cross products: the side of the opposite edge ab the vertex is on now and after.
    const double after = cross(b - a, to - a);
    if (!(after > 0.0))
    {
      return false;
    }
    if (minTwiceArea && after < minFraction * minTwiceArea[t])
    {
      const double before = cross(b - a, points[i] - a);
      if (after < before)
      {
        return false;
      }
    }
  }
  return true;
}

std::size_t flipDegenerateTriangles(const LargeVector<Vec2>& points,
  LargeVector<std::array<int, 3>>& triangles,
  double smallAngle,
  int passes)
{
  const double smallSine = std::sin(smallAngle * 3.14159265358979323846 / 180.0);
  std::map<std::pair<int, int>, int> owner; // directed edge -> triangle
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      owner[{ triangles[t][k], triangles[t][(k + 1) % 3] }] = static_cast<int>(t);
    }
  }
  std::size_t flips = 0;
  for (int pass = 0; pass < passes; ++pass)
  {
    std::size_t now = 0;
    for (std::size_t t = 0; t < triangles.size(); ++t)
    {
      const std::array<int, 3> tri = triangles[t];
      const Vec2 p0 = points[tri[0]], p1 = points[tri[1]], p2 = points[tri[2]];
      if (!(minAngleSine(p0, p1, p2) < smallSine))
      {
        continue;
      }
      int k = 0;
      double longest = -1.0;
      for (int j = 0; j < 3; ++j)
      {
        const double l = norm2(points[tri[(j + 1) % 3]] - points[tri[j]]);
        if (l > longest)
        {
          longest = l;
          k = j;
        }
      }
      const int a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      const auto it = owner.find({ b, a });
      if (it == owner.end())
      {
        continue;
      }
      const int u = it->second;
      const std::array<int, 3> other = triangles[u];
      const int j = other[0] == b ? 0 : (other[1] == b ? 1 : 2);
      const int d = other[(j + 2) % 3];
      const Vec2 pa = points[a], pb = points[b], pc = points[c], pd = points[d];
      const double scale = norm2(pc - pd);
      if (c == d || !(orient2d(pc, pa, pd) > 1e-12 * scale) ||
        !(orient2d(pd, pb, pc) > 1e-12 * scale))
      {
        continue;
      }
      const double before = std::min(minAngleSine(pa, pb, pc), minAngleSine(pb, pa, pd));
      const double after = std::min(minAngleSine(pc, pa, pd), minAngleSine(pd, pb, pc));
      if (!(after > before * (1.0 + 1e-9) + 1e-12))
      {
        continue;
      }
      for (const std::array<int, 3>& old : { tri, other })
      {
        for (int m = 0; m < 3; ++m)
        {
          owner.erase({ old[m], old[(m + 1) % 3] });
        }
      }
      triangles[t] = { c, a, d };
      triangles[u] = { d, b, c };
      for (int n : { static_cast<int>(t), u })
      {
        for (int m = 0; m < 3; ++m)
        {
          owner[{ triangles[n][m], triangles[n][(m + 1) % 3] }] = n;
        }
      }
      ++now;
    }
    flips += now;
    if (now == 0)
    {
      break;
    }
  }
  return flips;
}

namespace detail
{

//------------------------------------------------------------------------------
// Set-up.
void Compressor::buildGlobalStars()
{
  groupIntoRows(this->Grid.points.size(),
    this->GStarStart,
    this->GStarItems,
    [&](auto&& emit)
    {
      for (std::size_t t = 0; t < this->Grid.triangles.size(); ++t)
      {
        this->poll(t);
        for (int v : this->Grid.triangles[t])
        {
          emit(v, static_cast<int>(t));
        }
      }
    });
}

// A vertex whose triangles do not close around it lies on the mesh border.
bool Compressor::isBorderVertex(int g) const
{
  const int s0 = this->GStarStart[g], s1 = this->GStarStart[g + 1];
  for (int s = s0; s < s1; ++s)
  {
    const std::array<int, 3>& t = this->Grid.triangles[this->GStarItems[s]];
    const int k = t[0] == g ? 0 : (t[1] == g ? 1 : 2);
    const int next = t[(k + 1) % 3];
    bool found = false;
    for (int r = s0; r < s1 && !found; ++r)
    {
      const std::array<int, 3>& u = this->Grid.triangles[this->GStarItems[r]];
      const int j = u[0] == g ? 0 : (u[1] == g ? 1 : 2);
      found = u[(j + 2) % 3] == next;
    }
    if (!found)
    {
      return true;
    }
  }
  return false;
}

// Boundary distance of grid vertex g at its grid position. Caches it in Distance[g], which
// starts with the grid's known values (choosePushes()); vertices of different ids may ask from
// different threads.
double Compressor::gridDistance(int g, StripTreeScratch& rail)
{
  double& d = this->Distance[g];
  if (std::isnan(d))
  {
    this->Rails.closest(this->Grid.points[g], rail, &d);
  }
  return d;
}

void Compressor::choosePushes()
{
  const std::size_t np = this->Grid.points.size();
  // (Room for the optimization's splits, here and below: see withRoom().)
  withRoom(this->Candidate, np).assign(np, 0);
  withRoom(this->Push, np).assign(np, 0);
  if (this->Grid.pointBoundaryDistance.size() == np)
  {
    withRoom(this->Distance, np) = this->Grid.pointBoundaryDistance;
  }
  else
  {
    withRoom(this->Distance, np).assign(np, std::numeric_limits<double>::quiet_NaN());
  }
  for (std::size_t e = 0; e < this->Cls.edges.size(); ++e)
  {
    this->poll(e);
    if (this->Cls.edgeClass[e] != EdgeIntersection)
    {
      continue;
    }
    const int a = this->Cls.edges[e][0], b = this->Cls.edges[e][1];
    this->Candidate[a] = this->Candidate[b] = 1;
    const bool onA = this->Cls.vertexClass[a] == VertexBoundary;
    const bool onB = this->Cls.vertexClass[b] == VertexBoundary;
    if (onA || onB)
    {
      this->Push[a] |= onA;
      this->Push[b] |= onB;
      continue;
    }
    const int ra = this->Cls.vertexRegion[a], rb = this->Cls.vertexRegion[b];
    const auto closer = [&]() { return this->gridDistance(a) <= this->gridDistance(b) ? a : b; };
    switch (this->Params.pushCriterion)
    {
      case PushCriterion::AllCandidates:
        this->Push[a] = this->Push[b] = 1;
        break;
      case PushCriterion::OneSide:
        this->Push[ra == rb ? closer() : (ra == -1 ? a : (rb == -1 ? b : (ra > rb ? a : b)))] = 1;
        break;
      case PushCriterion::Closest:
        this->Push[closer()] = 1;
        break;
    }
  }
}

void Compressor::placeJunctions()
{
  const std::size_t np = this->Grid.points.size();
  withRoom(this->JunctionOf, np).assign(np, -1);
  withRoom(this->JunctionTarget, np).assign(np, -1);
  if (this->TheModel.junctions.empty())
  {
    return;
  }
  // Bucket grid over the candidate vertices.
  LargeVector<int> cand;
  Box2 box;
  for (std::size_t i = 0; i < np; ++i)
  {
    if (this->Candidate[i])
    {
      cand.push_back(static_cast<int>(i));
      box.add(this->Points[i]);
    }
  }
  if (cand.empty())
  {
    this->Result.warnings.push_back("no intersection edges: junctions were not placed");
    return;
  }
  const int cells =
    std::clamp(static_cast<int>(std::sqrt(static_cast<double>(cand.size()))), 1, 2048);
  const double cellSize =
    std::max(std::max(box.width(), box.height()) / cells, 1e-300) * (1.0 + 1e-9);
  const auto cellOf = [&](double v, double lo)
  { return std::clamp(static_cast<int>((v - lo) / cellSize), 0, cells - 1); };
  const auto cellIndex = [&](Vec2 p)
  { return cellOf(p.y, box.min.y) * cells + cellOf(p.x, box.min.x); };
  LargeVector<int> start, items;
  groupIntoRows(static_cast<std::size_t>(cells) * cells,
    start,
    items,
    [&](auto&& emit)
    {
      for (int v : cand)
      {
        emit(cellIndex(this->Points[v]), v);
      }
    });
  LargeVector<double> minTwice(this->Grid.triangles.size());
  for (std::size_t t = 0; t < minTwice.size(); ++t)
  {
    const std::array<int, 3>& tri = this->Grid.triangles[t];
    minTwice[t] = kCollapse *
      orient2d(this->Grid.points[tri[0]], this->Grid.points[tri[1]], this->Grid.points[tri[2]]);
  }
  std::size_t unplaced = 0;
  for (int node : this->TheModel.junctions)
  {
    const Vec2 p = this->TheModel.nodes[node];
    // Nearest free candidates: rings of cells until the ring is beyond 3x the nearest found.
    std::vector<std::pair<double, int>> near;
    const int cx = cellOf(p.x, box.min.x), cy = cellOf(p.y, box.min.y);
    double best = HUGE_VAL;
    for (int r = 0; r < cells; ++r)
    {
      for (int y = std::max(cy - r, 0); y <= std::min(cy + r, cells - 1); ++y)
      {
        for (int x = std::max(cx - r, 0); x <= std::min(cx + r, cells - 1); ++x)
        {
          if (std::abs(x - cx) != r && std::abs(y - cy) != r)
          {
            continue;
          }
          const int c = y * cells + x;
          for (int k = start[c]; k < start[c + 1]; ++k)
          {
            const int v = items[k];
            if (this->JunctionOf[v] < 0 && this->JunctionTarget[v] < 0)
            {
              const double d = norm(this->Points[v] - p);
              near.push_back({ d, v });
              best = std::min(best, d);
            }
          }
        }
      }
      if (best < HUGE_VAL && r * cellSize > 3.0 * best)
      {
        break;
      }
    }
    if (near.empty())
    {
      ++unplaced;
      continue;
    }
    std::sort(near.begin(), near.end());
    bool placed = false;
    for (std::size_t k = 0; k < near.size() && k < 12 && near[k].first <= 3.0 * best; ++k)
    {
      const int v = near[k].second;
      const int s0 = this->GStarStart[v];
      if (restrainAccepts(this->Points,
            this->Grid.triangles,
            this->GStarItems.data() + s0,
            this->GStarStart[v + 1] - s0,
            v,
            p,
            minTwice.data()))
      {
        this->Points[v] = p;
        this->JunctionOf[v] = node;
        placed = true;
        break;
      }
    }
    if (!placed)
    {
      this->JunctionTarget[near[0].second] = node;
    }
  }
  if (unplaced > 0)
  {
    this->Result.warnings.push_back(
      std::to_string(unplaced) + " junction(s) found no grid vertex to take them");
  }
}

void Compressor::buildSubMesh()
{
  const std::size_t np = this->Grid.points.size();
  const std::size_t nt = this->Grid.triangles.size();
  // Breadth-first rings from the candidates and junction vertices.
  LargeVector<int> ring(np, -1);
  LargeVector<std::uint8_t> border(np, 2); // 2 = not known yet
  const auto isBorder = [&](int g)
  {
    if (border[g] == 2)
    {
      border[g] = this->isBorderVertex(g) ? 1 : 0;
    }
    return border[g] == 1;
  };
  LargeVector<int> frontier;
  std::size_t onBorder = 0;
  for (std::size_t i = 0; i < np; ++i)
  {
    this->poll(i);
    if (this->Candidate[i] || this->JunctionOf[i] >= 0 || this->JunctionTarget[i] >= 0)
    {
      if (isBorder(static_cast<int>(i)))
      {
        onBorder += this->Push[i] || this->JunctionOf[i] >= 0 || this->JunctionTarget[i] >= 0;
        continue;
      }
      ring[i] = 0;
      frontier.push_back(static_cast<int>(i));
    }
  }
  if (onBorder > 0)
  {
    this->Result.warnings.push_back(std::to_string(onBorder) +
      " vertices chosen to be pushed lie on the border of the grid's domain and stay fixed "
      "(a coarse grid around the model)");
  }
  LargeVector<int> active = frontier;
  for (int r = 1; r <= this->Params.activeRings; ++r)
  {
    LargeVector<int> next;
    for (int g : frontier)
    {
      this->poll(static_cast<std::size_t>(&g - frontier.data()));
      for (int s = this->GStarStart[g]; s < this->GStarStart[g + 1]; ++s)
      {
        for (int v : this->Grid.triangles[this->GStarItems[s]])
        {
          if (ring[v] < 0 && !isBorder(v))
          {
            ring[v] = r;
            next.push_back(v);
          }
        }
      }
    }
    active.insert(active.end(), next.begin(), next.end());
    frontier.swap(next);
  }
  // Local vertices: the simulated ones first, in spatial order, then the halo.
  this->Progress.report(this->At, this->Stage);
  sortSpatially(active, this->Points);
  this->Progress.report(this->At, this->Stage);
  withRoom(this->LocalOf, np).assign(np, -1);
  withRoom(this->Global, np); // (np: its size is known once the halo is in)
  for (int g : active)
  {
    this->LocalOf[g] = static_cast<int>(this->Global.size());
    this->Global.push_back(g);
  }
  this->NumActive = static_cast<int>(this->Global.size());
  this->Progress.report(this->At, this->Stage); // (a gap of up to 0.07 s at 1 M without)
  LargeVector<int> localTri(nt, -1);
  withRoom(this->TriGlobal, nt); // (nt: as Global's)
  this->Progress.report(this->At, this->Stage);
  for (int g : active)
  {
    this->poll(static_cast<std::size_t>(&g - active.data()));
    for (int s = this->GStarStart[g]; s < this->GStarStart[g + 1]; ++s)
    {
      const int t = this->GStarItems[s];
      if (localTri[t] >= 0)
      {
        continue;
      }
      localTri[t] = static_cast<int>(this->TriGlobal.size());
      this->TriGlobal.push_back(t);
      for (int v : this->Grid.triangles[t])
      {
        if (this->LocalOf[v] < 0)
        {
          this->LocalOf[v] = static_cast<int>(this->Global.size());
          this->Global.push_back(v);
        }
      }
    }
  }
  const std::size_t nl = this->TriGlobal.size();
  const bool levels = this->Grid.triangleLevel.size() == nt;
  withRoom(this->Tri, nl).resize(nl);
  withRoom(this->Level, nl).resize(nl);
  for (std::size_t t = 0; t < nl; ++t)
  {
    this->poll(t);
    const std::array<int, 3>& g = this->Grid.triangles[this->TriGlobal[t]];
    this->Tri[t] = { this->LocalOf[g[0]], this->LocalOf[g[1]], this->LocalOf[g[2]] };
    this->Level[t] = levels ? this->Grid.triangleLevel[this->TriGlobal[t]] : 0;
  }
  this->Progress.report(this->At, this->Stage);
  // Neighbours across each edge k (from corner k to corner k + 1): a local triangle, -1 for
  // the domain border, -2 - (grid triangle id) for a triangle outside the sub-mesh.
  // (Each triangle writes its own slots: blocks of triangles, each block's halves at once.)
  withRoom(this->Nbr, nl).assign(nl, { -1, -1, -1 });
  this->Progress.report(this->At, this->Stage); // (its first writes: 0.01-0.03 s at 1 M)
  blockwise(
    nl,
    kTwoThreadBlock / 4, // (their stars' reads are slow: up to 0.12 s per 65536 at 1 M)
    kTwoThreadItems,
    [&](std::size_t from, std::size_t to, int)
    {
      for (std::size_t t = from; t < to; ++t)
      {
        const int gt = this->TriGlobal[t];
        const std::array<int, 3>& g = this->Grid.triangles[gt];
        for (int k = 0; k < 3; ++k)
        {
          const int a = g[k], b = g[(k + 1) % 3];
          int across = -1;
          for (int s = this->GStarStart[b]; s < this->GStarStart[b + 1] && across < 0; ++s)
          {
            const int u = this->GStarItems[s];
            const std::array<int, 3>& h = this->Grid.triangles[u];
            const int j = h[0] == b ? 0 : (h[1] == b ? 1 : 2);
            if (u != gt && h[(j + 1) % 3] == a)
            {
              across = u;
            }
          }
          this->Nbr[t][k] =
            across < 0 ? -1 : (localTri[across] >= 0 ? localTri[across] : -2 - across);
        }
      }
    },
    [&] { this->Progress.report(this->At, this->Stage); });
  // Spring edges (each edge once; both triangles of an edge share its id).
  LargeVector<std::array<int, 2>> edges;
  edges.reserve(3 * nl / 2 + 3);
  withRoom(this->TriEdge, nl).assign(nl, { -1, -1, -1 });
  for (std::size_t t = 0; t < nl; ++t)
  {
    this->poll(t);
    for (int k = 0; k < 3; ++k)
    {
      const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3];
      const int u = this->Nbr[t][k];
      if (u >= 0 && u < static_cast<int>(t))
      {
        for (int j = 0; j < 3; ++j)
        {
          if (this->Tri[u][j] == b && this->Tri[u][(j + 1) % 3] == a)
          {
            this->TriEdge[t][k] = this->TriEdge[u][j];
          }
        }
      }
      else
      {
        this->TriEdge[t][k] = static_cast<int>(edges.size());
        edges.push_back({ std::min(a, b), std::max(a, b) });
      }
    }
  }
  const std::size_t nv = this->Global.size();
  LargeVector<Vec2> x, rest(nv);
  withRoom(x, nv).resize(nv); // (the spring system's positions)
  for (std::size_t i = 0; i < nv; ++i)
  {
    x[i] = this->Points[this->Global[i]];
    rest[i] = this->Grid.points[this->Global[i]];
  }
  // The set-up's own arrays go (22 MB at 1 M): the spring system's, next, take their memory
  // instead of new memory (see LargeArray.h).
  this->Points = LargeVector<Vec2>();
  this->GStarStart = LargeVector<int>();
  this->GStarItems = LargeVector<int>();
  withRoom(this->RestTwice, nl).resize(nl);
  for (std::size_t t = 0; t < nl; ++t)
  {
    this->poll(t);
    const std::array<int, 3>& tri = this->Tri[t];
    this->RestTwice[t] = orient2d(rest[tri[0]], rest[tri[1]], rest[tri[2]]);
  }
  SpringParams sp;
  sp.configuration = this->Params.springConfiguration;
  sp.stiffness = this->Params.springStiffness;
  sp.damping = this->Params.damping;
  sp.splitSprings = this->Params.splitSprings;
  SpringMesh sm;
  sm.triangles = this->Tri;
  sm.edges = std::move(edges);
  this->Progress.report(this->At, this->Stage);
  this->Sys = std::make_unique<SpringSystem>(
    std::move(sm), std::move(x), std::move(rest), sp, this->Progress.sub(this->At, this->At));
  this->Sys->releaseRestPositions(); // (no set is added later: the stars take that memory)
  this->Progress.report(this->At, this->Stage);
  this->rebuildStars();
  // (Reports between the arrays too: at 1 M their first writes took up to 0.2 s together.)
  this->Progress.report(this->At, this->Stage);

  // States.
  withRoom(this->St, nv).assign(nv, Halo);
  withRoom(this->Loc, nv).assign(nv, Location{});
  this->Progress.report(this->At, this->Stage);
  withRoom(this->PinOnArrival, nv).assign(nv, 0);
  withRoom(this->PushOf, nv).assign(nv, -1);
  this->Claimed.assign(this->TheModel.nodes.size(), 0);
  LargeVector<int> pushIds; // the pushes onto their nearest curve point, placed below
  for (std::size_t i = 0; i < nv; ++i)
  {
    this->poll(i);
    const int li = static_cast<int>(i);
    const int g = this->Global[i];
    if (li >= this->NumActive)
    {
      this->Sys->setKind(li, ParticleKind::Fixed);
    }
    else if (this->JunctionOf[g] >= 0)
    {
      this->St[i] = Pinned;
      this->Loc[i] = this->Rails.locationsOfNode(this->JunctionOf[g]).front();
      this->Claimed[this->JunctionOf[g]] = 1;
      this->Sys->setKind(li, ParticleKind::Fixed);
      ++this->Result.junctionVertices;
    }
    else if (this->JunctionTarget[g] >= 0)
    {
      this->St[i] = Pushing;
      PushRecord& p = this->pushRecord(li);
      this->Loc[i] = p.first = this->Rails.locationsOfNode(this->JunctionTarget[g]).front();
      p.target = this->TheModel.nodes[this->JunctionTarget[g]];
      this->PinOnArrival[i] = 1;
      this->Claimed[this->JunctionTarget[g]] = 1;
      this->Sys->setKind(li, ParticleKind::Driven);
      ++this->Result.pushedVertices;
      ++this->Result.junctionVertices;
    }
    else if (this->Push[g])
    {
      this->St[i] = Pushing;
      pushIds.push_back(li);
      this->pushRecord(li); // (here: the threads below write records that exist)
      this->Sys->setKind(li, ParticleKind::Driven);
      ++this->Result.pushedVertices;
    }
    else
    {
      this->St[i] = Free;
    }
  }
  // Their nearest curve points (queries only: in blocks, each block's halves on two threads).
  StripTreeScratch scratch2;
  blockwise(
    pushIds.size(),
    kTwoThreadBlock,
    kTwoThreadItems / 4,
    [&](std::size_t from, std::size_t to, int which)
    {
      StripTreeScratch& scratch = which == 0 ? this->RailScratch : scratch2;
      for (std::size_t j = from; j < to; ++j)
      {
        const int i = pushIds[j];
        this->Loc[i] = this->Pushes[this->PushOf[i]].first =
          this->Rails.closest(this->positions()[i], scratch);
      }
    },
    [&] { this->Progress.report(this->At, this->Stage); });
  for (const int i : pushIds)
  {
    this->pushRecord(i).target = this->Rails.position(this->Loc[i]);
    const int point = this->Rails.pointAt(this->Loc[i]);
    this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(this->Loc[i].chain, point);
  }
  this->Result.simulatedVertices = static_cast<std::size_t>(this->NumActive);
  this->claimStopPoints();
  this->spreadTargets();
  for (int i = 0; i < this->NumActive; ++i)
  {
    this->poll(static_cast<std::size_t>(i));
    if (this->St[i] == Pushing)
    {
      this->setBudget(i);
    }
  }
}

void Compressor::rebuildStars()
{
  // (Progress between and within the steps: at 1 M the first writes to these arrays took up
  // to 0.4 s in all on a slow hour of this machine.)
  // On large meshes the triangles' two halves are counted and placed at once (a counting
  // sort in two halves: each star lists the first half's triangles, then the second's, so in
  // ascending order as one pass would).
  const std::size_t nv = this->Global.size(), nt = this->Tri.size();
  const bool two = nt >= kTwoThreadItems;
  const std::size_t middle = two ? nt / 2 : nt;
  this->StarStart.assign(nv + 1, 0);
  LargeVector<int> second(two ? nv : 0, 0); // the second half's count, then its next slot
  const auto count = [&](std::size_t from, std::size_t to, int* counts)
  {
    for (std::size_t t = from; t < to; ++t)
    {
      for (int v : this->Tri[t])
      {
        ++counts[v];
      }
    }
  };
  this->Progress.report(this->At, this->Stage); // (right after the assignment)
  if (two)
  {
    bothHalves([&] { count(0, middle, this->StarStart.data() + 1); },
      [&] { count(middle, nt, second.data()); });
  }
  else
  {
    count(0, nt, this->StarStart.data() + 1);
  }
  this->Progress.report(this->At, this->Stage);
  LargeVector<int> fill(nv);
  for (std::size_t i = 0; i < nv; ++i)
  {
    const int first = this->StarStart[i + 1];
    this->StarStart[i + 1] = this->StarStart[i] + first + (two ? second[i] : 0);
    fill[i] = this->StarStart[i];
    if (two)
    {
      second[i] = this->StarStart[i] + first;
    }
  }
  this->Progress.report(this->At, this->Stage);
  this->StarItems.resize(this->StarStart.back());
  this->Progress.report(this->At, this->Stage);
  const auto place = [&](std::size_t from, std::size_t to, int* next)
  {
    for (std::size_t t = from; t < to; ++t)
    {
      for (int v : this->Tri[t])
      {
        this->StarItems[next[v]++] = static_cast<int>(t);
      }
    }
  };
  if (two)
  {
    bothHalves([&] { place(0, middle, fill.data()); }, [&] { place(middle, nt, second.data()); });
  }
  else
  {
    place(0, nt, fill.data());
  }
  this->Flipped.clear();
  this->StarTriangles = this->Tri.size();
}

// The stars after flips, splits and collapses: the same tables as rebuildStars(), which lists
// every star's triangles in ascending order, computed from the stars before. Every triangle
// whose corners changed since is listed in Flipped (flip(), splitEdge(), collapseInto()), and
// the triangles and vertices added since (the optimization's splits) are new. A vertex left by
// a changed triangle is in another changed one (a flip keeps the four vertices of its two
// triangles, a split its two triangles' and a collapse its star's), so only the vertices of the
// changed triangles have other stars: each is merged from its old star without the changed
// triangles and the changed triangles that hold it now; the other stars' items are copied in
// blocks. (Each triangle has three items, a collapsed one three times its vertex.)
void Compressor::updateStars()
{
  const std::size_t nv = this->Global.size(), nt = this->Tri.size();
  if (nt < this->StarTriangles || this->StarStart.empty() || this->StarStart.size() > nv + 1)
  {
    this->rebuildStars();
    return;
  }
  const int itemsBefore = this->StarStart.back();
  this->StarStart.resize(nv + 1, itemsBefore); // (new vertices: empty stars)
  for (std::size_t t = this->StarTriangles; t < nt; ++t)
  {
    this->Flipped.push_back(static_cast<int>(t));
  }
  this->StarTriangles = nt;
  if (this->Flipped.empty())
  {
    return;
  }
  auto& flipped = this->Flipped;
  sortUnique(flipped);
  this->FlippedMark.resize(this->Tri.size(), 0);
  // (vertex, triangle) of the flipped triangles now, by vertex then triangle.
  LargeVector<std::pair<int, int>> now;
  now.reserve(3 * flipped.size());
  for (int t : flipped)
  {
    this->FlippedMark[t] = 1;
    for (int v : this->Tri[t])
    {
      now.emplace_back(v, t);
    }
  }
  std::sort(now.begin(), now.end());
  // The new items go to the scratch buffer, which then swaps with the old ones: a flip round
  // writes every item once, into memory the rounds before already paged in.
  LargeVector<int>& items = this->StarScratch;
  items.resize(3 * nt);
  const int* old = this->StarItems.data();
  int* out = items.data();
  int copied = 0; // old items copied or replaced so far
  int written = 0;
  int shift = 0; // new start minus old start of the vertices after the last one merged
  int next = 0;  // first vertex whose start is not shifted yet
  for (std::size_t k = 0; k < now.size();)
  {
    const int v = now[k].first;
    const int s0 = this->StarStart[v], s1 = this->StarStart[v + 1];
    // The stars between: copied, their starts shifted.
    std::copy(old + copied, old + s0, out + written);
    written += s0 - copied;
    for (int w = next; w <= v; ++w)
    {
      this->StarStart[w] += shift;
    }
    // v's star: the old one without the flipped triangles, merged with v's flipped ones.
    std::size_t end = k;
    while (end < now.size() && now[end].first == v)
    {
      ++end;
    }
    int s = s0;
    const auto skipFlipped = [&]()
    {
      while (s < s1 && this->FlippedMark[old[s]])
      {
        ++s;
      }
    };
    skipFlipped();
    for (std::size_t f = k; f < end; ++f)
    {
      for (; s < s1 && old[s] < now[f].second; ++s, skipFlipped())
      {
        out[written++] = old[s];
      }
      out[written++] = now[f].second;
    }
    for (; s < s1; ++s, skipFlipped())
    {
      out[written++] = old[s];
    }
    copied = s1;
    shift = written - s1;
    next = v + 1;
    k = end;
  }
  std::copy(old + copied, old + this->StarItems.size(), out + written);
  for (std::size_t w = static_cast<std::size_t>(next); w <= nv; ++w)
  {
    this->StarStart[w] += shift;
  }
  this->StarItems.swap(items);
  for (int t : flipped)
  {
    this->FlippedMark[t] = 0;
  }
  flipped.clear();
}

// Whether a claimed stop point (a junction or feature with its vertex) is within arc length
// `reach` of l along its segment.
bool Compressor::nearClaimedStop(const Location& l, double reach) const
{
  const BoundaryRails::Chain& c = this->Rails.chain(l.chain);
  const int p0 = l.segment, p1 = (l.segment + 1) % static_cast<int>(c.points.size());
  const double len = norm(c.points[p1] - c.points[p0]);
  return (this->Claimed[c.nodes[p0]] && l.t * len <= reach) ||
    (this->Claimed[c.nodes[p1]] && (1.0 - l.t) * len <= reach);
}

// A stop point (junction or feature) takes one vertex: the junction's own vertex, else the
// pushed vertex closest to it; the others aim beside it.
void Compressor::claimStopPoints()
{
  LargeVector<std::pair<double, int>> order;
  const auto& x = this->positions();
  for (int i = 0; i < this->NumActive; ++i)
  {
    if (this->St[i] == Pushing && !this->junctionBound(i))
    {
      order.push_back({ norm(this->pushed(i).target - x[i]), i });
    }
  }
  std::sort(order.begin(), order.end());
  for (const std::pair<double, int>& item : order)
  {
    const int i = item.second;
    const int point = this->Rails.pointAt(this->Loc[i]);
    if (this->nearClaimedStop(this->Loc[i], 0.3 * this->Sys->localLength(i)))
    {
      this->retarget(i);
    }
    else if (point >= 0 && this->PinOnArrival[i])
    {
      this->Claimed[this->Rails.chain(this->Loc[i].chain).nodes[point]] = 1;
    }
  }
}

// Of two pushed vertices aiming at nearly the same point of a chain (closer than a quarter
// of the local edge length), the one farther from its target aims beside it.
void Compressor::spreadTargets()
{
  struct Item
  {
    Location l;
    int vertex;
  };
  LargeVector<Item> items;
  for (int i = 0; i < this->NumActive; ++i)
  {
    if (this->St[i] == Pushing && !this->junctionBound(i))
    {
      items.push_back({ this->Loc[i], i });
    }
  }
  std::sort(items.begin(),
    items.end(),
    [](const Item& a, const Item& b)
    {
      return a.l.chain != b.l.chain
        ? a.l.chain < b.l.chain
        : (a.l.segment != b.l.segment ? a.l.segment < b.l.segment : a.l.t < b.l.t);
    });
  const auto& x = this->positions();
  for (std::size_t k = 1; k < items.size(); ++k)
  {
    const int a = items[k - 1].vertex, b = items[k].vertex;
    if (items[k - 1].l.chain != items[k].l.chain)
    {
      continue;
    }
    const double h = std::min(this->Sys->localLength(a), this->Sys->localLength(b));
    const Vec2 ta = this->pushed(a).target, tb = this->pushed(b).target;
    if (norm(ta - tb) < 0.25 * h)
    {
      this->retarget(norm2(ta - x[a]) <= norm2(tb - x[b]) ? b : a);
    }
  }
}

void Compressor::setBudget(int i)
{
  const double step = this->Params.pushVelocity * this->Params.timeStep * this->Sys->localLength(i);
  PushRecord& p = this->pushRecord(i);
  p.steps = 0;
  p.budget =
    static_cast<int>(std::ceil(norm(p.target - this->positions()[i]) / step)) + kStuckSteps;
}

// Aims pushed vertex i half an edge length (one edge length after two retargets) beside its
// first target or beside its current closest point, whichever candidate is nearest to it,
// avoiding taken stop points.
void Compressor::retarget(int i)
{
  const auto& x = this->positions();
  PushRecord& p = this->pushRecord(i);
  const double h = 0.5 * this->Sys->localLength(i) * (1 + p.retargets / 2);
  const Location now = this->Rails.closest(x[i], this->RailScratch);
  bool found = false;
  Location best;
  double bestD = HUGE_VAL;
  for (const Location& from : { p.first, now })
  {
    for (double s : { h, -h })
    {
      const Location l = this->Rails.slide(from, s).location;
      const Vec2 at = this->Rails.position(l);
      const double d = norm2(at - x[i]);
      if (d < bestD && norm(at - p.target) > 0.05 * h && !this->nearClaimedStop(l, 0.3 * h))
      {
        best = l;
        bestD = d;
        found = true;
      }
    }
  }
  ++p.retargets;
  if (!found)
  {
    return;
  }
  this->Loc[i] = best;
  p.target = this->Rails.position(best);
  const int point = this->Rails.pointAt(best);
  this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(best.chain, point);
}

void Compressor::startPush(int i, const Location& target)
{
  this->St[i] = Pushing;
  PushRecord& p = this->pushRecord(i);
  this->Loc[i] = p.first = target;
  p.target = this->Rails.position(target);
  const int point = this->Rails.pointAt(target);
  this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(target.chain, point);
  p.stuck = 0;
  p.retargets = 0;
  this->Sys->setKind(i, ParticleKind::Driven);
  ++this->Result.pushedVertices;
  if (this->nearClaimedStop(target, 0.3 * this->Sys->localLength(i)))
  {
    this->retarget(i);
  }
  else if (point >= 0 && this->PinOnArrival[i])
  {
    this->Claimed[this->Rails.chain(target.chain).nodes[point]] = 1;
  }
  this->setBudget(i);
}

//------------------------------------------------------------------------------
// Simulation.
void Compressor::pushStep(int i, double dt)
{
  auto& x = this->positions();
  PushRecord& p = this->Pushes[this->PushOf[i]];
  const Vec2 d = p.target - x[i];
  const double remaining = norm(d);
  const double h = this->Sys->localLength(i);
  const double stepLength = this->Params.pushVelocity * dt * h;
  const bool arrive = remaining <= stepLength;
  const Vec2 to = arrive ? p.target : x[i] + (stepLength / remaining) * d;
  if (!this->accepts(i, to))
  {
    this->Sys->velocities()[i] = Vec2{};
    ++p.stuck;
    if (p.stuck == kStuckSteps / 2 && this->Params.flipDegenerate)
    {
      // Ask for the edges opposite i in the triangles that block the move to be flipped.
      for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
      {
        const int t = this->StarItems[s];
        const std::array<int, 3>& tri = this->Tri[t];
        const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
        const Vec2 a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
        if (cross(b - a, to - a) < kCollapse * this->RestTwice[t])
        {
          this->Blocked.push_back({ t, (k + 1) % 3 });
        }
      }
    }
    if (p.stuck == kStuckSteps && p.retargets < kMaxRetargets && !this->junctionBound(i))
    {
      this->retarget(i); // (i has its record: none is made, p stays valid)
      p.stuck = 0;
    }
    return;
  }
  p.stuck = 0;
  x[i] = to;
  if (!arrive)
  {
    this->Sys->velocities()[i] = (this->Params.pushVelocity * h / remaining) * d;
    return;
  }
  this->Sys->velocities()[i] = Vec2{};
  ++this->Result.arrivedVertices;
  if (this->PinOnArrival[i])
  {
    this->St[i] = Pinned;
    this->Sys->setKind(i, ParticleKind::Fixed);
  }
  else
  {
    this->St[i] = Rail;
  }
}

void Compressor::railStep(int i, double dt)
{
  auto& x = this->positions();
  // First-order motion along the rail: the vertex moves by dt^2 F_t / m_i (the step the
  // particle would make from rest), with no momentum. With the stable mass m_i this is at
  // most half the step to the equilibrium of its springs along the rail, so the rails settle
  // without oscillating.
  const Vec2 tangent = this->Rails.tangent(this->Loc[i]);
  const Vec2 force = this->Sys->forces()[i];
  double s = dt * dt * dot(force, tangent) / this->Sys->stableMass(i, dt);
  const double limit = this->Sys->params().maxStep * this->Sys->localLength(i);
  s = std::clamp(s, -limit, limit);
  double u = s / dt;
  if (s == 0.0)
  {
    return;
  }
  BoundaryRails::Slide slide = this->Rails.slide(this->Loc[i], s);
  if (!slide.stopped && slide.location.segment != this->Loc[i].segment &&
    dot(force, this->Rails.tangent(slide.location)) * s < 0.0)
  {
    // The force pulls back on the next segment: the bend is an equilibrium, rest on it
    // instead of chattering around it.
    slide.location = this->Loc[i];
    slide.location.t = s > 0.0 ? 1.0 : 0.0;
    u = 0.0;
  }
  const Vec2 to = this->Rails.position(slide.location);
  if (!this->accepts(i, to))
  {
    this->Sys->velocities()[i] = Vec2{};
    return;
  }
  x[i] = to;
  this->Loc[i] = slide.location;
  if (slide.stopped)
  {
    this->Sys->velocities()[i] = Vec2{};
    const int point = this->Rails.pointAt(slide.location);
    const BoundaryRails::Chain& c = this->Rails.chain(slide.location.chain);
    const bool chainEnd =
      !c.closed && (point == 0 || point + 1 == static_cast<int>(c.points.size()));
    if (!chainEnd)
    {
      // Passed over a feature point: stays there for good (6.4).
      this->Claimed[c.nodes[point]] = 1;
      this->St[i] = Pinned;
      this->Sys->setKind(i, ParticleKind::Fixed);
    }
    return;
  }
  this->Sys->velocities()[i] = u * this->Rails.tangent(slide.location);
}

// A new push wave: the compression moved free vertices, so an edge between two free (or
// halo) vertices may now cross a boundary. It can only when the boundary distances of its
// ends add up to at most its length; then the regions of its ends decide, and the push
// criterion picks the end to push.
std::size_t Compressor::pushNewCrossings()
{
  // The stars' scratch goes (12 MB at 1 M): the wave's lists take its memory, and the next
  // updateStars() makes it again (at most once a wave) rather than memory new to the run.
  LargeVector<int>().swap(this->StarScratch);
  const auto& x = this->positions();
  const std::size_t nv = x.size();
  const auto crossable = [&](int a, int b)
  {
    const bool freeA = this->St[a] == Free, freeB = this->St[b] == Free;
    return (freeA || freeB) && (freeA || this->St[a] == Halo) && (freeB || this->St[b] == Halo);
  };
  // The queries of the two loops below, independent of each other, first: the regions of the
  // vertices of the edges between free (or free and halo) vertices, and of the barycentres of
  // the faces with two corners on curves and a free third, each list cut into blocks whose two
  // halves run on two threads (bothHalves; progress between blocks). Each vertex caches its
  // grid distance (Distance) from one thread only, so the result is the serial one.
  LargeVector<int> asked; // vertex ids, increasing
  bool unknown = false;   // a vertex whose grid distance is not known yet
  {
    LargeVector<std::uint8_t> mark(nv, 0);
    for (const std::array<int, 2>& e : this->Sys->mesh().edges)
    {
      if (crossable(e[0], e[1]))
      {
        mark[e[0]] = mark[e[1]] = 1;
      }
    }
    for (std::size_t v = 0; v < nv; ++v)
    {
      if (mark[v])
      {
        asked.push_back(static_cast<int>(v));
        unknown = unknown || std::isnan(this->Distance[this->Global[v]]);
      }
    }
  }
  // (The faces by increasing id, on two threads.)
  LargeVector<std::array<int, 2>> faces; // (face, its free corner)
  gatherInOrder<std::array<int, 2>>(
    this->Tri.size(),
    kTwoThreadBlock,
    kTwoThreadItems,
    [&](std::size_t t, std::vector<std::array<int, 2>>& found)
    {
      int freeCorner = -1, onCurve = 0;
      for (int v : this->Tri[t])
      {
        if (this->onCurve(v))
        {
          ++onCurve;
        }
        else if (this->St[v] == Free)
        {
          freeCorner = v;
        }
      }
      if (onCurve == 2 && freeCorner >= 0)
      {
        found.push_back({ static_cast<int>(t), freeCorner });
      }
    },
    [&](const std::array<int, 2>& face) { faces.push_back(face); },
    [] {});
  if (unknown && !this->CurveCells)
  {
    this->buildCurveCells(); // (before the threads, which read it)
  }
  LargeVector<int> region(nv, -3), faceRegion(faces.size(), -3);
  if (this->WaveVertexAt.size() != nv)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    this->WaveVertexAt.assign(nv, Vec2{ nan, nan });
    this->WaveVertexRegion.assign(nv, -3);
  }
  // The last call's answer for each face asked now, if it asked about it (both lists are by
  // increasing face id).
  LargeVector<int> faceBefore(faces.size(), -1);
  for (std::size_t k = 0, j = 0; k < faces.size() && j < this->WaveFaces.size(); ++k)
  {
    while (j < this->WaveFaces.size() && this->WaveFaces[j].face < faces[k][0])
    {
      ++j;
    }
    if (j < this->WaveFaces.size() && this->WaveFaces[j].face == faces[k][0])
    {
      faceBefore[k] = static_cast<int>(j);
    }
  }
  // (Both answers depend on the position only, for a vertex off the curves; each vertex and
  // face is asked by one thread.)
  const auto query =
    [&](std::size_t from, std::size_t to, StripTreeScratch& rail, DistanceField::Scratch& field)
  {
    for (std::size_t i = from; i < to; ++i)
    {
      if (i < asked.size())
      {
        const int v = asked[i];
        if (this->onCurve(v) || !(x[v] == this->WaveVertexAt[v]))
        {
          region[v] = this->vertexRegion(v, rail, field);
          if (!this->onCurve(v))
          {
            this->WaveVertexAt[v] = x[v];
            this->WaveVertexRegion[v] = region[v];
          }
        }
        else
        {
          region[v] = this->WaveVertexRegion[v];
        }
      }
      else
      {
        const std::size_t k = i - asked.size();
        const std::array<int, 3>& tri = this->Tri[faces[k][0]];
        const Vec2 centre = (1.0 / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]);
        const int before = faceBefore[k];
        faceRegion[k] = before >= 0 && centre == this->WaveFaces[before].at
          ? this->WaveFaces[before].region
          : this->Field.region(centre, field);
      }
    }
  };
  StripTreeScratch rail2;
  DistanceField::Scratch field2;
  const std::size_t queries = asked.size() + faces.size();
  for (std::size_t begin = 0; begin < queries; begin += kQueryBlock)
  {
    this->Progress.report(this->At, this->Stage);
    const std::size_t end = std::min(queries, begin + kQueryBlock);
    const std::size_t middle = begin + (end - begin) / 2;
    bothHalves([&] { query(begin, middle, this->RailScratch, this->FieldScratch); },
      [&] { query(middle, end, rail2, field2); });
  }
  this->WaveFaces.clear();
  for (std::size_t k = 0; k < faces.size(); ++k)
  {
    const std::array<int, 3>& tri = this->Tri[faces[k][0]];
    this->WaveFaces.push_back(
      { faces[k][0], faceRegion[k], (1.0 / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]) });
  }
  const auto regionOf = [&](int v)
  {
    if (region[v] == -3)
    {
      region[v] = this->vertexRegion(v);
    }
    return region[v];
  };
  LargeVector<std::uint8_t> push(nv, 0);
  for (const std::array<int, 2>& e : this->Sys->mesh().edges)
  {
    this->poll(static_cast<std::size_t>(&e - this->Sys->mesh().edges.data()));
    const int a = e[0], b = e[1];
    if (!crossable(a, b))
    {
      continue;
    }
    const bool freeA = this->St[a] == Free, freeB = this->St[b] == Free;
    const int ra = region[a], rb = region[b];
    if (ra == rb)
    {
      continue;
    }
    int pushed = a;
    switch (this->Params.pushCriterion)
    {
      case PushCriterion::AllCandidates:
        push[a] |= freeA;
        push[b] |= freeB;
        continue;
      case PushCriterion::OneSide:
        pushed = ra == -1 ? a : (rb == -1 ? b : (ra > rb ? a : b));
        break;
      case PushCriterion::Closest:
      {
        double da = 0.0, db = 0.0;
        this->Rails.closest(x[a], this->RailScratch, &da);
        this->Rails.closest(x[b], this->RailScratch, &db);
        pushed = da <= db ? a : b;
        break;
      }
    }
    push[this->St[pushed] == Free ? pushed : (pushed == a ? b : a)] = 1;
  }
  // A face with two corners on curves and a free third corner whose barycentre lies in
  // another region than that corner: the boundary bulges into the face between the two curve
  // vertices (or a region too thin to hold a vertex runs through it); the free corner is
  // pushed onto it. (Crossings between free vertices are the edges above.)
  for (std::size_t k = 0; k < faces.size(); ++k)
  {
    this->poll(k);
    const int freeCorner = faces[k][1];
    if (!push[freeCorner] && faceRegion[k] != regionOf(freeCorner))
    {
      push[freeCorner] = 1;
    }
  }
  std::size_t count = 0;
  for (int i = 0; i < this->NumActive; ++i)
  {
    this->poll(static_cast<std::size_t>(i));
    if (push[i] && this->St[i] == Free)
    {
      this->startPush(i, this->Rails.closest(x[i], this->RailScratch));
      ++count;
    }
  }
  return count;
}

// Whether flipping edge k of t gives two counter-clockwise triangles (a convex quad).
bool Compressor::flipValid(int t, int k) const
{
  const int u = this->Nbr[t][k];
  if (u < 0)
  {
    return false;
  }
  const auto& x = this->positions();
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3], c = this->Tri[t][(k + 2) % 3];
  const std::array<int, 3>& tu = this->Tri[u];
  const int j = tu[0] == b ? 0 : (tu[1] == b ? 1 : 2);
  const int d = tu[(j + 2) % 3];
  if (c == d || tu[(j + 1) % 3] != a)
  {
    return false;
  }
  const double scale = norm2(x[c] - x[d]);
  return orient2d(x[c], x[a], x[d]) > 1e-12 * scale && orient2d(x[d], x[b], x[c]) > 1e-12 * scale;
}

// Flips edge k of t (shared with u = Nbr[t][k]): (a, b, c) + (b, a, d) -> (c, a, d) + (d, b, c).
void Compressor::flip(int t, int k)
{
  const Quad q = this->quadOf(t, k);
  const int u = q.u, j = q.j, a = q.a, b = q.b, c = q.c, d = q.d;
  const int nBC = this->Nbr[t][(k + 1) % 3], nCA = this->Nbr[t][(k + 2) % 3];
  const int nAD = this->Nbr[u][(j + 1) % 3], nDB = this->Nbr[u][(j + 2) % 3];
  const int eAB = this->TriEdge[t][k], eBC = this->TriEdge[t][(k + 1) % 3];
  const int eCA = this->TriEdge[t][(k + 2) % 3];
  const int eAD = this->TriEdge[u][(j + 1) % 3], eDB = this->TriEdge[u][(j + 2) % 3];
  ++this->Flips;
  this->Flipped.push_back(t);
  this->Flipped.push_back(u);
  this->noteChanged(t);
  this->noteChanged(u);
  if (!this->MovedAll)
  {
    this->FlippedSinceTest.push_back(t);
    this->FlippedSinceTest.push_back(u);
  }
  this->Tri[t] = { c, a, d };
  this->Nbr[t] = { nCA, nAD, u };
  this->TriEdge[t] = { eCA, eAD, eAB };
  this->Tri[u] = { d, b, c };
  this->Nbr[u] = { nDB, nBC, t };
  this->TriEdge[u] = { eDB, eBC, eAB };
  const auto relink = [&](int n, int from, int to)
  {
    if (n >= 0)
    {
      for (int m = 0; m < 3; ++m)
      {
        if (this->Nbr[n][m] == from)
        {
          this->Nbr[n][m] = to;
        }
      }
    }
  };
  relink(nAD, u, t);
  relink(nBC, t, u);
  if (!this->Detached)
  {
    this->Sys->flip(eAB, { c, d }, t, this->Tri[t], u, this->Tri[u]);
  }
  this->RestTwice[t] = this->twiceArea(t);
  this->RestTwice[u] = this->twiceArea(u);
  this->Level[t] = this->Level[u] = std::max(this->Level[t], this->Level[u]);
}

// Flips edge k of t if valid and improving the pair's smallest angle. degenerate: the paper's
// rule (6.5), regions are not known yet; otherwise both faces and both new faces must have
// the same region.
bool Compressor::tryFlip(int t, int k, bool degenerate)
{
  if (!this->flipValid(t, k))
  {
    return false;
  }
  const auto& x = this->positions();
  const Quad q = this->quadOf(t, k);
  const int u = q.u, a = q.a, b = q.b, c = q.c, d = q.d;
  const double before = std::min(minAngleSine(x[a], x[b], x[c]), minAngleSine(x[b], x[a], x[d]));
  const double after = std::min(minAngleSine(x[c], x[a], x[d]), minAngleSine(x[d], x[b], x[c]));
  if (!(after > before * (1.0 + 1e-9) + 1e-12))
  {
    return false;
  }
  if (!degenerate &&
    (this->Tag[t] != this->Tag[u] || this->faceTag(c, a, d, x[c], x[a], x[d]) != this->Tag[t] ||
      this->faceTag(d, b, c, x[d], x[b], x[c]) != this->Tag[t]))
  {
    return false;
  }
  this->flip(t, k);
  return true;
}

std::size_t Compressor::flipDegenerate()
{
  if (!this->Params.flipDegenerate)
  {
    return 0;
  }
  static const double smallSine = std::sin(kSmallAngle * 3.14159265358979323846 / 180.0);
  std::size_t flips = 0;
  const auto& x = this->positions();
  const auto degenerate = [&](std::size_t t)
  {
    const std::array<int, 3>& tri = this->Tri[t];
    return this->twiceArea(static_cast<int>(t)) < kSmallArea * this->RestTwice[t] ||
      minAngleSine(x[tri[0]], x[tri[1]], x[tri[2]]) < smallSine;
  };
  // The test of every triangle first, in two halves on two threads (it only reads), or, when
  // few particles were awake since the last test, of the triangles around them and those
  // flipped since (the others kept their shape and their marks); then the flips in order,
  // testing again the triangles a flip before changed: the serial result.
  const std::size_t nt = this->Tri.size();
  LargeVector<std::uint8_t>& marks = this->DegenerateMarks;
  this->noteMoved();
  if (!this->MovedAll && marks.size() == nt)
  {
    const auto retest = [&](int t) { marks[t] = degenerate(t) ? kDegenerate : 0; };
    for (const int i : this->Moved)
    {
      for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
      {
        retest(this->StarItems[s]);
      }
    }
    for (const int t : this->FlippedSinceTest)
    {
      retest(t);
    }
  }
  else
  {
    marks.resize(nt);
    const auto test = [&](std::size_t from, std::size_t to)
    {
      for (std::size_t t = from; t < to; ++t)
      {
        marks[t] = degenerate(t) ? kDegenerate : 0;
      }
    };
    bothHalves([&] { test(0, nt / 2); }, [&] { test(nt / 2, nt); });
  }
  for (const int i : this->Moved)
  {
    this->MovedMark[i] = 0;
  }
  this->Moved.clear();
  this->FlippedSinceTest.clear();
  this->MovedAll = false;
  for (std::size_t t = 0; t < nt; ++t)
  {
    this->poll(t);
    const int ti = static_cast<int>(t);
    if (!(marks[t] & kChanged ? degenerate(t) : marks[t] == kDegenerate))
    {
      continue;
    }
    const std::array<int, 3>& tri = this->Tri[t];
    int longest = 0;
    double best = -1.0;
    for (int k = 0; k < 3; ++k)
    {
      const double l = norm2(x[tri[k]] - x[tri[(k + 1) % 3]]);
      if (l > best)
      {
        best = l;
        longest = k;
      }
    }
    const std::size_t before = this->Flipped.size();
    if (this->tryFlip(ti, longest, true))
    {
      ++flips;
      for (std::size_t i = before; i < this->Flipped.size(); ++i)
      {
        marks[this->Flipped[i]] |= kChanged;
      }
    }
  }
  if (flips > 0)
  {
    this->updateStars();
  }
  this->Result.flips += flips;
  return flips;
}

// Flips the edges that blocked pushes (when valid), so the pushed vertices can go on.
std::size_t Compressor::unblockPushes()
{
  std::size_t flips = 0;
  for (const std::pair<int, int>& b : this->Blocked)
  {
    if (this->flipValid(b.first, b.second))
    {
      this->flip(b.first, b.second);
      ++flips;
    }
  }
  this->Blocked.clear();
  if (flips > 0)
  {
    this->updateStars();
  }
  this->Result.flips += flips;
  return flips;
}

// Sleeping particles: the particles that moved by more than kSleep local lengths since
// the last update, or are pushed, and their neighbours stay awake; the others are not
// integrated and springs between sleeping particles are not evaluated until they wake. In a
// wave's tail (`tail`) the pushed particles keep two rings of edges around them awake.
// Returns the number of moving particles.
std::size_t Compressor::refreshAwake(LargeVector<Vec2>& windowStart,
  const std::vector<int>& pushed,
  bool tail)
{
  const auto& x = this->positions();
  const std::size_t nv = x.size();
  LargeVector<std::uint8_t> awake(nv, 0);
  std::size_t moving = 0;
  // The awake particles as they wake, while they are few (kFewAwake of the particles).
  SpringSystem::AwakeSets few;
  bool listed = true;
  const auto wake = [&](int v)
  {
    if (v < this->NumActive && !awake[v])
    {
      awake[v] = 1;
      if (listed)
      {
        few.particles.push_back(v);
        listed = static_cast<double>(few.particles.size()) <= kFewAwake * static_cast<double>(nv);
      }
    }
  };
  const auto visit = [&](int i)
  {
    const bool seed =
      this->St[i] == Pushing || norm(x[i] - windowStart[i]) > kSleep * this->Sys->localLength(i);
    windowStart[i] = x[i];
    if (!seed)
    {
      return;
    }
    ++moving;
    for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
    {
      for (int v : this->Tri[this->StarItems[s]])
      {
        wake(v);
        if (tail && this->St[i] == Pushing && v < this->NumActive)
        {
          for (int r = this->StarStart[v]; r < this->StarStart[v + 1]; ++r)
          {
            for (int w : this->Tri[this->StarItems[r]])
            {
              wake(w);
            }
          }
        }
      }
    }
  };
  // Only the awake particles moved since the last refresh: the others are no seeds, but for
  // the pushes a wave just started (among `pushed`, the simulation's pushed vertices), and
  // their window starts hold.
  const LargeVector<int>* list = this->Sys->awakeParticles();
  if (list)
  {
    for (const int i : *list)
    {
      visit(i);
    }
    for (const int i : pushed)
    {
      if (this->St[i] == Pushing && !this->Sys->awake(i))
      {
        visit(i);
      }
    }
  }
  else
  {
    for (int i = 0; i < this->NumActive; ++i)
    {
      visit(i);
    }
  }
  // (The visits and the new sets take 0.02-0.05 s each at 1 M with every particle awake.)
  this->Progress.report(this->At, this->Stage);
  this->noteMoved();
  if (!listed || few.particles.empty() || this->Detached ||
    this->Tri.size() != this->Sys->numberOfTriangles())
  {
    this->Sys->setAwake(std::move(awake));
    return moving;
  }
  // A few awake: their live springs from their stars, not from passes over every spring. The
  // triangles with an awake corner are the awake particles' stars; the edges with an awake
  // end are edges of those triangles.
  std::sort(few.particles.begin(), few.particles.end());
  for (const int v : few.particles)
  {
    for (int s = this->StarStart[v]; s < this->StarStart[v + 1]; ++s)
    {
      few.triangles.push_back(this->StarItems[s]);
    }
  }
  sortUnique(few.triangles);
  for (const int t : few.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      if (awake[this->Tri[t][k]] || awake[this->Tri[t][(k + 1) % 3]])
      {
        few.edges.push_back(this->TriEdge[t][k]);
      }
    }
  }
  sortUnique(few.edges);
  this->Sys->setAwake(std::move(awake), std::move(few));
  return moving;
}

void Compressor::noteMoved()
{
  // (Many: flipDegenerate tests every triangle anyway.)
  const LargeVector<int>* list = this->Sys->awakeParticles();
  if (this->MovedAll || !list || 8 * (this->Moved.size() + list->size()) >= this->Global.size())
  {
    this->MovedAll = true;
    return;
  }
  this->MovedMark.resize(this->Global.size(), 0);
  for (const int i : *list)
  {
    if (!this->MovedMark[i])
    {
      this->MovedMark[i] = 1;
      this->Moved.push_back(i);
    }
  }
}

void Compressor::simulate()
{
  const double dt = this->Params.timeStep;
  const int maxIt = this->Params.maxIterations;
  const int n = this->NumActive;
  int settled = 0, waves = 0, it = 0;
  bool wasPushing = true;
  LargeVector<Vec2> windowStart = this->positions();
  // The pushed vertices, increasing (a push starts only in the waves, when it is rebuilt).
  std::vector<int> pushed;
  const auto findPushed = [&]()
  {
    pushed.clear();
    for (int i = 0; i < n; ++i)
    {
      if (this->St[i] == Pushing)
      {
        pushed.push_back(i);
      }
    }
  };
  findPushed();
  for (; it < maxIt; ++it)
  {
    this->At = 0.1 + 0.6 * static_cast<double>(it) / maxIt;
    this->Progress.report(this->At, this->Stage);
    this->Sys->computeForces();
    // (Reports within the step too: with every particle awake at 1 M, the forces and the
    // moves take 0.02-0.03 s each, twice that on this machine's slow minutes.)
    this->Progress.report(this->At, this->Stage);
    double largest = this->Sys->integrate(dt, &this->TheGuard);
    this->Progress.report(this->At, this->Stage);
    bool pushing = false;
    for (const int i : pushed)
    {
      if (this->St[i] != Pushing)
      {
        continue; // (a push another one ended)
      }
      const Vec2 before = this->positions()[i];
      this->pushStep(i, dt);
      largest = std::max(largest, norm(this->positions()[i] - before) / this->Sys->localLength(i));
      if (this->St[i] == Pushing)
      {
        PushRecord& p = this->Pushes[this->PushOf[i]];
        pushing |= ++p.steps < p.budget;
      }
    }
    pushed.erase(std::remove_if(
                   pushed.begin(), pushed.end(), [this](int i) { return this->St[i] != Pushing; }),
      pushed.end());
    if (!this->Blocked.empty())
    {
      this->unblockPushes();
    }
    bool wave = false;
    if (!pushing && wasPushing && waves < kMaxWaves)
    {
      ++waves;
      pushing = wave = this->pushNewCrossings() > 0;
      waves = wave ? waves : kMaxWaves; // nothing new: the mesh is settled on the curves
      if (wave)
      {
        findPushed();
      }
    }
    wasPushing = pushing;
    if (!pushing)
    {
      // The awake vertices on the rails, increasing.
      const LargeVector<int>* awake = this->Sys->awakeParticles();
      const std::size_t count = awake ? awake->size() : static_cast<std::size_t>(n);
      for (std::size_t j = 0; j < count; ++j)
      {
        const int i = awake ? (*awake)[j] : static_cast<int>(j);
        if (i < n && this->St[i] == Rail)
        {
          const Vec2 before = this->positions()[i];
          this->railStep(i, dt);
          largest =
            std::max(largest, norm(this->positions()[i] - before) / this->Sys->localLength(i));
        }
      }
    }
    if ((it + 1) % this->Params.flipInterval == 0)
    {
      this->flipDegenerate();
    }
    // In a wave's tail (its last few pushes still on their way), the sleep test runs at every
    // step: the rest of the mesh sleeps unless it moved kSleep local lengths in that one step,
    // as after every wave, instead of waiting on the slowest push awake; the two rings of edges
    // around each push still on its way stay awake (one ring, as elsewhere, let the mesh
    // beside a late push settle before it arrived: a lake's boundary 0.46 -> 0.63 local edges
    // off, countries147 of random_lakes_countries.py 142 148).
    const bool tail = pushing && static_cast<double>(pushed.size()) <= kFewPushes * n;
    if (wave || (it + 1) % kWakeInterval == 0 || tail)
    {
      this->Progress.report(this->At, this->Stage); // (after a wave's, before the refresh's work)
      const std::size_t moving = this->refreshAwake(windowStart, pushed, tail);
      if (!pushing && waves >= kMaxWaves && moving <= static_cast<std::size_t>(kQuietFraction * n))
      {
        ++it;
        break; // nothing moves any more
      }
    }
    settled = (!pushing && largest < kSettled) ? settled + 1 : 0;
    if (settled >= kSettledSteps)
    {
      ++it;
      break;
    }
  }
  this->Result.iterations = it;
  this->flipDegenerate();
  this->MovedAll = true; // (no more tests: flips after the simulation are not tracked)
}

//------------------------------------------------------------------------------
// Faces.

// Region of local vertex i (kOnCurve for vertices on a curve). A vertex that moved less than
// its grid position's distance to the boundary stayed in the grid vertex's region.
int Compressor::vertexRegion(int i, StripTreeScratch& rail, DistanceField::Scratch& field)
{
  if (this->onCurve(i))
  {
    return kOnCurve;
  }
  const int g = this->Global[i];
  const Vec2 x = this->positions()[i];
  if (this->Cls.vertexClass[g] != VertexBoundary &&
    this->movedLessThanGridDistance(g, norm(x - this->Grid.points[g]), rail))
  {
    return this->Cls.vertexRegion[g];
  }
  return this->Field.region(x, field);
}

// moved < gridDistance(g), without the strip-tree query when the cells near the curves show
// that no curve lies within `moved` of the grid point (the tree's distance is then larger), or
// within the radius r they search, which `moved` is below (at 1 M the first wave of new pushes
// so spares some 80 k tree queries: 0.22 -> 0.19 s).
bool Compressor::movedLessThanGridDistance(int g, double moved, StripTreeScratch& rail)
{
  if (std::isnan(this->Distance[g]))
  {
    if (!this->CurveCells)
    {
      this->buildCurveCells();
    }
    if (this->CurveCells->noneWithin(this->Grid.points[g], moved))
    {
      return true;
    }
    // The distance from the cells when they settle it (the tree's, bit for bit), kept as
    // gridDistance() keeps it.
    double d2 = 0.0;
    const double r = 2.0 * this->CurveCell;
    if (this->CurveCells->nearestDistance2(this->Grid.points[g], r, d2))
    {
      if (d2 < r * r)
      {
        this->Distance[g] = std::sqrt(d2);
        return moved < this->Distance[g];
      }
      // No segment within r: the tree's distance is at least r (the margin covers its
      // rounding), so the answer is known; the distance stays to be asked when needed.
      if (moved < (1.0 - 1e-9) * r)
      {
        return true;
      }
    }
  }
  return moved < this->gridDistance(g, rail);
}

// The rails' segments in cells half the median longest edge of the sub-mesh wide (every 16th
// triangle), for movedLessThanGridDistance. Which positions give the width does not change
// its answers: the cells only spare strip-tree queries whose answer they already know (and
// settle the distances within two cells of the curves).
void Compressor::buildCurveCells()
{
  const auto& x = this->positions();
  std::vector<double> longest;
  for (std::size_t t = 0; t < this->Tri.size(); t += 16)
  {
    const std::array<int, 3>& tri = this->Tri[t];
    longest.push_back(std::max({ norm2(x[tri[1]] - x[tri[0]]),
      norm2(x[tri[2]] - x[tri[1]]),
      norm2(x[tri[0]] - x[tri[2]]) }));
  }
  double cell = 0.0;
  if (!longest.empty())
  {
    std::nth_element(longest.begin(), longest.begin() + longest.size() / 2, longest.end());
    cell = 0.5 * std::sqrt(longest[longest.size() / 2]);
  }
  const std::size_t most = std::min<std::size_t>(std::size_t(1) << 21, 2 * this->Tri.size() + 4096);
  this->CurveCells = std::make_unique<SegmentGrid>(this->Rails.segmentGrid(cell, most));
  this->CurveCell = cell;
}

// Region of the face (a, b, c) at the given positions: the common region of its corners off
// the curves, else (all corners on curves, or corners in different regions) the region of its
// barycentre.
int Compressor::faceTag(int a, int b, int c, Vec2 pa, Vec2 pb, Vec2 pc)
{
  return this->faceTag(a, b, c, pa, pb, pc, this->FieldScratch);
}

int Compressor::faceTag(int a,
  int b,
  int c,
  Vec2 pa,
  Vec2 pb,
  Vec2 pc,
  DistanceField::Scratch& field)
{
  int region = kOnCurve;
  for (int v : { a, b, c })
  {
    const int r = this->VRegion[v];
    if (r == kOnCurve)
    {
      continue;
    }
    if (region == kOnCurve)
    {
      region = r;
    }
    else if (region != r)
    {
      region = kOnCurve;
      break;
    }
  }
  return region != kOnCurve ? region : this->Field.region((1.0 / 3.0) * (pa + pb + pc), field);
}

int Compressor::faceTag(int t)
{
  return this->faceTag(t, this->FieldScratch);
}

int Compressor::faceTag(int t, DistanceField::Scratch& field)
{
  const auto& x = this->positions();
  const std::array<int, 3>& tri = this->Tri[t];
  return this->faceTag(tri[0], tri[1], tri[2], x[tri[0]], x[tri[1]], x[tri[2]], field);
}

void Compressor::classifyFaces()
{
  // Queries only, each vertex's and each face's own answer (a vertex's kept grid distance is
  // its own too): in blocks, each block's halves at once, the second with its own scratches.
  const std::size_t nv = this->Global.size();
  const std::size_t nt = this->Tri.size();
  if (nv >= kTwoThreadItems && !this->CurveCells)
  {
    this->buildCurveCells(); // (before the threads, which read it)
  }
  StripTreeScratch rail2;
  DistanceField::Scratch field2;
  withRoom(this->VRegion, nv).resize(nv);
  blockwise(
    nv,
    kTwoThreadBlock,
    kTwoThreadItems,
    [&](std::size_t from, std::size_t to, int part)
    {
      StripTreeScratch& rail = part == 0 ? this->RailScratch : rail2;
      DistanceField::Scratch& field = part == 0 ? this->FieldScratch : field2;
      for (std::size_t i = from; i < to; ++i)
      {
        this->VRegion[i] = this->vertexRegion(static_cast<int>(i), rail, field);
      }
    },
    [&](std::size_t done)
    { this->Progress.report(0.7 + 0.05 * static_cast<double>(done) / nv, "classifying faces"); });
  withRoom(this->Tag, nt).resize(nt);
  blockwise(
    nt,
    kTwoThreadBlock,
    kTwoThreadItems,
    [&](std::size_t from, std::size_t to, int part)
    {
      DistanceField::Scratch& field = part == 0 ? this->FieldScratch : field2;
      for (std::size_t t = from; t < to; ++t)
      {
        this->Tag[t] = this->faceTag(static_cast<int>(t), field);
      }
    },
    [&](std::size_t done)
    { this->Progress.report(0.75 + 0.05 * static_cast<double>(done) / nt, "classifying faces"); });
}

void Compressor::retagStar(int i)
{
  for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
  {
    this->Tag[this->StarItems[s]] = this->faceTag(this->StarItems[s]);
  }
}

void fillFromGrid(CompressionResult& result, const TriangleMesh& grid)
{
  const std::size_t np = grid.points.size(), nt = grid.triangles.size();
  withRoom(result.points, np) = grid.points;
  withRoom(result.triangles, nt) = grid.triangles;
  if (grid.triangleLevel.size() == nt)
  {
    withRoom(result.triangleLevel, nt) = grid.triangleLevel;
  }
  else
  {
    withRoom(result.triangleLevel, nt).assign(nt, 0);
  }
  withRoom(result.vertexState, np).assign(np, VertexUntouched);
}

void Compressor::fillResult()
{
  if (this->ResultFilled)
  {
    return;
  }
  this->ResultFilled = true;
  // The grid's triangles outside the sub-mesh as kept (keepOutside()), the others written back
  // from the sub-mesh (writeBack()).
  const std::size_t np = this->Grid.points.size(), nt = this->GridTriangles;
  withRoom(this->Result.points, np) = this->Grid.points;
  withRoom(this->Result.triangles, nt).assign(nt, { 0, 0, 0 });
  withRoom(this->Result.triangleLevel, nt).assign(nt, 0);
  for (const OutsideTriangle& o : this->Outside)
  {
    this->Result.triangles[o.id] = o.corners;
    this->Result.triangleLevel[o.id] = o.level;
  }
  withRoom(this->Result.vertexState, np).assign(np, VertexUntouched);
}

// Once the sub-mesh is built, the grid's triangles are read no more but for those outside the
// sub-mesh (fillResult(), writeBack()), which are kept apart. With the grid handed over
// (compressHandedOver()), its arrays but the points go then (at 1 M triangles 21 MB that would
// stay through the simulation, one of the run's two memory peaks); its points' distances are
// in Distance.
void Compressor::keepOutside()
{
  const std::size_t nt = this->Grid.triangles.size();
  const bool levels = this->Grid.triangleLevel.size() == nt;
  LargeVector<std::uint8_t> inside(nt, 0);
  for (const int g : this->TriGlobal)
  {
    inside[g] = 1;
  }
  for (std::size_t t = 0; t < nt; ++t)
  {
    if (!inside[t])
    {
      this->Outside.push_back(
        { static_cast<int>(t), this->Grid.triangles[t], levels ? this->Grid.triangleLevel[t] : 0 });
    }
  }
  this->GridTriangles = nt;
  if (!this->SpentGrid)
  {
    return;
  }
  TriangleMesh& grid = *this->SpentGrid;
  LargeVector<std::array<int, 3>>().swap(grid.triangles);
  LargeVector<int>().swap(grid.triangleLevel);
  LargeVector<int>().swap(grid.pointLevel);
  LargeVector<int>().swap(grid.triangleNode);
  LargeVector<int>().swap(grid.pointVertex);
  LargeVector<double>().swap(grid.pointBoundaryDistance);
}

void Compressor::writeBack()
{
  this->fillResult();
  // Faces outside the simulated zone did not move and no boundary crosses their edges (their
  // corners are no candidates), so their corners lie in one region: they take it, even when
  // a whole island smaller than the face lies inside (aliasing, paper 6.6).
  for (const OutsideTriangle& o : this->Outside)
  {
    this->Result.triangleRegion[o.id] = this->Cls.vertexRegion[o.corners[0]];
  }
  const auto& x = this->positions();
  for (std::size_t i = 0; i < this->Global.size(); ++i)
  {
    this->Result.points[this->Global[i]] = x[i];
  }
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    const int g = this->TriGlobal[t];
    this->Result.triangles[g] = {
      this->Global[this->Tri[t][0]], this->Global[this->Tri[t][1]], this->Global[this->Tri[t][2]]
    };
    this->Result.triangleLevel[g] = this->Level[t];
    this->Result.triangleRegion[g] = this->Tag[t];
  }
  for (int i = 0; i < static_cast<int>(this->Global.size()); ++i)
  {
    if (!this->active(i))
    {
      continue;
    }
    std::int8_t s = VertexFree;
    switch (this->St[i])
    {
      case Rail:
        s = VertexOnCurve;
        break;
      case Pinned:
        s = VertexPinned;
        break;
      case Pushing:
        s = VertexStuck;
        break;
      default:
        break;
    }
    this->Result.vertexState[this->Global[i]] = s;
  }
  for (const int i : this->StuckVertices)
  {
    if (this->St[i] == Free)
    {
      this->Result.vertexState[this->Global[i]] = VertexStuck;
    }
  }
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    const bool dead = this->Tri[t][0] == this->Tri[t][1];
    this->Result.degenerateTriangles += !dead && !(this->twiceArea(static_cast<int>(t)) > 0.0);
  }
  this->Result.offCurveBoundaryVertices = this->offCurveBoundaryVertices().size();
}

void Compressor::run()
{
  Clock::time_point t0 = Clock::now();
  this->Points = this->Grid.points;
  this->Progress.report(0.0, this->Stage);
  this->buildGlobalStars();
  this->choosePushes();
  if (this->Spent)
  {
    // The classification's edges are read by choosePushes() only: the sub-mesh's arrays, next,
    // take their memory instead of new memory (see LargeArray.h).
    LargeVector<std::array<int, 2>>().swap(this->Spent->edges);
    LargeVector<std::int8_t>().swap(this->Spent->edgeClass);
  }
  this->placeJunctions();
  this->buildSubMesh();
  this->keepOutside();
  this->Result.secondsPerStage.push_back({ "compression set-up", secondsSince(t0) });

  t0 = Clock::now();
  this->Progress.report(0.1, "compressing the grid");
  this->simulate();
  this->Result.secondsPerStage.push_back({ "simulation", secondsSince(t0) });

  t0 = Clock::now();
  this->At = 0.7;
  this->classifyFaces();
  this->Result.secondsPerStage.push_back({ "face classification", secondsSince(t0) });

  if (this->Params.optimize)
  {
    t0 = Clock::now();
    this->At = 0.8;
    this->Stage = "optimizing the mesh";
    this->Progress.report(this->At, this->Stage);
    withRoom(this->H, this->Global.size()).resize(this->Global.size());
    for (std::size_t i = 0; i < this->H.size(); ++i)
    {
      this->H[i] = this->Sys->localLength(static_cast<int>(i));
    }
    this->Result.snappedVertices = this->snapBoundaryVertices();
    this->Result.boundarySplits = this->refineBoundary();
    // Pushes that never arrived are over: those vertices are free ones from here on (smoothed,
    // collapsed when squeezed), and reported as stuck.
    this->StuckVertices.clear();
    for (int i = 0; i < this->NumActive; ++i)
    {
      if (this->St[i] == Pushing)
      {
        this->St[i] = Free;
        this->StuckVertices.push_back(i);
      }
    }
    for (int pass = 0; pass < this->Params.optimizationPasses; ++pass)
    {
      this->At = 0.8 + 0.2 * pass / this->Params.optimizationPasses;
      this->Progress.report(this->At, this->Stage);
      this->collectBad();
      const std::size_t flips = this->optimizeFlips();
      const std::size_t moves = this->smooth();
      const std::size_t collapsed = this->collapseSqueezed();
      const std::size_t inserted = this->refineAngles();
      this->Result.collapsedVertices += collapsed;
      this->Result.optimizationFlips += flips;
      this->Result.smoothingMoves += moves;
      this->Result.angleVertices += inserted;
      if (flips == 0 && moves == 0 && inserted == 0 && collapsed == 0)
      {
        break;
      }
    }
    this->Changed = LargeVector<int>();
    this->BadMark = LargeVector<std::uint8_t>(); // (no more tracking)
    this->Result.secondsPerStage.push_back({ "optimization", secondsSince(t0) });
  }
  this->writeBack();
  this->Progress.report(1.0, this->Stage);
}

} // namespace detail

namespace
{
// compress(), with the classification handed over (`spent`, the same object) or not, and the
// grid too (`spentGrid`) or not.
CompressionResult compressWith(const TriangleMesh& grid,
  const Classification& classification,
  Classification* spent,
  TriangleMesh* spentGrid,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params,
  const ProgressReporter& progress)
{
  validate(params);
  const std::size_t np = grid.points.size();
  const std::size_t nt = grid.triangles.size();
  if (classification.vertexClass.size() != np || classification.vertexRegion.size() != np ||
    classification.cellRegion.size() != nt ||
    classification.edgeClass.size() != classification.edges.size())
  {
    throw ParameterError("compress: the classification does not belong to this mesh (" +
      std::to_string(classification.vertexClass.size()) + " vertex classes for " +
      std::to_string(np) + " points, " + std::to_string(classification.cellRegion.size()) +
      " face regions for " + std::to_string(nt) + " triangles)");
  }
  for (std::size_t t = 0; t < nt; ++t)
  {
    for (int v : grid.triangles[t])
    {
      if (v < 0 || static_cast<std::size_t>(v) >= np)
      {
        throw ParameterError("compress: triangle " + std::to_string(t) + " refers to point " +
          std::to_string(v) + ", not in [0, " + std::to_string(np) + ")");
      }
    }
  }
  CompressionResult result;
  // (With room for the optimization's splits: see withRoom(). The other arrays are filled
  // by the compressor when it needs them, Compressor::fillResult(), or from the grid when
  // nothing is compressed, fillFromGrid().)
  result.firstInsertedPoint = np;
  withRoom(result.triangleRegion, nt) = classification.cellRegion;
  if (spent)
  {
    LargeVector<int>().swap(spent->cellRegion); // (copied: read no more)
  }
  if (nt == 0 || model.empty())
  {
    detail::fillFromGrid(result, grid);
    result.warnings.push_back("compress: nothing to compress (empty mesh or model)");
    return result;
  }
  Compressor compressor(
    grid, classification, model, field, params, progress, result, spent, spentGrid);
  compressor.run();
  dropCollapsedTriangles(result);
  if (result.degenerateTriangles > 0)
  {
    result.warnings.push_back(std::to_string(result.degenerateTriangles) +
      " triangles have zero or negative area after compression");
  }
  if (result.offCurveBoundaryVertices > 0)
  {
    result.warnings.push_back(std::to_string(result.offCurveBoundaryVertices) +
      " vertices of the approximated boundary could not be placed on a curve");
  }
  return result;
}
} // namespace

std::size_t dropCollapsedTriangles(CompressionResult& r)
{
  std::size_t kept = 0;
  for (std::size_t t = 0; t < r.triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = r.triangles[t];
    if (tri[0] != tri[1]) // (a collapse sets all three corners to the vertex kept)
    {
      r.triangles[kept] = tri;
      r.triangleLevel[kept] = r.triangleLevel[t];
      r.triangleRegion[kept] = r.triangleRegion[t];
      ++kept;
    }
  }
  const std::size_t dropped = r.triangles.size() - kept;
  r.triangles.resize(kept);
  r.triangleLevel.resize(kept);
  r.triangleRegion.resize(kept);
  return dropped;
}

CompressionResult compress(const TriangleMesh& grid,
  const Classification& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params,
  const ProgressReporter& progress)
{
  return compressWith(grid, classification, nullptr, nullptr, model, field, params, progress);
}

CompressionResult compress(const TriangleMesh& grid,
  Classification&& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params,
  const ProgressReporter& progress)
{
  return compressWith(
    grid, classification, &classification, nullptr, model, field, params, progress);
}

CompressionResult compressHandedOver(TriangleMesh& grid,
  Classification&& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params,
  const ProgressReporter& progress)
{
  return compressWith(grid, classification, &classification, &grid, model, field, params, progress);
}

} // namespace strata
