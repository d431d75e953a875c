// Tests of the strip tree: exact nearest-segment queries, compared with a brute-force scan.
#include "StripTree.h"

#include "CoreTestUtilities.h"
#include "Errors.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace
{

using strata::NearestSegment;
using strata::StripTree;
using strata::StripTreeScratch;
using strata::Vec2;

using strata_test::kModels;
using strata_test::randomPoints;

struct Segments
{
  std::vector<Vec2> a, b;
  strata::Box2 box;
};

// The segments of every cell of a model file (consecutive points of each cell; polygon cells
// also get their closing segment). No Model involved: the tree works on any segment soup.
Segments readSegments(const std::string& name)
{
  const strata::RawPolylines raw = strata_test::readVtpAscii(strata_test::dataPath(name));
  Segments s;
  for (std::size_t c = 0; c < raw.numberOfCells(); ++c)
  {
    const std::int64_t begin = raw.offsets[c];
    const std::int64_t end = raw.offsets[c + 1];
    for (std::int64_t k = begin; k + 1 < end; ++k)
    {
      s.a.push_back(raw.points[raw.connectivity[k]]);
      s.b.push_back(raw.points[raw.connectivity[k + 1]]);
    }
    if (!raw.kinds.empty() && raw.kinds[c] == strata::CellKind::Polygon && end - begin > 2)
    {
      s.a.push_back(raw.points[raw.connectivity[end - 1]]);
      s.b.push_back(raw.points[raw.connectivity[begin]]);
    }
  }
  for (std::size_t i = 0; i < s.a.size(); ++i)
  {
    s.box.add(s.a[i]);
    s.box.add(s.b[i]);
  }
  return s;
}

// The plain reference: the minimum of pointSegmentDistance2 over all segments.
double plainBruteForce2(const Segments& s, Vec2 p)
{
  return strata_test::bruteForceDistance2(s.a, s.b, p);
}

// The same minimum, faster: segments are grouped in blocks of 16 consecutive ones, and a block
// (or segment) whose bounding box is farther than the best distance so far plus a margin is
// skipped without evaluating pointSegmentDistance2. The margin (1e-9 of the largest
// coordinate magnitude) exceeds the rounding error of the computed distances by orders of
// magnitude, so a skipped segment never has the smaller computed distance: the result is
// bit-identical to plainBruteForce2 (checked by a test below). Still a linear scan.
struct BruteForce
{
  struct Box
  {
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    void add(Vec2 p)
    {
      x0 = std::min(x0, p.x);
      y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x);
      y1 = std::max(y1, p.y);
    }
    double distance2(Vec2 p) const
    {
      const double dx = std::max(std::max(x0 - p.x, p.x - x1), 0.0);
      const double dy = std::max(std::max(y0 - p.y, p.y - y1), 0.0);
      return dx * dx + dy * dy;
    }
  };
  static constexpr std::size_t kBlock = 16;

  explicit BruteForce(const Segments& s)
    : S(s)
  {
    double magnitude = 0.0;
    for (std::size_t i = 0; i < s.a.size(); ++i)
    {
      Box box;
      box.add(s.a[i]);
      box.add(s.b[i]);
      Boxes.push_back(box);
      if (i % kBlock == 0)
      {
        Blocks.emplace_back();
      }
      Blocks.back().add(s.a[i]);
      Blocks.back().add(s.b[i]);
      magnitude = std::max({ magnitude,
        std::abs(s.a[i].x),
        std::abs(s.a[i].y),
        std::abs(s.b[i].x),
        std::abs(s.b[i].y) });
    }
    Margin = 1e-9 * magnitude;
  }

  double nearest2(Vec2 p) const
  {
    double best = HUGE_VAL;
    double threshold2 = HUGE_VAL;
    auto scanBlock = [&](std::size_t k)
    {
      const std::size_t end = std::min(Boxes.size(), (k + 1) * kBlock);
      for (std::size_t i = k * kBlock; i < end; ++i)
      {
        if (Boxes[i].distance2(p) > threshold2)
        {
          continue;
        }
        const double d2 = strata::pointSegmentDistance2(p, S.a[i], S.b[i]);
        if (d2 < best)
        {
          best = d2;
          const double t = std::sqrt(best) + Margin;
          threshold2 = t * t;
        }
      }
    };
    // Start with the block of the nearest box for a tight threshold, then scan all blocks.
    std::size_t first = 0;
    double firstD2 = HUGE_VAL;
    for (std::size_t k = 0; k < Blocks.size(); ++k)
    {
      const double d2 = Blocks[k].distance2(p);
      if (d2 < firstD2)
      {
        firstD2 = d2;
        first = k;
      }
    }
    if (!Blocks.empty())
    {
      scanBlock(first);
    }
    for (std::size_t k = 0; k < Blocks.size(); ++k)
    {
      if (Blocks[k].distance2(p) <= threshold2)
      {
        scanBlock(k);
      }
    }
    return best;
  }

  const Segments& S;
  std::vector<Box> Boxes, Blocks;
  double Margin = 0.0;
};

