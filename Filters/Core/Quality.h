// StrataMesh core: quality measures of triangles and of triangle meshes (angles, radius
// ratio, area) and their summaries. Independent of the mesher: any points + triangles. No VTK.
#ifndef StrataMeshCore_Quality_h
#define StrataMeshCore_Quality_h

#include "Geometry.h"
#include "LargeArray.h"
#include "Progress.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace strata
{

/// Quality of one triangle.
struct TriangleQuality
{
  double minAngle = 0.0;    ///< smallest angle, degrees (0 for a degenerate triangle)
  double maxAngle = 0.0;    ///< largest angle, degrees (180 for a degenerate triangle)
  double radiusRatio = 0.0; ///< 2 * inradius / circumradius: 1 equilateral, 0 degenerate
  double area = 0.0;        ///< signed area: > 0 counter-clockwise, < 0 clockwise
};

/// The three angles of triangle abc in degrees (at a, b, c), computed with atan2 so that they
/// are accurate for needle and cap triangles; each is in [0, 180] and they sum to 180 unless
/// the triangle has a zero-length edge (then the angles at its ends are 0 and the other 180,
/// or all 0 when the triangle is a point).
std::array<double, 3> triangleAngles(Vec2 a, Vec2 b, Vec2 c);

/// Smallest angle of triangle abc in degrees (same conventions as triangleAngles).
double minimumAngle(Vec2 a, Vec2 b, Vec2 c);

/// Cosine of the largest angle of abc (decreasing in the angle; 1 at a zero-length edge's
/// ends), cheaper than triangleAngles where only comparisons are needed.
inline double largestAngleCosine(Vec2 a, Vec2 b, Vec2 c)
{
  const auto cosAt = [](Vec2 p, Vec2 q, Vec2 r)
  {
    const Vec2 u = q - p, v = r - p;
    const double n = norm(u) * norm(v);
    return n > 0.0 ? dot(u, v) / n : 1.0;
  };
  return std::min({ cosAt(a, b, c), cosAt(b, c, a), cosAt(c, a, b) });
}

/// All quality measures of triangle abc.
TriangleQuality triangleQuality(Vec2 a, Vec2 b, Vec2 c);

/// Summary of a mesh's quality.
struct QualitySummary
{
  std::size_t triangles = 0;
  double minAngle = 0.0;               ///< smallest angle of all triangles, degrees
  double maxAngle = 0.0;               ///< largest angle of all triangles, degrees
  double meanMinAngle = 0.0;           ///< mean over triangles of their smallest angle
  double percentAngles30to60 = 0.0;    ///< percent of all angles (3 per triangle) in [30, 60]
  double percentTriangles30to60 = 0.0; ///< percent of triangles whose smallest angle is in [30, 60]
  double minRadiusRatio = 0.0;         ///< smallest radius ratio
  double totalArea = 0.0;              ///< sum of the signed areas
  std::size_t inverted = 0;            ///< triangles with negative signed area
  std::size_t degenerate = 0;          ///< triangles with zero signed area
  /// Number of triangles whose smallest angle falls in [10 k, 10 (k + 1)) degrees, k = 0..5.
  std::array<std::size_t, 6> minAngleHistogram{};
};

/// Quality of every triangle of a mesh (indices into points; throws ParameterError for an
/// index out of range). `progress` is told the fraction done, with `stage`, between blocks of
/// triangles (at 1 M triangles the whole takes 0.03-0.06 s).
LargeVector<TriangleQuality> triangleQualities(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles,
  const ProgressReporter& progress = ProgressReporter(),
  const char* stage = "measuring the triangles");

/// Summary over the given per-triangle qualities (an empty list gives zeros).
QualitySummary summarizeQuality(const LargeVector<TriangleQuality>& qualities);

/// Summary of a mesh's quality (triangleQualities, then summarizeQuality).
QualitySummary summarizeQuality(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles);

} // namespace strata

#endif
