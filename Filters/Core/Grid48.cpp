// StrataMesh core: the adaptive 4-8 grid (paper Sections 2 and 2.1).
//
// Lattice and hierarchy
// ---------------------
// The domain is a square of side D around the model's bounds (bounds' larger side plus a
// margin on every side). Vertices are points of the integer lattice {0..2^31}^2 on it, mapped
// once to model coordinates by origin + (D / 2^31) * (i, j). Level 0 is four triangles
// (centre, corner k, corner k + 1): right angle at the centre, hypotenuse = a side of the
// square. A level-l triangle (v0, v1, v2) (counter-clockwise, right angle at v0, hypotenuse
// v1-v2) is bisected at m = midpoint(v1, v2) into (m, v0, v1) and (m, v2, v0): again right
// isosceles, right angle at the newest vertex m, hypotenuse = a leg of the parent. Level-2k
// hypotenuses are axis-parallel with length 2^(31-k), level-2k+1 ones diagonal with
// components 2^(30-k), so every midpoint up to the split of level 59 is a lattice point:
// coordinates are exact integers, angles exactly 45/45/90, and a lattice point is the
// midpoint of exactly one hypotenuse in the hierarchy, hence created once (shared vertices
// without any lookup).
//
// Nodes are kept in flat arrays (struct of arrays): vertices, the three neighbours (across
// v1-v2, v2-v0, v0-v1), first child (the two children are consecutive ids) and level; the
// parent is stored once per pair of children. About 32 bytes per node and 17 per vertex;
// a binary hierarchy has about two nodes per leaf and half a vertex per leaf.
//
// Conforming bisection (the 4-8 diamond rule)
// -------------------------------------------
// In a conforming 4-8 mesh the neighbour N across the hypotenuse of a leaf T of level l is
// either of level l and shares the hypotenuse (T and N form a diamond), or of level l - 1 and
// T's hypotenuse is one of N's legs. split(T): if N is coarser, split(N) first (recursively;
// afterwards one of N's children shares T's hypotenuse); then bisect T and its partner at the
// same new vertex and link the four children across the two halves of the old hypotenuse.
// Neighbours outside the diamond keep pointing at the right child because each child takes
// over one leg of its parent (replaceNeighbour). There is never a hanging vertex, and
// neighbouring leaves differ by at most one level. Splitting level-l nodes only ever forces
// splits of coarser nodes, so the nodes of level <= L (with the leaves coarser than L) form
// the conforming mesh of level L: extract(L) is a cut through the hierarchy, and the meshes of
// levels 0..L are nested.
//
// Refinement
// ----------
// A stack of leaves to examine starts with all current leaves; every split pushes the new
// children (forced splits included), and popped nodes that are no longer leaves are skipped.
// A leaf T of level l is split when
//  (a) global (Section 2): l < maxLevel, and with m the hypotenuse midpoint, d = distance
//      from m to the nearest boundary (DistanceField::boundaryDistance) and h the hypotenuse
//      length: d > tolerance and h > d;
//  (b) local (Section 2.1, l < localMaxLevel): T (closed) contains two or more polygon
//      vertices, or is crossed (touched) by the segments of two or more boundary curves;
//  (c) thin regions (l < localMaxLevel): T is crossed by one curve in two or more separate
//      strands;
//  (d) close feature points, beyond the paper (l < junctionMaxLevel, which may exceed
//      localMaxLevel; default localMaxLevel + 8): T (closed) contains two or more feature
//      points: Model::junctions and, with featurePointAngle > 0, curve vertices sharper than
//      it. Compression gives each junction its own mesh vertex, so junctions much closer than
//      the local edges (gulf_section: pairs 0.7 m, 3.7 m and 10.9 m apart among 60-180 m
//      edges) made slivers (2.1 degrees at MaxLevel 10); separating them into different
//      triangles makes the edges there comparable to their distance, and the 4-8 grading
//      keeps the triangles around well shaped (12.7 degrees, +1.5% triangles). Cheap: only
//      the feature points whose nearest other feature point is within the hypotenuse of
//      localMaxLevel are kept (a handful), sorted by x; T is tested against those within its
//      hypotenuse of each other, and only when (b) did not already decide (below
//      localMaxLevel (b) splits any triangle holding two model vertices). A pair that is the
//      end of a thin strip is left alone: when, at max(hypotenuse(localMaxLevel), 8 d) from
//      the pair's midpoint on one side (d the pair's distance), a cross-section 3 d long
//      parallel to the pair still meets two curves, the strip goes on thinner than its
//      triangles and separating its ends only resolves it there (thin_layer.vtp: the
//      1-unit layer ending on the border; refining its ends kept the compression moving 90
//      steps longer, and the rails then left a 5.6-degree sliver in the aliased middle).
//  (e) sizes in model units (l < minLevel): every triangle, so that with minLevel the level
//      of maxEdgeLength no grid edge is longer than it. minEdgeLength instead lowers
//      maxLevel, localMaxLevel and junctionMaxLevel (Grid48Params, resolveParams): no
//      criterion splits beyond its level, and conforming splits only ever split coarser
//      triangles, so no leaf is finer.
//  (f) target edge length field (l < targetMaxLevel, only with params.targetEdgeLength): T's
//      hypotenuse is longer than the smallest target at its corners and its centroid. Corner
//      values are cached per vertex (refiner-local, so the field is evaluated about once per
//      vertex plus once per tested triangle). The centroid catches a small-target spot
//      inside T (it is h / 6 from the hypotenuse midpoint, which becomes the next vertex);
//      a spot smaller than T that misses the four samples is not seen, which for a smooth
//      sizing field (an interpolated image, or the graded law of points) only shifts the
//      refinement by a level. The floor targetMaxLevel (default localMaxLevel + 4, or the
//      cap of minEdgeLength) bounds the memory of a field asking for tiny edges; when the
//      field coarsened an automatic maxLevel, the floor stays 8 levels below the usual
//      automatic level, so that coarsening at depth does not limit refinement near wells. Grading:
//      conformity keeps edge neighbours within one level, i.e. hypotenuses within sqrt(2).
//      The field can also coarsen: with maxLevel automatic its level is the coarser of the
//      usual one and that of the largest target (resolveParams), so the boundary criteria
//      (a)-(d) stop earlier where the field asks for large triangles, and (f) refines where
//      it asks for small ones.
//  (g) thin layers (opt-in, Grid48Params::thinLayerRefinement; localMaxLevel <= l <
//      junctionMaxLevel): two strands of the boundary cross T (two curves, or one curve twice)
//      and the layer between them is at least the leg of junctionMaxLevel (the finest edge)
//      thick everywhere in T but thinner than T's legs (BoundaryIndex::thinLayer: the
//      smallest distance from the ends and middles of either strand's parts inside T to the
//      other strand). Below localMaxLevel (b) and (c) already split such triangles whatever
//      the layer's thickness; beyond it, (g) goes on while the layer is thinner than the
//      cells, so the compression finds grid vertices inside it: a layer one to sixteen finest
//      edges thick is kept instead of being cut where the recovery's probes no longer fit
//      (random faulted sections: the boundary within half the local edge on 31 of 48 instead
//      of 12). Two curves meeting at a common end within twice T's longest edge at 30 degrees
//      or more are a junction, not a layer; a pinch-out's tip is not split (the thickness
//      there goes to 0), so it ends in cells the tip cutting of the refinement can handle.
//      With Grid48Params::thinLayerZones, only T whose centroid lies within a zone widened by
//      T's hypotenuse (the Mesher's retry around the places a first mesh lost a layer).
// "Curves" are the edges of the boundary graph: the distinct boundary segments (a segment
// shared by two loops in the Loops form is counted once) chained through the nodes where
// exactly two of them meet; chains break at junctions and curve ends. In the SharedCurves form
// these are the input curves (joined at nodes of degree 2); in the Loops form a border shared
// by two regions is one curve rather than two input loops, so both forms of one model refine
// alike. With this definition the brief's rule "(c) crossed by two curves bounding the same
// region, or by curves of three or more regions" is already contained in (b) whenever two
// different curves are involved; what (c) adds is the same curve crossing T twice, i.e. a
// region (or exterior gap) bounded on both sides by one curve: a lens, a fold, a narrow bay,
// a thin layer given as one loop. Two hits of one curve belong to one strand when they are
// consecutive along it and the node between them lies in T.
// Whether the result is order independent: each criterion depends on the triangle only, and
// every split made is required (by a criterion or by conformity of a required split), so the
// result is the coarsest conforming refinement of the start in which no leaf meets a
// criterion. Hence resuming with finer parameters equals building from scratch with them.
//
// Speed
// -----
// (a) is decided exactly, mostly without a best-first search in the strip tree:
//  - bounds: T's corners are h / 2 away from m, so a corner with a known distance dv gives
//    d in [dv - h / 2, dv + h / 2], which may settle h > d (and d > tolerance) at once;
//  - when h spans at most four cells of the boundary index below, "is some segment closer
//    than h to m" and "is some segment within the tolerance of m" are asked of the index:
//    the same comparisons on the same exact point/segment distances, from a few cells;
//  - otherwise (coarse levels) DistanceField::boundaryDistance, whose value is kept for the
//    new vertex when the split happens (TriangleMesh::pointBoundaryDistance).
// A "no" is shared with the diamond's partner (same midpoint, same level). When d > h / 2
// (the hypotenuse midpoint is the circumcentre) no boundary touches the diamond: the local
// test is skipped, and the children of a triangle that no model feature touches inherit that.
// (b) and (c) query the boundary index (BoundaryIndex): a uniform grid of cells over the
// domain, every model vertex listed in its cell and every distinct segment in the cells it
// crosses; the triangle's bounding box selects cells, then exact tests (point in closed
// triangle; segment/triangle by separating axes) decide, stopping as soon as the answer is
// known.
#include "Grid48.h"