// Runs body(i, scratch) for i in [0, n) on all cores, one scratch per thread.
void parallelFor(std::size_t n, const std::function<void(std::size_t, StripTreeScratch&)>& body)
{
  const unsigned threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  std::atomic<std::size_t> next{ 0 };
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
  {
    pool.emplace_back(
      [&]()
      {
        StripTreeScratch scratch;
        for (std::size_t i = next.fetch_add(256); i < n; i = next.fetch_add(256))
        {
          for (std::size_t j = i; j < std::min(n, i + 256); ++j)
          {
            body(j, scratch);
          }
        }
      });
  }
  for (std::thread& t : pool)
  {
    t.join();
  }
}

// Checks the tree against brute force at every point: exact distance (relative error below
// 1e-12; exactly 0 when brute force gives 0) and a result consistent with its own segment.
// Returns the number of mismatches and describes the first one.
std::size_t compareWithBruteForce(const Segments& s,
  const StripTree& tree,
  const std::vector<Vec2>& points,
  std::string& first)
{
  const BruteForce bruteForce(s);
  std::atomic<std::size_t> bad{ 0 };
  std::vector<std::string> messages(points.size());
  parallelFor(points.size(),
    [&](std::size_t i, StripTreeScratch& scratch)
    {
      const Vec2 p = points[i];
      const NearestSegment ns = tree.nearest(p, scratch);
      const double bf2 = bruteForce.nearest2(p);
      bool ok = ns.segment >= 0 && ns.segment < static_cast<int>(s.a.size());
      if (ok)
      {
        double t;
        const double own2 = strata::pointSegmentDistance2(p, s.a[ns.segment], s.b[ns.segment], &t);
        ok = own2 == ns.distance2 && t == ns.t && ns.t >= 0.0 && ns.t <= 1.0;
      }
      if (ok)
      {
        const double d = std::sqrt(ns.distance2);
        const double bf = std::sqrt(bf2);
        ok = bf2 == 0.0 ? ns.distance2 == 0.0 : std::abs(d - bf) <= 1e-12 * bf;
      }
      if (!ok)
      {
        std::ostringstream msg;
        msg.precision(17);
        msg << "p = (" << p.x << ", " << p.y << "): tree gives segment " << ns.segment
            << " at distance^2 " << ns.distance2 << " (t = " << ns.t << "), brute force " << bf2;
        messages[i] = msg.str();
        ++bad;
      }
    });
  for (const std::string& m : messages)
  {
    if (!m.empty())
    {
      first = m;
      break;
    }
  }
  return bad;
}

} // namespace

TEST(StripTreeTest, empty_tree_finds_no_segment)
{
  StripTreeScratch scratch;
  const StripTree tree;
  EXPECT_EQ(tree.numberOfSegments(), 0u);
  EXPECT_EQ(tree.numberOfNodes(), 0u);
  const NearestSegment ns = tree.nearest({ 1.0, 2.0 }, scratch);
  EXPECT_EQ(ns.segment, -1);
  EXPECT_EQ(ns.distance2, HUGE_VAL);

  const StripTree built(std::vector<Vec2>{}, std::vector<Vec2>{});
  EXPECT_EQ(built.nearest({ 0.0, 0.0 }, scratch).segment, -1);
}

TEST(StripTreeTest, mismatched_segment_ends_throw_parameter_error)
{
  EXPECT_THROW(StripTree({ { 0, 0 }, { 1, 0 } }, { { 1, 0 } }), strata::ParameterError);
}

TEST(StripTreeTest, single_segment_gives_exact_distance_and_parameter)
{
  StripTreeScratch scratch;
  const StripTree tree({ { 0.0, 0.0 } }, { { 4.0, 0.0 } });
  EXPECT_EQ(tree.numberOfNodes(), 1u);
  EXPECT_EQ(tree.segmentStart(0), Vec2({ 0.0, 0.0 }));
  EXPECT_EQ(tree.segmentEnd(0), Vec2({ 4.0, 0.0 }));

  NearestSegment ns = tree.nearest({ 1.0, 3.0 }, scratch);
  EXPECT_EQ(ns.segment, 0);
  EXPECT_EQ(ns.distance2, 9.0);
  EXPECT_EQ(ns.t, 0.25);

  ns = tree.nearest({ -3.0, 4.0 }, scratch); // beyond the start
  EXPECT_EQ(ns.distance2, 25.0);
  EXPECT_EQ(ns.t, 0.0);

  ns = tree.nearest({ 7.0, -4.0 }, scratch); // beyond the end
  EXPECT_EQ(ns.distance2, 25.0);
  EXPECT_EQ(ns.t, 1.0);

  ns = tree.nearest({ 2.0, 0.0 }, scratch); // on the segment
  EXPECT_EQ(ns.distance2, 0.0);
  EXPECT_EQ(ns.t, 0.5);
}

