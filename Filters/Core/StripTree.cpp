// StrataMesh core: strip tree (paper Section 3) and exact nearest-segment queries (Section 4).
//
// Structure
// ---------
// The segments keep the order they were given in. A node covers a run of them and its strip
// is a rectangle containing every vertex of the run (both ends of every segment, since runs
// need not be connected): in the paper's strip trees it is aligned with the central segment,
// from the first vertex of the run to the last one; here the axis-aligned bounding box is used
// instead when it has a smaller area (the central segment of a whole ring has length 0). A
// strip is stored as its centre o, its axis u and its half extents hx (along u) and hy (along
// the normal (-u.y, u.x)), in doubles (single precision was tried: the axis rounding loosens
// every bound by ~1e-7 of the distance, which makes queries far from the curve 10x slower).
//
// The tree is complete and implicit: node ids are breadth-first (root 1, children of i at 2 i
// and 2 i + 1), and the nodes of depth d split [0, n) evenly: node j of depth d (id 2^d + j)
// covers [j n / 2^d, (j + 1) n / 2^d) (integer division), so nothing but the strips is stored.
// Depth is the smallest depth whose runs have at most kBucket segments; the nodes of that depth
// are buckets, scanned, never split (the binary tree down to single segments, 2n - 1 nodes, is
// what numberOfNodes() reports). The strips of the two children of node i are stored side by
// side in Pairs[i] (96 bytes, lanes 0 and 1), so that one expansion reads one contiguous pair
// and computes both bounds with two-wide SSE2 arithmetic; the pairs of the grandchildren of i
// are Pairs[2 i] and Pairs[2 i + 1], adjacent, prefetched when i is expanded. For 1e6 segments:
// Depth 17, 2^17 pairs, 12.6 MB (the previous node-per-segment layout took 176 MB).
// Construction scans each node's run three times (frame choice, centre, extents): O(n Depth),
// about 0.1 s for 1e6 segments.
//
// Exactness of the bounds. The query maps p to a strip's frame, m(p) = ((p - o).u,
// (p - o) x u), and takes the distance from m(p) to [-hx, hx] x [-hy, hy]. u has length
// kAxisScale = 1 - 1e-13 (up to rounding), so m shortens every distance by that factor, while
// rounding moves the computed m(p) by a few ulps of |p - o| only (differences of doubles are
// correctly rounded): the shortening (450 ulps of the distance) covers the rounding of the
// part of |p - o| that is the distance to the run, and the half extents are computed with the
// query's own arithmetic and then inflated by 1e-12 of themselves and of the run's box
// diagonal, which covers the rest. Hence a key never exceeds the true squared distance to any
// segment of the run (a point exactly on a segment finds distance 0); the test suite checks
// it against brute force.
//
// Query
// -----
// Every vertex of a run lies in its strip, which is convex, so the whole run does: for every
// segment s of the run, dist(p, s) >= dist(p, strip), and the key of a node is the square of
// that lower bound, computed without division or square root.
//
// Best-first search with a binary min-heap of (key, node id) in the caller's scratch (cleared,
// never shrunk: no allocation once warm). Expanding a node computes the keys of its two
// children; children that are buckets are not pushed but scanned at once, segment by segment,
// with the exact distance, unless their key is not below the best squared distance so far,
// best2 (the paper stops when it pops a leaf, whose key is its exact distance; computing the
// exact distances of the leaves when they would be pushed is the same search with fewer heap
// operations). Other children are kept only if their key is below best2 (pruning). When the
// smallest key in the heap is not below best2, no open node can hold a closer segment: best2
// is exact and the search stops. The result is the minimum of pointSegmentDistance2
// (Geometry.h) over all segments, as a brute-force scan finds it, up to ties between segments
// whose distances agree to rounding. A NaN coordinate gives NaN keys, which nothing keeps.
//
// Two refinements keep it fast (see Testing/Benchmark/bench_distance.cxx): a first dive from the
// root follows the child with the smaller key down to the buckets without using the heap, so
// that best2 is tight at once and the siblings passed on the way enter the heap only if their
// key is still below it; and a child whose key is not above the heap's smallest is expanded at
// once instead of being pushed and popped. The arithmetic is branch-free where the outcome is
// unpredictable (SSE2 min, max and selects; a mispredicted branch costs as much as a bound).
// About 28 expansions and 18 segment distances per query for 1e6 segments (points uniform in
// the curve's box).
//
// SegmentGrid
// -----------
// A filter in front of bounded queries (nearest(p, scratch, r) with r about a cell) near and
// far from the segments: square cells over the segments' box; each segment is listed in every
// cell it passes within the margin (1e-10 of the coordinates' magnitude) of (clipped to each
// row it crosses; CSR lists, segments in order, so that a row of cells is tested empty with
// two reads). The cells meeting the box of the disc of
// radius r (1 + 1e-9) around p hold every segment within r + margin of p, far more than the
// rounding of the distances: when none is listed there, the tree finds none within r; else
// the listed ones (at most 64 cells) are scanned with the tree's own segment distance, and a
// single closest one is exactly what the tree returns (its result is the minimum over all
// segments, see Query). Ties (the two segments of a vertex, duplicated segments) are left to
// the tree, which takes whichever it meets first, except by nearestDistance2(), for which
// the tied segments' common distance is the answer. The caller picks the cell size.
#include "StripTree.h"