#include "Errors.h"
#include "Rows.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>

namespace strata
{

namespace
{

constexpr int kLatticeBits = 31;
// (g): a layer is split while thinner than this many of the triangle's legs.
constexpr double kThinLayerLegs = 1.0;
constexpr std::uint32_t kLatticeSize = 1u << kLatticeBits;
constexpr std::uint8_t kGlobalNo = 0x40; // global criterion already said no (this refine call)
constexpr std::uint8_t kEmpty = 0x80;    // no model vertex or segment touches the triangle
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kNoLabel = std::numeric_limits<int>::min();
constexpr int kMaxCells = 1024; // per axis, for the boundary index

struct Domain
{
  Vec2 origin;
  double side = 1.0;
};

Domain domainOf(const Box2& bounds, double margin)
{
  if (!(margin >= 0.0 && margin <= 1.0))
  {
    throw ParameterError("Grid48: margin " + std::to_string(margin) + " is not in [0, 1]");
  }
  Domain d;
  if (bounds.empty())
  {
    d.side = 1.0;
    d.origin = { -0.5, -0.5 };
    return d;
  }
  if (!std::isfinite(bounds.min.x) || !std::isfinite(bounds.min.y) ||
    !std::isfinite(bounds.max.x) || !std::isfinite(bounds.max.y))
  {
    throw ParameterError("Grid48: the bounds are not finite");
  }
  double s = std::max(bounds.width(), bounds.height());
  if (!(s > 0.0))
  {
    s = 1.0 / (1.0 + 2.0 * margin);
  }
  d.side = s * (1.0 + 2.0 * margin);
  d.origin = bounds.center() - 0.5 * Vec2{ d.side, d.side };
  return d;
}

// The value of a target edge length field at p (input coordinates): +inf for no wish (NaN,
// +inf); ParameterError for a value <= 0 (or -inf).
double targetAt(const std::function<double(Vec2)>& target, Vec2 p)
{
  const double t = target(p);
  if (std::isnan(t) || t == HUGE_VAL)
  {
    return HUGE_VAL;
  }
  if (!(t > 0.0))
  {
    throw ParameterError("Grid48: the target edge length " + std::to_string(t) + " at (" +
      std::to_string(p.x) + ", " + std::to_string(p.y) + ") is not > 0");
  }
  return t;
}

// The largest finite target of the field sampled on a 65 x 65 lattice over the model's
// bounds (input coordinates); 0 when no sample is finite.
double largestTarget(const Model& model, const std::function<double(Vec2)>& target)
{
  constexpr int n = 64;
  const Box2 box = model.bounds.empty() ? Box2{ { 0.0, 0.0 }, { 0.0, 0.0 } } : model.bounds;
  double largest = 0.0;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      const Vec2 local{ box.min.x + (box.max.x - box.min.x) * i / n,
        box.min.y + (box.max.y - box.min.y) * j / n };
      const double t = targetAt(target, local + model.origin);
      if (t < HUGE_VAL)
      {
        largest = std::max(largest, t);
      }
    }
  }
  return largest;
}

// Median length of the model's curve segments (0 when there are none).
double medianSegmentLength(const Model& model)
{
  std::vector<double> lengths;
  for (const Curve& c : model.curves)
  {
    const std::size_t n = c.points.size();
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      lengths.push_back(norm(c.points[i + 1] - c.points[i]));
    }
    if (c.closed && n > 2)
    {
      lengths.push_back(norm(c.points[0] - c.points[n - 1]));
    }
  }
  if (lengths.empty())
  {
    return 0.0;
  }
  auto mid = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), mid, lengths.end());
  return *mid;
}

inline bool pointInTriangle(Vec2 q, Vec2 a, Vec2 b, Vec2 c)
{
  return orient2d(a, b, q) >= 0.0 && orient2d(b, c, q) >= 0.0 && orient2d(c, a, q) >= 0.0;
}

// Whether segment pq meets the closed counter-clockwise triangle abc (separating axes: the
// three edge normals and the segment's normal; bounding boxes first).
inline bool segmentMeetsTriangle(Vec2 p, Vec2 q, Vec2 a, Vec2 b, Vec2 c)
{
  if (std::max(p.x, q.x) < std::min({ a.x, b.x, c.x }) ||
    std::min(p.x, q.x) > std::max({ a.x, b.x, c.x }) ||
    std::max(p.y, q.y) < std::min({ a.y, b.y, c.y }) ||
    std::min(p.y, q.y) > std::max({ a.y, b.y, c.y }))
  {
    return false;
  }
  if ((orient2d(a, b, p) < 0.0 && orient2d(a, b, q) < 0.0) ||
    (orient2d(b, c, p) < 0.0 && orient2d(b, c, q) < 0.0) ||
    (orient2d(c, a, p) < 0.0 && orient2d(c, a, q) < 0.0))
  {
    return false;
  }
  const double oa = orient2d(p, q, a);
  const double ob = orient2d(p, q, b);
  const double oc = orient2d(p, q, c);
  return !((oa > 0.0 && ob > 0.0 && oc > 0.0) || (oa < 0.0 && ob < 0.0 && oc < 0.0));
}

// The part of segment pq (which meets it) inside the closed counter-clockwise triangle abc
// (Cyrus-Beck clipping), by its two ends and its middle: out[0], out[1], out[2].
inline void clipToTriangle(Vec2 p, Vec2 q, Vec2 a, Vec2 b, Vec2 c, Vec2 out[3])
{
  const Vec2 d = q - p;
  const Vec2 corners[3] = { a, b, c };
  double t0 = 0.0, t1 = 1.0;
  for (int e = 0; e < 3; ++e)
  {
    const Vec2 u = corners[e], v = corners[(e + 1) % 3];
    const double at = orient2d(u, v, p), along = cross(v - u, d); // inside: at + t along >= 0
    if (along > 0.0)
    {
      t0 = std::max(t0, -at / along);
    }
    else if (along < 0.0)
    {
      t1 = std::min(t1, -at / along);
    }
  }
  t1 = std::max(t0, t1); // a touch
  out[0] = p + t0 * d;
  out[1] = p + (0.5 * (t0 + t1)) * d;
  out[2] = p + t1 * d;
}

// Whether segments ab and pq are within distance tol (closed). If they do not properly cross,
// their distance is attained at an end point of one of them.
inline bool segmentsWithin(Vec2 a, Vec2 b, Vec2 p, Vec2 q, double tol)
{
  if (std::max(p.x, q.x) < std::min(a.x, b.x) - tol ||
    std::min(p.x, q.x) > std::max(a.x, b.x) + tol ||
    std::max(p.y, q.y) < std::min(a.y, b.y) - tol || std::min(p.y, q.y) > std::max(a.y, b.y) + tol)
  {
    return false;
  }
  const double o1 = orient2d(a, b, p);
  const double o2 = orient2d(a, b, q);
  const double o3 = orient2d(p, q, a);
  const double o4 = orient2d(p, q, b);
  if (((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) &&
    ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0)))
  {
    return true;
  }
  const double t2 = tol * tol;
  return pointSegmentDistance2(p, a, b) <= t2 || pointSegmentDistance2(q, a, b) <= t2 ||
    pointSegmentDistance2(a, p, q) <= t2 || pointSegmentDistance2(b, p, q) <= t2;
}

// Whether q lies within distance r (closed) of the closed counter-clockwise triangle abc.
inline bool pointNearTriangle(Vec2 q, Vec2 a, Vec2 b, Vec2 c, double r)
{
  const double r2 = r * r;
  return pointInTriangle(q, a, b, c) || pointSegmentDistance2(q, a, b) <= r2 ||
    pointSegmentDistance2(q, b, c) <= r2 || pointSegmentDistance2(q, c, a) <= r2;
}

// Whether segment pq lies within distance r (closed) of the closed counter-clockwise triangle
// abc.
inline bool segmentNearTriangle(Vec2 p, Vec2 q, Vec2 a, Vec2 b, Vec2 c, double r)
{
  return segmentMeetsTriangle(p, q, a, b, c) || segmentsWithin(p, q, a, b, r) ||
    segmentsWithin(p, q, b, c, r) || segmentsWithin(p, q, c, a, r);
}

} // namespace

BoundaryIndex::BoundaryIndex(const Model& model, Vec2 origin, double side)
{
  this->build(model, origin, side);
}

BoundaryIndex::BoundaryIndex(const Model& model)
{
  const Domain d = domainOf(model.bounds, 0.01);
  this->build(model, d.origin, d.side);
}

std::size_t BoundaryIndex::memoryBytes() const
{
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return bytes(this->A) + bytes(this->B) + bytes(this->ChainOf) + bytes(this->ChainBegin) +
    bytes(this->ChainLabels) + bytes(this->Nodes) + bytes(this->SegStart) + bytes(this->SegItems) +
    bytes(this->NodeStart) + bytes(this->NodeItems) + bytes(this->Stamp) + bytes(this->Hits);
}

