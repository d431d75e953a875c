// Queries per second of the strip tree (against brute force) and of the distance field.
//   bench_distance --benchmark_min_time=0.5
// items_per_second is queries per second (construction benchmarks: segments per second).
// Query points: fixed-seed uniform random points in the curve's bounding box.
#include "DistanceField.h"
#include "Model.h"
#include "StripTree.h"
#include "VtpAscii.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace
{

using strata::Box2;
using strata::Vec2;

struct Curve
{
  std::vector<Vec2> a, b;
  Box2 box;
};

std::vector<Vec2> queryPoints(const Box2& box, std::size_t n = 1 << 16)
{
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> ux(box.min.x, box.max.x);
  std::uniform_real_distribution<double> uy(box.min.y, box.max.y);
  std::vector<Vec2> points(n);
  for (Vec2& p : points)
  {
    p = { ux(rng), uy(rng) };
  }
  return points;
}

const strata::Model& lakeModel()
{
  static const strata::Model model =
    strata::buildModel(strata_test::readVtpAscii(strata_test::dataPath("lake_superior_full.vtp")));
  return model;
}

// All boundary segments of the lake (its one region's rings), local coordinates.
const Curve& lake()
{
  static const Curve curve = []
  {
    Curve c;
    for (const strata::Region& region : lakeModel().regions)
    {
      for (const strata::Ring& ring : region.rings)
      {
        for (std::size_t i = 0; i < ring.points.size(); ++i)
        {
          c.a.push_back(ring.points[i]);
          c.b.push_back(ring.points[(i + 1) % ring.points.size()]);
          c.box.add(ring.points[i]);
        }
      }
    }
    return c;
  }();
  return curve;
}

// Closed flower r = 1 + 0.3 sin(17 t) + 0.05 sin(911 t), 1e6 segments.
const Curve& flower()
{
  static const Curve curve = []
  {
    const int n = 1000000;
    auto point = [n](int i)
    {
      const double t = 2.0 * M_PI * (i % n) / n;
      const double r = 1.0 + 0.3 * std::sin(17.0 * t) + 0.05 * std::sin(911.0 * t);
      return Vec2{ r * std::cos(t), r * std::sin(t) };
    };
    Curve c;
    c.a.resize(n);
    c.b.resize(n);
    for (int i = 0; i < n; ++i)
    {
      c.a[i] = point(i);
      c.b[i] = point(i + 1);
      c.box.add(c.a[i]);
    }
    return c;
  }();
  return curve;
}

void stripTreeQueries(benchmark::State& state, const Curve& curve, double farFactor = 0.0)
{
  const strata::StripTree tree(curve.a, curve.b);
  std::vector<Vec2> points = queryPoints(curve.box);
  if (farFactor > 0.0)
  {
    // Moved away from the box centre by farFactor box sizes (bounds then differ by a tiny
    // fraction of the distance: a test of their precision).
    const Vec2 c = curve.box.center();
    const double size = std::max(curve.box.width(), curve.box.height());
    for (Vec2& p : points)
    {
      const Vec2 v = p - c;
      const double len = std::sqrt(v.x * v.x + v.y * v.y);
      p = len > 0.0 ? c + (farFactor * size / len) * v : p;
    }
  }
  strata::StripTreeScratch scratch;
  std::size_t i = 0;
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(tree.nearest(points[i++ & (points.size() - 1)], scratch));
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["segments"] = static_cast<double>(curve.a.size());
}

void bruteForceQueries(benchmark::State& state, const Curve& curve)
{
  const std::vector<Vec2> points = queryPoints(curve.box);
  std::size_t i = 0;
  for (auto _ : state)
  {
    const Vec2 p = points[i++ & (points.size() - 1)];
    double best = HUGE_VAL;
    for (std::size_t s = 0; s < curve.a.size(); ++s)
    {
      best = std::min(best, strata::pointSegmentDistance2(p, curve.a[s], curve.b[s]));
    }
    benchmark::DoNotOptimize(best);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["segments"] = static_cast<double>(curve.a.size());
}

void BM_StripTree_Lake(benchmark::State& state)
{
  stripTreeQueries(state, lake());
}
BENCHMARK(BM_StripTree_Lake);

void BM_BruteForce_Lake(benchmark::State& state)
{
  bruteForceQueries(state, lake());
}
BENCHMARK(BM_BruteForce_Lake);

void BM_StripTree_Flower1e6(benchmark::State& state)
{
  stripTreeQueries(state, flower());
}
BENCHMARK(BM_StripTree_Flower1e6);

// Points 1e4 curve sizes away from the curve's centre.
void BM_StripTree_Flower1e6_Far(benchmark::State& state)
{
  stripTreeQueries(state, flower(), 1e4);
}
BENCHMARK(BM_StripTree_Flower1e6_Far);

void BM_BruteForce_Flower1e6(benchmark::State& state)
{
  bruteForceQueries(state, flower());
}
BENCHMARK(BM_BruteForce_Flower1e6)->Unit(benchmark::kMillisecond);

void BM_StripTreeBuild_Flower1e6(benchmark::State& state)
{
  const Curve& curve = flower();
  for (auto _ : state)
  {
    const strata::StripTree tree(curve.a, curve.b);
    benchmark::DoNotOptimize(tree.numberOfNodes());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(curve.a.size()));
}
BENCHMARK(BM_StripTreeBuild_Flower1e6)->Unit(benchmark::kMillisecond);

void BM_SignedDistance_Lake(benchmark::State& state)
{
  const strata::DistanceField field(lakeModel());
  const std::vector<Vec2> points = queryPoints(lakeModel().bounds);
  strata::DistanceField::Scratch scratch;
  std::size_t i = 0;
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(field.signedDistance(0, points[i++ & (points.size() - 1)], scratch));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SignedDistance_Lake);

void BM_Query_Lake(benchmark::State& state)
{
  const strata::DistanceField field(lakeModel());
  const std::vector<Vec2> points = queryPoints(lakeModel().bounds);
  strata::DistanceField::Scratch scratch;
  std::size_t i = 0;
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(field.query(points[i++ & (points.size() - 1)], scratch));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Query_Lake);

} // namespace

BENCHMARK_MAIN();
