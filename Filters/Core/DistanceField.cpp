// StrataMesh core: signed distance to the regions of a model (paper Sections 3-4).
//
// Data
// ----
// For every region, one strip tree (StripTree.cpp) over the segments of all its rings, ring
// after ring (segment i of a ring goes from points[i] to points[i + 1 mod n]); each segment
// knows its predecessor and successor in its ring. Rings are oriented with the region on
// their left (Model.h), so the orientation of every boundary edge says on which side the
// region lies. A vertex whose node id occurs more than once in the region's rings (two rings
// touching at a vertex, or a ring visiting a vertex twice) gets a "star": the list of all the
// region's segments that leave or reach it. One more strip tree holds every boundary segment
// of every region once (a segment shared by two regions, i.e. the same pair of node ids, is
// kept once, with the input cell id of its first occurrence; found with a hash set, O(n)) for
// boundaryDistance() and the nearest input curve.
//
// Signed distance to region R
// ---------------------------
// 1. Magnitude: the exact distance d to R's boundary, from the strip tree's best-first search
//    (closest segment s and parameter t of the closest point q on it).
// 2. d == 0: p is on the boundary, which counts as inside: +0.
// 3. p outside R's bounding box: outside, -d (no sign test needed).
// 4. Sign at q. The open disk of radius d around p holds no boundary point, so the segment
//    from p to q crosses no boundary and p is on the same side as the points next to q in
//    the direction of p:
//    - 0 < t < 1 (q inside segment a->b): inside iff p is left of a->b (orient2d > 0), or on
//      its line (orient2d == 0: a point on a segment whose computed distance is a rounding
//      residue rather than 0 is on the boundary, hence inside).
//    - t == 0 or t == 1 (q is a vertex v): gather the edges of R at v (the ring's incoming and
//      outgoing segment, or the star of a shared vertex), as directions from v: w - v for an
//      outgoing edge v->w, u - v for an incoming edge u->v. The direction p - v falls in the
//      angular sector between two consecutive edge directions; find the edge immediately
//      clockwise of p - v. If it is outgoing, the region lies on its left, i.e. counter-
//      clockwise of it: inside. If it is incoming, its left side is clockwise of the
//      direction u - v: outside. This holds for convex and reflex corners alike, and for any
//      number of rings touching at v, provided that the rings do not cross (the even-odd
//      region then alternates between in and out around v, which the orientation encodes).
//    The angular search uses no trigonometry: a direction e is ranked by its counter-
//    clockwise angle from p - v, first by half plane, then by cross products.
//
// query(p): every region whose box contains p is tested; the containing region is the one
// with signed distance >= 0 (on a boundary shared by several, the largest signed distance,
// ties to the smallest id). Its signed distance is returned; outside every region, minus the
// distance to the nearest boundary of any region. boundaryDistance and nearestCurve come from
// the global tree. region(p) is query(p).region without the global tree's query.
//
// Threads: everything is const after construction; the only mutable state of a query is the
// caller's scratch (the search heap), one per thread. Queries do not allocate once the
// scratch is warm.
#include "DistanceField.h"

#include "Errors.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>
#include <utility>