void BoundaryIndex::build(const Model& model, Vec2 origin, double side)
{
  this->Origin = origin;
  // Distinct undirected segments, by node ids.
  struct Seg
  {
    std::uint64_t key;
    int u, v;
    int left, right; // region ids on both sides; kNoLabel when unknown (Loops form)
  };
  const bool loops = model.form != ModelForm::SharedCurves;
  std::vector<Seg> segs;
  for (const Curve& c : model.curves)
  {
    const std::size_t n = c.nodes.size();
    auto add = [&](int u, int v)
    {
      if (u != v)
      {
        const auto lo = static_cast<std::uint32_t>(std::min(u, v));
        const auto hi = static_cast<std::uint32_t>(std::max(u, v));
        segs.push_back({ (static_cast<std::uint64_t>(lo) << 32) | hi,
          u,
          v,
          c.left,
          loops ? kNoLabel : c.right });
      }
    };
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      add(c.nodes[i], c.nodes[i + 1]);
    }
    if (c.closed && n > 2)
    {
      add(c.nodes[n - 1], c.nodes[0]);
    }
  }
  std::sort(segs.begin(), segs.end(), [](const Seg& x, const Seg& y) { return x.key < y.key; });
  {
    // Merge the copies of a segment; in the Loops form its labels are the regions of the
    // loops through it, plus the exterior when only one loop has it.
    std::size_t out = 0;
    for (std::size_t i = 0; i < segs.size();)
    {
      std::size_t j = i + 1;
      Seg merged = segs[i];
      for (; j < segs.size() && segs[j].key == segs[i].key; ++j)
      {
        if (loops && merged.right == kNoLabel && segs[j].left != merged.left)
        {
          merged.right = segs[j].left;
        }
      }
      if (loops && merged.right == kNoLabel)
      {
        merged.right = -1;
      }
      segs[out++] = merged;
      i = j;
    }
    segs.resize(out);
  }

  // Node -> incident segments (CSR).
  const std::size_t nodeCount = model.nodes.size();
  std::vector<int> start, incident;
  groupIntoRows(nodeCount,
    start,
    incident,
    [&](auto&& emit)
    {
      for (std::size_t k = 0; k < segs.size(); ++k)
      {
        emit(segs[k].u, static_cast<int>(k));
        emit(segs[k].v, static_cast<int>(k));
      }
    });
  auto degree = [&](int node) { return start[node + 1] - start[node]; };

  // Chains through nodes of degree 2.
  std::vector<char> used(segs.size(), 0);
  this->ChainBegin.push_back(0);
  auto walk = [&](int node, int seg)
  {
    const int first = node;
    while (true)
    {
      used[seg] = 1;
      const int other = segs[seg].u == node ? segs[seg].v : segs[seg].u;
      this->A.push_back(model.nodes[node]);
      this->B.push_back(model.nodes[other]);
      this->ChainOf.push_back(static_cast<int>(this->ChainBegin.size()) - 1);
      if (node == first)
      {
        this->ChainLabels.push_back({ segs[seg].left, segs[seg].right });
      }
      node = other;
      if (node == first || degree(node) != 2)
      {
        break;
      }
      const int e0 = incident[start[node]];
      const int e1 = incident[start[node] + 1];
      seg = e0 == seg ? e1 : e0;
      if (used[seg])
      {
        break;
      }
    }
    this->ChainBegin.push_back(static_cast<int>(this->A.size()));
  };
  for (std::size_t node = 0; node < nodeCount; ++node)
  {
    if (degree(static_cast<int>(node)) == 2)
    {
      continue;
    }
    for (int k = start[node]; k < start[node + 1]; ++k)
    {
      if (!used[incident[k]])
      {
        walk(static_cast<int>(node), incident[k]);
      }
    }
  }
  for (std::size_t k = 0; k < segs.size(); ++k)
  {
    if (!used[k])
    {
      walk(segs[k].u, static_cast<int>(k)); // a cycle without junction
    }
  }
  this->Nodes = model.nodes;

  // Uniform grid: cells about twice the median segment length, so that a cell holds a few
  // segments of each curve through it; at least 2 sqrt(segments) and at most 1024 per axis.
  const std::size_t ns = this->A.size();
  const double median = medianSegmentLength(model);
  const double bySize = median > 0.0 ? side / (2.0 * median) : 1.0;
  this->Cells = static_cast<int>(
    std::clamp(std::max(std::ceil(bySize), 2.0 * std::ceil(std::sqrt(static_cast<double>(ns)))),
      1.0,
      static_cast<double>(kMaxCells)));
  this->CellSize = side / this->Cells;
  this->InvCell = 1.0 / this->CellSize;
  const std::size_t cellCount = static_cast<std::size_t>(this->Cells) * this->Cells;

  groupIntoRows(cellCount,
    this->NodeStart,
    this->NodeItems,
    [&](auto&& emit)
    {
      for (std::size_t i = 0; i < this->Nodes.size(); ++i)
      {
        const Vec2 p = this->Nodes[i];
        emit(static_cast<std::size_t>(cellY(p.y)) * this->Cells + cellX(p.x), static_cast<int>(i));
      }
    });
  groupIntoRows(cellCount,
    this->SegStart,
    this->SegItems,
    [&](auto&& emit)
    {
      for (std::size_t s = 0; s < ns; ++s)
      {
        forSegmentCells(
          static_cast<int>(s), [&](std::size_t cell) { emit(cell, static_cast<int>(s)); });
      }
    });
  this->Stamp.assign(ns, 0);
}

// Calls visit(cell) for every cell that segment s may cross: the cells of its bounding box
// whose rectangle (padded by 1e-6 of a cell against rounding in cellX/cellY) it meets.
template<typename Visit>
void BoundaryIndex::forSegmentCells(int s, Visit&& visit) const
{
  const Vec2 p = this->A[s];
  const Vec2 q = this->B[s];
  const int x0 = cellX(std::min(p.x, q.x));
  const int x1 = cellX(std::max(p.x, q.x));
  const int y0 = cellY(std::min(p.y, q.y));
  const int y1 = cellY(std::max(p.y, q.y));
  const bool thin = x0 == x1 || y0 == y1;
  const double pad = 1e-6 * this->CellSize;
  for (int y = y0; y <= y1; ++y)
  {
    for (int x = x0; x <= x1; ++x)
    {
      if (!thin)
      {
        const Vec2 lo{ this->Origin.x + x * this->CellSize - pad,
          this->Origin.y + y * this->CellSize - pad };
        const Vec2 hi{ lo.x + this->CellSize + 2 * pad, lo.y + this->CellSize + 2 * pad };
        const double o0 = orient2d(p, q, lo);
        const double o1 = orient2d(p, q, { hi.x, lo.y });
        const double o2 = orient2d(p, q, hi);
        const double o3 = orient2d(p, q, { lo.x, hi.y });
        if ((o0 > 0 && o1 > 0 && o2 > 0 && o3 > 0) || (o0 < 0 && o1 < 0 && o2 < 0 && o3 < 0))
        {
          continue;
        }
      }
      visit(static_cast<std::size_t>(y) * this->Cells + x);
    }
  }
}

BoundaryIndex::TriangleResult BoundaryIndex::testTriangle(Vec2 a,
  Vec2 b,
  Vec2 c,
  bool local,
  bool thin)
{
  const int x0 = cellX(std::min({ a.x, b.x, c.x }));
  const int x1 = cellX(std::max({ a.x, b.x, c.x }));
  const int y0 = cellY(std::min({ a.y, b.y, c.y }));
  const int y1 = cellY(std::max({ a.y, b.y, c.y }));

  // Polygon vertices inside or on the triangle (without (b), one is enough to know that the
  // triangle is not empty).
  int vertices = 0;
  const int enough = local ? 2 : 1;
  for (int y = y0; y <= y1 && vertices < enough; ++y)
  {
    const std::size_t row = static_cast<std::size_t>(y) * this->Cells;
    for (int k = this->NodeStart[row + x0]; k < this->NodeStart[row + x1 + 1]; ++k)
    {
      if (pointInTriangle(this->Nodes[this->NodeItems[k]], a, b, c) && ++vertices >= enough)
      {
        break;
      }
    }
  }
  if (local && vertices >= 2)
  {
    return CriterionHolds;
  }

  // Segments crossing or touching it.
  if (++this->CurrentStamp == 0)
  {
    std::fill(this->Stamp.begin(), this->Stamp.end(), 0);
    this->CurrentStamp = 1;
  }
  this->Hits.clear();
  int chain = -1;
  for (int y = y0; y <= y1; ++y)
  {
    for (int x = x0; x <= x1; ++x)
    {
      const std::size_t cell = static_cast<std::size_t>(y) * this->Cells + x;
      for (int k = this->SegStart[cell]; k < this->SegStart[cell + 1]; ++k)
      {
        const int s = this->SegItems[k];
        if (this->Stamp[s] == this->CurrentStamp)
        {
          continue;
        }
        this->Stamp[s] = this->CurrentStamp;
        if (!segmentMeetsTriangle(this->A[s], this->B[s], a, b, c))
        {
          continue;
        }
        if (local && chain >= 0 && this->ChainOf[s] != chain)
        {
          return CriterionHolds; // (b): two curves
        }
        chain = this->ChainOf[s];
        this->Hits.push_back(s);
      }
    }
  }
  if (this->Hits.empty())
  {
    return vertices > 0 ? SomethingInside : NothingInside;
  }
  if (!thin)
  {
    return SomethingInside;
  }

  // (c): strands per curve (hits are grouped by curve once sorted, as curves are contiguous);
  // without (b) also two curves sharing a region, or three regions.
  std::sort(this->Hits.begin(), this->Hits.end());
  int labels[8];
  int labelCount = 0;
  const std::size_t n = this->Hits.size();
  for (std::size_t i = 0; i < n;)
  {
    const int curve = this->ChainOf[this->Hits[i]];
    std::size_t j = i + 1;
    int strands = 1;
    for (; j < n && this->ChainOf[this->Hits[j]] == curve; ++j)
    {
      const int s = this->Hits[j - 1];
      if (this->Hits[j] != s + 1 || !pointInTriangle(this->B[s], a, b, c))
      {
        ++strands;
      }
    }
    const int first = this->ChainBegin[curve];
    const int last = this->ChainBegin[curve + 1] - 1;
    if (strands > 1 && this->Hits[i] == first && this->Hits[j - 1] == last &&
      this->B[last] == this->A[first] && pointInTriangle(this->A[first], a, b, c))
    {
      --strands; // the strand wraps around the start of a closed curve
    }
    if (strands > 1)
    {
      return CriterionHolds;
    }
    if (!local)
    {
      const std::array<int, 2>& cl = this->ChainLabels[curve];
      const bool shared = std::find(labels, labels + labelCount, cl[0]) != labels + labelCount ||
        std::find(labels, labels + labelCount, cl[1]) != labels + labelCount;
      if (shared && i > 0)
      {
        return CriterionHolds; // two curves bounding the same region
      }
      for (const int l : cl)
      {
        if (std::find(labels, labels + labelCount, l) == labels + labelCount)
        {
          labels[labelCount++] = l;
        }
      }
      if (labelCount >= 3)
      {
        return CriterionHolds; // curves of three regions
      }
    }
    i = j;
  }
  return SomethingInside;
}

