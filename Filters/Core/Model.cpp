// StrataMesh core: the input model (see Model.h and Data/FORMAT.md).
//
// How buildModel works
// --------------------
// 1. Cells. The form (Loops or Shared curves) comes from the arrays that are present. Each cell
//    is classified in input order: non-line cells, polygons in the Shared curves form, loops of
//    region -1 and curves with the same region on both sides are ignored with a warning; point
//    ids out of range, region ids below -1 and non-finite coordinates are errors naming the
//    cell (and point). The cells that remain are the candidates.
// 2. Local frame and tolerance. origin = centre of the bounding box of the candidates' points;
//    every coordinate is stored as input minus origin, so that UTM magnitudes (1e7) lose no
//    digits. The merge tolerance is ModelParams::mergeTolerance times the bounding-box
//    diagonal; no absolute tolerance is used anywhere, so a model scaled by 1e-6 behaves alike.
// 3. Nodes. Points are merged greedily into nodes through a hash grid (cells of the mean input
//    edge length, at least 4 tolerances; the neighbour cells are looked at only for points
//    within the tolerance of a cell border): a point joins the nearest node within the
//    tolerance, else it starts a new node, so any two nodes are more than the tolerance apart.
//    Each candidate becomes a node path; consecutive repeats are dropped. Loops are closed (the
//    last point is dropped when it merges with the first, otherwise the closing edge is
//    implied, as FORMAT.md says, and its gap remembered); a shared curve is closed when its end
//    nodes are equal. Paths with too few distinct nodes are dropped with a warning.
// 4. Crossings. The segments of all curves (closing edges included) are deduplicated by node
//    pair (neighbouring loops repeat shared borders; in the Shared curves form a repeated
//    segment is an error). The unique segments are rasterised into a sparse uniform grid whose
//    cell size is the mean segment length (so the number of grid entries stays proportional to
//    the number of segments), and every pair in a grid cell is tested: segments may share an
//    end node, anything else that touches within the tolerance (proper crossing, an end point
//    on the other segment, collinear overlap) is an error. Of all defects found the one of
//    the lowest pair of segment numbers is reported, so that the message does not depend on
//    the grid (a shifted or scaled model reports the same defect).
// 4b. Borders between two loops of one region (Loops form). A segment that a region's loops
//    have twice, one on each side (two loops side by side: a country given as its provinces;
//    a hole that touches its outer loop along a border; a loop that runs back along itself)
//    is no border of that region by the even-odd rule. Once the rings are oriented (6), each
//    such region's rings are traced again from its border segments alone (keepBorders). A
//    segment that is no border of any region is "dead": it is left out of the junctions'
//    degrees and of the curves (a loop is cut into open runs there), with one warning per
//    region, so the mesh does not follow it (before, it did: the region was meshed in two
//    with a false boundary warning and finer meshes made again for it).
// 5. Regions. Loops form: the rings of region r are its loops. Shared curves form: curves are
//    cut into pieces at nodes of the segment graph whose degree is not 2 (junctions), an end
//    of degree 1 is a dangling end (error), and the faces of the planar graph are traced: each
//    piece is used in both directions (forward with its left label on the left, reversed with
//    its right label on the left); arriving at a node, the walk continues with the first
//    outgoing piece clockwise from the reversed incoming direction, which traces every face
//    cycle with the face on its left. One cycle must carry one label; cycles of labels >= 0
//    are the rings of that region, cycles of -1 are dropped.
// 6. Orientation. For each region, the even-odd depth of each ring among the region's other
//    rings is found by a crossing-number test of a midpoint of one of its segments that lies
//    on no other ring of the region (the region's segments are bucketed by rows). Rings of even
//    depth are made counter-clockwise, odd ones clockwise, so the region is on the left of every
//    ring. In the Shared curves form the traced orientation must already agree; a face cycle that
//    does not is a region labelled outside the model's outer boundary (error).
// 7. Junctions are the nodes of degree != 2 in the graph of unique segments.
// 8. Overlaps. Every place must belong to one region at most. Two regions on the same side of
//    one segment (loops of two regions, or one loop given twice, along the same border with
//    their regions inside it) are an error, and so is a region's border inside another
//    region that does not border it there: the even-odd test of a midpoint of each ring and
//    of each run of it between junctions against the other regions' rings. Without it an
//    island whose surrounding region has no hole for it (a Loops form region without the hole
//    loop; a Shared curves island whose outer side is labelled -1) was meshed as one of the
//    two, the other's area lost with a misleading warning.
#include "Model.h"