#include "Errors.h"
#include "Rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace strata
{

namespace
{

// Branch-free min, max and select. Compilers often turn std::max(x, 0.0) followed by a
// multiplication into a conditional jump, which mispredicts about half the time in the
// searches below; the SSE2 forms are single instructions.
inline double maxOf(double a, double b)
{
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
  return std::max(a, b);
#endif
}

inline double minOf(double a, double b)
{
#if defined(__SSE2__)
  return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
  return std::min(a, b);
#endif
}

inline double clamp01(double x)
{
  return minOf(maxOf(x, 0.0), 1.0);
}

// x if a == b, else y.
inline double selectIfEqual(double a, double b, double x, double y)
{
#if defined(__SSE2__)
  const __m128d mask = _mm_cmpeq_sd(_mm_set_sd(a), _mm_set_sd(b));
  return _mm_cvtsd_f64(
    _mm_or_pd(_mm_and_pd(mask, _mm_set_sd(x)), _mm_andnot_pd(mask, _mm_set_sd(y))));
#else
  return a == b ? x : y;
#endif
}

// x if a < b, else y.
inline double selectIfLess(double a, double b, double x, double y)
{
#if defined(__SSE2__)
  const __m128d mask = _mm_cmplt_sd(_mm_set_sd(a), _mm_set_sd(b));
  return _mm_cvtsd_f64(
    _mm_or_pd(_mm_and_pd(mask, _mm_set_sd(x)), _mm_andnot_pd(mask, _mm_set_sd(y))));
#else
  return a < b ? x : y;
#endif
}

// pointSegmentDistance2 (Geometry.h) without branches, bit for bit the same result and t:
// the same operations, with the clamps and the choice of the end point as selects.
inline double segmentDistance2Exact(Vec2 p, Vec2 a, Vec2 b, double& t)
{
  const Vec2 ab = b - a;
  const double len2 = norm2(ab);
  // clamp01 maps NaN (0 / 0) to 0, and the select covers a length that underflows to 0.
  const double s = selectIfEqual(len2, 0.0, 0.0, clamp01(dot(p - a, ab) / len2));
  t = s;
  const Vec2 q{ selectIfEqual(s, 1.0, b.x, a.x + s * ab.x),
    selectIfEqual(s, 1.0, b.y, a.y + s * ab.y) };
  return norm2(p - q);
}

// The children of a node: either buckets (scanned) or stored nodes (bounded, pushed).
// Buckets hold at most this many segments.
constexpr int kBucket = 8;

// Length of the strips' axes: just below 1, so that with rounding the map from the plane to a
// strip's frame never lengthens a distance (see the top of the file).
constexpr double kAxisScale = 1.0 - 1e-13;

// Depth of a node from its breadth-first id (root 1).
inline int depthOf(int id)
{
#if defined(__GNUC__)
  return 31 - __builtin_clz(static_cast<unsigned>(id));
#else
  int d = 0;
  while (id > 1)
  {
    id >>= 1;
    ++d;
  }
  return d;
#endif
}

// Squared distances from p to the strips of both children of a pair (lower bounds of the
// squared distance to their segments): in each strip's frame, the distance to the rectangle
// [-hx, hx] x [-hy, hy]. NaN coordinates give NaN keys, which no comparison keeps.
template<class Pair>
inline void stripBounds2(const Pair& pair, Vec2 p, double key[2])
{
#if defined(__SSE2__)
  const __m128d rx = _mm_sub_pd(_mm_set1_pd(p.x), _mm_load_pd(pair.ox));
  const __m128d ry = _mm_sub_pd(_mm_set1_pd(p.y), _mm_load_pd(pair.oy));
  const __m128d ux = _mm_load_pd(pair.ux);
  const __m128d uy = _mm_load_pd(pair.uy);
  const __m128d along = _mm_add_pd(_mm_mul_pd(rx, ux), _mm_mul_pd(ry, uy));
  const __m128d across = _mm_sub_pd(_mm_mul_pd(ry, ux), _mm_mul_pd(rx, uy));
  const __m128d sign = _mm_set1_pd(-0.0);
  const __m128d zero = _mm_setzero_pd();
  // max(0, x) returns x when x is NaN.
  const __m128d dx = _mm_max_pd(zero, _mm_sub_pd(_mm_andnot_pd(sign, along), _mm_load_pd(pair.hx)));
  const __m128d dy =
    _mm_max_pd(zero, _mm_sub_pd(_mm_andnot_pd(sign, across), _mm_load_pd(pair.hy)));
  _mm_storeu_pd(key, _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)));
#else
  for (int k = 0; k < 2; ++k)
  {
    const double rx = p.x - pair.ox[k];
    const double ry = p.y - pair.oy[k];
    const double along = rx * pair.ux[k] + ry * pair.uy[k];
    const double across = ry * pair.ux[k] - rx * pair.uy[k];
    double dx = std::abs(along) - pair.hx[k];
    double dy = std::abs(across) - pair.hy[k];
    dx = dx < 0.0 ? 0.0 : dx; // NaN stays NaN
    dy = dy < 0.0 ? 0.0 : dy;
    key[k] = dx * dx + dy * dy;
  }
#endif
}