template<typename Visit>
bool BoundaryIndex::anySegment(double x0, double y0, double x1, double y1, Visit&& visit)
{
  const int cx0 = cellX(x0);
  const int cx1 = cellX(x1);
  const int cy0 = cellY(y0);
  const int cy1 = cellY(y1);
  if (cx0 == cx1 && cy0 == cy1)
  {
    // One cell (the common case for small queries): no duplicates, no stamps.
    const std::size_t cell = static_cast<std::size_t>(cy0) * this->Cells + cx0;
    for (int k = this->SegStart[cell]; k < this->SegStart[cell + 1]; ++k)
    {
      if (visit(this->SegItems[k]))
      {
        return true;
      }
    }
    return false;
  }
  if (++this->CurrentStamp == 0)
  {
    std::fill(this->Stamp.begin(), this->Stamp.end(), 0);
    this->CurrentStamp = 1;
  }
  for (int y = cy0; y <= cy1; ++y)
  {
    for (int x = cx0; x <= cx1; ++x)
    {
      const std::size_t cell = static_cast<std::size_t>(y) * this->Cells + x;
      for (int k = this->SegStart[cell]; k < this->SegStart[cell + 1]; ++k)
      {
        const int s = this->SegItems[k];
        if (this->Stamp[s] != this->CurrentStamp)
        {
          this->Stamp[s] = this->CurrentStamp;
          if (visit(s))
          {
            return true;
          }
        }
      }
    }
  }
  return false;
}

bool BoundaryIndex::thinLayer(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest)
{
  return this->layerAcross(a, b, c, thinnest, thickest) ||
    this->layerBeside(a, b, c, thinnest, thickest);
}

// Whether curves ck and cm (different) have a common end near the triangle (within
// sqrt(longest2) of its centroid) at which they meet at 30 degrees or more: a junction, not a
// pinch-out.
bool BoundaryIndex::junctionNear(int ck, int cm, Vec2 centroid, double longest2) const
{
  const double cos30 = 0.86602540378443864676;
  for (int endK = 0; endK < 2; ++endK)
  {
    const int sk = endK == 0 ? this->ChainBegin[ck] : this->ChainBegin[ck + 1] - 1;
    const Vec2 xk = endK == 0 ? this->A[sk] : this->B[sk];
    const Vec2 dk = (endK == 0 ? this->B[sk] : this->A[sk]) - xk;
    for (int endM = 0; endM < 2; ++endM)
    {
      const int sm = endM == 0 ? this->ChainBegin[cm] : this->ChainBegin[cm + 1] - 1;
      const Vec2 xm = endM == 0 ? this->A[sm] : this->B[sm];
      const Vec2 dm = (endM == 0 ? this->B[sm] : this->A[sm]) - xm;
      if (xk == xm && norm2(xk - centroid) <= longest2 &&
        dot(dk, dm) < cos30 * std::sqrt(norm2(dk) * norm2(dm)))
      {
        return true;
      }
    }
  }
  return false;
}

// The segments meeting the closed triangle abc (r = 0) or within r of it, in Hits (increasing),
// and their strands in StrandEnd: runs of consecutive segments of one curve joined at a node
// inside the triangle (r = 0) or within r of it. Returns the number of strands, at most 16.
std::size_t BoundaryIndex::strands(Vec2 a, Vec2 b, Vec2 c, double r)
{
  this->Hits.clear();
  this->StrandEnd.clear();
  this->anySegment(std::min({ a.x, b.x, c.x }) - r,
    std::min({ a.y, b.y, c.y }) - r,
    std::max({ a.x, b.x, c.x }) + r,
    std::max({ a.y, b.y, c.y }) + r,
    [&](int s)
    {
      if (r > 0.0 ? segmentNearTriangle(this->A[s], this->B[s], a, b, c, r)
                  : segmentMeetsTriangle(this->A[s], this->B[s], a, b, c))
      {
        this->Hits.push_back(s);
      }
      return false;
    });
  if (this->Hits.size() < 2)
  {
    return 0;
  }
  std::sort(this->Hits.begin(), this->Hits.end());
  const std::size_t n = this->Hits.size();
  for (std::size_t i = 1; i <= n; ++i)
  {
    const int s = this->Hits[i - 1];
    if (i == n || this->Hits[i] != s + 1 || this->ChainOf[s + 1] != this->ChainOf[s] ||
      !(r > 0.0 ? pointNearTriangle(this->B[s], a, b, c, r) : pointInTriangle(this->B[s], a, b, c)))
    {
      this->StrandEnd.push_back(static_cast<int>(i));
    }
  }
  return std::min<std::size_t>(this->StrandEnd.size(), 16);
}

bool BoundaryIndex::layerAcross(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest)
{
  // The segments meeting the triangle, in strands (a closed curve's strand through its start
  // counts as two, which meet at that node: their thickness is 0, never a layer).
  const std::size_t strands = this->strands(a, b, c, 0.0);
  if (strands < 2)
  {
    return false;
  }
  const std::size_t n = this->Hits.size();
  // Each hit's part inside the triangle, by its ends and middle.
  this->StrandPoints.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    clipToTriangle(
      this->A[this->Hits[i]], this->B[this->Hits[i]], a, b, c, &this->StrandPoints[3 * i]);
  }
  const auto first = [&](std::size_t k) { return k == 0 ? 0 : this->StrandEnd[k - 1]; };
  // The smallest distance from strand k's points in the triangle to strand m's segments.
  const auto nearest = [&](std::size_t k, std::size_t m)
  {
    double least = HUGE_VAL;
    for (int i = 3 * first(k); i < 3 * this->StrandEnd[k]; ++i)
    {
      double d2 = HUGE_VAL;
      for (int j = first(m); j < this->StrandEnd[m]; ++j)
      {
        d2 = std::min(d2,
          pointSegmentDistance2(
            this->StrandPoints[i], this->A[this->Hits[j]], this->B[this->Hits[j]]));
      }
      least = std::min(least, d2);
    }
    return std::sqrt(least);
  };
  const double longest2 =
    4.0 * std::max({ norm2(b - a), norm2(c - b), norm2(a - c) }); // (twice the longest)^2
  const Vec2 centroid = (1.0 / 3.0) * (a + b + c);
  for (std::size_t k = 0; k < strands; ++k)
  {
    const int ck = this->ChainOf[this->Hits[first(k)]];
    for (std::size_t m = k + 1; m < strands; ++m)
    {
      const int cm = this->ChainOf[this->Hits[first(m)]];
      if (ck != cm && this->junctionNear(ck, cm, centroid, longest2))
      {
        continue;
      }
      const double thickness = std::min(nearest(k, m), nearest(m, k));
      if (thickness >= thinnest && thickness < thickest)
      {
        return true;
      }
    }
  }
  return false;
}