TEST(StripTreeTest, zero_length_segment_is_its_point)
{
  StripTreeScratch scratch;
  const StripTree single({ { 1.0, 1.0 } }, { { 1.0, 1.0 } });
  NearestSegment ns = single.nearest({ 4.0, 5.0 }, scratch);
  EXPECT_EQ(ns.segment, 0);
  EXPECT_EQ(ns.distance2, 25.0);
  EXPECT_EQ(ns.t, 0.0);
  EXPECT_EQ(single.nearest({ 1.0, 1.0 }, scratch).distance2, 0.0);

  // Zero-length segments mixed into a curve, and a whole run collapsed to one point.
  Segments s;
  for (int i = 0; i < 100; ++i)
  {
    const Vec2 p{ std::cos(0.1 * i), std::sin(0.1 * i) };
    s.a.push_back(p);
    s.b.push_back(i % 3 == 0 ? p : Vec2{ std::cos(0.1 * (i + 1)), std::sin(0.1 * (i + 1)) });
  }
  for (int i = 0; i < 40; ++i)
  {
    s.a.push_back({ 2.0, 2.0 });
    s.b.push_back({ 2.0, 2.0 });
  }
  for (std::size_t i = 0; i < s.a.size(); ++i)
  {
    s.box.add(s.a[i]);
    s.box.add(s.b[i]);
  }
  const StripTree tree(s.a, s.b);
  std::mt19937_64 rng(7);
  std::vector<Vec2> points = randomPoints(s.box, 0.5, 20000, rng);
  points.push_back({ 2.0, 2.0 });
  points.insert(points.end(), s.a.begin(), s.a.end());
  std::string first;
  EXPECT_EQ(compareWithBruteForce(s, tree, points, first), 0u) << first;
}

TEST(StripTreeTest, nan_query_point_finds_no_segment_and_terminates)
{
  const Segments s = readSegments("lake_superior.vtp");
  const StripTree tree(s.a, s.b);
  StripTreeScratch scratch;
  const NearestSegment ns = tree.nearest({ std::nan(""), 0.0 }, scratch);
  EXPECT_EQ(ns.segment, -1);
  EXPECT_EQ(ns.distance2, HUGE_VAL);
}

TEST(StripTreeTest, tree_has_two_n_minus_one_nodes)
{
  for (int n : { 1, 2, 3, 7, 8, 9, 100, 1023, 1024, 1025 })
  {
    std::vector<Vec2> a(n), b(n);
    for (int i = 0; i < n; ++i)
    {
      a[i] = { double(i), 0.0 };
      b[i] = { double(i + 1), 0.0 };
    }
    const StripTree tree(a, b);
    EXPECT_EQ(tree.numberOfSegments(), std::size_t(n));
    EXPECT_EQ(tree.numberOfNodes(), std::size_t(2 * n - 1));
  }
}

TEST(StripTreeTest, nearest_equals_brute_force_on_random_points)
{
  // 1e5 points per model in the model's box grown by 10% on each side.
  std::mt19937_64 rng(12345);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    ASSERT_FALSE(s.a.empty());
    const StripTree tree(s.a, s.b);
    const std::vector<Vec2> points = randomPoints(s.box, 0.1, 100000, rng);
    std::string first;
    EXPECT_EQ(compareWithBruteForce(s, tree, points, first), 0u) << first;
  }
}

TEST(StripTreeTest, brute_force_reference_with_box_skipping_equals_plain_scan)
{
  std::mt19937_64 rng(8);
  for (const std::string& name : { "lake_superior_full.vtp", "countries_westeurope.vtp" })
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    const BruteForce bruteForce(s);
    std::vector<Vec2> points = randomPoints(s.box, 0.1, 3000, rng);
    points.insert(points.end(), s.a.begin(), s.a.begin() + 1000);
    for (std::size_t i = 0; i < 1000; ++i)
    {
      points.push_back(s.a[i] + 0.3 * (s.b[i] - s.a[i]));
    }
    std::size_t differ = 0;
    for (const Vec2 p : points)
    {
      differ += bruteForce.nearest2(p) != plainBruteForce2(s, p);
    }
    EXPECT_EQ(differ, 0u);
  }
}

TEST(StripTreeTest, nearest_equals_brute_force_far_outside)
{
  // Points 10 to 1e6 model sizes away: many nodes have nearly equal bounds.
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  std::uniform_real_distribution<double> exponent(1.0, 6.0);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    const StripTree tree(s.a, s.b);
    const double size = s.box.diagonal();
    std::vector<Vec2> points;
    for (int i = 0; i < 5000; ++i)
    {
      const double r = size * std::pow(10.0, exponent(rng));
      const double phi = angle(rng);
      points.push_back(s.box.center() + Vec2{ r * std::cos(phi), r * std::sin(phi) });
    }
    std::string first;
    EXPECT_EQ(compareWithBruteForce(s, tree, points, first), 0u) << first;
  }
}

TEST(StripTreeTest, bounded_query_finds_the_nearest_within_its_radius_and_nothing_beyond)
{
  // With maxDistance r: the exact nearest when it is nearer than r, else segment -1; r at
  // 0.5, 1 and 2 times the true distance of each random point.
  std::mt19937_64 rng(7);
  for (const std::string& name : { "lake_superior_full.vtp", "geology_marmousi.vtp" })
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    const StripTree tree(s.a, s.b);
    StripTreeScratch scratch;
    std::size_t wrong = 0;
    for (const Vec2 p : randomPoints(s.box, 0.1, 20000, rng))
    {
      const double d2 = plainBruteForce2(s, p);
      for (const double f : { 0.5, 1.0, 2.0 })
      {
        const double r = f * std::sqrt(d2);
        const strata::NearestSegment n = tree.nearest(p, scratch, r);
        const bool nearer = d2 < r * r;
        wrong += nearer ? (n.segment < 0 || n.distance2 != d2) : n.segment >= 0;
      }
    }
    EXPECT_EQ(wrong, 0u);
  }
}