// Min-heap on the key only (ties in any order).
using HeapEntry = std::pair<double, int>;

inline void heapPush(std::vector<HeapEntry>& heap, double key, int node)
{
  std::size_t i = heap.size();
  heap.emplace_back(key, node);
  HeapEntry* h = heap.data();
  while (i > 0)
  {
    const std::size_t parent = (i - 1) / 2;
    if (h[parent].first <= key)
    {
      break;
    }
    h[i] = h[parent];
    i = parent;
  }
  h[i] = HeapEntry(key, node);
}

inline HeapEntry heapPop(std::vector<HeapEntry>& heap)
{
  HeapEntry* h = heap.data();
  const HeapEntry top = h[0];
  const HeapEntry last = h[heap.size() - 1];
  heap.pop_back();
  const std::size_t n = heap.size();
  if (n == 0)
  {
    return top;
  }
  std::size_t i = 0;
  for (;;)
  {
    std::size_t child = 2 * i + 1;
    if (child >= n)
    {
      break;
    }
    if (child + 1 < n && h[child + 1].first < h[child].first)
    {
      ++child;
    }
    if (h[child].first >= last.first)
    {
      break;
    }
    h[i] = h[child];
    i = child;
  }
  h[i] = last;
  return top;
}

} // namespace

StripTree::StripTree(std::vector<Vec2> a, std::vector<Vec2> b)
  : A(std::move(a))
  , B(std::move(b))
{
  if (this->A.size() != this->B.size())
  {
    throw ParameterError("StripTree: " + std::to_string(this->A.size()) + " segment starts but " +
      std::to_string(this->B.size()) + " segment ends");
  }
  // 2n - 1 nodes must be indexable by int.
  if (this->A.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2))
  {
    throw ParameterError("StripTree: too many segments (" + std::to_string(this->A.size()) +
      "), at most " + std::to_string(std::numeric_limits<int>::max() / 2));
  }
  if (this->A.empty())
  {
    return;
  }
  this->build();
}