bool BoundaryIndex::layerBeside(Vec2 a, Vec2 b, Vec2 c, double thinnest, double thickest)
{
  // The segments within `thickest` of the triangle, in strands joined at nodes within it too,
  // so that a curve passing by is one strand and a layer's end near the triangle (where its
  // two sides join) is not a layer beside it.
  const double r = thickest;
  const std::size_t strands = this->strands(a, b, c, r);
  if (strands < 2)
  {
    return false;
  }
  const std::size_t n = this->Hits.size();
  const auto first = [&](std::size_t k) { return k == 0 ? 0 : this->StrandEnd[k - 1]; };
  // The hits meeting the triangle, with their parts inside it (StrandPoints), and whether
  // each strand has one.
  this->StrandPoints.resize(3 * n);
  this->HitMeets.assign(n, 0);
  std::uint32_t meeting = 0; // bit k: strand k meets the triangle
  for (std::size_t k = 0; k < strands; ++k)
  {
    for (int i = first(k); i < this->StrandEnd[k]; ++i)
    {
      const int s = this->Hits[i];
      if (segmentMeetsTriangle(this->A[s], this->B[s], a, b, c))
      {
        this->HitMeets[i] = 1;
        meeting |= std::uint32_t(1) << k;
        clipToTriangle(this->A[s], this->B[s], a, b, c, &this->StrandPoints[3 * i]);
      }
    }
  }
  // Strands k and m of a closed curve that are one strand through its start.
  const auto wrapped = [&](std::size_t k, std::size_t m)
  {
    const int sk = this->Hits[first(k)], sm = this->Hits[this->StrandEnd[m] - 1];
    const int chain = this->ChainOf[sk];
    return this->ChainOf[sm] == chain && sk == this->ChainBegin[chain] &&
      sm == this->ChainBegin[chain + 1] - 1 && this->B[sm] == this->A[sk] &&
      pointNearTriangle(this->A[sk], a, b, c, r);
  };
  for (std::size_t k = 0; k < strands; ++k)
  {
    if (!(meeting >> k & 1))
    {
      continue;
    }
    const int ck = this->ChainOf[this->Hits[first(k)]];
    for (std::size_t m = 0; m < strands; ++m)
    {
      if (meeting >> m & 1)
      {
        continue; // (a layer across the triangle: layerAcross)
      }
      const int cm = this->ChainOf[this->Hits[first(m)]];
      if (ck != cm || wrapped(k, m) || wrapped(m, k))
      {
        continue; // (two curves: see thinLayer)
      }
      // The smallest and the largest distance from strand k's points in the triangle to
      // strand m: the layer is at least `thinnest` thick there and thinner than `thickest` all
      // along k's part in the triangle (a curve ending across another's path is no layer).
      double least = HUGE_VAL, most = 0.0;
      for (int i = first(k); i < this->StrandEnd[k]; ++i)
      {
        if (!this->HitMeets[i])
        {
          continue;
        }
        for (int e = 0; e < 3; ++e)
        {
          double d2 = HUGE_VAL;
          for (int j = first(m); j < this->StrandEnd[m]; ++j)
          {
            d2 = std::min(d2,
              pointSegmentDistance2(
                this->StrandPoints[3 * i + e], this->A[this->Hits[j]], this->B[this->Hits[j]]));
          }
          least = std::min(least, d2);
          most = std::max(most, d2);
        }
      }
      if (std::sqrt(least) >= thinnest && std::sqrt(most) < thickest)
      {
        return true;
      }
    }
  }
  return false;
}

bool BoundaryIndex::nearPoint(Vec2 p, double tolerance)
{
  const double t2 = tolerance * tolerance;
  return this->anySegment(p.x - tolerance,
    p.y - tolerance,
    p.x + tolerance,
    p.y + tolerance,
    [&](int s) { return pointSegmentDistance2(p, this->A[s], this->B[s]) <= t2; });
}

bool BoundaryIndex::closerThan(Vec2 p, double distance)
{
  const double r2 = distance * distance;
  return this->anySegment(p.x - distance,
    p.y - distance,
    p.x + distance,
    p.y + distance,
    [&](int s) { return pointSegmentDistance2(p, this->A[s], this->B[s]) < r2; });
}

bool BoundaryIndex::nearSegment(Vec2 a, Vec2 b, double tolerance)
{
  return this->anySegment(std::min(a.x, b.x) - tolerance,
    std::min(a.y, b.y) - tolerance,
    std::max(a.x, b.x) + tolerance,
    std::max(a.y, b.y) + tolerance,
    [&](int s) { return segmentsWithin(a, b, this->A[s], this->B[s], tolerance); });
}

bool BoundaryIndex::twoCurvesMeet(Vec2 a, Vec2 b)
{
  int first = -1;
  return this->anySegment(std::min(a.x, b.x),
    std::min(a.y, b.y),
    std::max(a.x, b.x),
    std::max(a.y, b.y),
    [&](int s)
    {
      if (!segmentsWithin(a, b, this->A[s], this->B[s], 0.0))
      {
        return false;
      }
      const int curve = this->ChainOf[s];
      if (first < 0)
      {
        first = curve;
        return false;
      }
      return curve != first;
    });
}

// The refinement loop of refine(): criteria, flags and progress.
class Grid48Refiner
{
public:
  Grid48Refiner(Grid48& grid,
    const Model& model,
    const DistanceField& field,
    const Grid48Params& params)
    : G(grid)
    , Field(field)
    , P(params)
    , ModelOrigin(model.origin)
  {
    this->Index.reset(new BoundaryIndex(model, grid.Origin, grid.Side));
    this->IndexReach = 4.0 * this->Index->cellSize();
    this->Local = this->P.localMaxLevel > this->P.maxLevel &&
      (this->P.localRefinement || this->P.thinRegionRefinement);
    this->TopLevel = std::max({ this->P.maxLevel, this->P.localMaxLevel, this->P.minLevel });
    if (this->P.junctionRefinement && this->P.junctionMaxLevel > 0)
    {
      this->TopLevel = std::max(this->TopLevel, this->P.junctionMaxLevel);
      this->collectFeaturePoints(model);
    }
    this->ThinLayers = this->Local && this->P.thinLayerRefinement &&
      this->P.junctionMaxLevel > this->P.localMaxLevel;
    if (this->ThinLayers)
    {
      this->TopLevel = std::max(this->TopLevel, this->P.junctionMaxLevel);
      this->FinestLeg = this->G.hypotenuseLength(this->P.junctionMaxLevel) * 0.70710678118654752440;
    }
    if (this->P.targetEdgeLength)
    {
      this->TargetLevel = this->P.targetMaxLevel;
      this->TopLevel = std::max(this->TopLevel, this->TargetLevel);
    }
  }

  // Whether leaf t meets a criterion; *distance receives the boundary distance of the
  // hypotenuse midpoint when it was computed.
  bool wantsSplit(int t, double* distance)
  {
    *distance = kNaN;
    std::uint8_t& flags = this->G.Level[t];
    const int level = flags & Grid48::kLevelMask;
    if (level >= this->TopLevel)
    {
      return false;
    }
    if (level < this->P.minLevel)
    {
      return true; // (e) uniform lower bound (maxEdgeLength)
    }
    const std::array<int, 3>& v = this->G.Vert[t];
    if (level < this->P.maxLevel && !(flags & kGlobalNo))
    {
      const auto l1 = this->G.Lattice[v[1]];
      const auto l2 = this->G.Lattice[v[2]];
      const Vec2 q = this->G.Origin +
        this->G.Scale *
          Vec2{ 0.5 * (static_cast<double>(l1[0]) + l2[0]),
            0.5 * (static_cast<double>(l1[1]) + l2[1]) };
      const double h = this->G.hypotenuseLength(level);
      const double tol = this->P.tolerance;
      // Bounds on d(q) from the corners with a known distance: each is h / 2 away from q.
      double lo = 0.0;
      double hi = HUGE_VAL;
      for (int k = 0; k < 3; ++k)
      {
        const double dv = this->G.VertexDistance[v[k]];
        if (!std::isnan(dv))
        {
          lo = std::max(lo, dv - 0.5 * h);
          hi = std::min(hi, dv + 0.5 * h);
        }
      }
      const double slack = 1e-9 * h + 1e-13 * this->G.Side; // rounding of the coordinates
      double d = kNaN;
      bool split;
      if (lo > h + slack)
      {
        split = false; // d >= lo > h
      }
      else if (hi < h - slack && lo > tol + slack)
      {
        split = true;
      }
      else if (h <= this->IndexReach)
      {
        // The boundary index decides d < h and d > tol exactly from a few cells.
        if (!this->Index->closerThan(q, h))
        {
          split = false;
          lo = h;
        }
        else
        {
          split = !this->Index->nearPoint(q, tol);
        }
        ++this->G.Stats.indexQueries;
      }
      else
      {
        d = this->Field.boundaryDistance(q, this->Scratch);
        ++this->G.Stats.distanceQueries;
        split = d > tol && h > d;
        lo = hi = d;
      }
      if (split)
      {
        *distance = d;
        return true;
      }
      std::uint8_t add = kGlobalNo;
      if (lo > 0.5 * h + slack)
      {
        add |= kEmpty; // the diamond lies in the circumdisk, which no boundary touches
      }
      flags |= add;
      const int partner = this->G.Nbr[t][0];
      if (partner >= 0 && (this->G.Level[partner] & Grid48::kLevelMask) == level)
      {
        this->G.Level[partner] |= add;
      }
    }
    const bool localTested = level < this->P.localMaxLevel && this->Local && !(flags & kEmpty);
    if (localTested)
    {
      ++this->G.Stats.localTests;
      const Vec2 a = this->G.vertexPosition(v[0]);
      const Vec2 b = this->G.vertexPosition(v[1]);
      const Vec2 c = this->G.vertexPosition(v[2]);
      const BoundaryIndex::TriangleResult r =
        this->Index->testTriangle(a, b, c, this->P.localRefinement, this->P.thinRegionRefinement);
      if (r == BoundaryIndex::CriterionHolds)
      {
        return true;
      }
      if (r == BoundaryIndex::NothingInside)
      {
        flags |= kEmpty;
      }
    }
    // (g) thin layers: a layer at least the finest leg thick that is thinner than T's legs,
    // across T or (one curve twice) beside it. Below localMaxLevel (c) has split the layers
    // across T; one that lies along a grid edge is beside the triangles on both sides of it (a
    // comb's tooth 0.12 of a leg wide astride the edges of level 13 at LocalMaxLevel 14: no
    // triangle held both of its sides, and the mesh cut it).
    if (this->ThinLayers && level >= this->P.maxLevel && level < this->P.junctionMaxLevel &&
      !(flags & kEmpty) && this->inThinLayerZone(v, level))
    {
      ++this->G.Stats.localTests;
      const double leg = this->G.hypotenuseLength(level) * 0.70710678118654752440;
      if (this->Index->thinLayer(this->G.vertexPosition(v[0]),
            this->G.vertexPosition(v[1]),
            this->G.vertexPosition(v[2]),
            this->FinestLeg,
            kThinLayerLegs * leg))
      {
        return true;
      }
    }
    // (d) close feature points. When the local test ran with localRefinement and said no, T
    // holds at most one model vertex, hence at most one feature point.
    if (level < this->P.junctionMaxLevel && !this->FeatureX.empty() && !(flags & kEmpty) &&
      !(localTested && this->P.localRefinement) && this->twoFeaturePoints(v, level))
    {
      return true;
    }
    // (f) target edge length field.
    return level < this->TargetLevel && this->longerThanTarget(v, level);
  }