TEST(StripTreeTest, nearest_is_zero_on_vertices_and_segment_interiors)
{
  // Every vertex (distance exactly 0) and a point inside every segment (distance 0 or a
  // rounding residue, equal to brute force).
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    const StripTree tree(s.a, s.b);
    std::vector<Vec2> vertices, interior;
    for (std::size_t i = 0; i < s.a.size(); ++i)
    {
      vertices.push_back(s.a[i]);
      vertices.push_back(s.b[i]);
      const Vec2 d = s.b[i] - s.a[i];
      interior.push_back(s.a[i] + u(rng) * d);
      interior.push_back(s.a[i] + 0.5 * d);
      // Axis-aligned segments give exact interior points.
      if (d.x == 0.0 || d.y == 0.0)
      {
        interior.push_back(s.a[i] + 0.25 * d);
      }
    }
    StripTreeScratch scratch;
    std::size_t nonzero = 0;
    for (const Vec2 v : vertices)
    {
      nonzero += tree.nearest(v, scratch).distance2 != 0.0;
    }
    EXPECT_EQ(nonzero, 0u);
    std::string first;
    EXPECT_EQ(compareWithBruteForce(s, tree, interior, first), 0u) << first;
  }
}

TEST(StripTreeTest, nearest_equals_brute_force_on_degenerate_layouts)
{
  // Collinear runs (widths 0), duplicated segments, a segment soup with no connectivity, and
  // points exactly on the common line.
  Segments s;
  for (int i = 0; i < 500; ++i)
  {
    s.a.push_back({ double(i), 0.0 });
    s.b.push_back({ double(i + 1), 0.0 });
  }
  for (int i = 0; i < 100; ++i)
  {
    s.a.push_back({ 10.0, 5.0 });
    s.b.push_back({ 20.0, 5.0 });
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-50.0, 550.0);
  for (int i = 0; i < 500; ++i)
  {
    s.a.push_back({ u(rng), u(rng) });
    s.b.push_back({ u(rng), u(rng) });
  }
  for (std::size_t i = 0; i < s.a.size(); ++i)
  {
    s.box.add(s.a[i]);
    s.box.add(s.b[i]);
  }
  const StripTree tree(s.a, s.b);
  std::vector<Vec2> points = randomPoints(s.box, 0.2, 20000, rng);
  for (int i = 0; i < 2000; ++i)
  {
    points.push_back({ u(rng), 0.0 });
    points.push_back({ u(rng), 5.0 });
  }
  std::string first;
  EXPECT_EQ(compareWithBruteForce(s, tree, points, first), 0u) << first;
}

TEST(StripTreeTest, nearest_equals_brute_force_on_a_million_segment_curve)
{
  // Closed flower curve (the root's central segment has length 0), 1e6 segments.
  const int n = 1000000;
  Segments s;
  s.a.resize(n);
  s.b.resize(n);
  auto curve = [n](int i)
  {
    const double t = 2.0 * M_PI * (i % n) / n;
    const double r = 1.0 + 0.3 * std::sin(17.0 * t) + 0.05 * std::sin(911.0 * t);
    return Vec2{ r * std::cos(t), r * std::sin(t) };
  };
  for (int i = 0; i < n; ++i)
  {
    s.a[i] = curve(i);
    s.b[i] = curve(i + 1);
    s.box.add(s.a[i]);
  }
  const StripTree tree(s.a, s.b);
  EXPECT_EQ(tree.numberOfNodes(), std::size_t(2 * n - 1));
  std::mt19937_64 rng(1);
  const std::vector<Vec2> points = randomPoints(s.box, 0.0, 300, rng);
  std::string first;
  EXPECT_EQ(compareWithBruteForce(s, tree, points, first), 0u) << first;
}

TEST(StripTreeTest, warm_scratch_does_not_grow)
{
  const Segments s = readSegments("lake_superior_full.vtp");
  const StripTree tree(s.a, s.b);
  std::mt19937_64 rng(5);
  const std::vector<Vec2> points = randomPoints(s.box, 0.5, 20000, rng);
  StripTreeScratch scratch;
  for (const Vec2 p : points)
  {
    tree.nearest(p, scratch);
  }
  const std::size_t capacity = scratch.heap.capacity();
  const auto* data = scratch.heap.data();
  for (const Vec2 p : points)
  {
    tree.nearest(p, scratch);
  }
  EXPECT_EQ(scratch.heap.capacity(), capacity);
  EXPECT_EQ(scratch.heap.data(), data);
}

TEST(StripTreeTest, concurrent_queries_with_own_scratch_agree_with_serial_ones)
{
  const Segments s = readSegments("countries_westeurope.vtp");
  const StripTree tree(s.a, s.b);
  std::mt19937_64 rng(6);
  const std::vector<Vec2> points = randomPoints(s.box, 0.1, 50000, rng);
  std::vector<NearestSegment> serial(points.size());
  StripTreeScratch scratch;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    serial[i] = tree.nearest(points[i], scratch);
  }
  std::vector<std::thread> threads;
  std::atomic<int> mismatches{ 0 };
  for (int t = 0; t < 4; ++t)
  {
    threads.emplace_back(
      [&, t]()
      {
        StripTreeScratch own;
        for (std::size_t i = t; i < points.size(); i += 2)
        {
          const NearestSegment ns = tree.nearest(points[i], own);
          if (ns.segment != serial[i].segment || ns.distance2 != serial[i].distance2 ||
            ns.t != serial[i].t)
          {
            ++mismatches;
          }
        }
      });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
  EXPECT_EQ(mismatches, 0);
}