// Chooses Depth, the smallest with buckets of at most kBucket segments, and computes the
// strip of every node below the root, level by level. Each node scans its run twice (choice
// of the frame, then the extents about the chosen centre): O(n Depth).
void StripTree::build()
{
  const std::int64_t n = static_cast<std::int64_t>(this->A.size());
  this->Depth = 0;
  while (((n - 1) >> this->Depth) + 1 > kBucket)
  {
    ++this->Depth;
  }
  if (this->Depth == 0)
  {
    return;
  }
  this->Pairs.assign(std::size_t(1) << this->Depth, ChildPair{});
  const Vec2* a = this->A.data();
  const Vec2* b = this->B.data();
  for (int d = 1; d <= this->Depth; ++d)
  {
    const std::int64_t count = std::int64_t(1) << d;
    for (std::int64_t j = 0; j < count; ++j)
    {
      const int first = static_cast<int>((j * n) >> d);
      const int end = static_cast<int>(((j + 1) * n) >> d);

      Box2 box;
      for (int i = first; i < end; ++i)
      {
        box.add(a[i]);
        box.add(b[i]);
      }
      const double diagonal = box.diagonal();
      // Axis: the central segment's direction when it is not negligible, shortened so that
      // rounding can never lengthen it to 1 (see the top of the file).
      const Vec2 c0 = a[first];
      const Vec2 chord = b[end - 1] - c0;
      const double chordLength = norm(chord);
      Vec2 u{ kAxisScale, 0.0 };
      if (chordLength > 1e-9 * diagonal && chordLength > 0.0)
      {
        // Extents of the run in the central segment's frame; keep it unless the axis-aligned
        // box is smaller.
        const Vec2 v = (kAxisScale / chordLength) * chord;
        double lo0 = HUGE_VAL, hi0 = -HUGE_VAL, lo1 = HUGE_VAL, hi1 = -HUGE_VAL;
        auto extend = [&](Vec2 q)
        {
          const Vec2 r = q - c0;
          const double along = r.x * v.x + r.y * v.y;
          const double across = r.y * v.x - r.x * v.y;
          lo0 = std::min(lo0, along);
          hi0 = std::max(hi0, along);
          lo1 = std::min(lo1, across);
          hi1 = std::max(hi1, across);
        };
        for (int i = first; i < end; ++i)
        {
          extend(a[i]);
          extend(b[i]);
        }
        if ((hi0 - lo0) * (hi1 - lo1) < box.width() * box.height())
        {
          u = v;
        }
      }
      // Centre of the strip, then its half extents about it, computed as the query does.
      Vec2 o = box.center();
      if (u.y != 0.0)
      {
        double lo0 = HUGE_VAL, hi0 = -HUGE_VAL, lo1 = HUGE_VAL, hi1 = -HUGE_VAL;
        for (int i = first; i < end; ++i)
        {
          for (const Vec2 q : { a[i], b[i] })
          {
            const Vec2 r = q - c0;
            const double along = r.x * u.x + r.y * u.y;
            const double across = r.y * u.x - r.x * u.y;
            lo0 = std::min(lo0, along);
            hi0 = std::max(hi0, along);
            lo1 = std::min(lo1, across);
            hi1 = std::max(hi1, across);
          }
        }
        // u has length kAxisScale and its normal is (-u.y, u.x).
        const double s = 0.5 / (kAxisScale * kAxisScale);
        const double ma = (lo0 + hi0) * s;
        const double mc = (lo1 + hi1) * s;
        o = Vec2{ c0.x + ma * u.x - mc * u.y, c0.y + ma * u.y + mc * u.x };
      }
      double hx = 0.0, hy = 0.0;
      for (int i = first; i < end; ++i)
      {
        for (const Vec2 q : { a[i], b[i] })
        {
          const double rx = q.x - o.x;
          const double ry = q.y - o.y;
          hx = std::max(hx, std::abs(rx * u.x + ry * u.y));
          hy = std::max(hy, std::abs(ry * u.x - rx * u.y));
        }
      }
      // Slack against rounding (see the top of the file).
      const double slack = 1e-12 * diagonal;
      const std::int64_t id = count + j;
      ChildPair& pair = this->Pairs[static_cast<std::size_t>(id >> 1)];
      const int lane = static_cast<int>(id & 1);
      pair.ox[lane] = o.x;
      pair.oy[lane] = o.y;
      pair.ux[lane] = u.x;
      pair.uy[lane] = u.y;
      pair.hx[lane] = hx * (1.0 + 1e-12) + slack;
      pair.hy[lane] = hy * (1.0 + 1e-12) + slack;
    }
  }
}