  // Whether (g) may split the triangle of vertices v and level `level` (Grid48Params::
  // thinLayerZones).
  bool inThinLayerZone(const std::array<int, 3>& v, int level) const
  {
    if (this->P.thinLayerZones.empty())
    {
      return true;
    }
    const Vec2 g = (1.0 / 3.0) *
      (this->G.vertexPosition(v[0]) + this->G.vertexPosition(v[1]) + this->G.vertexPosition(v[2]));
    const double h = this->G.hypotenuseLength(level);
    return std::any_of(this->P.thinLayerZones.begin(),
      this->P.thinLayerZones.end(),
      [&](const Grid48Params::Zone& z)
      { return norm2(g - z.centre) <= (z.radius + h) * (z.radius + h); });
  }

  // Examines every leaf (and every leaf created meanwhile) and splits those that meet a
  // criterion.
  void run(const ProgressReporter& progress)
  {
    Grid48& g = this->G;
    for (std::uint8_t& l : g.Level)
    {
      l &= Grid48::kLevelMask; // flags are per call (parameters and model may have changed)
    }
    LargeVector<int> pending;
    pending.reserve(1024);
    for (int n = static_cast<int>(g.Level.size()) - 1; n >= 0; --n)
    {
      if (g.Child[n] < 0)
      {
        pending.push_back(n);
      }
    }
    std::size_t examined = 0;
    double reported = 0.0;
    progress.report(0.0, "refining the 4-8 grid");
    while (!pending.empty())
    {
      const int t = pending.back();
      pending.pop_back();
      if (g.Child[t] >= 0)
      {
        continue; // split meanwhile (forced); its children are pending
      }
      if (++examined % 4096 == 0)
      {
        // The stack's size is a rough measure of the work left.
        const double done = static_cast<double>(examined);
        reported = std::max(reported, done / (done + 4.0 * pending.size()));
        progress.report(reported, "refining the 4-8 grid");
      }
      double d;
      if (this->wantsSplit(t, &d))
      {
        g.split(t, d, &pending);
      }
    }
    progress.report(1.0, "refining the 4-8 grid");
  }

private:
  // The feature points (junctions, and vertices sharper than featurePointAngle) whose nearest
  // other feature point is within the largest hypotenuse at which (d) can matter, sorted by x,
  // with that nearest distance.
  void collectFeaturePoints(const Model& model)
  {
    std::vector<int> ids(model.junctions.begin(), model.junctions.end());
    if (this->P.featurePointAngle > 0.0)
    {
      const double cosLimit = std::cos(this->P.featurePointAngle * 3.14159265358979323846 / 180.0);
      for (const Curve& c : model.curves)
      {
        const std::size_t n = c.points.size();
        for (std::size_t i = 0; i < n; ++i)
        {
          if (!c.closed && (i == 0 || i + 1 == n))
          {
            continue; // curve ends: junctions or nodes of degree two between curves
          }
          const Vec2 p = c.points[i];
          const Vec2 u = c.points[(i + n - 1) % n] - p;
          const Vec2 w = c.points[(i + 1) % n] - p;
          const double nu = norm(u) * norm(w);
          // angle(u, w) < featurePointAngle  <=>  cos(angle) > cos(featurePointAngle)
          if (nu > 0.0 && dot(u, w) / nu > cosLimit)
          {
            ids.push_back(c.nodes[i]);
          }
        }
      }
    }
    sortUnique(ids);
    std::vector<Vec2> pts;
    pts.reserve(ids.size());
    for (int id : ids)
    {
      pts.push_back(model.nodes[id]);
    }
    std::sort(pts.begin(), pts.end(), [](Vec2 a, Vec2 b) { return a.x < b.x; });
    // Below localMaxLevel the local criterion (b) already splits triangles holding two model
    // vertices; (d) matters there only without it.
    const int from = this->Local && this->P.localRefinement ? this->P.localMaxLevel : 0;
    const double reach = this->G.hypotenuseLength(from) * (1.0 + 1e-9);
    for (std::size_t i = 0; i < pts.size(); ++i)
    {
      double best = HUGE_VAL;
      std::size_t nearest = i;
      const auto closer = [&](std::size_t j)
      {
        const double d = norm(pts[j] - pts[i]);
        if (d < best)
        {
          best = d;
          nearest = j;
        }
      };
      for (std::size_t j = i + 1; j < pts.size() && pts[j].x - pts[i].x < std::min(best, reach);
           ++j)
      {
        closer(j);
      }
      for (std::size_t j = i; j-- > 0 && pts[i].x - pts[j].x < std::min(best, reach);)
      {
        closer(j);
      }
      if (best <= reach && !this->thinStripEnd(pts[i], pts[nearest], best))
      {
        this->FeatureX.push_back(pts[i].x);
        this->FeatureY.push_back(pts[i].y);
        this->FeatureNearest.push_back(best);
      }
    }
  }

  // Whether feature points p and q, d apart, end a thin strip (see (d) at the top): on one
  // side of pq, at max(hypotenuse(localMaxLevel), 8 d) from its midpoint, a cross-section 3 d
  // long parallel to pq still meets two curves. The fault throws of gulf_section are no such
  // ends: their horizons diverge within that distance.
  bool thinStripEnd(Vec2 p, Vec2 q, double d)
  {
    if (!(d > 0.0))
    {
      return false;
    }
    const Vec2 t = (1.0 / d) * (q - p);
    const Vec2 n{ -t.y, t.x };
    const Vec2 m = 0.5 * (p + q);
    const double reach = std::max(this->G.hypotenuseLength(this->P.localMaxLevel), 8.0 * d);
    for (const double side : { 1.0, -1.0 })
    {
      const Vec2 x = m + (reach * side) * n;
      if (this->Index->twoCurvesMeet(x - (1.5 * d) * t, x + (1.5 * d) * t))
      {
        return true;
      }
    }
    return false;
  }

  // (f): whether the hypotenuse of level `level` is longer than the smallest target at the
  // corners of v and at its centroid.
  bool longerThanTarget(const std::array<int, 3>& v, int level)
  {
    const double h = this->G.hypotenuseLength(level);
    const double limit = h / (1.0 + 1e-12); // a target equal to h does not split
    if (this->VertexTarget.size() < this->G.Lattice.size())
    {
      this->VertexTarget.resize(this->G.Lattice.size(), -1.0);
    }
    Vec2 centroid{ 0.0, 0.0 };
    for (const int k : v)
    {
      const Vec2 p = this->G.vertexPosition(k);
      double& t = this->VertexTarget[k];
      if (t < 0.0)
      {
        t = targetAt(this->P.targetEdgeLength, p + this->ModelOrigin);
      }
      if (t < limit)
      {
        return true;
      }
      centroid = centroid + p;
    }
    return targetAt(this->P.targetEdgeLength, (1.0 / 3.0) * centroid + this->ModelOrigin) < limit;
  }

  // Whether the closed triangle v holds two or more of the feature points kept.
  bool twoFeaturePoints(const std::array<int, 3>& v, int level)
  {
    ++this->G.Stats.featureTests;
    const Vec2 a = this->G.vertexPosition(v[0]);
    const Vec2 b = this->G.vertexPosition(v[1]);
    const Vec2 c = this->G.vertexPosition(v[2]);
    // Two points in T are at most its hypotenuse apart.
    const double h = this->G.hypotenuseLength(level) * (1.0 + 1e-9);
    const double x0 = std::min({ a.x, b.x, c.x });
    const double x1 = std::max({ a.x, b.x, c.x });
    const double y0 = std::min({ a.y, b.y, c.y });
    const double y1 = std::max({ a.y, b.y, c.y });
    int count = 0;
    for (auto it = std::lower_bound(this->FeatureX.begin(), this->FeatureX.end(), x0);
         it != this->FeatureX.end() && *it <= x1;
         ++it)
    {
      const std::size_t i = static_cast<std::size_t>(it - this->FeatureX.begin());
      const double y = this->FeatureY[i];
      if (this->FeatureNearest[i] <= h && y >= y0 && y <= y1 &&
        pointInTriangle({ *it, y }, a, b, c) && ++count >= 2)
      {
        return true;
      }
    }
    return false;
  }

  Grid48& G;
  const DistanceField& Field;
  const Grid48Params& P;
  std::unique_ptr<BoundaryIndex> Index;
  int TopLevel = 0;    // no criterion splits a leaf of this level or finer
  Vec2 ModelOrigin;    // local + ModelOrigin = input coordinates (for the target field)
  int TargetLevel = 0; // (f) splits below this level (0: no field)
  std::vector<double> VertexTarget; // target at each grid vertex, -1 until evaluated
  std::vector<double> FeatureX, FeatureY, FeatureNearest;
  bool Local = false;
  bool ThinLayers = false; // (g)
  double FinestLeg = 0.0;  // (g): the leg of junctionMaxLevel
  double IndexReach = 0.0; // hypotenuses up to this length are decided with the index
  DistanceField::Scratch Scratch;
};