#include "Errors.h"
#include "Rows.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace strata
{
namespace
{

//------------------------------------------------------------------------------
// Message helpers.
std::string num(double v)
{
  if (std::isnan(v))
  {
    return "nan";
  }
  if (std::isinf(v))
  {
    return v > 0 ? "inf" : "-inf";
  }
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.12g", v);
  return buf;
}

std::string shortNum(double v)
{
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

std::string pointText(Vec2 p)
{
  return "(" + num(p.x) + ", " + num(p.y) + ")";
}

std::string cellText(std::int64_t c)
{
  return "cell " + std::to_string(c);
}

//------------------------------------------------------------------------------
// Warnings, at most Limit of each kind (then one summary line), in the order they arise.
enum WarningKind
{
  NotLineCell,
  PolygonAsLoop,
  PolygonIgnored,
  ExteriorLoop,
  SameRegionBothSides,
  RepeatedPoints,
  DegenerateCell,
  ShortLoop,
  ImpliedClosing,
  CancelledBorder,
  NumberOfWarningKinds
};

class Warnings
{
public:
  void add(WarningKind kind, std::string text)
  {
    if (this->Counts[kind]++ < Limit)
    {
      this->Texts.push_back(std::move(text));
    }
  }

  /// The first few warnings, for an error message that follows from them.
  std::string brief() const
  {
    std::string out;
    for (std::size_t i = 0; i < this->Texts.size() && i < 3; ++i)
    {
      out += (i ? "; " : "") + this->Texts[i];
    }
    if (this->Texts.size() > 3)
    {
      out += "; ...";
    }
    return out;
  }

  std::vector<std::string> take()
  {
    static const char* const what[NumberOfWarningKinds] = {
      "cells that are not line cells were ignored",
      "polygon cells were read as closed loops",
      "polygon cells were ignored",
      "loops of region -1 were ignored",
      "cells with the same region on both sides were ignored",
      "cells had repeated consecutive points dropped",
      "cells of zero length were ignored",
      "loops with fewer than 3 distinct points were ignored",
      "loops were closed by joining their last point to their first",
      "regions had borders between two of their own loops, which are no border",
    };
    for (int k = 0; k < NumberOfWarningKinds; ++k)
    {
      if (this->Counts[k] > Limit)
      {
        this->Texts.push_back(
          "and " + std::to_string(this->Counts[k] - Limit) + " more such warnings: " + what[k]);
      }
    }
    return std::move(this->Texts);
  }

private:
  static constexpr int Limit = 20;
  int Counts[NumberOfWarningKinds] = {};
  std::vector<std::string> Texts;
};

//------------------------------------------------------------------------------
// Greedy point merging through a hash grid (open addressing, one list of nodes per grid cell).
class NodeMerger
{
public:
  NodeMerger(Vec2 min, double cellSize, double tol, std::size_t maxNodes)
    : Min(min)
    , InvCell(1.0 / cellSize)
    , Tol2(tol * tol)
    , Margin(tol / cellSize + 1e-6) // + rounding of cell coordinates up to 2^30
  {
    std::size_t capacity = 16;
    while (capacity < 2 * maxNodes + 2)
    {
      capacity *= 2;
    }
    this->Keys.assign(capacity, EmptyKey);
    this->Heads.assign(capacity, -1);
    this->Mask = capacity - 1;
    this->Nodes.reserve(maxNodes);
    this->Next.reserve(maxNodes);
  }

  /// The id of the node that p merges with (a new one when none is within the tolerance).
  int insert(Vec2 p)
  {
    const double fx = (p.x - this->Min.x) * this->InvCell;
    const double fy = (p.y - this->Min.y) * this->InvCell;
    const std::int64_t ix = static_cast<std::int64_t>(std::floor(fx));
    const std::int64_t iy = static_cast<std::int64_t>(std::floor(fy));
    const double rx = fx - static_cast<double>(ix);
    const double ry = fy - static_cast<double>(iy);
    int best = -1;
    double bestD = 0.0;
    for (int dx = -1; dx <= 1; ++dx)
    {
      if ((dx < 0 && rx > this->Margin) || (dx > 0 && 1.0 - rx > this->Margin))
      {
        continue;
      }
      for (int dy = -1; dy <= 1; ++dy)
      {
        if ((dy < 0 && ry > this->Margin) || (dy > 0 && 1.0 - ry > this->Margin))
        {
          continue;
        }
        for (int n = this->find(key(ix + dx, iy + dy)); n >= 0; n = this->Next[n])
        {
          const double d = norm2(this->Nodes[n] - p);
          if (d <= this->Tol2 && (best < 0 || d < bestD))
          {
            best = n;
            bestD = d;
          }
        }
      }
    }
    if (best >= 0)
    {
      return best;
    }
    const int id = static_cast<int>(this->Nodes.size());
    this->Nodes.push_back(p);
    int& head = this->slot(key(ix, iy));
    this->Next.push_back(head);
    head = id;
    return id;
  }

  std::vector<Vec2> Nodes;

private:
  static constexpr std::uint64_t EmptyKey = ~std::uint64_t(0);

  // Grid indices are >= -1 (a neighbour of column 0) and < 2^31 (the cell size is chosen so).
  static std::uint64_t key(std::int64_t ix, std::int64_t iy)
  {
    return (static_cast<std::uint64_t>(ix + 1) << 32) | static_cast<std::uint64_t>(iy + 1);
  }
  std::size_t hash(std::uint64_t k) const
  {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 20) & this->Mask;
  }
  int find(std::uint64_t k) const
  {
    for (std::size_t i = this->hash(k);; i = (i + 1) & this->Mask)
    {
      if (this->Keys[i] == k)
      {
        return this->Heads[i];
      }
      if (this->Keys[i] == EmptyKey)
      {
        return -1;
      }
    }
  }
  int& slot(std::uint64_t k)
  {
    std::size_t i = this->hash(k);
    while (this->Keys[i] != k && this->Keys[i] != EmptyKey)
    {
      i = (i + 1) & this->Mask;
    }
    this->Keys[i] = k;
    return this->Heads[i];
  }

  Vec2 Min;
  double InvCell;
  double Tol2;
  double Margin;
  std::size_t Mask = 0;
  std::vector<std::uint64_t> Keys;
  std::vector<int> Heads;
  std::vector<int> Next;
};

//------------------------------------------------------------------------------
// Per kept curve facts that only messages need.
struct CurveInfo
{
  bool impliedClosing = false; ///< a loop whose last point did not merge with its first
  double gap = 0.0;            ///< distance between those points
  Vec2 first, last;            ///< input coordinates of those points
};

/// Segment k of curve `curve`: curve.nodes[k] -> curve.nodes[(k + 1) % size].
struct Segment
{
  int a;
  int b;
  int curve;
  int k;
};

std::uint64_t edgeKey(int a, int b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

//------------------------------------------------------------------------------
// Segment pair tests.
enum class Contact
{
  None,
  Cross,  ///< proper crossing
  Touch,  ///< an end point on the other segment
  Overlap ///< collinear overlap
};

/// Whether p is within tol of segment ab (tol = 0: exactly on it).
bool onSegment(Vec2 p, Vec2 a, Vec2 b, double tol)
{
  const Vec2 ab = b - a;
  const double len2 = norm2(ab);
  const double d = orient2d(a, b, p);
  if (d * d > tol * tol * len2)
  {
    return false;
  }
  const double slack = tol * std::sqrt(len2);
  const double t = dot(p - a, ab);
  return t >= -slack && t <= len2 + slack;
}

Contact testPair(const std::vector<Vec2>& P,
  const Segment& s,
  const Segment& t,
  double tol,
  Vec2& where)
{
  const Vec2 a = P[s.a], b = P[s.b], c = P[t.a], d = P[t.b];
  if (std::max(a.x, b.x) + tol < std::min(c.x, d.x) ||
    std::max(c.x, d.x) + tol < std::min(a.x, b.x) ||
    std::max(a.y, b.y) + tol < std::min(c.y, d.y) || std::max(c.y, d.y) + tol < std::min(a.y, b.y))
  {
    return Contact::None;
  }
  const bool sharedA = s.a == t.a || s.a == t.b;
  const bool sharedB = s.b == t.a || s.b == t.b;
  if (sharedA || sharedB)
  {
    // Two segments from one node meet only there, unless they run along each other.
    const Vec2 u = sharedA ? b : a;
    const int other = (t.a == (sharedA ? s.a : s.b)) ? t.b : t.a;
    const Vec2 w = P[other];
    const Vec2 x = P[sharedA ? s.a : s.b];
    if (dot(u - x, w - x) <= 0.0)
    {
      return Contact::None; // u and w are more than tol from x, on opposite sides
    }
    if (onSegment(u, c, d, tol))
    {
      where = u;
      return Contact::Overlap;
    }
    if (onSegment(w, a, b, tol))
    {
      where = w;
      return Contact::Overlap;
    }
    return Contact::None;
  }
  // Quick rejection: one segment lies on one side of the other's line, farther than tol.
  const double o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  const double o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  const double tol2 = tol * tol;
  const double ab2 = norm2(b - a), cd2 = norm2(d - c);
  if ((o1 * o2 > 0.0 && std::min(o1 * o1, o2 * o2) > tol2 * ab2) ||
    (o3 * o4 > 0.0 && std::min(o3 * o3, o4 * o4) > tol2 * cd2))
  {
    return Contact::None;
  }
  int touching = 0;
  for (const auto& [p, q0, q1] : { std::make_tuple(c, a, b),
         std::make_tuple(d, a, b),
         std::make_tuple(a, c, d),
         std::make_tuple(b, c, d) })
  {
    if (onSegment(p, q0, q1, tol))
    {
      if (touching++ == 0)
      {
        where = p;
      }
    }
  }
  if (touching)
  {
    return touching > 1 ? Contact::Overlap : Contact::Touch;
  }
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
  {
    where = a + (o3 / (o3 - o4)) * (b - a);
    return Contact::Cross;
  }
  return Contact::None;
}

/// Sorts (key, value) pairs by key: least significant digit radix sort, 11 bits a pass.
void radixSort(std::vector<std::pair<std::uint64_t, std::uint32_t>>& v)
{
  std::uint64_t maxKey = 0;
  for (const auto& e : v)
  {
    maxKey = std::max(maxKey, e.first);
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> tmp(v.size());
  for (int shift = 0; shift < 64 && (maxKey >> shift) != 0; shift += 11)
  {
    std::size_t count[2049] = {};
    for (const auto& e : v)
    {
      ++count[((e.first >> shift) & 2047) + 1];
    }
    for (int d = 0; d < 2048; ++d)
    {
      count[d + 1] += count[d];
    }
    for (const auto& e : v)
    {
      tmp[count[(e.first >> shift) & 2047]++] = e;
    }
    v.swap(tmp);
  }
}

struct Defect
{
  Contact contact = Contact::None;
  std::size_t s = 0, t = 0; ///< indices into the segment list, s < t
  Vec2 where;
};

/// Tests all pairs of the unique segments that share a grid cell; returns the defect of the
/// lowest (s, t) pair, or contact None.
Defect findContacts(const std::vector<Vec2>& P,
  const std::vector<Segment>& segs,
  const std::vector<std::size_t>& unique,
  const Box2& bounds,
  double tol)
{
  Defect best;
  if (unique.size() < 2)
  {
    return best;
  }
  double total = 0.0;
  for (std::size_t u : unique)
  {
    total += norm(P[segs[u].b] - P[segs[u].a]);
  }
  const double span = std::max(bounds.width(), bounds.height()) + 4.0 * tol;
  double h = total / static_cast<double>(unique.size());
  h = std::max({ h, 4.0 * tol, span / 1073741824.0 });
  if (!(h > 0.0))
  {
    h = 1.0;
  }
  const double inv = 1.0 / h;
  const Vec2 lo{ bounds.min.x - 2.0 * tol, bounds.min.y - 2.0 * tol };
  const double slack = 1e-9 * h + 1e-12 * span; // covers rounding of coordinates and indices
  auto index = [&](double v, double v0)
  { return static_cast<std::int64_t>(std::max(0.0, std::floor((v - v0) * inv))); };

  const auto columns = static_cast<std::uint64_t>(index(bounds.max.x + 3.0 * tol + h, lo.x)) + 1;

  // Rasterise: each segment goes into the grid cells its tol-neighbourhood may touch.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  entries.reserve(unique.size() * 3);
  for (std::size_t i = 0; i < unique.size(); ++i)
  {
    const Segment& sg = segs[unique[i]];
    const Vec2 a = P[sg.a], b = P[sg.b];
    const double y0 = std::min(a.y, b.y) - tol, y1 = std::max(a.y, b.y) + tol;
    const std::int64_t r0 = index(y0 - slack, lo.y), r1 = index(y1 + slack, lo.y);
    for (std::int64_t r = r0; r <= r1; ++r)
    {
      double xa, xb;
      // The part of the segment within tol of row r; the row is widened by 1% of h so that
      // rounding in the parameters below cannot lose a piece of a nearly horizontal segment.
      const double sy0 = std::max(y0, lo.y + (static_cast<double>(r) - 0.01) * h - tol);
      const double sy1 = std::min(y1, lo.y + (static_cast<double>(r) + 1.01) * h + tol);
      if (a.y == b.y || r0 == r1)
      {
        xa = std::min(a.x, b.x);
        xb = std::max(a.x, b.x);
      }
      else
      {
        const double ta = std::clamp((sy0 - a.y) / (b.y - a.y), 0.0, 1.0);
        const double tb = std::clamp((sy1 - a.y) / (b.y - a.y), 0.0, 1.0);
        const double x0 = a.x + ta * (b.x - a.x), x1 = a.x + tb * (b.x - a.x);
        xa = std::min(x0, x1);
        xb = std::max(x0, x1);
      }
      const std::int64_t c0 = index(xa - tol - slack, lo.x);
      const std::int64_t c1 =
        std::min(index(xb + tol + slack, lo.x), static_cast<std::int64_t>(columns) - 1);
      for (std::int64_t c = c0; c <= c1; ++c)
      {
        entries.emplace_back(
          static_cast<std::uint64_t>(r) * columns + static_cast<std::uint64_t>(c),
          static_cast<std::uint32_t>(i));
      }
    }
  }
  radixSort(entries);

  for (std::size_t g = 0; g < entries.size();)
  {
    std::size_t e = g + 1;
    while (e < entries.size() && entries[e].first == entries[g].first)
    {
      ++e;
    }
    for (std::size_t i = g; i < e; ++i)
    {
      const std::size_t si = unique[entries[i].second];
      for (std::size_t j = i + 1; j < e; ++j)
      {
        const std::size_t sj = unique[entries[j].second];
        const std::size_t s = std::min(si, sj), t = std::max(si, sj);
        if (best.contact != Contact::None && (s > best.s || (s == best.s && t >= best.t)))
        {
          continue;
        }
        Vec2 where;
        const Contact contact = testPair(P, segs[s], segs[t], tol, where);
        if (contact != Contact::None)
        {
          best.contact = contact;
          best.s = s;
          best.t = t;
          best.where = where;
        }
      }
    }
    g = e;
  }
  return best;
}

//------------------------------------------------------------------------------
// Rings.
double signedArea(const std::vector<Vec2>& pts)
{
  double sum = 0.0;
  const Vec2 o = pts.empty() ? Vec2{} : pts[0];
  for (std::size_t i = 1; i + 1 < pts.size(); ++i)
  {
    sum += cross(pts[i] - o, pts[i + 1] - o);
  }
  return 0.5 * sum;
}

/// Crossing-number point location among the rings of one region. The segments are bucketed in
/// horizontal rows, so that a query looks only at the segments of the row of the point.
class RegionLocator
{
public:
  explicit RegionLocator(const std::vector<Ring>& rings)
    : Rings(&rings)
  {
    Box2 box;
    std::size_t n = 0;
    double rise = 0.0;
    for (const Ring& ring : rings)
    {
      const std::size_t m = ring.points.size();
      for (std::size_t j = 0; j < m; ++j)
      {
        box.add(ring.points[j]);
        rise += std::abs(ring.points[(j + 1) % m].y - ring.points[j].y);
      }
      n += m;
    }
    // Rows: about 4 segments a row, but at most about 8 n bucket entries in all.
    const double height = box.height();
    double rows = std::max(1.0, static_cast<double>(n) / 4.0);
    if (rise > 0.0 && height > 0.0)
    {
      rows = std::min(rows, 8.0 * static_cast<double>(n) * height / rise);
    }
    this->Rows = static_cast<int>(std::clamp(rows, 1.0, 1048576.0));
    this->Y0 = box.min.y;
    this->InvH = height > 0.0 ? this->Rows / height : 0.0;
    groupIntoRows(static_cast<std::size_t>(this->Rows),
      this->Start,
      this->Entries,
      [&](auto&& emit)
      {
        for (std::size_t r = 0; r < rings.size(); ++r)
        {
          const std::vector<Vec2>& pts = rings[r].points;
          const std::size_t m = pts.size();
          for (std::size_t j = 0; j < m; ++j)
          {
            const Vec2 a = pts[j], b = pts[(j + 1) % m];
            const int r0 = this->row(std::min(a.y, b.y)), r1 = this->row(std::max(a.y, b.y));
            for (int w = r0; w <= r1; ++w)
            {
              emit(w, std::make_pair(static_cast<int>(r), static_cast<int>(j)));
            }
          }
        }
      });
  }

  /// Appends the ring of every segment that the ray from p towards +x crosses.
  void crossings(Vec2 p, std::vector<int>& out) const
  {
    const int w = this->row(p.y);
    for (std::size_t e = this->Start[w]; e < this->Start[w + 1]; ++e)
    {
      if (this->crosses(p, this->Entries[e]))
      {
        out.push_back(this->Entries[e].first);
      }
    }
  }

  /// Whether p is inside ring r (even-odd).
  bool inside(Vec2 p, int r) const
  {
    bool in = false;
    const int w = this->row(p.y);
    for (std::size_t e = this->Start[w]; e < this->Start[w + 1]; ++e)
    {
      if (this->Entries[e].first == r && this->crosses(p, this->Entries[e]))
      {
        in = !in;
      }
    }
    return in;
  }

private:
  int row(double y) const
  {
    const double f = std::floor((y - this->Y0) * this->InvH);
    return static_cast<int>(std::clamp(f, 0.0, static_cast<double>(this->Rows - 1)));
  }

  bool crosses(Vec2 p, std::pair<int, int> entry) const
  {
    const std::vector<Vec2>& pts = (*this->Rings)[entry.first].points;
    const Vec2 a = pts[entry.second], b = pts[(entry.second + 1) % pts.size()];
    return (a.y > p.y) != (b.y > p.y) && a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) > p.x;
  }

  const std::vector<Ring>* Rings;
  int Rows = 1;
  double Y0 = 0.0;
  double InvH = 0.0;
  std::vector<std::size_t> Start;
  std::vector<std::pair<int, int>> Entries; ///< (ring, segment) per row
};

void reverseRing(Ring& ring)
{
  // Keep the first point: q[i] = p[(n - i) % n]; segment j of q is segment n - 1 - j of p.
  std::reverse(ring.points.begin() + 1, ring.points.end());
  std::reverse(ring.nodes.begin() + 1, ring.nodes.end());
  std::reverse(ring.segmentCell.begin(), ring.segmentCell.end());
}

/// Orients the rings of a region by their even-odd depth. In the Shared curves form the traced
/// orientation must agree (throws otherwise).
void orientRings(Region& region, bool traced, Vec2 origin)
{
  std::vector<Ring>& rings = region.rings;
  const std::size_t k = rings.size();
  std::vector<int> depth(k, 0);
  if (k > 1)
  {
    std::vector<std::uint64_t> keys;
    std::vector<Box2> boxes(k);
    for (std::size_t i = 0; i < k; ++i)
    {
      const std::size_t n = rings[i].nodes.size();
      for (std::size_t j = 0; j < n; ++j)
      {
        keys.push_back(edgeKey(rings[i].nodes[j], rings[i].nodes[(j + 1) % n]));
        boxes[i].add(rings[i].points[j]);
      }
    }
    std::sort(keys.begin(), keys.end());
    const RegionLocator locator(rings);
    auto ringKeys = [&](std::size_t o)
    {
      const std::size_t n = rings[o].nodes.size();
      std::vector<std::uint64_t> own(n);
      for (std::size_t j = 0; j < n; ++j)
      {
        own[j] = edgeKey(rings[o].nodes[j], rings[o].nodes[(j + 1) % n]);
      }
      std::sort(own.begin(), own.end());
      return own;
    };
    auto midpoint = [&](const Ring& ring, std::size_t j)
    { return 0.5 * (ring.points[j] + ring.points[(j + 1) % ring.points.size()]); };
    std::vector<int> crossed;
    for (std::size_t i = 0; i < k; ++i)
    {
      // Test a segment midpoint that lies on no other ring of the region: the depth is the
      // number of other rings that the ray from it crosses an odd number of times.
      const Ring& ring = rings[i];
      const std::size_t n = ring.nodes.size();
      std::size_t pick = n;
      for (std::size_t j = 0; j < n && pick == n; ++j)
      {
        const auto range = std::equal_range(
          keys.begin(), keys.end(), edgeKey(ring.nodes[j], ring.nodes[(j + 1) % n]));
        pick = range.second - range.first == 1 ? j : n;
      }
      if (pick < n)
      {
        crossed.clear();
        locator.crossings(midpoint(ring, pick), crossed);
        std::sort(crossed.begin(), crossed.end());
        for (std::size_t c = 0; c < crossed.size();)
        {
          std::size_t e = c + 1;
          while (e < crossed.size() && crossed[e] == crossed[c])
          {
            ++e;
          }
          if (crossed[c] != static_cast<int>(i) && (e - c) % 2 == 1)
          {
            ++depth[i];
          }
          c = e;
        }
        continue;
      }
      // Every segment of this ring is also on other rings of the region (loops of one region
      // side by side): for each ring o that might contain it, test a segment o does not have.
      for (std::size_t o = 0; o < k; ++o)
      {
        const Box2& bi = boxes[i];
        const Box2& bo = boxes[o];
        if (o == i || bi.min.x < bo.min.x || bi.min.y < bo.min.y || bi.max.x > bo.max.x ||
          bi.max.y > bo.max.y)
        {
          continue; // ring i is not inside ring o's box, so not inside ring o
        }
        const std::vector<std::uint64_t> other = ringKeys(o);
        std::size_t j = 0;
        while (j < n &&
          std::binary_search(
            other.begin(), other.end(), edgeKey(ring.nodes[j], ring.nodes[(j + 1) % n])))
        {
          ++j;
        }
        if (j < n && locator.inside(midpoint(ring, j), static_cast<int>(o)))
        {
          ++depth[i];
        }
      }
    }
  }
  for (std::size_t i = 0; i < k; ++i)
  {
    Ring& ring = rings[i];
    const bool ccw = signedArea(ring.points) > 0.0;
    const bool even = depth[i] % 2 == 0;
    if (ccw == even)
    {
      continue;
    }
    if (traced)
    {
      const std::string where = pointText(ring.points[0] + origin);
      if (!ccw)
      {
        throw InputError("region " + std::to_string(region.id) +
          " is unbounded: the face outside the outer boundary through " + where + " (" +
          cellText(ring.segmentCell[0]) + ") is labelled " + std::to_string(region.id) +
          "; the exterior must be -1");
      }
      throw InputError("inconsistent region labels: the boundary of region " +
        std::to_string(region.id) + " through " + where + " (" + cellText(ring.segmentCell[0]) +
        ") lies inside another boundary of region " + std::to_string(region.id));
    }
    reverseRing(ring);
  }
}

//------------------------------------------------------------------------------
// Borders between two loops of one region (Loops form, step 4b). A segment that a region's
// loops have twice (one on each side: the same-side case is an error of step 8) is no border
// of it by the even-odd rule: a region given as pieces side by side (a country of provinces),
// or a hole that touches its outer loop along a border.
struct LoopSegment
{
  std::uint64_t key;
  int region;
  std::int64_t cell;
  bool operator<(const LoopSegment& o) const
  {
    return std::tie(key, region, cell) < std::tie(o.key, o.region, o.cell);
  }
};

/// Whether region `region` has the segment `key` an odd number of times (sorted `all`).
bool isLoopBorder(const std::vector<LoopSegment>& all, std::uint64_t key, int region)
{
  const auto lo = std::lower_bound(
    all.begin(), all.end(), LoopSegment{ key, region, std::numeric_limits<std::int64_t>::min() });
  std::size_t count = 0;
  for (auto it = lo; it != all.end() && it->key == key && it->region == region; ++it)
  {
    ++count;
  }
  return count % 2 == 1;
}

constexpr double kTwoPi = 6.283185307179586476925286766559;

/// Makes the rings of an oriented region again from its border segments alone, when some of
/// its segments are no border (isBorder(key) false): each border segment keeps its direction
/// (the region on its left), and a walk arriving at a node goes on with the first border
/// segment clockwise from the reversed incoming direction, so that rings touching at a node
/// are traced apart and every ring keeps the region on its left.
template<class IsBorder>
void keepBorders(Region& region,
  const std::vector<Vec2>& nodes,
  const Vec2 origin,
  const IsBorder& isBorder)
{
  struct Arc
  {
    int from;
    int to;
    std::int64_t cell;
  };
  std::vector<Arc> arcs;
  bool cancelled = false;
  for (const Ring& ring : region.rings)
  {
    const std::size_t n = ring.nodes.size();
    for (std::size_t j = 0; j < n; ++j)
    {
      const int a = ring.nodes[j], b = ring.nodes[(j + 1) % n];
      if (isBorder(edgeKey(a, b)))
      {
        arcs.push_back({ a, b, ring.segmentCell[j] });
      }
      else
      {
        cancelled = true;
      }
    }
  }
  if (!cancelled)
  {
    return;
  }
  std::vector<int> byFrom(arcs.size());
  for (std::size_t i = 0; i < arcs.size(); ++i)
  {
    byFrom[i] = static_cast<int>(i);
  }
  std::sort(
    byFrom.begin(), byFrom.end(), [&arcs](int x, int y) { return arcs[x].from < arcs[y].from; });
  std::vector<int> next(arcs.size(), -1);
  for (std::size_t i = 0; i < arcs.size(); ++i)
  {
    const int v = arcs[i].to;
    const Vec2 back = nodes[arcs[i].from] - nodes[v];
    auto it = std::lower_bound(
      byFrom.begin(), byFrom.end(), v, [&arcs](int x, int value) { return arcs[x].from < value; });
    double best = std::numeric_limits<double>::infinity();
    for (; it != byFrom.end() && arcs[*it].from == v; ++it)
    {
      const Vec2 d = nodes[arcs[*it].to] - nodes[v];
      const double ccw = std::atan2(cross(back, d), dot(back, d));
      const double cw = ccw > 0.0 ? kTwoPi - ccw : -ccw;
      if (cw > 0.0 && cw < best)
      {
        best = cw;
        next[i] = *it;
      }
    }
  }
  std::vector<char> used(arcs.size(), 0);
  std::vector<Ring> rings;
  for (std::size_t s = 0; s < arcs.size(); ++s)
  {
    if (used[s])
    {
      continue;
    }
    Ring ring;
    int a = static_cast<int>(s);
    while (a >= 0 && !used[a])
    {
      used[a] = 1;
      ring.nodes.push_back(arcs[a].from);
      ring.points.push_back(nodes[arcs[a].from]);
      ring.segmentCell.push_back(arcs[a].cell);
      a = next[a];
    }
    if (a != static_cast<int>(s))
    {
      throw InputError("the borders of region " + std::to_string(region.id) + " do not close at " +
        pointText(nodes[arcs[s].from] + origin) + " (" + cellText(arcs[s].cell) +
        ") once the segments between two of its loops are left out");
    }
    if (ring.nodes.size() >= 3)
    {
      rings.push_back(std::move(ring));
    }
  }
  region.rings = std::move(rings);
}

//------------------------------------------------------------------------------
// Overlapping regions (step 8). Throws when two regions share ground. A segment that one region
// has an even number of times (two of its loops side by side, a hole touching its outer loop)
// is no border of it (the even-odd rule); the others are, with the region on the left of its
// oriented ring. Two regions on one side of a segment overlap (loops of two regions given along
// the same border with both inside it), and so is one region twice on one side (a loop given
// twice). A border segment of one region inside another region that does not border it there
// is an overlap too (an island inside a region that has no hole for it: a Loops form region
// without the hole loop, or a Shared curves island whose outer side is labelled -1). That test
// is made at the midpoint of the first border segment of each ring and of each run of it
// between nodes of degree != 2: along such a run no other border comes near, so every region
// but those bordering the run contains all of it or none of it. A test point inside another
// region but within 1e-6 of the model's size of its border is let through (kOverlapNoise).
constexpr double kOverlapNoise = 1e-6;

void checkOverlaps(const Model& model, const std::vector<int>& degree, bool loops)
{
  struct Side
  {
    std::uint64_t key;
    int region; ///< index into model.regions
    bool left;  ///< the region lies left of the segment from its lower node id to its higher
    std::int64_t cell;
  };
  const auto segmentText = [&model](std::uint64_t key)
  {
    const auto a = static_cast<std::size_t>(key >> 32);
    const auto b = static_cast<std::size_t>(key & 0xffffffffu);
    return "the segment from " + pointText(model.nodes[a] + model.origin) + " to " +
      pointText(model.nodes[b] + model.origin);
  };
  // The Loops form's sides (the Shared curves form has one label per side by construction):
  // one entry per (segment, region) that the region has an odd number of times, its borders.
  // One region twice on one side is a loop given twice (two loops of a region side by side, or
  // a hole touching its outer loop, put it on both sides: by the even-odd rule, on neither).
  std::vector<Side> sides;
  std::vector<Side> borders;
  if (loops)
  {
    for (std::size_t r = 0; r < model.regions.size(); ++r)
    {
      for (const Ring& ring : model.regions[r].rings)
      {
        const std::size_t n = ring.nodes.size();
        for (std::size_t j = 0; j < n; ++j)
        {
          const int a = ring.nodes[j], b = ring.nodes[(j + 1) % n];
          sides.push_back({ edgeKey(a, b), static_cast<int>(r), a < b, ring.segmentCell[j] });
        }
      }
    }
    std::sort(sides.begin(),
      sides.end(),
      [](const Side& s, const Side& t)
      { return std::tie(s.key, s.region, s.left) < std::tie(t.key, t.region, t.left); });
    for (std::size_t i = 0; i < sides.size();)
    {
      std::size_t e = i + 1;
      while (e < sides.size() && sides[e].key == sides[i].key && sides[e].region == sides[i].region)
      {
        if (sides[e].left == sides[e - 1].left)
        {
          throw InputError(cellText(sides[e - 1].cell) + " and " + cellText(sides[e].cell) +
            " both put region " + std::to_string(model.regions[sides[i].region].id) +
            " on the same side of " + segmentText(sides[i].key) +
            ": a loop given twice cancels itself by the even-odd rule; give each loop once");
        }
        ++e;
      }
      if ((e - i) % 2 == 1)
      {
        if (!borders.empty() && borders.back().key == sides[i].key &&
          borders.back().left == sides[i].left)
        {
          const Side& s = borders.back();
          throw InputError("regions " + std::to_string(model.regions[s.region].id) + " and " +
            std::to_string(model.regions[sides[i].region].id) + " overlap: " + cellText(s.cell) +
            " and " + cellText(sides[i].cell) + " both put their region on the same side of " +
            segmentText(s.key) + "; each place belongs to one region");
        }
        borders.push_back(sides[i]);
      }
      i = e;
    }
  }
  if (model.regions.size() < 2)
  {
    return;
  }
  // The regions that have a segment (bordering it or, in the Loops form, cancelling it):
  // their parity at its midpoint is left out. In the Shared curves form, its curve's labels.
  std::vector<std::pair<int, int>> cellLabels;
  if (!loops)
  {
    for (const Curve& c : model.curves)
    {
      const auto cell = static_cast<std::size_t>(c.sourceCell);
      if (cellLabels.size() <= cell)
      {
        cellLabels.resize(cell + 1, { -1, -1 });
      }
      cellLabels[cell] = { model.regionIndex(c.left), model.regionIndex(c.right) };
    }
  }
  // The test points: the midpoint of the first border segment of each ring and of each run of
  // it between nodes of degree != 2.
  struct Test
  {
    Vec2 m;
    int region;
    std::uint64_t key;
    std::int64_t cell;
  };
  std::vector<Test> tests;
  for (std::size_t r = 0; r < model.regions.size(); ++r)
  {
    for (const Ring& ring : model.regions[r].rings)
    {
      const std::size_t n = ring.nodes.size();
      bool runStart = true;
      for (std::size_t j = 0; j < n; ++j)
      {
        runStart = runStart || degree[ring.nodes[j]] != 2;
        const std::uint64_t key = edgeKey(ring.nodes[j], ring.nodes[(j + 1) % n]);
        if (!runStart)
        {
          continue;
        }
        if (loops)
        {
          const auto it = std::lower_bound(borders.begin(),
            borders.end(),
            std::make_pair(key, static_cast<int>(r)),
            [](const Side& s, const std::pair<std::uint64_t, int>& k)
            { return std::make_pair(s.key, s.region) < k; });
          if (it == borders.end() || it->key != key || it->region != static_cast<int>(r))
          {
            continue; // no border of this region
          }
        }
        runStart = false;
        tests.push_back({ 0.5 * (ring.points[j] + ring.points[(j + 1) % n]),
          static_cast<int>(r),
          key,
          ring.segmentCell[j] });
      }
    }
  }
  // One sweep over every ring segment: the rays from the test points towards +x that it
  // crosses (the test points sorted by y; a segment is crossed by the points whose y lies in
  // [its lower y, its upper y)), each crossing noted as (test, ring).
  std::vector<int> byY(tests.size());
  for (std::size_t t = 0; t < tests.size(); ++t)
  {
    byY[t] = static_cast<int>(t);
  }
  std::sort(byY.begin(), byY.end(), [&tests](int x, int y) { return tests[x].m.y < tests[y].m.y; });
  std::vector<std::pair<int, int>> crossings; // (test, ring)
  std::vector<int> ringRegion;
  std::vector<std::int64_t> ringCell;
  for (std::size_t r = 0; r < model.regions.size(); ++r)
  {
    for (const Ring& ring : model.regions[r].rings)
    {
      const int index = static_cast<int>(ringRegion.size());
      ringRegion.push_back(static_cast<int>(r));
      ringCell.push_back(ring.segmentCell[0]);
      const std::size_t n = ring.points.size();
      for (std::size_t j = 0; j < n; ++j)
      {
        const Vec2 a = ring.points[j], b = ring.points[(j + 1) % n];
        const double lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
        auto it = std::lower_bound(
          byY.begin(), byY.end(), lo, [&tests](int t, double y) { return tests[t].m.y < y; });
        for (; it != byY.end() && tests[*it].m.y < hi; ++it)
        {
          const Vec2 p = tests[*it].m;
          if ((a.y > p.y) != (b.y > p.y) && a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) > p.x)
          {
            crossings.emplace_back(*it, index);
          }
        }
      }
    }
  }
  std::sort(crossings.begin(), crossings.end());
  std::vector<int> parity(model.regions.size(), 0);
  for (std::size_t i = 0; i < crossings.size();)
  {
    const Test& test = tests[crossings[i].first];
    std::size_t e = i;
    for (; e < crossings.size() && crossings[e].first == crossings[i].first; ++e)
    {
      parity[ringRegion[crossings[e].second]] ^= 1;
    }
    parity[test.region] = 0;
    if (loops)
    {
      const auto lo = std::lower_bound(sides.begin(),
        sides.end(),
        test.key,
        [](const Side& s, std::uint64_t k) { return s.key < k; });
      for (auto it = lo; it != sides.end() && it->key == test.key; ++it)
      {
        parity[it->region] = 0;
      }
    }
    else if (static_cast<std::size_t>(test.cell) < cellLabels.size())
    {
      for (const int q : { cellLabels[test.cell].first, cellLabels[test.cell].second })
      {
        if (q >= 0)
        {
          parity[q] = 0;
        }
      }
    }
    // A region the test point lies inside (its parity odd) overlaps the test's region, unless
    // the overlap is thinner than kOverlapNoise of the model's size there: rounding or
    // digitizing noise between two neighbours' copies of a border (far thinner than any
    // triangle), which the mesh cannot show either way.
    int over = -1;
    for (std::size_t k = i; k < e; ++k)
    {
      const int ring = crossings[k].second;
      const int q = ringRegion[ring];
      if (over < 0 && parity[q] != 0)
      {
        double nearest = std::numeric_limits<double>::infinity();
        for (const Ring& other : model.regions[q].rings)
        {
          const std::size_t n = other.points.size();
          for (std::size_t j = 0; j < n; ++j)
          {
            nearest = std::min(
              nearest, pointSegmentDistance2(test.m, other.points[j], other.points[(j + 1) % n]));
          }
        }
        over = std::sqrt(nearest) < kOverlapNoise * model.size() ? -1 : ring;
      }
      parity[q] = 0;
    }
    if (over >= 0)
    {
      const int id = model.regions[test.region].id;
      const int q = model.regions[ringRegion[over]].id;
      throw InputError("regions " + std::to_string(id) + " and " + std::to_string(q) +
        " overlap: the border of region " + std::to_string(id) + " at " +
        pointText(test.m + model.origin) + " (" + cellText(test.cell) + ") lies inside region " +
        std::to_string(q) + " (" + cellText(ringCell[over]) + ")" +
        (loops ? "; in the Loops form a region around another needs a loop around the hole "
                 "too (the even-odd rule)"
               : "; in the Shared curves form a curve inside region " + std::to_string(q) +
              " has " + std::to_string(q) + " on that side, not -1"));
    }
    i = e;
  }
}

//------------------------------------------------------------------------------
// Face tracing of the Shared curves form. Returns rings per region id.
std::map<int, std::vector<Ring>> traceFaces(const Model& model, const std::vector<int>& degree)
{
  const std::vector<Vec2>& P = model.nodes;
  // Pieces: runs of a curve between nodes of degree != 2 (both ends included).
  std::vector<int> pieceNodes;
  std::vector<std::size_t> pieceStart{ 0 };
  std::vector<int> pieceCurve;
  for (std::size_t ci = 0; ci < model.curves.size(); ++ci)
  {
    const std::vector<int>& q = model.curves[ci].nodes;
    const std::size_t m = q.size();
    auto close = [&]()
    {
      pieceStart.push_back(pieceNodes.size());
      pieceCurve.push_back(static_cast<int>(ci));
    };
    if (!model.curves[ci].closed)
    {
      pieceNodes.push_back(q[0]);
      for (std::size_t k = 1; k < m; ++k)
      {
        pieceNodes.push_back(q[k]);
        if (k + 1 == m || degree[q[k]] != 2)
        {
          close();
          if (k + 1 < m)
          {
            pieceNodes.push_back(q[k]);
          }
        }
      }
      continue;
    }
    std::size_t s = 0;
    while (s < m && degree[q[s]] == 2)
    {
      ++s;
    }
    s = s == m ? 0 : s;
    pieceNodes.push_back(q[s]);
    for (std::size_t j = 1; j <= m; ++j)
    {
      const int v = q[(s + j) % m];
      pieceNodes.push_back(v);
      if (j == m || degree[v] != 2)
      {
        close();
        if (j < m)
        {
          pieceNodes.push_back(v);
        }
      }
    }
  }

  // Half-curves h = 2 * piece + (0 forward, 1 reversed).
  const std::size_t halves = 2 * pieceCurve.size();
  auto first = [&](std::size_t h)
  {
    const std::size_t p = h / 2;
    return (h & 1) ? pieceNodes[pieceStart[p + 1] - 1] : pieceNodes[pieceStart[p]];
  };
  auto second = [&](std::size_t h)
  {
    const std::size_t p = h / 2;
    return (h & 1) ? pieceNodes[pieceStart[p + 1] - 2] : pieceNodes[pieceStart[p] + 1];
  };
  auto label = [&](std::size_t h)
  {
    const Curve& c = model.curves[pieceCurve[h / 2]];
    return (h & 1) ? c.right : c.left;
  };
  auto cell = [&](std::size_t h) { return model.curves[pieceCurve[h / 2]].sourceCell; };

  // Outgoing half-curves of every node, counter-clockwise by the direction of the first segment.
  std::vector<std::size_t> nodeStart, out;
  groupIntoRows(P.size(),
    nodeStart,
    out,
    [&](auto&& emit)
    {
      for (std::size_t h = 0; h < halves; ++h)
      {
        emit(first(h), h);
      }
    });
  auto upper = [](Vec2 d) { return d.y > 0 || (d.y == 0 && d.x > 0); };
  std::vector<std::size_t> position(halves);
  for (std::size_t v = 0; v < P.size(); ++v)
  {
    const auto b = out.begin() + nodeStart[v], e = out.begin() + nodeStart[v + 1];
    if (e - b > 1)
    {
      std::sort(b,
        e,
        [&](std::size_t g, std::size_t h)
        {
          const Vec2 u = P[second(g)] - P[first(g)], w = P[second(h)] - P[first(h)];
          if (upper(u) != upper(w))
          {
            return upper(u);
          }
          return cross(u, w) > 0;
        });
    }
    for (std::size_t i = nodeStart[v]; i < nodeStart[v + 1]; ++i)
    {
      position[out[i]] = i - nodeStart[v];
    }
  }
  auto next = [&](std::size_t h)
  {
    const std::size_t twin = h ^ 1;
    const int v = first(twin);
    const std::size_t deg = nodeStart[v + 1] - nodeStart[v];
    return out[nodeStart[v] + (position[twin] + deg - 1) % deg];
  };

  std::map<int, std::vector<Ring>> rings;
  std::vector<char> visited(halves, 0);
  std::vector<std::size_t> cycle;
  for (std::size_t h0 = 0; h0 < halves; ++h0)
  {
    if (visited[h0])
    {
      continue;
    }
    cycle.clear();
    for (std::size_t h = h0; !visited[h]; h = next(h))
    {
      visited[h] = 1;
      cycle.push_back(h);
    }
    for (std::size_t i = 1; i < cycle.size(); ++i)
    {
      if (label(cycle[i]) != label(cycle[i - 1]))
      {
        throw InputError("inconsistent region labels: " + cellText(cell(cycle[i - 1])) +
          " says region " + std::to_string(label(cycle[i - 1])) + " and " +
          cellText(cell(cycle[i])) + " says region " + std::to_string(label(cycle[i])) +
          " for the same face (near " + pointText(P[first(cycle[i])] + model.origin) + ")");
      }
    }
    const int id = label(h0);
    if (id < 0)
    {
      continue;
    }
    Ring ring;
    for (std::size_t h : cycle)
    {
      const std::size_t p = h / 2;
      const std::size_t b = pieceStart[p], e = pieceStart[p + 1];
      const std::int64_t c = cell(h);
      for (std::size_t j = 0; j + 1 < e - b; ++j)
      {
        const int v = (h & 1) ? pieceNodes[e - 1 - j] : pieceNodes[b + j];
        ring.nodes.push_back(v);
        ring.points.push_back(P[v]);
        ring.segmentCell.push_back(c);
      }
    }
    rings[id].push_back(std::move(ring));
  }
  return rings;
}

} // namespace

//------------------------------------------------------------------------------
int Model::regionIndex(int id) const
{
  const auto it = std::lower_bound(this->regions.begin(),
    this->regions.end(),
    id,
    [](const Region& r, int value) { return r.id < value; });
  return (it != this->regions.end() && it->id == id) ? static_cast<int>(it - this->regions.begin())
                                                     : -1;
}

//------------------------------------------------------------------------------
double Model::size() const
{
  const double d = this->bounds.diagonal();
  return this->empty() || !(d > 0.0) ? 1.0 : d;
}

//------------------------------------------------------------------------------
namespace
{

Model buildModelChecked(const RawPolylines& input, const ModelParams& params)
{
  if (!(params.mergeTolerance >= 0.0 && params.mergeTolerance <= 1e-3))
  {
    throw ParameterError(
      "mergeTolerance = " + num(params.mergeTolerance) + " is outside its range [0, 1e-3]");
  }

  Model model;
  Warnings warnings;
  const std::size_t nCells = input.numberOfCells();
  const std::size_t nPoints = input.points.size();

  // --- Form and array sizes.
  const bool hasShared = !input.leftRegion.empty() || !input.rightRegion.empty();
  ModelForm form = input.form;
  if (form == ModelForm::Auto)
  {
    if (!input.leftRegion.empty() && !input.rightRegion.empty())
    {
      form = ModelForm::SharedCurves;
    }
    else if (!input.regionId.empty())
    {
      form = ModelForm::Loops;
    }
    else if (nCells > 0 && hasShared)
    {
      throw InputError(std::string("the Shared curves form needs both LeftRegion and RightRegion "
                                   "cell arrays, but only ") +
        (input.leftRegion.empty() ? "RightRegion" : "LeftRegion") + " was given");
    }
    else if (nCells > 0)
    {
      throw InputError("no region arrays: the input needs a RegionId cell array (Loops form) or "
                       "LeftRegion and RightRegion cell arrays (Shared curves form)");
    }
    else
    {
      form = ModelForm::Loops;
    }
  }
  model.form = form;
  if (nCells == 0)
  {
    model.warnings.push_back("empty input: no cells");
    return model;
  }

  if (input.offsets.front() < 0 ||
    input.offsets.back() > static_cast<std::int64_t>(input.connectivity.size()))
  {
    throw InputError("cell offsets out of range: they span [" +
      std::to_string(input.offsets.front()) + ", " + std::to_string(input.offsets.back()) +
      ") but the connectivity has " + std::to_string(input.connectivity.size()) + " entries");
  }
  for (std::size_t c = 0; c < nCells; ++c)
  {
    if (input.offsets[c + 1] < input.offsets[c])
    {
      throw InputError(cellText(static_cast<std::int64_t>(c)) + " has a negative size (offsets " +
        std::to_string(input.offsets[c]) + " then " + std::to_string(input.offsets[c + 1]) + ")");
    }
  }
  if (!input.kinds.empty() && input.kinds.size() != nCells)
  {
    throw InputError("the cell kinds have " + std::to_string(input.kinds.size()) +
      " values but the input has " + std::to_string(nCells) + " cells");
  }
  if (nPoints >= static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
    input.connectivity.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max()))
  {
    throw InputError("the input is too large: at most 2^31 - 1 points and connectivity entries");
  }
  auto checkSize = [&](const std::vector<int>& values, const char* name)
  {
    if (values.empty())
    {
      const std::string formName =
        form == ModelForm::Loops ? "the Loops form" : "the Shared curves form";
      throw InputError(formName + " needs a " + name + " cell array, but there is none");
    }
    if (values.size() != nCells)
    {
      throw InputError(std::string(name) + " has " + std::to_string(values.size()) +
        " values but the input has " + std::to_string(nCells) + " cells");
    }
  };
  const bool loops = form == ModelForm::Loops;
  if (loops)
  {
    checkSize(input.regionId, "RegionId");
  }
  else
  {
    checkSize(input.leftRegion, "LeftRegion");
    checkSize(input.rightRegion, "RightRegion");
  }

  // --- 1. Classify the cells.
  std::vector<std::size_t> candidates;
  Box2 inputBox;
  for (std::size_t c = 0; c < nCells; ++c)
  {
    const auto cid = static_cast<std::int64_t>(c);
    const CellKind kind = input.kinds.empty() ? CellKind::Line : input.kinds[c];
    if (kind == CellKind::Other)
    {
      warnings.add(NotLineCell,
        cellText(cid) + " is not a line cell (StrataMesh reads VTK_LINE / VTK_POLY_LINE): ignored");
      continue;
    }
    if (kind == CellKind::Polygon && !loops)
    {
      warnings.add(PolygonIgnored,
        cellText(cid) +
          " is a polygon cell; the Shared curves form reads line cells only: ignored");
      continue;
    }
    const std::int64_t begin = input.offsets[c], end = input.offsets[c + 1];
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::int64_t id = input.connectivity[i];
      if (id < 0 || id >= static_cast<std::int64_t>(nPoints))
      {
        throw InputError(cellText(cid) + " refers to point " + std::to_string(id) +
          ", but the input has " + std::to_string(nPoints) + " points");
      }
    }
    if (loops)
    {
      const int r = input.regionId[c];
      if (r < -1)
      {
        throw InputError(cellText(cid) + " has RegionId " + std::to_string(r) +
          " (region ids are >= 0, and -1 is the exterior)");
      }
      if (r == -1)
      {
        warnings.add(ExteriorLoop, cellText(cid) + " is a loop of region -1 (exterior): ignored");
        continue;
      }
    }
    else
    {
      const int l = input.leftRegion[c], r = input.rightRegion[c];
      for (const auto& [value, name] :
        { std::make_pair(l, "LeftRegion"), std::make_pair(r, "RightRegion") })
      {
        if (value < -1)
        {
          throw InputError(cellText(cid) + " has " + name + " " + std::to_string(value) +
            " (region ids are >= 0, and -1 is the exterior)");
        }
      }
      if (l == r)
      {
        warnings.add(SameRegionBothSides,
          cellText(cid) + " has region " + std::to_string(l) +
            " on both sides (LeftRegion = RightRegion): it bounds nothing, ignored");
        continue;
      }
    }
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::int64_t id = input.connectivity[i];
      const Vec2 p = input.points[id];
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
      {
        const bool badX = !std::isfinite(p.x);
        throw InputError("point " + std::to_string(id) + " (" + cellText(cid) +
          ") has a non-finite coordinate " + (badX ? "x = " : "y = ") + num(badX ? p.x : p.y));
      }
      inputBox.add(p);
    }
    if (kind == CellKind::Polygon)
    {
      warnings.add(PolygonAsLoop, cellText(cid) + " is a polygon cell: read as a closed loop");
    }
    candidates.push_back(c);
  }
  const std::string noLines = "no usable line cells (StrataMesh reads VTK_LINE / VTK_POLY_LINE "
                              "cells)";
  if (candidates.empty())
  {
    throw InputError(noLines + ": " + warnings.brief());
  }

  // --- 2. Local frame and tolerance.
  model.origin = inputBox.center();
  const double diagonal = inputBox.diagonal();
  const double tol = params.mergeTolerance * diagonal;
  auto local = [&](std::int64_t id) { return input.points[id] - model.origin; };
  const Box2 localBox{ inputBox.min - model.origin, inputBox.max - model.origin };

  // --- 3. Nodes and cleaned curves.
  double edgeSum = 0.0;
  std::size_t edgeCount = 0, references = 0;
  for (std::size_t c : candidates)
  {
    references += static_cast<std::size_t>(input.offsets[c + 1] - input.offsets[c]);
    for (std::int64_t i = input.offsets[c] + 1; i < input.offsets[c + 1]; ++i)
    {
      const double d = norm(local(input.connectivity[i]) - local(input.connectivity[i - 1]));
      if (d > 0.0)
      {
        edgeSum += d;
        ++edgeCount;
      }
    }
  }
  const double span = std::max(localBox.width(), localBox.height());
  double cellSize = edgeCount ? edgeSum / static_cast<double>(edgeCount) : span;
  cellSize = std::max({ cellSize, 4.0 * tol, span / 1073741824.0 });
  if (!(cellSize > 0.0))
  {
    cellSize = 1.0;
  }
  NodeMerger merger(localBox.min, cellSize, tol, references);

  std::vector<CurveInfo> infos;
  std::vector<int> path;
  for (std::size_t c : candidates)
  {
    const auto cid = static_cast<std::int64_t>(c);
    const std::int64_t begin = input.offsets[c], end = input.offsets[c + 1];
    const bool polygon = !input.kinds.empty() && input.kinds[c] == CellKind::Polygon;
    path.clear();
    std::size_t repeated = 0;
    for (std::int64_t i = begin; i < end; ++i)
    {
      const int n = merger.insert(local(input.connectivity[i]));
      if (!path.empty() && path.back() == n)
      {
        ++repeated;
        continue;
      }
      path.push_back(n);
    }
    const std::int64_t count = end - begin;
    if (path.size() < 2)
    {
      warnings.add(DegenerateCell,
        count == 0     ? cellText(cid) + " has no points: ignored"
          : count == 1 ? cellText(cid) + " has only one point: ignored"
                       : cellText(cid) + " has zero length (its " + std::to_string(count) +
            " points coincide): ignored");
      continue;
    }
    if (repeated)
    {
      warnings.add(RepeatedPoints,
        cellText(cid) + ": dropped " + std::to_string(repeated) + " repeated consecutive point" +
          (repeated > 1 ? "s" : ""));
    }
    CurveInfo info;
    bool closed = false;
    if (path.front() == path.back())
    {
      path.pop_back();
      closed = true;
    }
    else if (loops)
    {
      closed = true;
      info.impliedClosing = true;
      info.first = input.points[input.connectivity[begin]];
      info.last = input.points[input.connectivity[end - 1]];
      info.gap = norm(local(input.connectivity[end - 1]) - local(input.connectivity[begin]));
    }
    if (closed)
    {
      // At least 3 distinct nodes.
      std::size_t second = 1;
      while (second < path.size() && path[second] == path[0])
      {
        ++second;
      }
      bool third = false;
      for (std::size_t k = second + 1; k < path.size() && !third; ++k)
      {
        third = path[k] != path[0] && path[k] != path[second];
      }
      if (!third)
      {
        warnings.add(ShortLoop,
          cellText(cid) + (loops ? " is a loop" : " is a closed curve") +
            " with fewer than 3 distinct points: ignored");
        continue;
      }
    }
    if (info.impliedClosing && !polygon)
    {
      warnings.add(ImpliedClosing,
        cellText(cid) + ": loop closed by joining its last point " + pointText(info.last) +
          " to its first point " + pointText(info.first) + " (gap " + shortNum(info.gap) + ")");
    }
    Curve curve;
    curve.nodes = path;
    curve.closed = closed;
    curve.left = loops ? input.regionId[c] : input.leftRegion[c];
    curve.right = loops ? -1 : input.rightRegion[c];
    curve.sourceCell = cid;
    model.curves.push_back(std::move(curve));
    infos.push_back(info);
  }
  if (model.curves.empty())
  {
    throw InputError(noLines + ": " + warnings.brief());
  }

  // Keep the nodes that kept curves use, numbered in order of first use.
  {
    std::vector<int> renumber(merger.Nodes.size(), -1);
    for (Curve& curve : model.curves)
    {
      for (int& n : curve.nodes)
      {
        if (renumber[n] < 0)
        {
          renumber[n] = static_cast<int>(model.nodes.size());
          model.nodes.push_back(merger.Nodes[n]);
        }
        n = renumber[n];
      }
      curve.points.reserve(curve.nodes.size());
      for (int n : curve.nodes)
      {
        curve.points.push_back(model.nodes[n]);
        model.bounds.add(model.nodes[n]);
      }
    }
  }

  // --- 4. Segments, deduplicated, and the crossing check.
  std::vector<Segment> segs;
  for (std::size_t ci = 0; ci < model.curves.size(); ++ci)
  {
    const Curve& curve = model.curves[ci];
    const std::size_t m = curve.nodes.size();
    const std::size_t ns = curve.closed ? m : m - 1;
    for (std::size_t k = 0; k < ns; ++k)
    {
      segs.push_back(
        { curve.nodes[k], curve.nodes[(k + 1) % m], static_cast<int>(ci), static_cast<int>(k) });
    }
  }
  std::vector<std::size_t> unique;
  {
    // Bucket the segments by their lower node (counting sort, stable), then compare the higher
    // nodes within a bucket; the first of equal segments is kept.
    std::vector<std::size_t> start, byLow;
    groupIntoRows(model.nodes.size(),
      start,
      byLow,
      [&](auto&& emit)
      {
        for (std::size_t s = 0; s < segs.size(); ++s)
        {
          emit(std::min(segs[s].a, segs[s].b), s);
        }
      });
    auto high = [&](std::size_t s) { return std::max(segs[s].a, segs[s].b); };
    std::vector<char> keep(segs.size(), 1);
    for (std::size_t v = 0; v < model.nodes.size(); ++v)
    {
      if (start[v + 1] - start[v] < 2)
      {
        continue;
      }
      const auto b = byLow.begin() + start[v], e = byLow.begin() + start[v + 1];
      std::sort(b,
        e,
        [&](std::size_t s, std::size_t t)
        { return high(s) != high(t) ? high(s) < high(t) : s < t; });
      for (auto it = b + 1; it != e; ++it)
      {
        if (high(*it) != high(*(it - 1)))
        {
          continue;
        }
        keep[*it] = 0;
        if (!loops)
        {
          const Segment& s = segs[*(it - 1)];
          const Segment& t = segs[*it];
          const std::int64_t cs = model.curves[s.curve].sourceCell;
          const std::int64_t ct = model.curves[t.curve].sourceCell;
          const std::string along = "the segment from " +
            pointText(model.nodes[s.a] + model.origin) + " to " +
            pointText(model.nodes[s.b] + model.origin);
          throw InputError((cs == ct ? cellText(cs) + " runs twice along " + along
                                     : cellText(cs) + " and " + cellText(ct) + " both run along " +
                along + ": in the Shared curves form each border is given once"));
        }
      }
    }
    unique.reserve(segs.size());
    for (std::size_t s = 0; s < segs.size(); ++s)
    {
      if (keep[s])
      {
        unique.push_back(s);
      }
    }
  }

  const Defect defect = findContacts(model.nodes, segs, unique, model.bounds, tol);
  if (defect.contact != Contact::None)
  {
    const Segment& s = segs[defect.s];
    const Segment& t = segs[defect.t];
    const std::int64_t cs = model.curves[s.curve].sourceCell;
    const std::int64_t ct = model.curves[t.curve].sourceCell;
    const std::string at = pointText(defect.where + model.origin);
    auto isClosing = [&](const Segment& g)
    {
      return infos[g.curve].impliedClosing &&
        static_cast<std::size_t>(g.k) + 1 == model.curves[g.curve].nodes.size();
    };
    const bool closingS = isClosing(s), closingT = isClosing(t);
    if (closingS || closingT)
    {
      const Segment& closing = closingS ? s : t;
      const Segment& other = closingS ? t : s;
      const CurveInfo& info = infos[closing.curve];
      const char* verb = defect.contact == Contact::Cross ? "crosses"
        : defect.contact == Contact::Touch                ? "touches"
                                                          : "overlaps";
      throw InputError("loop of " + cellText(model.curves[closing.curve].sourceCell) +
        " does not close (gap " + shortNum(info.gap) + " between its first point " +
        pointText(info.first) + " and last point " + pointText(info.last) + "); its closing edge " +
        verb + " " + cellText(model.curves[other.curve].sourceCell) + " at " + at);
    }
    if (cs == ct)
    {
      throw InputError(cellText(cs) + " intersects itself at " + at);
    }
    const char* verb = defect.contact == Contact::Cross ? "cross"
      : defect.contact == Contact::Touch                ? "touch"
                                                        : "overlap";
    throw InputError(cellText(cs) + " and " + cellText(ct) + " " + verb + " at " + at +
      " without a shared vertex");
  }

  // --- 4b. Borders between two loops of one region (Loops form): no border of it, and of no
  // region when every region that has the segment has it twice ("dead": left out of the
  // junctions and of the curves, below).
  std::vector<LoopSegment> loopSegments;
  std::vector<std::uint64_t> dead;
  if (loops)
  {
    loopSegments.reserve(segs.size());
    for (const Segment& g : segs)
    {
      const Curve& c = model.curves[g.curve];
      loopSegments.push_back({ edgeKey(g.a, g.b), c.left, c.sourceCell });
    }
    std::sort(loopSegments.begin(), loopSegments.end());
    std::map<int, std::pair<std::size_t, std::size_t>> deadOf; // region -> (count, first index)
    for (std::size_t i = 0; i < loopSegments.size();)
    {
      std::size_t e = i;
      bool odd = false;
      while (e < loopSegments.size() && loopSegments[e].key == loopSegments[i].key)
      {
        std::size_t f = e;
        while (f < loopSegments.size() && loopSegments[f].key == loopSegments[e].key &&
          loopSegments[f].region == loopSegments[e].region)
        {
          ++f;
        }
        odd = odd || (f - e) % 2 == 1;
        e = f;
      }
      if (!odd)
      {
        dead.push_back(loopSegments[i].key);
        ++deadOf.emplace(loopSegments[i].region, std::make_pair(std::size_t(0), i))
            .first->second.first;
      }
      i = e;
    }
    for (const auto& [region, entry] : deadOf)
    {
      const LoopSegment& g = loopSegments[entry.second];
      const LoopSegment& h = loopSegments[entry.second + 1];
      const auto a = static_cast<std::size_t>(g.key >> 32);
      const auto b = static_cast<std::size_t>(g.key & 0xffffffffu);
      warnings.add(CancelledBorder,
        "region " + std::to_string(region) + ": " + std::to_string(entry.first) +
          (entry.first == 1 ? " segment has" : " segments have") +
          " the region on both sides (the first from " + pointText(model.nodes[a] + model.origin) +
          " to " + pointText(model.nodes[b] + model.origin) +
          (g.cell == h.cell ? ", where " + cellText(g.cell) + " runs back along itself"
                            : ", between " + cellText(g.cell) + " and " + cellText(h.cell)) +
          "): by the even-odd rule no border, so the mesh does not follow it");
    }
  }
  const auto isDead = [&dead](std::uint64_t key)
  { return !dead.empty() && std::binary_search(dead.begin(), dead.end(), key); };

  // --- Degrees and junctions.
  std::vector<int> degree(model.nodes.size(), 0);
  for (std::size_t u : unique)
  {
    if (isDead(edgeKey(segs[u].a, segs[u].b)))
    {
      continue;
    }
    ++degree[segs[u].a];
    ++degree[segs[u].b];
  }
  for (std::size_t v = 0; v < degree.size(); ++v)
  {
    if (degree[v] != 2 && degree[v] != 0) // (0: a node only dead segments reach)
    {
      model.junctions.push_back(static_cast<int>(v));
    }
  }

  // --- 5. Regions.
  std::map<int, std::vector<Ring>> rings;
  if (loops)
  {
    for (const Curve& curve : model.curves)
    {
      Ring ring;
      ring.points = curve.points;
      ring.nodes = curve.nodes;
      ring.segmentCell.assign(curve.nodes.size(), curve.sourceCell);
      rings[curve.left].push_back(std::move(ring));
    }
  }
  else
  {
    for (const Curve& curve : model.curves)
    {
      if (curve.closed)
      {
        continue;
      }
      for (int end : { curve.nodes.front(), curve.nodes.back() })
      {
        if (degree[end] != 1)
        {
          continue;
        }
        std::string open;
        if (curve.left >= 0 && curve.right >= 0)
        {
          open = "regions " + std::to_string(curve.left) + " and " + std::to_string(curve.right) +
            " are not closed";
        }
        else
        {
          open = "region " + std::to_string(std::max(curve.left, curve.right)) + " is not closed";
        }
        throw InputError("dangling curve end at " + pointText(model.nodes[end] + model.origin) +
          " (end of " + cellText(curve.sourceCell) + "): " + open);
      }
    }
    rings = traceFaces(model, degree);
  }

  // --- 6. Orientation and bounds.
  for (auto& [id, list] : rings)
  {
    Region region;
    region.id = id;
    region.rings = std::move(list);
    orientRings(region, !loops, model.origin);
    for (const Ring& ring : region.rings)
    {
      for (const Vec2& p : ring.points)
      {
        region.bounds.add(p);
      }
    }
    model.regions.push_back(std::move(region));
  }

  // --- 8. Overlaps.
  checkOverlaps(model, degree, loops);

  // --- 4b, continued: each region's rings without the segments between two of its loops, and
  // the curves without the dead segments.
  if (loops)
  {
    for (Region& region : model.regions)
    {
      keepBorders(region,
        model.nodes,
        model.origin,
        [&](std::uint64_t key) { return isLoopBorder(loopSegments, key, region.id); });
    }
  }
  if (!dead.empty())
  {
    std::vector<Curve> curves;
    for (Curve& c : model.curves)
    {
      const std::size_t n = c.nodes.size();
      const std::size_t ns = c.closed ? n : n - 1;
      std::size_t start = ns;
      for (std::size_t k = 0; k < ns && start == ns; ++k)
      {
        start = isDead(edgeKey(c.nodes[k], c.nodes[(k + 1) % n])) ? k : ns;
      }
      if (start == ns)
      {
        curves.push_back(std::move(c));
        continue;
      }
      // The runs of live segments, from the one after the first dead segment on.
      Curve run;
      const auto flush = [&]()
      {
        if (run.nodes.size() >= 2)
        {
          run.closed = false;
          run.left = c.left;
          run.right = c.right;
          run.sourceCell = c.sourceCell;
          curves.push_back(std::move(run));
        }
        run = Curve();
      };
      for (std::size_t i = 1; i <= ns; ++i)
      {
        const std::size_t k = c.closed ? (start + i) % ns : start + i;
        if (k >= ns)
        {
          break;
        }
        const std::size_t k1 = (k + 1) % n;
        if (isDead(edgeKey(c.nodes[k], c.nodes[k1])))
        {
          flush();
          continue;
        }
        if (run.nodes.empty())
        {
          run.nodes.push_back(c.nodes[k]);
          run.points.push_back(c.points[k]);
        }
        run.nodes.push_back(c.nodes[k1]);
        run.points.push_back(c.points[k1]);
      }
      flush();
      if (!c.closed)
      {
        // (an open curve: its run before the first dead segment too)
        Curve head;
        for (std::size_t k = 0; k <= start; ++k)
        {
          head.nodes.push_back(c.nodes[k]);
          head.points.push_back(c.points[k]);
        }
        run = std::move(head);
        flush();
      }
    }
    model.curves = std::move(curves);
  }

  model.warnings = warnings.take();
  return model;
}

} // namespace

Model buildModel(const RawPolylines& input, const ModelParams& params)
{
  Model model;
  try
  {
    model = buildModelChecked(input, params);
  }
  catch (const InputError& e)
  {
    if (input.formNote.empty())
    {
      throw;
    }
    throw InputError(std::string(e.what()) + " (" + input.formNote + ")");
  }
  model.warnings.insert(model.warnings.begin(), input.notes.begin(), input.notes.end());
  return model;
}

} // namespace strata