NearestSegment StripTree::nearest(Vec2 p, StripTreeScratch& scratch, double maxDistance) const
{
  NearestSegment best;
  const std::int64_t n = static_cast<std::int64_t>(this->A.size());
  if (n == 0)
  {
    return best;
  }
  const Vec2* a = this->A.data();
  const Vec2* b = this->B.data();

  double best2 = maxDistance < HUGE_VAL ? maxDistance * maxDistance : HUGE_VAL;
  int bestSeg = -1;
  double bestT = 0.0;
  auto scan = [&](int first, int end)
  {
    for (int i = first; i < end; ++i)
    {
      double t;
      const double d2 = segmentDistance2Exact(p, a[i], b[i], t);
      const bool closer = d2 < best2;
      bestSeg = closer ? i : bestSeg;
      bestT = selectIfLess(d2, best2, t, bestT);
      best2 = minOf(d2, best2);
    }
  };
  auto finish = [&]()
  {
    best.segment = bestSeg;
    best.distance2 = best2;
    best.t = bestT;
    return best;
  };

  const int depth = this->Depth;
  if (depth == 0)
  {
    scan(0, static_cast<int>(n));
    return finish();
  }
  const ChildPair* pairs = this->Pairs.data();
  // First segment of the run of node id (depth d): the runs of depth d split [0, n) evenly.
  auto runFirst = [n](std::int64_t j, int d) { return static_cast<int>((j * n) >> d); };

  // Expands node id of depth d: computes the bounds of its two children; scans the children
  // that are buckets unless their bound is not below best2 (the nearer one first), and returns
  // the others with their keys in open[0..count), the smaller key first, all below best2.
  auto expand = [&](int id, int d, HeapEntry open[2])
  {
    const ChildPair& pair = pairs[id];
    if (d + 2 <= depth)
    {
      // The children's pairs, adjacent: request them now so that their memory latency
      // overlaps with this expansion and the next.
      const char* q = reinterpret_cast<const char*>(pairs + 2 * id);
      prefetch(q);
      prefetch(q + 64);
      prefetch(q + 128);
    }
    double key[2];
    stripBounds2(pair, p, key);
    if (d + 1 == depth)
    {
      const std::int64_t j = 2 * (id - (std::int64_t(1) << d));
      const int first = runFirst(j, d + 1);
      const int mid = runFirst(j + 1, d + 1);
      const int end = runFirst(j + 2, d + 1);
      if (key[1] < key[0])
      {
        if (key[1] < best2)
        {
          scan(mid, end);
        }
        if (key[0] < best2)
        {
          scan(first, mid);
        }
      }
      else
      {
        if (key[0] < best2)
        {
          scan(first, mid);
        }
        if (key[1] < best2)
        {
          scan(mid, end);
        }
      }
      return 0;
    }
    int count = 0;
    const bool swap = key[1] < key[0];
    const int near = swap ? 1 : 0;
    if (key[near] < best2)
    {
      open[count++] = HeapEntry(key[near], 2 * id + near);
      if (key[1 - near] < best2)
      {
        open[count++] = HeapEntry(key[1 - near], 2 * id + 1 - near);
      }
    }
    return count;
  };

  std::vector<HeapEntry>& heap = scratch.heap;
  heap.clear();

  // Dive: from the root, follow the child with the smaller key down to the buckets, to get a
  // tight best2 at once. The siblings left behind are kept aside and enter the heap only if
  // their key is below best2 once the dive is over, so that the heap stays small.
  double asideKey[2 * sizeof(int) * 8]; // at most one per level (not initialised: no cost)
  int asideNode[2 * sizeof(int) * 8];
  int asideCount = 0;
  int current = 1;
  int d = 0;
  for (;;)
  {
    HeapEntry open[2];
    const int count = expand(current, d, open);
    if (count == 0)
    {
      break;
    }
    if (count == 2)
    {
      asideKey[asideCount] = open[1].first;
      asideNode[asideCount++] = open[1].second;
    }
    current = open[0].second;
    ++d;
  }
  for (int k = 0; k < asideCount; ++k)
  {
    if (asideKey[k] < best2)
    {
      heapPush(heap, asideKey[k], asideNode[k]);
    }
  }

  // Best-first: expand the open node with the smallest key; when that key is not below best2,
  // no open node can hold a closer segment and best is exact. A child whose key is not above
  // the heap's smallest is expanded at once instead of being pushed and popped.
  while (!heap.empty())
  {
    const HeapEntry top = heapPop(heap);
    if (top.first >= best2)
    {
      break;
    }
    current = top.second;
    d = depthOf(current);
    for (;;)
    {
      HeapEntry open[2];
      const int count = expand(current, d, open);
      if (count > 0 && (heap.empty() || open[0].first <= heap.front().first))
      {
        if (count == 2)
        {
          heapPush(heap, open[1].first, open[1].second);
        }
        current = open[0].second;
        ++d;
        continue;
      }
      for (int k = 0; k < count; ++k)
      {
        heapPush(heap, open[k].first, open[k].second);
      }
      break;
    }
  }
  return finish();
}