Grid48::Grid48(const Box2& bounds, double margin)
{
  const Domain d = domainOf(bounds, margin);
  this->Origin = d.origin;
  this->Side = d.side;
  this->Scale = d.side / static_cast<double>(kLatticeSize);
  this->Params.margin = margin;

  const std::uint32_t n = kLatticeSize;
  this->Lattice = { { 0, 0 }, { n, 0 }, { n, n }, { 0, n }, { n / 2, n / 2 } };
  this->VertexLevel.assign(5, 0);
  this->VertexDistance.assign(5, kNaN);
  for (int k = 0; k < 4; ++k)
  {
    this->Vert.push_back({ 4, k, (k + 1) % 4 });
    this->Nbr.push_back({ -1, (k + 1) % 4, (k + 3) % 4 });
    this->Child.push_back(-1);
    this->Level.push_back(0);
  }
  this->Leaves = 4;
}

double Grid48::hypotenuseLength(int level) const
{
  // side / 2^(level / 2): exact powers of two times 1 or sqrt(1/2).
  const double s = std::ldexp(this->Side, -(level / 2));
  return (level % 2) ? s * 0.70710678118654752440 : s;
}

Vec2 Grid48::vertexPosition(int vertex) const
{
  const auto& l = this->Lattice[vertex];
  return this->Origin + this->Scale * Vec2{ static_cast<double>(l[0]), static_cast<double>(l[1]) };
}

Grid48Params Grid48::resolveParams(const Model& model, const Grid48Params& params)
{
  return resolveParams(model, params, domainOf(model.bounds, params.margin).side);
}

Grid48Params Grid48::resolveParams(const Model& model, const Grid48Params& params, double side)
{
  Grid48Params p = params;
  if (!(p.margin >= 0.0 && p.margin <= 1.0))
  {
    throw ParameterError("Grid48: margin " + std::to_string(p.margin) + " is not in [0, 1]");
  }
  if (p.maxLevel < -1 || p.maxLevel > MaxSupportedLevel)
  {
    throw ParameterError("Grid48: MaxLevel " + std::to_string(p.maxLevel) +
      " is not -1 (automatic) or in [0, " + std::to_string(MaxSupportedLevel) + "]");
  }
  if (!(p.maxEdgeLength >= 0.0) || !std::isfinite(p.maxEdgeLength))
  {
    throw ParameterError("Grid48: MaximumEdgeLength " + std::to_string(p.maxEdgeLength) +
      " is not a finite value >= 0 (0: no bound)");
  }
  if (!(p.minEdgeLength >= 0.0) || !std::isfinite(p.minEdgeLength))
  {
    throw ParameterError("Grid48: MinimumEdgeLength " + std::to_string(p.minEdgeLength) +
      " is not a finite value >= 0 (0: no cap)");
  }
  if (p.maxEdgeLength > 0.0 && p.minEdgeLength > p.maxEdgeLength)
  {
    throw ParameterError("Grid48: MinimumEdgeLength " + std::to_string(p.minEdgeLength) +
      " is above MaximumEdgeLength " + std::to_string(p.maxEdgeLength));
  }
  // Hypotenuse of a level: side / 2^(level / 2), exact powers of two times 1 or sqrt(1/2).
  const auto hypotenuse = [side](int level)
  {
    const double s = std::ldexp(side, -(level / 2));
    return (level % 2) ? s * 0.70710678118654752440 : s;
  };
  const double slack = 1e-12; // relative: a length equal to a level's hypotenuse selects it
  // Level of maxEdgeLength: the coarsest whose hypotenuse is <= it (-1: none asked).
  int edgeLevel = -1;
  if (p.maxEdgeLength > 0.0)
  {
    edgeLevel = 0;
    while (edgeLevel <= MaxUniformLevel && hypotenuse(edgeLevel) > p.maxEdgeLength * (1 + slack))
    {
      ++edgeLevel;
    }
    if (edgeLevel > MaxUniformLevel)
    {
      throw ParameterError("Grid48: MaximumEdgeLength " + std::to_string(p.maxEdgeLength) +
        " is below " + std::to_string(hypotenuse(MaxUniformLevel)) + ", the hypotenuse of level " +
        std::to_string(MaxUniformLevel) + " (the finest uniform refinement, 4 * 2^" +
        std::to_string(MaxUniformLevel) + " triangles)");
    }
  }
  // Cap of minEdgeLength: the finest level whose hypotenuse is >= it, not below edgeLevel.
  int cap = MaxSupportedLevel;
  if (p.minEdgeLength > 0.0)
  {
    cap = 0;
    while (cap < MaxSupportedLevel && hypotenuse(cap + 1) >= p.minEdgeLength * (1 - slack))
    {
      ++cap;
    }
    cap = std::max(cap, edgeLevel);
  }
  // Levels without the edge lengths (explicit ones validated against each other), then the
  // lengths: maxEdgeLength overrides the automatic level and raises the ones set, minEdgeLength
  // lowers them all.
  int maxLevel = p.maxLevel;
  int automaticLevel = -1; // the usual automatic MaxLevel, before a field coarsens it
  if (maxLevel == -1)
  {
    const double m = medianSegmentLength(model);
    int level = 10;
    if (m > 0.0)
    {
      // hypotenuse(l) = side / 2^(l / 2) = 4 m  <=>  l = 2 log2(side / (4 m))
      level = static_cast<int>(std::lround(2.0 * std::log2(side / (4.0 * m))));
    }
    maxLevel = std::clamp(level, 10, 20);
    automaticLevel = maxLevel;
    if (p.targetEdgeLength && p.maxEdgeLength == 0.0)
    {
      // The field may coarsen: the coarsest level whose hypotenuse is <= its largest target.
      const double largest = largestTarget(model, p.targetEdgeLength);
      if (largest > 0.0)
      {
        int fieldLevel = 0;
        while (fieldLevel < maxLevel && hypotenuse(fieldLevel) > largest * (1 + slack))
        {
          ++fieldLevel;
        }
        maxLevel = fieldLevel;
      }
    }
  }
  if (p.localMaxLevel != -1 && (p.localMaxLevel < maxLevel || p.localMaxLevel > MaxSupportedLevel))
  {
    throw ParameterError("Grid48: LocalMaxLevel " + std::to_string(p.localMaxLevel) +
      " is not -1 (automatic) or in [MaxLevel = " + std::to_string(maxLevel) + ", " +
      std::to_string(MaxSupportedLevel) + "]");
  }
  const int localLevel =
    p.localMaxLevel == -1 ? std::min(maxLevel + 4, MaxSupportedLevel) : p.localMaxLevel;
  if (p.junctionMaxLevel != -1 &&
    (p.junctionMaxLevel < localLevel || p.junctionMaxLevel > MaxSupportedLevel))
  {
    throw ParameterError("Grid48: JunctionMaxLevel " + std::to_string(p.junctionMaxLevel) +
      " is not -1 (automatic) or in [LocalMaxLevel = " + std::to_string(localLevel) + ", " +
      std::to_string(MaxSupportedLevel) + "]");
  }
  if (edgeLevel >= 0)
  {
    maxLevel = p.maxLevel == -1 ? edgeLevel : std::max(p.maxLevel, edgeLevel);
  }
  p.maxLevel = std::min(maxLevel, cap);
  p.localMaxLevel = p.localMaxLevel == -1 ? std::min(p.maxLevel + 4, MaxSupportedLevel)
                                          : std::max(p.localMaxLevel, p.maxLevel);
  p.localMaxLevel = std::min(p.localMaxLevel, cap);
  if (p.junctionMaxLevel == -1)
  {
    p.junctionMaxLevel = p.localMaxLevel > p.maxLevel
      ? std::min(p.localMaxLevel + 8, MaxSupportedLevel)
      : p.localMaxLevel;
  }
  p.junctionMaxLevel = std::min(std::max(p.junctionMaxLevel, p.localMaxLevel), cap);
  if (p.targetMaxLevel == -1)
  {
    // The floor: 4 levels below LocalMaxLevel, or below the usual automatic LocalMaxLevel when
    // the field coarsened MaxLevel (so that coarsening elsewhere does not limit refinement).
    const int base = std::max(p.localMaxLevel, automaticLevel + 4);
    p.targetMaxLevel = p.minEdgeLength > 0.0 ? cap : std::min(base + 4, MaxSupportedLevel);
  }
  else if (p.targetMaxLevel < p.localMaxLevel || p.targetMaxLevel > MaxSupportedLevel)
  {
    throw ParameterError("Grid48: TargetMaxLevel " + std::to_string(p.targetMaxLevel) +
      " is not -1 (automatic) or in [LocalMaxLevel = " + std::to_string(p.localMaxLevel) + ", " +
      std::to_string(MaxSupportedLevel) + "]");
  }
  p.targetMaxLevel = std::min(p.targetMaxLevel, cap);
  if (p.minLevel == -1)
  {
    p.minLevel = std::max(edgeLevel, 0);
  }
  else if (p.minLevel < 0 || p.minLevel > std::min(p.maxLevel, MaxUniformLevel))
  {
    throw ParameterError("Grid48: MinLevel " + std::to_string(p.minLevel) +
      " is not -1 (automatic) or in [0, min(MaxLevel = " + std::to_string(p.maxLevel) + ", " +
      std::to_string(MaxUniformLevel) + ")]");
  }
  else
  {
    p.minLevel = std::max(p.minLevel, edgeLevel);
  }
  if (!(p.featurePointAngle >= 0.0 && p.featurePointAngle <= 180.0))
  {
    throw ParameterError(
      "Grid48: FeaturePointAngle " + std::to_string(p.featurePointAngle) + " is not in [0, 180]");
  }
  if (!(p.tolerance >= 0.0) || !std::isfinite(p.tolerance))
  {
    throw ParameterError("Grid48: Tolerance " + std::to_string(p.tolerance) +
      " is not a finite value >= 0 (0: automatic)");
  }
  for (std::size_t i = 0; i < p.thinLayerZones.size(); ++i)
  {
    const Grid48Params::Zone& z = p.thinLayerZones[i];
    if (!std::isfinite(z.centre.x) || !std::isfinite(z.centre.y) || !(z.radius >= 0.0) ||
      !std::isfinite(z.radius))
    {
      throw ParameterError("Grid48: thin layer zone " + std::to_string(i) + " (radius " +
        std::to_string(z.radius) + ") is not a finite disk");
    }
  }
  if (p.tolerance == 0.0)
  {
    p.tolerance = 1e-3 * hypotenuse(p.maxLevel);
  }
  return p;
}