namespace strata
{

namespace
{

// Rank of direction e by its counter-clockwise angle from d, in (0, 2 pi]: half 0 holds
// (0, pi], half 1 holds (pi, 2 pi] (the direction of d itself counts as 2 pi, so an edge along
// d is the one immediately clockwise of d).
inline int halfPlane(Vec2 d, Vec2 e)
{
  const double c = cross(d, e);
  if (c > 0.0)
  {
    return 0;
  }
  if (c < 0.0)
  {
    return 1;
  }
  return dot(d, e) < 0.0 ? 0 : 1;
}

// Whether the counter-clockwise angle from d to e1 is smaller than that to e2.
inline bool angleLess(Vec2 d, Vec2 e1, Vec2 e2)
{
  const int h1 = halfPlane(d, e1);
  const int h2 = halfPlane(d, e2);
  if (h1 != h2)
  {
    return h1 < h2;
  }
  return cross(e1, e2) > 0.0;
}

} // namespace

DistanceField::DistanceField(const Model& model)
{
  std::vector<Vec2> allA, allB;
  std::unordered_set<std::uint64_t> seen;
  std::vector<std::pair<int, int>> occurrences; // (node, 2 * segment + outgoing), per region

  this->Regions.resize(model.regions.size());
  for (std::size_t ri = 0; ri < model.regions.size(); ++ri)
  {
    const Region& region = model.regions[ri];
    RegionTree& r = this->Regions[ri];
    r.id = region.id;

    std::size_t count = 0;
    for (const Ring& ring : region.rings)
    {
      count += ring.points.size();
    }
    std::vector<Vec2> a, b;
    a.reserve(count);
    b.reserve(count);
    r.prev.reserve(count);
    r.next.reserve(count);
    occurrences.clear();
    for (const Ring& ring : region.rings)
    {
      const int n = static_cast<int>(ring.points.size());
      if (n == 0)
      {
        continue;
      }
      if (ring.nodes.size() != ring.points.size() || ring.segmentCell.size() != ring.points.size())
      {
        throw InputError("DistanceField: a ring of region " + std::to_string(region.id) + " has " +
          std::to_string(n) + " points but " + std::to_string(ring.nodes.size()) +
          " node ids and " + std::to_string(ring.segmentCell.size()) + " segment cells");
      }
      const int base = static_cast<int>(a.size());
      for (int i = 0; i < n; ++i)
      {
        const int j = (i + 1) % n;
        const Vec2 p = ring.points[i];
        const Vec2 q = ring.points[j];
        a.push_back(p);
        b.push_back(q);
        r.bounds.add(p);
        r.prev.push_back(base + (i + n - 1) % n);
        r.next.push_back(base + j);
        // Vertices without a node id (< 0) are never taken as shared.
        if (ring.nodes[i] >= 0)
        {
          occurrences.emplace_back(ring.nodes[i], 2 * (base + i) + 1); // leaves node i
        }
        if (ring.nodes[j] >= 0)
        {
          occurrences.emplace_back(ring.nodes[j], 2 * (base + i)); // reaches node j
        }

        // Global tree: each undirected segment (pair of node ids) once.
        const auto lo = static_cast<std::uint32_t>(std::min(ring.nodes[i], ring.nodes[j]));
        const auto hi = static_cast<std::uint32_t>(std::max(ring.nodes[i], ring.nodes[j]));
        const bool identified = ring.nodes[i] >= 0 && ring.nodes[j] >= 0;
        if (!identified || seen.insert((static_cast<std::uint64_t>(lo) << 32) | hi).second)
        {
          allA.push_back(p);
          allB.push_back(q);
          this->AllCell.push_back(ring.segmentCell[i]);
        }
      }
    }

    // Stars of the shared vertices: the nodes met more than twice (more than one incoming and
    // one outgoing segment) in this region's rings.
    const int segments = static_cast<int>(a.size());
    r.startStar.assign(segments, -1);
    r.endStar.assign(segments, -1);
    r.starOffsets.assign(1, 0);
    std::sort(occurrences.begin(), occurrences.end());
    for (std::size_t i = 0; i < occurrences.size();)
    {
      std::size_t j = i;
      while (j < occurrences.size() && occurrences[j].first == occurrences[i].first)
      {
        ++j;
      }
      if (j - i > 2)
      {
        const int star = static_cast<int>(r.starOffsets.size()) - 1;
        for (std::size_t k = i; k < j; ++k)
        {
          const int edge = occurrences[k].second;
          r.starEdges.push_back(edge);
          (edge & 1 ? r.startStar : r.endStar)[edge >> 1] = star;
        }
        r.starOffsets.push_back(static_cast<int>(r.starEdges.size()));
      }
      i = j;
    }
    r.tree = StripTree(std::move(a), std::move(b));
  }
  this->All = StripTree(std::move(allA), std::move(allB));
}

double DistanceField::signedDistanceImpl(const RegionTree& r, Vec2 p, Scratch& scratch) const
{
  const NearestSegment ns = r.tree.nearest(p, scratch);
  if (ns.segment < 0)
  {
    return -HUGE_VAL; // a region without boundary contains nothing
  }
  const double d = std::sqrt(ns.distance2);
  if (d == 0.0)
  {
    return 0.0; // on the boundary: inside
  }
  if (r.bounds.distance2(p) > 0.0)
  {
    return -d;
  }
  const int s = ns.segment;
  const Vec2 a = r.tree.segmentStart(s);
  const Vec2 b = r.tree.segmentEnd(s);
  if (ns.t > 0.0 && ns.t < 1.0)
  {
    // Only a point within rounding of the segment's line can give orient2d == 0 here; it is on
    // the boundary for all practical purposes, which counts as inside.
    return orient2d(a, b, p) >= 0.0 ? d : -d;
  }

  // The closest point is vertex v: sector rule over the edges incident to v.
  const bool atStart = ns.t == 0.0;
  const Vec2 v = atStart ? a : b;
  const Vec2 dir = p - v;
  const int star = atStart ? r.startStar[s] : r.endStar[s];
  int single[2];
  const int* edges = single;
  int count = 2;
  if (star >= 0)
  {
    edges = r.starEdges.data() + r.starOffsets[star];
    count = r.starOffsets[star + 1] - r.starOffsets[star];
  }
  else if (atStart)
  {
    single[0] = 2 * r.prev[s];
    single[1] = 2 * s + 1;
  }
  else
  {
    single[0] = 2 * s;
    single[1] = 2 * r.next[s] + 1;
  }
  // The edge immediately clockwise of dir has the largest counter-clockwise angle from dir.
  int bestEdge = -1;
  Vec2 bestDir;
  for (int k = 0; k < count; ++k)
  {
    const int edge = edges[k];
    const int seg = edge >> 1;
    const Vec2 e = (edge & 1) ? r.tree.segmentEnd(seg) - v : r.tree.segmentStart(seg) - v;
    if (bestEdge < 0 || angleLess(dir, bestDir, e))
    {
      bestEdge = edge;
      bestDir = e;
    }
  }
  return (bestEdge & 1) ? d : -d;
}

double DistanceField::signedDistance(std::size_t regionIndex, Vec2 p, Scratch& scratch) const
{
  if (regionIndex >= this->Regions.size())
  {
    throw ParameterError("DistanceField::signedDistance: region index " +
      std::to_string(regionIndex) + " is not in [0, " + std::to_string(this->Regions.size()) + ")");
  }
  return this->signedDistanceImpl(this->Regions[regionIndex], p, scratch);
}

bool DistanceField::inside(std::size_t regionIndex, Vec2 p, Scratch& scratch) const
{
  if (regionIndex >= this->Regions.size())
  {
    throw ParameterError("DistanceField::inside: region index " + std::to_string(regionIndex) +
      " is not in [0, " + std::to_string(this->Regions.size()) + ")");
  }
  const RegionTree& r = this->Regions[regionIndex];
  if (r.bounds.distance2(p) > 0.0)
  {
    return false;
  }
  return this->signedDistanceImpl(r, p, scratch) >= 0.0;
}

double DistanceField::boundaryDistance(Vec2 p, Scratch& scratch, std::int64_t* nearestCurve) const
{
  const NearestSegment ns = this->All.nearest(p, scratch);
  if (nearestCurve)
  {
    *nearestCurve = ns.segment >= 0 ? this->AllCell[ns.segment] : -1;
  }
  return std::sqrt(ns.distance2);
}

int DistanceField::regionImpl(Vec2 p, Scratch& scratch, double& best) const
{
  int region = -1;
  best = -HUGE_VAL;
  for (const RegionTree& r : this->Regions)
  {
    if (r.bounds.distance2(p) > 0.0)
    {
      continue;
    }
    const double sd = this->signedDistanceImpl(r, p, scratch);
    if (sd >= 0.0 && (sd > best || (sd == best && r.id < region)))
    {
      best = sd;
      region = r.id;
    }
  }
  return region;
}

int DistanceField::region(Vec2 p, Scratch& scratch) const
{
  double best = 0.0;
  return this->regionImpl(p, scratch, best);
}

PointQuery DistanceField::query(Vec2 p, Scratch& scratch) const
{
  PointQuery q;
  q.boundaryDistance = this->boundaryDistance(p, scratch, &q.nearestCurve);
  double best = 0.0;
  q.region = this->regionImpl(p, scratch, best);
  q.signedDistance = q.region >= 0 ? best : -q.boundaryDistance;
  return q;
}

} // namespace strata
