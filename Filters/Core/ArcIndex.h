// StrataMesh core: where a point lies along a polyline (the Delaunay refinement's kept corners'
// sides). No VTK.
#ifndef StrataMeshCore_ArcIndex_h
#define StrataMeshCore_ArcIndex_h

#include "Geometry.h"
#include "Rows.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace strata
{

/// The arc length along the polyline of a point within tol of it (its first such segment), or
/// -1.
inline double arcAlong(const std::vector<Vec2>& line, Vec2 p, double tol)
{
  double sum = 0.0;
  for (std::size_t j = 1; j < line.size(); ++j)
  {
    double u = 0.0;
    const double l = norm(line[j] - line[j - 1]);
    if (pointSegmentDistance2(p, line[j - 1], line[j], &u) <= tol * tol)
    {
      return sum + u * l;
    }
    sum += l;
  }
  return -1.0;
}

/// arcAlong() on a polyline of many segments, the same values: its segments in bins along the
/// longer side of its box (each in every bin its extent overlaps, in order; a query looks in
/// the bins within tol and a rounding margin of it), and the arc length at each segment's
/// start summed as arcAlong() sums it, so that the same segment is found (the first within
/// tol: the least of the bins' first) and the same arc given, without walking the segments
/// before it. (A kept corner's sides along zigzag curves have thousands of points, and each
/// vertex near them walked them all: four horizons of 40 k points 0.5 apart with
/// MinimumEdgeLength 20, 47 -> 21 s.) The first kWalkedQueries queries walk; the bins are made
/// at the next. The line must outlive the index.
class ArcIndex
{
public:
  explicit ArcIndex(const std::vector<Vec2>& line)
    : Line(line)
  {
  }
  /// arcAlong(line, p, tol), the same value.
  double arc(Vec2 p, double tol)
  {
    if (this->Line.size() <= kIndexedPoints || ++this->Queries <= kWalkedQueries)
    {
      return arcAlong(this->Line, p, tol);
    }
    if (this->Start.empty())
    {
      this->index();
    }
    // (A segment the test below accepts passes within tol of p up to rounding, far below the
    // margin: its bins are among those within reach of p.)
    const double c = this->Along ? p.y : p.x;
    const double reach = tol * (1.0 + 1e-9) + this->Margin;
    if (!std::isfinite(c) || !std::isfinite(reach))
    {
      return arcAlong(this->Line, p, tol);
    }
    const int b0 = this->binOf(c - reach), b1 = this->binOf(c + reach);
    int first = -1;
    for (int b = b0; b <= b1; ++b)
    {
      for (std::size_t k = this->BinStart[b]; k < this->BinStart[b + 1]; ++k)
      {
        const int j = this->Items[k];
        if (first >= 0 && j >= first)
        {
          break; // (in order: the rest of the bin comes later)
        }
        if (pointSegmentDistance2(p, this->Line[j], this->Line[j + 1]) <= tol * tol)
        {
          first = j;
          break;
        }
      }
    }
    if (first < 0)
    {
      return -1.0;
    }
    const std::size_t k = static_cast<std::size_t>(first);
    double u = 0.0;
    pointSegmentDistance2(p, this->Line[k], this->Line[k + 1], &u);
    return this->Start[k] + u * norm(this->Line[k + 1] - this->Line[k]);
  }

private:
  static constexpr std::size_t kIndexedPoints = 32; // walked up to this many points
  static constexpr int kWalkedQueries = 2;          // ... and for this many queries

  int binOf(double c) const { return clampedCell((c - this->Lo) * this->InvWidth, this->Bins); }

  void index()
  {
    const std::vector<Vec2>& line = this->Line;
    const std::size_t n = line.size() - 1; // segments
    Box2 box;
    for (const Vec2& q : line)
    {
      box.add(q);
    }
    this->Along = box.height() > box.width(); // bins along y
    this->Margin = 1e-10 * box.scale();
    this->Lo = this->Along ? box.min.y : box.min.x;
    const double extent = this->Along ? box.height() : box.width();
    this->Bins = static_cast<int>(std::min<std::size_t>(n, 1 << 16));
    this->InvWidth = extent > 0.0 ? this->Bins / extent : 0.0;
    this->Start.reserve(n);
    double sum = 0.0;
    for (std::size_t j = 1; j < line.size(); ++j)
    {
      this->Start.push_back(sum);
      sum += norm(line[j] - line[j - 1]);
    }
    groupIntoRows(static_cast<std::size_t>(this->Bins),
      this->BinStart,
      this->Items,
      [&](auto&& emit)
      {
        for (std::size_t j = 0; j < n; ++j)
        {
          const double c0 = this->Along ? line[j].y : line[j].x;
          const double c1 = this->Along ? line[j + 1].y : line[j + 1].x;
          const int b1 = this->binOf(std::max(c0, c1));
          for (int b = this->binOf(std::min(c0, c1)); b <= b1; ++b)
          {
            emit(static_cast<std::size_t>(b), static_cast<int>(j));
          }
        }
      });
  }

  const std::vector<Vec2>& Line;
  int Queries = 0;
  std::vector<double> Start; // the arc length at each segment's start (empty: not indexed)
  bool Along = false;        // bins along y (else x)
  double Lo = 0.0, InvWidth = 0.0, Margin = 0.0; // Margin: the rounding's, at the line's scale
  int Bins = 1;
  std::vector<std::size_t> BinStart;
  std::vector<int> Items;
};

} // namespace strata

#endif
