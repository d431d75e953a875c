// StrataMesh core: triangle quality measures.
//
// Angles come from atan2(|cross|, dot) of the two edge vectors at each corner, which keeps
// full relative accuracy for tiny and for nearly flat angles (acos of a normalised dot product
// loses half the digits near 0 and 180 degrees). The radius ratio is 2 r / R with
// r = 2 A / perimeter and R = (l0 l1 l2) / (4 A), i.e. 16 A^2 / (perimeter l0 l1 l2).
#include "Quality.h"

#include "Errors.h"
#include "Parallel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace strata
{

namespace
{
constexpr double kDegrees = 57.295779513082320876798; // 180 / pi

inline double angleBetween(Vec2 u, Vec2 v)
{
  if ((u.x == 0.0 && u.y == 0.0) || (v.x == 0.0 && v.y == 0.0))
  {
    return 0.0;
  }
  return std::atan2(std::fabs(cross(u, v)), dot(u, v)) * kDegrees;
}
} // namespace

std::array<double, 3> triangleAngles(Vec2 a, Vec2 b, Vec2 c)
{
  std::array<double, 3> angles = {
    angleBetween(b - a, c - a), angleBetween(c - b, a - b), angleBetween(a - c, b - c)
  };
  // A zero-length edge: the corner opposite it sees two equal edges (angle 0, as atan2
  // reports); the angles at its two merged ends are undefined and split the remaining 180.
  const bool ab = a == b, bc = b == c, ca = c == a;
  if (ab && bc)
  {
    angles = { 0.0, 0.0, 0.0 };
  }
  else if (ab)
  {
    angles = { 90.0, 90.0, 0.0 };
  }
  else if (bc)
  {
    angles = { 0.0, 90.0, 90.0 };
  }
  else if (ca)
  {
    angles = { 90.0, 0.0, 90.0 };
  }
  return angles;
}

double minimumAngle(Vec2 a, Vec2 b, Vec2 c)
{
  // The smallest angle is opposite the shortest edge.
  const Vec2 ab = b - a, bc = c - b, ca = a - c;
  const double lab = norm2(ab), lbc = norm2(bc), lca = norm2(ca);
  if (lab == 0.0 || lbc == 0.0 || lca == 0.0)
  {
    return 0.0;
  }
  if (lab <= lbc && lab <= lca)
  {
    return angleBetween(a - c, b - c);
  }
  if (lbc <= lca)
  {
    return angleBetween(b - a, c - a);
  }
  return angleBetween(c - b, a - b);
}

TriangleQuality triangleQuality(Vec2 a, Vec2 b, Vec2 c)
{
  TriangleQuality q;
  const std::array<double, 3> angles = triangleAngles(a, b, c);
  q.minAngle = std::min({ angles[0], angles[1], angles[2] });
  q.maxAngle = std::max({ angles[0], angles[1], angles[2] });
  const double twiceArea = orient2d(a, b, c);
  q.area = 0.5 * twiceArea;
  const double l0 = norm(b - a), l1 = norm(c - b), l2 = norm(a - c);
  const double denominator = (l0 + l1 + l2) * l0 * l1 * l2;
  // 16 A^2 / (P l0 l1 l2) = 4 (2A)^2 / (P l0 l1 l2)
  q.radiusRatio = denominator > 0.0 ? 4.0 * twiceArea * twiceArea / denominator : 0.0;
  q.radiusRatio = std::min(q.radiusRatio, 1.0);
  if (q.area == 0.0)
  {
    q.minAngle = 0.0;
    q.maxAngle = 180.0;
  }
  return q;
}

LargeVector<TriangleQuality> triangleQualities(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles,
  const ProgressReporter& progress,
  const char* stage)
{
  LargeVector<TriangleQuality> out(triangles.size());
  const int n = static_cast<int>(points.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      if (tri[k] < 0 || tri[k] >= n)
      {
        throw ParameterError("triangleQualities: triangle " + std::to_string(t) +
          " refers to point " + std::to_string(tri[k]) + ", not in [0, " + std::to_string(n) + ")");
      }
    }
  }
  // Each triangle on its own: in blocks, each block's two halves at once for large meshes.
  const std::size_t nt = triangles.size();
  blockwise(
    nt,
    4 * kTwoThreadBlock,
    kTwoThreadItems,
    [&](std::size_t from, std::size_t to, int)
    {
      for (std::size_t t = from; t < to; ++t)
      {
        const std::array<int, 3>& tri = triangles[t];
        out[t] = triangleQuality(points[tri[0]], points[tri[1]], points[tri[2]]);
      }
    },
    [&](std::size_t done)
    { progress.report(static_cast<double>(done) / static_cast<double>(nt), stage); });
  return out;
}

QualitySummary summarizeQuality(const LargeVector<TriangleQuality>& qualities)
{
  QualitySummary s;
  s.triangles = qualities.size();
  if (qualities.empty())
  {
    return s;
  }
  s.minAngle = 180.0;
  s.maxAngle = 0.0;
  s.minRadiusRatio = 1.0;
  std::size_t anglesIn = 0, trianglesIn = 0;
  double sumMin = 0.0;
  for (const TriangleQuality& q : qualities)
  {
    s.minAngle = std::min(s.minAngle, q.minAngle);
    s.maxAngle = std::max(s.maxAngle, q.maxAngle);
    s.minRadiusRatio = std::min(s.minRadiusRatio, q.radiusRatio);
    s.totalArea += q.area;
    sumMin += q.minAngle;
    s.inverted += q.area < 0.0;
    s.degenerate += q.area == 0.0;
    // The middle angle is 180 - min - max.
    const double mid = 180.0 - q.minAngle - q.maxAngle;
    for (double angle : { q.minAngle, mid, q.maxAngle })
    {
      anglesIn += angle >= 30.0 && angle <= 60.0;
    }
    trianglesIn += q.minAngle >= 30.0 && q.minAngle <= 60.0;
    const int bin = std::clamp(static_cast<int>(q.minAngle / 10.0), 0, 5);
    ++s.minAngleHistogram[bin];
  }
  const double n = static_cast<double>(qualities.size());
  s.meanMinAngle = sumMin / n;
  s.percentAngles30to60 = 100.0 * static_cast<double>(anglesIn) / (3.0 * n);
  s.percentTriangles30to60 = 100.0 * static_cast<double>(trianglesIn) / n;
  return s;
}

QualitySummary summarizeQuality(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles)
{
  return summarizeQuality(triangleQualities(points, triangles));
}

} // namespace strata