Grid48 Grid48::build(const Model& model,
  const DistanceField& field,
  const Grid48Params& params,
  const ProgressReporter& progress)
{
  const Grid48Params resolved = resolveParams(model, params); // validates before any work
  Grid48 grid(model.bounds, resolved.margin);
  grid.refine(model, field, resolved, progress);
  return grid;
}

void Grid48::refine(const Model& model,
  const DistanceField& field,
  const Grid48Params& params,
  const ProgressReporter& progress)
{
  Grid48Params p = params;
  p.margin = this->Params.margin;
  p = resolveParams(model, p, this->Side);
  if (!model.bounds.empty())
  {
    const double slack = 1e-9 * this->Side;
    if (model.bounds.min.x < this->Origin.x - slack ||
      model.bounds.min.y < this->Origin.y - slack ||
      model.bounds.max.x > this->Origin.x + this->Side + slack ||
      model.bounds.max.y > this->Origin.y + this->Side + slack)
    {
      throw ParameterError("Grid48::refine: the model's bounds are not inside the grid's domain");
    }
  }
  this->Params = p;
  Grid48Refiner refiner(*this, model, field, this->Params);
  refiner.run(progress);
}

std::size_t Grid48::refineWhere(const std::function<bool(const Grid48&, int node)>& split,
  int maxLevel,
  const ProgressReporter& progress)
{
  maxLevel = std::min(maxLevel, MaxSupportedLevel);
  const std::size_t before = this->Stats.splits;
  LargeVector<int> pending;
  for (int n = static_cast<int>(this->Level.size()) - 1; n >= 0; --n)
  {
    if (this->Child[n] < 0)
    {
      pending.push_back(n);
    }
  }
  std::size_t examined = 0;
  while (!pending.empty())
  {
    const int t = pending.back();
    pending.pop_back();
    if (this->Child[t] >= 0 || this->nodeLevel(t) >= maxLevel)
    {
      continue;
    }
    if (++examined % 16384 == 0)
    {
      progress.report(0.5, "refining the 4-8 grid");
    }
    if (split(*this, t))
    {
      this->split(t, kNaN, &pending);
    }
  }
  progress.report(1.0, "refining the 4-8 grid");
  return this->Stats.splits - before;
}

int Grid48::addVertex(std::array<std::uint32_t, 2> lattice, int level, double distance)
{
  reserveGrowth(this->Lattice);
  reserveGrowth(this->VertexLevel);
  reserveGrowth(this->VertexDistance);
  this->Lattice.push_back(lattice);
  this->VertexLevel.push_back(static_cast<std::uint8_t>(level));
  this->VertexDistance.push_back(distance);
  return static_cast<int>(this->Lattice.size()) - 1;
}

void Grid48::replaceNeighbour(int node, int from, int to)
{
  if (node < 0)
  {
    return;
  }
  for (int& n : this->Nbr[node])
  {
    if (n == from)
    {
      n = to;
      return;
    }
  }
}

// Children (m, v0, v1) and (m, v2, v0) of node (v0, v1, v2); the neighbours across the two
// halves of the hypotenuse are left to split().
void Grid48::bisect(int node, int m)
{
  const std::array<int, 3> v = this->Vert[node];
  const std::array<int, 3> n = this->Nbr[node];
  const int c = static_cast<int>(this->Level.size());
  const std::uint8_t level = static_cast<std::uint8_t>((this->Level[node] & kLevelMask) + 1);
  const std::uint8_t inherited = this->Level[node] & kEmpty;
  reserveGrowth(this->Vert, 2);
  reserveGrowth(this->Nbr, 2);
  reserveGrowth(this->Child, 2);
  reserveGrowth(this->Level, 2);
  reserveGrowth(this->PairParent);
  this->Vert.push_back({ m, v[0], v[1] });
  this->Vert.push_back({ m, v[2], v[0] });
  this->Nbr.push_back({ n[2], -1, c + 1 });
  this->Nbr.push_back({ n[1], c, -1 });
  this->Child.push_back(-1);
  this->Child.push_back(-1);
  this->Level.push_back(level | inherited);
  this->Level.push_back(level | inherited);
  this->PairParent.push_back(node);
  this->Child[node] = c;
  this->replaceNeighbour(n[2], node, c);
  this->replaceNeighbour(n[1], node, c + 1);
}

void Grid48::split(int t, double midpointDistance, LargeVector<int>* pending, bool forced)
{
  const int level = this->nodeLevel(t);
  int n = this->Nbr[t][0];
  if (n >= 0 && this->nodeLevel(n) < level)
  {
    this->split(n, kNaN, pending, true);
    n = this->Nbr[t][0]; // now the child of the old neighbour that shares the hypotenuse
  }
  const auto l1 = this->Lattice[this->Vert[t][1]];
  const auto l2 = this->Lattice[this->Vert[t][2]];
  const int m =
    this->addVertex({ static_cast<std::uint32_t>((static_cast<std::uint64_t>(l1[0]) + l2[0]) / 2),
                      static_cast<std::uint32_t>((static_cast<std::uint64_t>(l1[1]) + l2[1]) / 2) },
      level + 1,
      midpointDistance);
  this->bisect(t, m);
  const int ct = this->Child[t];
  if (n >= 0)
  {
    this->bisect(n, m);
    const int cn = this->Child[n];
    // t's child (m, v0, v1) meets n's child (m, v1, w0) along m-v1, and t's (m, v2, v0)
    // meets n's (m, w0, v2) along m-v2.
    this->Nbr[ct][1] = cn + 1;
    this->Nbr[cn + 1][2] = ct;
    this->Nbr[ct + 1][2] = cn;
    this->Nbr[cn][1] = ct + 1;
  }
  const int count = n >= 0 ? 2 : 1;
  this->Leaves += count;
  this->Stats.splits += count;
  if (forced)
  {
    this->Stats.forcedSplits += count;
  }
  this->MaxLeafLevel = std::max(this->MaxLeafLevel, level + 1);
  if (pending)
  {
    pending->push_back(ct);
    pending->push_back(ct + 1);
    if (n >= 0)
    {
      pending->push_back(this->Child[n]);
      pending->push_back(this->Child[n] + 1);
    }
  }
}

TriangleMesh Grid48::extract(int level, const ProgressReporter& progress) const
{
  if (level < -1)
  {
    throw ParameterError(
      "Grid48::extract: level " + std::to_string(level) + " is not -1 (finest) or >= 0");
  }
  const int cut = level < 0 ? MaxSupportedLevel + 1 : level;
  TriangleMesh mesh;
  // The finest mesh's sizes are known: no array grows by copies.
  const std::size_t leaves = level < 0 ? this->Leaves : 0, vertices = this->Lattice.size();
  mesh.triangles.reserve(leaves);
  mesh.triangleLevel.reserve(leaves);
  mesh.triangleNode.reserve(leaves);
  mesh.points.reserve(level < 0 ? vertices : 0);
  mesh.pointLevel.reserve(level < 0 ? vertices : 0);
  mesh.pointVertex.reserve(level < 0 ? vertices : 0);
  mesh.pointBoundaryDistance.reserve(level < 0 ? vertices : 0);
  LargeVector<int> map(vertices, -1);
  std::vector<int> stack = { 3, 2, 1, 0 };
  auto point = [&](int v)
  {
    int& id = map[v];
    if (id < 0)
    {
      id = static_cast<int>(mesh.points.size());
      mesh.points.push_back(this->vertexPosition(v));
      mesh.pointLevel.push_back(this->VertexLevel[v]);
      mesh.pointVertex.push_back(v);
      mesh.pointBoundaryDistance.push_back(this->VertexDistance[v]);
    }
    return id;
  };
  while (!stack.empty())
  {
    const int n = stack.back();
    stack.pop_back();
    const int l = this->nodeLevel(n);
    if (this->Child[n] >= 0 && l < cut)
    {
      stack.push_back(this->Child[n] + 1);
      stack.push_back(this->Child[n]);
      continue;
    }
    if ((mesh.triangles.size() & 0xffff) == 0)
    {
      progress.report(this->Leaves > 0
          ? std::min(
              1.0, static_cast<double>(mesh.triangles.size()) / static_cast<double>(this->Leaves))
          : 0.0,
        "extracting the grid");
    }
    const std::array<int, 3>& v = this->Vert[n];
    mesh.triangles.push_back({ point(v[0]), point(v[1]), point(v[2]) });
    mesh.triangleLevel.push_back(l);
    mesh.triangleNode.push_back(n);
  }
  return mesh;
}

std::size_t Grid48::memoryBytes() const
{
  // (Sizes: the capacity beyond them, reserved fourfold as the arrays grow, is never written.)
  auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
  return bytes(this->Vert) + bytes(this->Nbr) + bytes(this->Child) + bytes(this->Level) +
    bytes(this->PairParent) + bytes(this->Lattice) + bytes(this->VertexLevel) +
    bytes(this->VertexDistance);
}

} // namespace strata