namespace
{

// Whenever a SegmentGrid settles a bounded query, its answer is bit for bit the strip tree's
// (segment, squared distance, parameter), nearestDistance2() the tree's squared distance even
// for ties, and noneWithin() only when the tree finds nothing:
// random points, the vertices and points beside them (ties between the two segments of a
// vertex), radii from a tenth of a cell to ten cells, three cell sizes.
std::size_t compareGridWithTree(const Segments& s,
  const std::vector<Vec2>& points,
  double cell,
  std::size_t& settled,
  std::size_t& queries)
{
  std::size_t settledDistances = 0;
  const StripTree tree(s.a, s.b);
  const strata::SegmentGrid grid(s.a, s.b, cell, std::size_t(1) << 22);
  StripTreeScratch scratch;
  std::size_t wrong = 0;
  for (const Vec2 p : points)
  {
    for (const double f : { 0.1, 0.5, 1.0, 2.0, 10.0 })
    {
      const double r = f * cell;
      const NearestSegment t = tree.nearest(p, scratch, r);
      NearestSegment g;
      g.segment = -7;
      ++queries;
      if (grid.nearest(p, r, g))
      {
        ++settled;
        wrong += g.segment != t.segment || g.distance2 != t.distance2 || g.t != t.t;
      }
      else
      {
        wrong += g.segment != -7; // untouched
      }
      wrong += grid.noneWithin(p, r) && t.segment >= 0;
      double d2 = -1.0;
      const bool told = grid.nearestDistance2(p, r, d2);
      wrong += told ? d2 != t.distance2 : d2 != -1.0;
      settledDistances += told;
    }
  }
  // Ties settle the distance too.
  wrong += settledDistances < settled;
  return wrong;
}

} // namespace

TEST(StripTreeTest, segment_grid_answers_as_the_tree)
{
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Segments s = readSegments(name);
    const double size = std::max(s.box.width(), s.box.height());
    for (const double cell : { size / 64.0, size / 512.0, size / 4096.0 })
    {
      std::vector<Vec2> points = randomPoints(s.box, 0.05, 4000, rng);
      for (std::size_t i = 0; i < s.a.size(); i += 7)
      {
        points.push_back(s.a[i]);
        points.push_back(s.a[i] + 0.3 * cell * Vec2{ u(rng), u(rng) });
        points.push_back(0.5 * (s.a[i] + s.b[i]) + 0.3 * cell * Vec2{ u(rng), u(rng) });
      }
      std::size_t settled = 0, queries = 0;
      EXPECT_EQ(compareGridWithTree(s, points, cell, settled, queries), 0u) << cell;
      // The grid is of use (the Loops files hold every shared curve twice: ties, unsettled).
      EXPECT_GT(settled, queries / 10) << cell;
    }
  }
}