//------------------------------------------------------------------------------
// SegmentGrid (see the top of the file).
SegmentGrid::SegmentGrid(std::vector<Vec2> a,
  std::vector<Vec2> b,
  double cellSize,
  std::size_t maxCells)
  : A(std::move(a))
  , B(std::move(b))
{
  if (this->A.size() != this->B.size())
  {
    throw ParameterError("SegmentGrid: " + std::to_string(this->A.size()) + " segment starts but " +
      std::to_string(this->B.size()) + " segment ends");
  }
  if (this->A.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
  {
    throw ParameterError("SegmentGrid: too many segments (" + std::to_string(this->A.size()) + ")");
  }
  Box2 box;
  for (std::size_t i = 0; i < this->A.size(); ++i)
  {
    box.add(this->A[i]);
    box.add(this->B[i]);
  }
  if (box.empty() || !std::isfinite(box.min.x) || !std::isfinite(box.min.y) ||
    !std::isfinite(box.max.x) || !std::isfinite(box.max.y))
  {
    return; // no grid: the queries answer false
  }
  const double scale = box.scale();
  this->Margin = std::max(1e-10 * scale, 1e-300);
  this->Origin = Vec2{ box.min.x - 2.0 * this->Margin, box.min.y - 2.0 * this->Margin };
  const double width = box.width() + 4.0 * this->Margin;
  const double height = box.height() + 4.0 * this->Margin;
  double cell = cellSize > 0.0 && std::isfinite(cellSize) ? cellSize : std::max(width, height);
  const double most = static_cast<double>(std::max<std::size_t>(maxCells, 1));
  for (;;)
  {
    const double nx = std::max(1.0, std::ceil(width / cell));
    const double ny = std::max(1.0, std::ceil(height / cell));
    if (nx * ny <= most)
    {
      this->Nx = static_cast<int>(nx);
      this->Ny = static_cast<int>(ny);
      break;
    }
    cell *= std::max(1.01, 0.5 * std::sqrt(nx * ny / most));
  }
  this->Cell = cell;
  this->InvCell = 1.0 / cell;
  const std::size_t nx = static_cast<std::size_t>(this->Nx);
  const std::size_t cells = nx * static_cast<std::size_t>(this->Ny);
  // (cell, segment) for every cell a segment passes within the margin of, in segment order.
  LargeVector<std::pair<std::uint32_t, int>> near;
  const double m = this->Margin;
  for (std::size_t s = 0; s < this->A.size(); ++s)
  {
    const Vec2 p = this->A[s], q = this->B[s];
    const double dx = q.x - p.x, dy = q.y - p.y;
    const int j0 = std::max(0, this->cellOf(std::min(p.y, q.y) - m, this->Origin.y, this->Ny));
    const int j1 =
      std::min(this->Ny - 1, this->cellOf(std::max(p.y, q.y) + m, this->Origin.y, this->Ny));
    // Nearly horizontal: the whole x range in every row (the clipped one below would round
    // by more than the margin).
    const bool flat = !(std::abs(dy) > 1e-4 * std::abs(dx));
    for (int j = j0; j <= j1; ++j)
    {
      double xlo = std::min(p.x, q.x), xhi = std::max(p.x, q.x);
      if (!flat)
      {
        // The part of the segment within the row's band widened by the margin.
        const double ylo = this->Origin.y + j * cell - m;
        const double yhi = this->Origin.y + (j + 1) * cell + m;
        double t0 = (ylo - p.y) / dy, t1 = (yhi - p.y) / dy;
        if (t1 < t0)
        {
          std::swap(t0, t1);
        }
        t0 = std::clamp(t0, 0.0, 1.0);
        t1 = std::clamp(t1, 0.0, 1.0);
        const double x0 = p.x + t0 * dx, x1 = p.x + t1 * dx;
        xlo = std::max(xlo, std::min(x0, x1));
        xhi = std::min(xhi, std::max(x0, x1));
      }
      const int i0 = std::max(0, this->cellOf(xlo - m, this->Origin.x, this->Nx));
      const int i1 = std::min(this->Nx - 1, this->cellOf(xhi + m, this->Origin.x, this->Nx));
      for (int i = i0; i <= i1; ++i)
      {
        near.emplace_back(static_cast<std::uint32_t>(
                            static_cast<std::size_t>(j) * nx + static_cast<std::size_t>(i)),
          static_cast<int>(s));
      }
    }
  }
  groupIntoRows(cells,
    this->Start,
    this->Items,
    [&](auto&& emit)
    {
      for (const auto& e : near)
      {
        emit(e.first, e.second);
      }
    });
}

int SegmentGrid::cellOf(double v, double lo, int count) const
{
  const double c = (v - lo) * this->InvCell;
  if (!(c >= 0.0))
  {
    return -1;
  }
  return c >= count ? count : static_cast<int>(c);
}

SegmentGrid::CellRange SegmentGrid::cellsUnder(double xlo, double xhi, double ylo, double yhi) const
{
  return { std::max(0, this->cellOf(xlo, this->Origin.x, this->Nx)),
    std::min(this->Nx - 1, this->cellOf(xhi, this->Origin.x, this->Nx)),
    std::max(0, this->cellOf(ylo, this->Origin.y, this->Ny)),
    std::min(this->Ny - 1, this->cellOf(yhi, this->Origin.y, this->Ny)) };
}

bool SegmentGrid::noneWithin(Vec2 p, double r) const
{
  const double reach = r * (1.0 + 1e-9);
  if (this->Start.empty() || !(r >= 0.0) || !std::isfinite(reach) || !std::isfinite(p.x) ||
    !std::isfinite(p.y))
  {
    return false;
  }
  const auto [i0, i1, j0, j1] =
    this->cellsUnder(p.x - reach, p.x + reach, p.y - reach, p.y + reach);
  return this->emptyCells(i0, i1, j0, j1) == 1;
}

// 1 when cells [i0, i1] x [j0, j1] list no segment (or the range is empty: beside the grid,
// which holds every segment), 0 when one does, -1 when there are too many rows to tell.
int SegmentGrid::emptyCells(int i0, int i1, int j0, int j1) const
{
  if (i0 > i1 || j0 > j1)
  {
    return 1;
  }
  if (j1 - j0 >= 256)
  {
    return -1;
  }
  for (int j = j0; j <= j1; ++j)
  {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(this->Nx);
    if (this->Start[row + i1 + 1] != this->Start[row + i0])
    {
      return 0;
    }
  }
  return 1;
}

bool SegmentGrid::nearest(Vec2 p, double r, NearestSegment& nearest) const
{
  return this->scan(p, r, false, nearest);
}

bool SegmentGrid::nearestDistance2(Vec2 p, double r, double& distance2) const
{
  NearestSegment n;
  if (!this->scan(p, r, true, n))
  {
    return false;
  }
  distance2 = n.distance2;
  return true;
}

template<typename Visit>
bool SegmentGrid::forEachUnder(double xlo, double xhi, double ylo, double yhi, Visit&& visit) const
{
  const auto [i0, i1, j0, j1] = this->cellsUnder(xlo, xhi, ylo, yhi);
  if (i0 > i1 || j0 > j1)
  {
    return true;
  }
  if ((i1 - i0 + 1) * (j1 - j0 + 1) > 64)
  {
    return false;
  }
  for (int j = j0; j <= j1; ++j)
  {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(this->Nx);
    for (std::uint32_t k = this->Start[row + i0]; k < this->Start[row + i1 + 1]; ++k)
    {
      visit(this->Items[k]);
    }
  }
  return true;
}

template<typename Counts>
bool SegmentGrid::smallestUnder(double xlo,
  double xhi,
  double ylo,
  double yhi,
  const std::vector<double>& value,
  Counts&& counts,
  double& smallest) const
{
  double least = std::numeric_limits<double>::infinity();
  if (!this->forEachUnder(xlo,
        xhi,
        ylo,
        yhi,
        [&](int s)
        {
          if (value[s] < least && counts(s))
          {
            least = value[s];
          }
        }))
  {
    return false;
  }
  smallest = least;
  return true;
}

bool SegmentGrid::smallestValue(Vec2 p,
  double r,
  const std::vector<double>& value,
  double& smallest) const
{
  const double reach = r * (1.0 + 1e-9);
  if (this->Start.empty() || !(r >= 0.0) || !std::isfinite(reach) || !std::isfinite(p.x) ||
    !std::isfinite(p.y) || value.size() != this->A.size())
  {
    return false;
  }
  return this->smallestUnder(
    p.x - reach, p.x + reach, p.y - reach, p.y + reach, value, [](int) { return true; }, smallest);
}

bool SegmentGrid::smallestValueNear(Vec2 a,
  Vec2 b,
  double r,
  const std::vector<double>& value,
  double& smallest) const
{
  const double reach = r * (1.0 + 1e-9);
  if (this->Start.empty() || !(r >= 0.0) || !std::isfinite(reach) || !std::isfinite(a.x) ||
    !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y) ||
    value.size() != this->A.size())
  {
    return false;
  }
  return this->smallestUnder(
    std::min(a.x, b.x) - reach,
    std::max(a.x, b.x) + reach,
    std::min(a.y, b.y) - reach,
    std::max(a.y, b.y) + reach,
    value,
    [&](int s) { return segmentSegmentDistance2(a, b, this->A[s], this->B[s]) <= reach * reach; },
    smallest);
}

