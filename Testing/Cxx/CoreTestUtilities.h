// Helpers shared by the core tests (test-only, header-only): the models of Data/, random
// sample points and the brute-force nearest-segment distance.
#ifndef StrataMesh_CoreTestUtilities_h
#define StrataMesh_CoreTestUtilities_h

#include "DistanceField.h"
#include "Geometry.h"
#include "Model.h"
#include "VtpAscii.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace strata_test
{

/// The models of Data/ used by the data-driven tests.
inline const std::vector<std::string> kModels = { "lake_superior.vtp",
  "lake_superior_full.vtp",
  "nested_holes.vtp",
  "touching_loops.vtp",
  "gulf_section.vtp",
  "gulf_section_loops.vtp",
  "salt_dome.vtp",
  "salt_dome_loops.vtp",
  "countries_westeurope.vtp",
  "countries_westeurope_loops.vtp",
  "geology_marmousi.vtp",
  "pinch_out.vtp",
  "thin_layer.vtp",
  "guitar.vtp" };

/// The model built from a file of Data/.
inline strata::Model loadModel(const std::string& name)
{
  return strata::buildModel(readVtpAscii(dataPath(name)));
}

/// A model of Data/ with its distance field, built once per test program and cached.
struct LoadedModel
{
  strata::Model model;
  std::unique_ptr<strata::DistanceField> field;
};

inline const LoadedModel& loadModelAndField(const std::string& name)
{
  static std::map<std::string, std::unique_ptr<LoadedModel>> cache;
  std::unique_ptr<LoadedModel>& entry = cache[name];
  if (!entry)
  {
    entry = std::make_unique<LoadedModel>();
    entry->model = loadModel(name);
    entry->field = std::make_unique<strata::DistanceField>(entry->model);
  }
  return *entry;
}

/// n uniform random points over `box` grown on every side by margin times its larger side.
inline std::vector<strata::Vec2> randomPoints(const strata::Box2& box,
  double margin,
  std::size_t n,
  std::mt19937_64& rng)
{
  const double mx = margin * std::max(box.width(), box.height());
  std::uniform_real_distribution<double> ux(box.min.x - mx, box.max.x + mx);
  std::uniform_real_distribution<double> uy(box.min.y - mx, box.max.y + mx);
  std::vector<strata::Vec2> points(n);
  for (strata::Vec2& p : points)
  {
    p = { ux(rng), uy(rng) };
  }
  return points;
}

/// The plain brute force: the minimum of pointSegmentDistance2 from p over the segments
/// a[i]-b[i], in index order (HUGE_VAL for none).
inline double bruteForceDistance2(const std::vector<strata::Vec2>& a,
  const std::vector<strata::Vec2>& b,
  strata::Vec2 p)
{
  double best = HUGE_VAL;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    best = std::min(best, strata::pointSegmentDistance2(p, a[i], b[i]));
  }
  return best;
}

/// Adds a cell through the given points (new point ids for each) to hand-made raw input.
inline void addCell(strata::RawPolylines& raw,
  const std::vector<strata::Vec2>& points,
  strata::CellKind kind = strata::CellKind::Line)
{
  if (raw.offsets.empty())
  {
    raw.offsets.push_back(0);
  }
  for (const strata::Vec2& p : points)
  {
    raw.connectivity.push_back(static_cast<std::int64_t>(raw.points.size()));
    raw.points.push_back(p);
  }
  raw.offsets.push_back(static_cast<std::int64_t>(raw.connectivity.size()));
  raw.kinds.push_back(kind);
}

/// A loop of region `region` (Loops form) through the points as given.
inline void addLoop(strata::RawPolylines& raw,
  const std::vector<strata::Vec2>& points,
  int region,
  strata::CellKind kind = strata::CellKind::Line)
{
  addCell(raw, points, kind);
  raw.regionId.push_back(region);
}

/// A loop of region `region` whose last point repeats its first one (explicitly closed).
inline void addClosedLoop(strata::RawPolylines& raw, std::vector<strata::Vec2> points, int region)
{
  points.push_back(points.front());
  addLoop(raw, points, region);
}

/// A curve of the Shared curves form.
inline void addCurve(strata::RawPolylines& raw,
  const std::vector<strata::Vec2>& points,
  int left,
  int right)
{
  addCell(raw, points);
  raw.leftRegion.push_back(left);
  raw.rightRegion.push_back(right);
}

} // namespace strata_test

#endif