namespace
{
// One value per segment: at random in [0, 1), or +infinity for one in ten.
std::vector<double> randomValues(std::size_t n, std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> value(n);
  for (double& v : value)
  {
    v = u(rng) < 0.1 ? std::numeric_limits<double>::infinity() : u(rng);
  }
  return value;
}

// A point of a random segment of s, moved by up to `reach` along each axis.
Vec2 pointNearSegments(const Segments& s, double reach, std::mt19937_64& rng)
{
  std::uniform_int_distribution<std::size_t> which(0, s.a.size() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t i = which(rng);
  const double t = u(rng), dx = 2.0 * u(rng) - 1.0, dy = 2.0 * u(rng) - 1.0;
  return s.a[i] + t * (s.b[i] - s.a[i]) + reach * Vec2{ dx, dy };
}

// A unit vector in a random direction.
Vec2 randomDirection(std::mt19937_64& rng)
{
  const double angle = 6.283185307179586 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  return { std::cos(angle), std::sin(angle) };
}
} // namespace

TEST(StripTreeTest, segment_grid_smallest_value_covers_every_segment_within_reach)
{
  // smallestValue(p, r) is at most the value of every segment within r of p, and is the value
  // of a segment near the box (within r + a cell diagonal of p in each direction), so that a
  // caller may bound what the segments near p hold: random values, points, radii.
  const Segments s = readSegments("lake_superior.vtp");
  const double size = std::max(s.box.width(), s.box.height());
  std::mt19937_64 rng(17);
  const std::vector<double> value = randomValues(s.a.size(), rng);
  for (const double cell : { size / 64.0, size / 512.0 })
  {
    SCOPED_TRACE(cell);
    const strata::SegmentGrid grid(s.a, s.b, cell, std::size_t(1) << 22);
    std::size_t told = 0, queries = 0, wrong = 0;
    for (const Vec2 p : randomPoints(s.box, 0.05, 1000, rng))
    {
      for (const double f : { 0.0, 0.3, 1.0, 2.5, 10.0 })
      {
        const double r = f * cell;
        double least = -1.0;
        ++queries;
        if (!grid.smallestValue(p, r, value, least))
        {
          wrong += least != -1.0; // untouched
          continue;
        }
        ++told;
        const double far = r + 2.0 * std::sqrt(2.0) * cell;
        bool attained = least == std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < s.a.size(); ++i)
        {
          const double d = std::sqrt(strata::pointSegmentDistance2(p, s.a[i], s.b[i]));
          wrong += d <= r && value[i] < least;
          attained = attained || (value[i] == least && d <= far);
        }
        wrong += !attained;
      }
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(told, queries / 2); // (a box of more than 64 cells is not told)
  }
  const strata::SegmentGrid grid(s.a, s.b, size / 64.0, 1000);
  double least = -1.0;
  EXPECT_FALSE(grid.smallestValue({ 0.0, 0.0 }, 100.0 * size, value, least));
  EXPECT_FALSE(
    grid.smallestValue({ std::numeric_limits<double>::quiet_NaN(), 0.0 }, 1.0, value, least));
  EXPECT_FALSE(grid.smallestValue(s.a[0], 1.0, std::vector<double>(1, 0.0), least));
  EXPECT_EQ(least, -1.0);
}

TEST(StripTreeTest, segment_grid_first_crossing_of_a_ray_is_the_nearest_segment_it_crosses)
{
  // firstCrossing(p, u, from, to) is the smallest s in (from, to) at which p + s u meets a
  // segment: rays of a few lengths from points near the shore, against every segment's
  // crossing found another way (the signed distance to its line, linear along the ray), up to
  // rounding (1e-9 of the model's size) at the segments' ends and the ray's.
  const Segments s = readSegments("lake_superior.vtp");
  const double size = std::max(s.box.width(), s.box.height());
  std::mt19937_64 rng(31);
  const double cell = size / 256.0;
  const strata::SegmentGrid grid(s.a, s.b, cell, std::size_t(1) << 22);
  std::size_t told = 0, queries = 0, wrong = 0, some = 0;
  const double inf = std::numeric_limits<double>::infinity(), slack = 1e-9 * size;
  for (int n = 0; n < 300; ++n)
  {
    // (From the shore itself for half the rays, as the mesher casts them.)
    const Vec2 p = pointNearSegments(s, n % 2 == 0 ? 0.0 : 2.0 * cell, rng);
    const Vec2 dir = randomDirection(rng);
    for (const double length : { 0.5, 3.0 })
    {
      const double from = 1e-7 * length * cell, to = length * cell;
      double first = -1.0;
      ++queries;
      if (!grid.firstCrossing(p, dir, from, to, first))
      {
        wrong += first != -1.0; // untouched
        continue;
      }
      ++told;
      // The first crossing within (from, to) by a margin, and with the margin.
      double inner = inf, outer = inf;
      for (std::size_t k = 0; k < s.a.size(); ++k)
      {
        const Vec2 e = s.b[k] - s.a[k];
        const double g0 = strata::cross(e, p - s.a[k]), g1 = strata::cross(e, p + dir - s.a[k]);
        if (g0 == g1)
        {
          continue; // parallel
        }
        const double at = g0 / (g0 - g1);
        const Vec2 x = p + at * dir;
        const double along = strata::dot(x - s.a[k], e) / strata::dot(e, e);
        const double l = strata::norm(e);
        if (along * l >= slack && (1.0 - along) * l >= slack && at > from + slack &&
          at < to - slack)
        {
          inner = std::min(inner, at);
        }
        if (along * l >= -slack && (1.0 - along) * l >= -slack && at > from - slack &&
          at < to + slack)
        {
          outer = std::min(outer, at);
        }
      }
      wrong += !(first >= outer - slack && first <= inner + slack);
      some += first < inf;
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(told, queries / 2);
  EXPECT_GT(some, queries / 10);
  double first = -1.0;
  EXPECT_FALSE(grid.firstCrossing({ 0.0, 0.0 }, { 1.0, 0.0 }, 0.0, 100.0 * size, first));
  EXPECT_FALSE(grid.firstCrossing(
    { std::numeric_limits<double>::quiet_NaN(), 0.0 }, { 1.0, 0.0 }, 0.0, 1.0, first));
  EXPECT_FALSE(grid.firstCrossing({ 0.0, 0.0 }, { 1.0, 0.0 }, 2.0, 1.0, first));
  EXPECT_EQ(first, -1.0);
}

TEST(StripTreeTest, segment_grid_smallest_value_near_a_segment_is_that_of_the_segments_within_reach)
{
  // smallestValueNear(a, b, r) is exactly the smallest value of the segments within r of the
  // segment ab: random values, query segments of a few lengths, radii. The distance between two
  // segments here: the least distance of a point of ab to cd, convex along ab, by a ternary
  // search.
  const Segments s = readSegments("lake_superior.vtp");
  const double size = std::max(s.box.width(), s.box.height());
  std::mt19937_64 rng(29);
  const std::vector<double> value = randomValues(s.a.size(), rng);
  const auto distance = [](Vec2 a, Vec2 b, Vec2 c, Vec2 d)
  {
    const auto at = [&](double t)
    { return std::sqrt(strata::pointSegmentDistance2(a + t * (b - a), c, d)); };
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 100; ++k)
    {
      const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
      if (at(m1) <= at(m2))
      {
        hi = m2;
      }
      else
      {
        lo = m1;
      }
    }
    return std::min({ at(0.0), at(1.0), at(0.5 * (lo + hi)) });
  };
  const double cell = size / 256.0;
  const strata::SegmentGrid grid(s.a, s.b, cell, std::size_t(1) << 22);
  std::size_t told = 0, queries = 0, wrong = 0, some = 0;
  // (Query segments from points within two cells of a random segment of the shore.)
  for (int n = 0; n < 150; ++n)
  {
    const Vec2 p = pointNearSegments(s, 2.0 * cell, rng);
    for (const double length : { 0.0, 0.5, 3.0 })
    {
      const Vec2 q = p + length * cell * randomDirection(rng);
      for (const double f : { 0.0, 0.3, 1.0 })
      {
        const double r = f * cell;
        double least = -1.0;
        ++queries;
        if (!grid.smallestValueNear(p, q, r, value, least))
        {
          wrong += least != -1.0; // untouched
          continue;
        }
        ++told;
        // The smallest value within r, and within r up to rounding (1e-9 of the model's size).
        const double inf = std::numeric_limits<double>::infinity(), slack = 1e-9 * size;
        double inner = inf, outer = inf;
        for (std::size_t i = 0; i < s.a.size(); ++i)
        {
          const double d = std::min(std::sqrt(strata::pointSegmentDistance2(p, s.a[i], s.b[i])),
            std::sqrt(strata::pointSegmentDistance2(q, s.a[i], s.b[i])));
          if (d - r > length * cell + slack)
          {
            continue; // (no point of pq is within r)
          }
          const double exact = distance(p, q, s.a[i], s.b[i]);
          inner = exact <= r - slack ? std::min(inner, value[i]) : inner;
          outer = exact <= r + slack ? std::min(outer, value[i]) : outer;
        }
        wrong += !(outer <= least && least <= inner);
        some += least < std::numeric_limits<double>::infinity();
      }
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(told, queries / 2);
  EXPECT_GT(some, queries / 4);
  double least = -1.0;
  EXPECT_FALSE(grid.smallestValueNear({ 0.0, 0.0 }, { 1.0, 0.0 }, 100.0 * size, value, least));
  EXPECT_FALSE(grid.smallestValueNear(
    { std::numeric_limits<double>::quiet_NaN(), 0.0 }, { 0.0, 0.0 }, 1.0, value, least));
  EXPECT_FALSE(grid.smallestValueNear(s.a[0], s.b[0], 1.0, std::vector<double>(1, 0.0), least));
  EXPECT_EQ(least, -1.0);
}

TEST(StripTreeTest, segment_grid_none_inside_only_when_no_segment_reaches_that_deep)
{
  // noneInside(a, b, c, depth) is true only when no segment has a point more than depth inside
  // the triangle (the distance to its nearest side line; brute force: the largest such
  // distance along each segment, a concave piecewise-linear function, at the segment's ends
  // and where two sides' distances cross), and it is of use: random triangles about a cell
  // wide over the model, depths from 2% to 90% of their inradius.
  const Segments s = readSegments("lake_superior.vtp");
  const double size = std::max(s.box.width(), s.box.height());
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto deepest = [&](Vec2 a, Vec2 b, Vec2 c)
  {
    const Vec2 corner[3] = { a, b, c };
    double best = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < s.a.size(); ++i)
    {
      double f0[3], f1[3];
      for (int k = 0; k < 3; ++k)
      {
        const Vec2 e = corner[(k + 1) % 3] - corner[k];
        const Vec2 d = (1.0 / strata::norm(e)) * e;
        f0[k] = strata::cross(d, s.a[i] - corner[k]);
        f1[k] = strata::cross(d, s.b[i] - corner[k]);
      }
      std::vector<double> ts = { 0.0, 1.0 };
      for (int k = 0; k < 3; ++k)
      {
        for (int l = k + 1; l < 3; ++l)
        {
          const double den = (f1[k] - f0[k]) - (f1[l] - f0[l]);
          if (den != 0.0)
          {
            const double t = (f0[l] - f0[k]) / den;
            if (t > 0.0 && t < 1.0)
            {
              ts.push_back(t);
            }
          }
        }
      }
      for (const double t : ts)
      {
        double inside = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k)
        {
          inside = std::min(inside, f0[k] + t * (f1[k] - f0[k]));
        }
        best = std::max(best, inside);
      }
    }
    return best;
  };
  for (const double cell : { size / 64.0, size / 512.0 })
  {
    SCOPED_TRACE(cell);
    const strata::SegmentGrid grid(s.a, s.b, cell, std::size_t(1) << 22);
    std::size_t told = 0, reached = 0, wrong = 0;
    for (std::size_t n = 0; n < 1500; ++n)
    {
      // Half the triangles around a curve point, half anywhere in the box.
      const std::size_t i = static_cast<std::size_t>(u(rng) * (s.a.size() - 1));
      const Vec2 centre = n % 2 == 0
        ? s.a[i] + cell * Vec2{ u(rng) - 0.5, u(rng) - 0.5 }
        : Vec2{ s.box.min.x + u(rng) * s.box.width(), s.box.min.y + u(rng) * s.box.height() };
      const double r = cell * (0.3 + 1.5 * u(rng));
      const double phi = 6.283185307179586 * u(rng);
      const Vec2 a = centre + r * Vec2{ std::cos(phi), std::sin(phi) };
      const Vec2 b =
        centre + r * Vec2{ std::cos(phi + 2.0 + 0.5 * u(rng)), std::sin(phi + 2.0 + 0.5 * u(rng)) };
      const Vec2 c =
        centre + r * Vec2{ std::cos(phi + 4.2 + 0.5 * u(rng)), std::sin(phi + 4.2 + 0.5 * u(rng)) };
      const double perimeter = strata::norm(b - a) + strata::norm(c - b) + strata::norm(a - c);
      const double inradius = strata::orient2d(a, b, c) / perimeter;
      if (!(inradius > 0.0))
      {
        continue;
      }
      const double depth = inradius * (0.02 + 0.88 * u(rng));
      const double deep = deepest(a, b, c);
      reached += deep > depth;
      if (grid.noneInside(a, b, c, depth))
      {
        ++told;
        wrong += deep > depth;
      }
    }
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(told, 300u);   // most triangles no curve reaches into are told
    EXPECT_GT(reached, 50u); // and the sample holds triangles a curve reaches into
  }
  // A triangle beside the grid (which holds every segment): none. What the cells cannot tell:
  // no grid, a NaN corner, a depth of zero, a side of length zero, a box of more than 64 cells.
  const strata::SegmentGrid grid(s.a, s.b, size / 512.0, std::size_t(1) << 22);
  const Vec2 a = s.box.min, b = a + Vec2{ 1e-3 * size, 0.0 }, c = a + Vec2{ 0.0, 1e-3 * size };
  EXPECT_TRUE(grid.noneInside(
    a - Vec2{ size, size }, b - Vec2{ size, size }, c - Vec2{ size, size }, 1e-6 * size));
  EXPECT_FALSE(strata::SegmentGrid({}, {}, 1.0, 100).noneInside(a, b, c, 1e-6 * size));
  EXPECT_FALSE(grid.noneInside({ std::numeric_limits<double>::quiet_NaN(), 0.0 }, b, c, 1.0));
  EXPECT_FALSE(grid.noneInside(a, b, c, 0.0));
  EXPECT_FALSE(grid.noneInside(a, a, c, 1e-6 * size));
  EXPECT_FALSE(grid.noneInside(
    s.box.min, s.box.min + Vec2{ size, 0.0 }, s.box.min + Vec2{ 0.0, size }, 1e-6 * size));
}

TEST(StripTreeTest, segment_grid_answers_as_the_tree_on_degenerate_layouts)
{
  // Collinear runs, duplicated segments (ties everywhere near them), a zero-length segment, a
  // segment soup, and points on the common lines; also no segment at all and NaN queries.
  Segments s;
  for (int i = 0; i < 500; ++i)
  {
    s.a.push_back({ double(i), 0.0 });
    s.b.push_back({ double(i + 1), 0.0 });
  }
  for (int i = 0; i < 10; ++i)
  {
    s.a.push_back({ 10.0, 5.0 });
    s.b.push_back({ 20.0, 5.0 });
  }
  s.a.push_back({ 30.0, 30.0 });
  s.b.push_back({ 30.0, 30.0 });
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-50.0, 550.0);
  for (int i = 0; i < 300; ++i)
  {
    s.a.push_back({ u(rng), u(rng) });
    s.b.push_back({ s.a.back().x + 0.01 * u(rng), s.a.back().y + 0.01 * u(rng) });
  }
  for (std::size_t i = 0; i < s.a.size(); ++i)
  {
    s.box.add(s.a[i]);
    s.box.add(s.b[i]);
  }
  std::vector<Vec2> points = randomPoints(s.box, 0.2, 5000, rng);
  for (int i = 0; i < 1000; ++i)
  {
    points.push_back({ u(rng), 0.0 });
    points.push_back({ u(rng), 5.0 });
    points.push_back({ std::floor(u(rng)), 0.0 });
  }
  points.push_back({ 30.0, 30.0 });
  for (const double cell : { 0.5, 3.0, 40.0 })
  {
    std::size_t settled = 0, queries = 0;
    EXPECT_EQ(compareGridWithTree(s, points, cell, settled, queries), 0u) << cell;
  }
  const strata::SegmentGrid none({}, {}, 1.0, 100);
  NearestSegment n;
  EXPECT_FALSE(none.nearest({ 0.0, 0.0 }, 1.0, n));
  EXPECT_FALSE(none.noneWithin({ 0.0, 0.0 }, 1.0));
  const strata::SegmentGrid grid(s.a, s.b, 1.0, 1000);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(grid.nearest({ nan, 0.0 }, 1.0, n));
  EXPECT_FALSE(grid.nearest({ 0.0, 0.0 }, HUGE_VAL, n));
  EXPECT_FALSE(grid.noneWithin({ 0.0, nan }, 1.0));
  EXPECT_THROW(strata::SegmentGrid(s.a, {}, 1.0, 1000), strata::ParameterError);
}
