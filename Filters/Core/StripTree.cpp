// StrataMesh core: strip tree (paper Section 3) and exact nearest-segment queries (Section 4).
//
// Structure
// ---------
// The segments keep the order they were given in. A node covers a run [first, last] of them;
// its central segment goes from the first vertex of the run (a[first]) to the last one
// (b[last]), its width is the largest distance of any vertex of the run (both ends of every
// segment, since runs need not be connected) from the central segment, and its box is the
// bounding box of the run. The root covers all segments; a node's children cover the halves
// [first, mid] and [mid + 1, last] with mid = first + (last - first) / 2; a leaf covers one
// segment. The 2n - 1 nodes live in one flat array, root first. The two children of a node are
// adjacent (one expansion reads one contiguous pair), and the left child's subtree is laid out
// before the right child's, so the pair of children of a node whose own pair starts at D and
// whose left child covers L segments is at D + 2 (left) and D + 2 L (right): the query can
// prefetch two levels ahead without reading anything. Construction is top-down with an
// explicit stack; each node scans its run once for its box and width: O(n log n), about
// 0.15 s for 1e6 segments.
//
// The width is inflated by 1e-12 of itself and of the node's box diagonal, far above the
// rounding error of the bound computations below, so that rounding can never make a bound
// exceed the true distance (a point exactly on a segment must find distance 0).
//
// Query
// -----
// Every vertex of a run lies within `width` of the central segment, so the whole run lies in
// the stadium (Minkowski sum of the central segment and a disk of radius `width`), which is
// convex. Hence for every segment s of the run, dist(p, s) >= dist(p, stadium)
// = max(0, dist(p, central) - width), and also dist(p, s) >= dist(p, box). The key of a node
// is the square of the larger of the two lower bounds.
//
// Best-first search with a binary min-heap of (key, node) in the caller's scratch (cleared,
// never shrunk: no allocation once warm). Expanding a node looks at its two children: a child
// covering at most kScanRun segments is not pushed but scanned at once, segment by segment,
// with the exact distance (the paper stops when it pops a leaf, whose key is its exact
// distance; computing the exact distances of the leaves when they would be pushed is the same
// search with fewer heap operations), unless its box is not nearer than the best distance so
// far. Other children get their key and are kept only if it is below the best squared
// distance found so far, best2 (pruning). When the smallest key in the heap is not below
// best2, no open node can hold a closer segment: best2 is exact and the search stops. The
// result is the minimum of pointSegmentDistance2 (Geometry.h) over all segments, as a
// brute-force scan finds it, up to ties between segments whose distances agree to rounding.
//
// Two refinements keep it fast (see Testing/Benchmark/bench_distance.cxx): a first dive from the
// root follows the child with the smaller key down to the leaves without using the heap, so that
// best2 is tight at once and the siblings passed on the way enter the heap only if their key is
// still below it; and a child whose key is not above the heap's smallest is expanded at once
// instead of being pushed and popped. The arithmetic is branch-free where the outcome is
// unpredictable (SSE2 min, max and selects; a mispredicted branch costs as much as a bound).
#include "StripTree.h"

#include "Errors.h"

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

// Runs of at most this many segments are scanned exactly instead of being descended.
constexpr int kScanRun = 8;

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