bool SegmentGrid::firstCrossing(Vec2 p, Vec2 u, double from, double to, double& s) const
{
  if (this->Start.empty() || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(u.x) ||
    !std::isfinite(u.y) || !std::isfinite(from) || !std::isfinite(to) || !(from <= to))
  {
    return false;
  }
  const Vec2 q = p + to * u;
  double first = std::numeric_limits<double>::infinity();
  if (!this->forEachUnder(std::min(p.x, q.x),
        std::max(p.x, q.x),
        std::min(p.y, q.y),
        std::max(p.y, q.y),
        [&](int segment)
        {
          // p + along u = A + at (B - A), at in [0, 1].
          const Vec2 e = this->B[segment] - this->A[segment], w = this->A[segment] - p;
          const double den = cross(u, e);
          if (den == 0.0)
          {
            return;
          }
          const double along = cross(w, e) / den, at = cross(w, u) / den;
          if (at >= 0.0 && at <= 1.0 && along > from && along < to && along < first)
          {
            first = along;
          }
        }))
  {
    return false;
  }
  s = first;
  return true;
}

bool SegmentGrid::noneInside(Vec2 a, Vec2 b, Vec2 c, double depth) const
{
  const Vec2 corner[3] = { a, b, c };
  for (const Vec2& v : corner)
  {
    if (!std::isfinite(v.x) || !std::isfinite(v.y))
    {
      return false;
    }
  }
  if (this->Start.empty() || !(depth > 0.0) || !std::isfinite(depth))
  {
    return false;
  }
  // Side k's signed distance, positive inside: f_k(x) = cross(u_k, x - corner k), u_k the
  // unit direction from corner k to corner k + 1.
  Vec2 u[3];
  for (int k = 0; k < 3; ++k)
  {
    const Vec2 e = corner[(k + 1) % 3] - corner[k];
    const double length = norm(e);
    if (!(length > 0.0))
    {
      return false;
    }
    u[k] = (1.0 / length) * e;
  }
  const double deeper = depth * (1.0 - 1e-6);
  const auto reaches = [&](Vec2 p, Vec2 q)
  {
    // Whether some t in [0, 1] has every f_k(p + t (q - p)) > deeper: the intersection of three
    // intervals of t (each side's f is linear along the segment).
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 3; ++k)
    {
      const double f0 = cross(u[k], p - corner[k]), f1 = cross(u[k], q - corner[k]);
      if (f0 <= deeper && f1 <= deeper)
      {
        return false;
      }
      if (f0 > deeper && f1 > deeper)
      {
        continue;
      }
      const double t = (deeper - f0) / (f1 - f0); // where f crosses the depth
      if (f1 > f0)
      {
        lo = std::max(lo, t);
      }
      else
      {
        hi = std::min(hi, t);
      }
    }
    return lo <= hi + 1e-9; // (a hair of slack: counted as reaching)
  };
  const double xmin = std::min({ a.x, b.x, c.x }), xmax = std::max({ a.x, b.x, c.x });
  const double ymin = std::min({ a.y, b.y, c.y }), ymax = std::max({ a.y, b.y, c.y });
  const auto [i0, i1, j0, j1] = this->cellsUnder(xmin, xmax, ymin, ymax);
  if (i0 > i1 || j0 > j1)
  {
    return true; // beside the grid, which holds every segment
  }
  if ((i1 - i0 + 1) * (j1 - j0 + 1) > 64)
  {
    return false;
  }
  for (int j = j0; j <= j1; ++j)
  {
    const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(this->Nx);
    for (std::uint32_t k = this->Start[row + i0]; k < this->Start[row + i1 + 1]; ++k)
    {
      const int s = this->Items[k];
      if (reaches(this->A[s], this->B[s]))
      {
        return false;
      }
    }
  }
  return true;
}

