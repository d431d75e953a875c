// StrataMesh core: strip tree over a set of segments (paper Section 3) and exact nearest-segment
// queries by best-first search (paper Section 4). No VTK.
#ifndef StrataMeshCore_StripTree_h
#define StrataMeshCore_StripTree_h

#include "Geometry.h"
#include "LargeArray.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace strata
{

/// Result of a nearest-segment query.
struct NearestSegment
{
  int segment = -1;            ///< index of the closest segment (-1 for an empty tree)
  double distance2 = HUGE_VAL; ///< squared distance to it
  double t = 0.0;              ///< parameter of the closest point on it (0 at its first vertex)
};

/// Scratch memory of a query (the heap); reuse one per thread so queries do not allocate.
/// (On cache lines of its own: a query writes it at every step, and a line it shared with
/// what another thread reads, or with the other thread's scratch, went back and forth.)
struct alignas(64) StripTreeScratch
{
  std::vector<std::pair<double, int>> heap;
};

/// A binary strip tree over segments given as pairs of points. Consecutive segments (in the
/// order given) are grouped: each node covers a run [first, last] of segments and stores its
/// strip, a rectangle aligned with the central segment from the run's first vertex to its
/// last vertex (or with the axes when that is smaller) containing every vertex of the run;
/// children hold the two halves. Runs need not be connected (rings of one region follow each
/// other): the bound stays valid because the strip is convex and contains every vertex of the
/// run.
class StripTree
{
public:
  StripTree() = default;
  /// Segment i goes from a[i] to b[i]. Throws ParameterError when the sizes differ.
  StripTree(std::vector<Vec2> a, std::vector<Vec2> b);

  std::size_t numberOfSegments() const { return this->A.size(); }
  Vec2 segmentStart(int i) const { return this->A[i]; }
  Vec2 segmentEnd(int i) const { return this->B[i]; }

  /// Exact closest segment to p (ties: any of them). Does not allocate once the scratch has
  /// grown to its working size. With maxDistance, only segments nearer than it are looked
  /// for (segment -1 and distance2 maxDistance^2 when there is none): far queries then prune
  /// the whole tree at once.
  NearestSegment nearest(Vec2 p, StripTreeScratch& scratch, double maxDistance = HUGE_VAL) const;

  /// Number of nodes of the binary tree down to single segments: 2 n - 1 for n > 0 segments
  /// (for tests and reports). Only the upper levels are stored, about 12 bytes per segment:
  /// runs of at most 8 segments are buckets, scanned (see StripTree.cpp).
  std::size_t numberOfNodes() const { return this->A.empty() ? 0 : 2 * this->A.size() - 1; }

private:
  // The bounds of the two children of a stored node, side by side (lane 0: the left child,
  // lane 1: the right one) so that an expansion computes both at once. A child's bound is an
  // oriented rectangle: centre o, unit axis u (shortened by 1e-13, see StripTree.cpp) and half
  // extents h along u and along its normal.
  struct alignas(32) ChildPair
  {
    double ox[2], oy[2];
    double ux[2], uy[2];
    double hx[2], hy[2];
  };
  void build();

  std::vector<Vec2> A, B;
  // Node ids in breadth-first order: the root is 1, the children of i are 2 i and 2 i + 1.
  // Pairs[i] holds the bounds of the children of node i (Pairs[0] is unused); the nodes of
  // depth Depth are buckets of at most kBucket segments, scanned, never split.
  std::vector<ChildPair> Pairs;
  int Depth = 0;
};

/// Which cells of a uniform grid lie near which segments: answers bounded nearest-segment
/// queries near the segments, and "no segment lies within r of p" in a few reads, when it
/// can (see StripTree.cpp); otherwise the caller asks a StripTree over the same segments.
class SegmentGrid
{
public:
  SegmentGrid() = default;
  /// Segment i goes from a[i] to b[i] (sizes as for StripTree); square cells of side cellSize
  /// over the segments' box, enlarged so that there are at most maxCells (and at least one).
  SegmentGrid(std::vector<Vec2> a, std::vector<Vec2> b, double cellSize, std::size_t maxCells);

  /// True only when no segment lies within r of p (false for a NaN or infinite p or r).
  bool noneWithin(Vec2 p, double r) const;
  /// When the cells settle it, sets `nearest` to exactly what StripTree::nearest(p, scratch,
  /// r) gives for these segments and returns true: no segment within r, or a single closest
  /// one (its squared distance below those of all others). False (nearest untouched) for a
  /// tie, a box of more than 64 cells, or a NaN or infinite p or r.
  bool nearest(Vec2 p, double r, NearestSegment& nearest) const;
  /// The squared distance of nearest(p, r), also for ties: true with what StripTree::nearest
  /// gives as distance2, false (distance2 untouched) when the cells cannot tell.
  bool nearestDistance2(Vec2 p, double r, double& distance2) const;
  /// The smallest value[s] over the segments s listed in the cells that the square of half
  /// side r around p overlaps (a superset of the segments within r of p; +infinity for none):
  /// true, or false (smallest untouched) for a box of more than 64 cells, a NaN or infinite
  /// p or r, or a `value` list without one entry per segment.
  bool smallestValue(Vec2 p, double r, const std::vector<double>& value, double& smallest) const;
  /// The smallest value[s] over the segments s within r of the segment from a to b (exactly:
  /// segmentSegmentDistance2; +infinity for none): true, or false (smallest untouched) for a
  /// box of more than 64 cells, a NaN or infinite a, b or r, or a `value` list without one
  /// entry per segment.
  bool smallestValueNear(Vec2 a,
    Vec2 b,
    double r,
    const std::vector<double>& value,
    double& smallest) const;
  /// True only when no segment has a point more than `depth` inside the counter-clockwise
  /// triangle abc (its distance to the nearest of the triangle's side lines; points within a
  /// relative 1e-6 of `depth` count as deeper). False when the cells cannot tell: a box of
  /// more than 64 cells, a NaN or infinite corner, a side of length zero or depth <= 0.
  bool noneInside(Vec2 a, Vec2 b, Vec2 c, double depth) const;
  /// The first crossing of the ray p + s u (u of unit length) with a segment for s in
  /// (from, to): the smallest such s at which the ray's line meets a segment not parallel to
  /// it (exactly, up to rounding), +infinity for none. True with `s` set, or false (s
  /// untouched) when the cells cannot tell: a box of more than 64 cells, a NaN or infinite
  /// input, or from > to.
  bool firstCrossing(Vec2 p, Vec2 u, double from, double to, double& s) const;

private:
  bool scan(Vec2 p, double r, bool ties, NearestSegment& nearest) const;

  // Cell index of coordinate v along an axis starting at lo, clamped to [-1, count].
  int cellOf(double v, double lo, int count) const;
  // The cells [i0, i1] x [j0, j1] under the box [xlo, xhi] x [ylo, yhi], clipped to the grid
  // (an empty range for a box beside it).
  struct CellRange
  {
    int i0, i1, j0, j1;
  };
  CellRange cellsUnder(double xlo, double xhi, double ylo, double yhi) const;
  int emptyCells(int i0, int i1, int j0, int j1) const;
  // visit(s) for each segment s listed in the cells under the box [xlo, xhi] x [ylo, yhi] (a
  // segment in several cells more than once): false, visiting none, for more than 64 cells.
  template<typename Visit>
  bool forEachUnder(double xlo, double xhi, double ylo, double yhi, Visit&& visit) const;
  // The smallest value[s] over the segments s listed in the cells under the box that
  // counts(s) accepts (+infinity for none): false for a box of more than 64 cells.
  template<typename Counts>
  bool smallestUnder(double xlo,
    double xhi,
    double ylo,
    double yhi,
    const std::vector<double>& value,
    Counts&& counts,
    double& smallest) const;

  std::vector<Vec2> A, B;
  Vec2 Origin;
  double Cell = 0.0, InvCell = 0.0, Margin = 0.0;
  int Nx = 0, Ny = 0;
  // The segments near cell j Nx + i: Items[Start[j Nx + i] .. Start[j Nx + i + 1]).
  LargeVector<std::uint32_t> Start;
  LargeVector<int> Items;
};

} // namespace strata

#endif