inline double positivePart(double x)
{
  return maxOf(x, 0.0);
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

// Squared distance from p to segment c0-c1 without branches. Used only for bounds: its
// rounding error, a few ulps of |p - c0| + |c1 - c0|, is far below the slack added to the
// widths.
inline double segmentDistance2(Vec2 p, Vec2 c0, Vec2 c1)
{
  const Vec2 ab = c1 - c0;
  const Vec2 ap = p - c0;
  const double len2 = norm2(ab) + std::numeric_limits<double>::min();
  const double t = clamp01(dot(ap, ab) / len2);
  return norm2(ap - t * ab);
}

// Squared distance from p to box b (0 inside).
inline double boxDistance2(const Box2& b, Vec2 p)
{
  const double dx = positivePart(std::max(b.min.x - p.x, p.x - b.max.x));
  const double dy = positivePart(std::max(b.min.y - p.y, p.y - b.max.y));
  return dx * dx + dy * dy;
}

// Squared lower bound of the distance from p to the stadium of half-width w around c0-c1.
inline double stadiumBound2(Vec2 p, Vec2 c0, Vec2 c1, double w)
{
  const double d = positivePart(std::sqrt(segmentDistance2(p, c0, c1)) - w);
  return d * d;
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
  this->Nodes.reserve(2 * this->A.size() - 1);
  this->build(0, static_cast<int>(this->A.size()) - 1);
}

// Builds the tree over [first, last] into the reserved node array and returns the root's
// index (0). Top-down with an explicit stack: a node's two children are allocated together
// (siblings are adjacent in memory, so an expansion reads one contiguous pair) and the left
// subtree is laid out before the right one. Each node scans its run once for its box and
// width: O(n log n) in total.
int StripTree::build(int first, int last)
{
  struct Pending
  {
    int node, first, last;
  };
  std::vector<Pending> stack;
  stack.reserve(128);
  const int root = static_cast<int>(this->Nodes.size());
  this->Nodes.emplace_back();
  stack.push_back({ root, first, last });
  const Vec2* a = this->A.data();
  const Vec2* b = this->B.data();
  while (!stack.empty())
  {
    const Pending job = stack.back();
    stack.pop_back();
    Node& n = this->Nodes[job.node];
    n.first = job.first;
    n.last = job.last;
    n.c0 = a[job.first];
    n.c1 = b[job.last];
    n.left = n.right = -1;

    // Box and width: the largest distance of the run's vertices (both ends of every segment)
    // from the central segment; squared distances, one square root at the end.
    const Vec2 c0 = n.c0;
    const Vec2 c1 = n.c1;
    const Vec2 ab = c1 - c0;
    const double len2 = norm2(ab);
    const double inv = len2 > 0.0 ? 1.0 / len2 : 0.0;
    auto vertex2 = [&](Vec2 v)
    {
      const Vec2 ap = v - c0;
      const double s = dot(ap, ab);
      if (s <= 0.0)
      {
        return norm2(ap);
      }
      if (s >= len2)
      {
        return norm2(v - c1);
      }
      const double c = cross(ab, ap);
      return c * c * inv;
    };
    double w2 = 0.0;
    Box2 box;
    for (int i = job.first; i <= job.last; ++i)
    {
      box.add(a[i]);
      box.add(b[i]);
      w2 = std::max({ w2, vertex2(a[i]), vertex2(b[i]) });
    }
    n.box = box;
    // Slack against rounding (see the top of the file).
    n.width = std::sqrt(w2) * (1.0 + 1e-12) + 1e-12 * box.diagonal();
    if (job.first == job.last)
    {
      continue; // a leaf: its central segment is the segment itself
    }
    const int mid = job.first + (job.last - job.first) / 2;
    const int left = static_cast<int>(this->Nodes.size());
    n.left = left;
    n.right = left + 1;
    this->Nodes.emplace_back(); // reserved: no reallocation, n stays valid (unused below)
    this->Nodes.emplace_back();
    stack.push_back({ left + 1, mid + 1, job.last });
    stack.push_back({ left, job.first, mid });
  }
  return root;
}

double StripTree::lowerBound2(const Node& n, Vec2 p) const
{
  return maxOf(boxDistance2(n.box, p), stadiumBound2(p, n.c0, n.c1, n.width));
}

NearestSegment StripTree::nearest(Vec2 p, StripTreeScratch& scratch) const
{
  NearestSegment best;
  if (this->Nodes.empty())
  {
    return best;
  }
  const Vec2* a = this->A.data();
  const Vec2* b = this->B.data();
  const Node* nodes = this->Nodes.data();

  double best2 = HUGE_VAL;
  int bestSeg = -1;
  double bestT = 0.0;
  auto scan = [&](int first, int last)
  {
    for (int i = first; i <= last; ++i)
    {
      double t;
      const double d2 = segmentDistance2Exact(p, a[i], b[i], t);
      const bool closer = d2 < best2;
      bestSeg = closer ? i : bestSeg;
      bestT = selectIfLess(d2, best2, t, bestT);
      best2 = minOf(d2, best2);
    }
  };

  const Node& root = nodes[0];
  if (root.last - root.first < kScanRun)
  {
    scan(root.first, root.last);
    best.segment = bestSeg;
    best.distance2 = best2;
    best.t = bestT;
    return best;
  }

  // The key of an internal node (lowerBound2, inlined).
  auto key2 = [p](const Node& n)
  { return maxOf(boxDistance2(n.box, p), stadiumBound2(p, n.c0, n.c1, n.width)); };

  // Expands node n: scans its child runs of at most kScanRun segments (unless the child's box
  // is not nearer than best2) and returns its other children with their keys in
  // open[0..count), the smaller key first, all below best2.
  auto expand = [&](const Node& n, HeapEntry open[2])
  {
    const int mid = n.first + (n.last - n.first) / 2;
    const int leftLength = mid - n.first + 1;
    const int rightLength = n.last - mid;
    const Node* children = nodes + n.left; // siblings are adjacent
#if defined(__GNUC__)
    // Near the leaves, nodes are no longer in the caches. Request the next two levels of
    // descendants now, so that their memory latency overlaps with this expansion. Their
    // position follows from the layout without reading the children: the pair of children
    // of a node whose own pair is at D and whose left child covers L segments is at D + 2 for
    // the left child and at D + 2 * L for the right child.
    auto fetchPair = [](const Node* pair)
    {
      const char* q = reinterpret_cast<const char*>(pair);
      __builtin_prefetch(q);
      __builtin_prefetch(q + 64);
      __builtin_prefetch(q + 128);
    };
    auto fetchBelow = [&](const Node* pair, int length)
    {
      fetchPair(pair);
      const int left = (length - 1) / 2 + 1;
      if (left > kScanRun)
      {
        fetchPair(pair + 2);
      }
      if (length - left > kScanRun)
      {
        fetchPair(pair + 2 * left);
      }
    };
    if (leftLength > kScanRun)
    {
      fetchBelow(children + 2, leftLength);
    }
    if (rightLength > kScanRun)
    {
      fetchBelow(children + 2 * leftLength, rightLength);
    }
#endif
    int count = 0;
    if (leftLength <= kScanRun)
    {
      if (boxDistance2(children[0].box, p) < best2)
      {
        scan(n.first, mid);
      }
    }
    else
    {
      open[count++] = HeapEntry(key2(children[0]), n.left);
    }
    if (rightLength <= kScanRun)
    {
      if (boxDistance2(children[1].box, p) < best2)
      {
        scan(mid + 1, n.last);
      }
    }
    else
    {
      open[count++] = HeapEntry(key2(children[1]), n.left + 1);
    }
    if (count == 2 && open[1].first < open[0].first)
    {
      std::swap(open[0], open[1]);
    }
    // A scan may have lowered best2 after a key was computed.
    while (count > 0 && open[count - 1].first >= best2)
    {
      --count;
    }
    return count;
  };

  std::vector<HeapEntry>& heap = scratch.heap;
  heap.clear();

  // Dive: from the root, follow the child with the smaller key down to the short runs, to get
  // a tight best2 at once. The siblings left behind are kept aside and enter the heap only if
  // their key is below best2 once the dive is over, so that the heap stays small.
  double asideKey[2 * sizeof(int) * 8]; // at most one per level (not initialised: no cost)
  int asideNode[2 * sizeof(int) * 8];
  int asideCount = 0;
  int current = 0;
  for (;;)
  {
    HeapEntry open[2];
    const int count = expand(nodes[current], open);
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
    for (;;)
    {
      HeapEntry open[2];
      const int count = expand(nodes[current], open);
      if (count > 0 && (heap.empty() || open[0].first <= heap.front().first))
      {
        if (count == 2)
        {
          heapPush(heap, open[1].first, open[1].second);
        }
        current = open[0].second;
        continue;
      }
      for (int k = 0; k < count; ++k)
      {
        heapPush(heap, open[k].first, open[k].second);
      }
      break;
    }
  }
  best.segment = bestSeg;
  best.distance2 = best2;
  best.t = bestT;
  return best;
}

} // namespace strata