// With ties: a tie settles the distance (not the segment).
bool SegmentGrid::scan(Vec2 p, double r, bool ties, NearestSegment& nearest) const
{
  const double reach = r * (1.0 + 1e-9);
  if (this->Start.empty() || !(r >= 0.0) || !std::isfinite(reach) || !std::isfinite(p.x) ||
    !std::isfinite(p.y))
  {
    return false;
  }
  // As StripTree::nearest: the squared bound, then segments strictly below the best so far.
  double best2 = r * r;
  int bestSeg = -1;
  double bestT = 0.0;
  const auto [i0, i1, j0, j1] =
    this->cellsUnder(p.x - reach, p.x + reach, p.y - reach, p.y + reach);
  if (i0 <= i1 && j0 <= j1)
  {
    // Scanned when at most 64 cells, else only told empty.
    const bool small = (i1 - i0 + 1) * (j1 - j0 + 1) <= 64;
    if (small || this->emptyCells(i0, i1, j0, j1) != 1)
    {
      if (!small)
      {
        return false;
      }
      bool tie = false;
      const Vec2* a = this->A.data();
      const Vec2* b = this->B.data();
      // Cells [u0, u1] of row j. In any order of the cells, the same closest segment (when
      // single) and the same tie: two different segments at the smallest distance.
      const auto cells = [&](int j, int u0, int u1)
      {
        const std::size_t row = static_cast<std::size_t>(j) * static_cast<std::size_t>(this->Nx);
        for (std::uint32_t k = this->Start[row + u0]; k < this->Start[row + u1 + 1]; ++k)
        {
          const int seg = this->Items[k];
          double t;
          const double d2 = segmentDistance2Exact(p, a[seg], b[seg], t);
          if (d2 < best2)
          {
            best2 = d2;
            bestSeg = seg;
            bestT = t;
            tie = false;
          }
          else if (d2 == best2 && bestSeg >= 0 && seg != bestSeg)
          {
            tie = true; // the tree takes either, whichever it meets first
          }
        }
      };
      // The 3 x 3 cells around p's first, when the box holds more: a segment they do not list
      // lies beyond their border (the cells list every segment within the margin of them),
      // so one found nearer than that border (by a relative 1e-6, over any rounding) settles
      // it; else the other cells of the box are scanned too.
      const int ci = this->cellOf(p.x, this->Origin.x, this->Nx);
      const int cj = this->cellOf(p.y, this->Origin.y, this->Ny);
      const bool inner = ci - 1 >= i0 && ci + 1 <= i1 && cj - 1 >= j0 && cj + 1 <= j1 &&
        (i1 - i0 > 2 || j1 - j0 > 2);
      bool settled = false;
      if (inner)
      {
        for (int j = cj - 1; j <= cj + 1; ++j)
        {
          cells(j, ci - 1, ci + 1);
        }
        const double border = std::min({ p.x - (this->Origin.x + (ci - 1) * this->Cell),
          this->Origin.x + (ci + 2) * this->Cell - p.x,
          p.y - (this->Origin.y + (cj - 1) * this->Cell),
          this->Origin.y + (cj + 2) * this->Cell - p.y });
        settled = bestSeg >= 0 && border > 0.0 && best2 < (1.0 - 1e-6) * border * border;
      }
      for (int j = j0; j <= j1 && !settled; ++j)
      {
        if (inner && j >= cj - 1 && j <= cj + 1)
        {
          if (ci - 2 >= i0)
          {
            cells(j, i0, ci - 2);
          }
          if (ci + 2 <= i1)
          {
            cells(j, ci + 2, i1);
          }
        }
        else
        {
          cells(j, i0, i1);
        }
      }
      if (tie && !ties)
      {
        return false;
      }
    }
  }
  nearest.segment = bestSeg;
  nearest.distance2 = best2;
  nearest.t = bestT;
  return true;
}

} // namespace strata
