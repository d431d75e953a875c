// Tests of the signed distance field: the sign is compared with a brute-force even-odd
// crossing-number test over each region's rings, the magnitude with a brute-force distance,
// on random points of every model in Data/ and on adversarial points (vertices, segment
// extensions, corners, horizontal rays through vertices, vertices shared by several rings).
#include "DistanceField.h"

#include "CoreTestUtilities.h"
#include "Errors.h"
#include "Model.h"
#include "VtpAscii.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace
{

using strata::Box2;
using strata::DistanceField;
using strata::Model;
using strata::PointQuery;
using strata::Region;
using strata::Ring;
using strata::Vec2;

using strata_test::kModels;
using strata_test::loadModel;
using strata_test::randomPoints;

/// A Loops-form model from rings given region by region, each ring oriented with its region on
/// the left. Equal coordinates get equal node ids; segment i of the k-th ring overall belongs
/// to input cell k.
Model makeModel(const std::vector<std::vector<std::vector<Vec2>>>& regions)
{
  Model model;
  std::map<std::pair<double, double>, int> ids;
  std::int64_t cell = 0;
  for (std::size_t r = 0; r < regions.size(); ++r)
  {
    Region region;
    region.id = static_cast<int>(r);
    for (const std::vector<Vec2>& points : regions[r])
    {
      Ring ring;
      ring.points = points;
      for (const Vec2 p : points)
      {
        const auto found = ids.emplace(std::make_pair(p.x, p.y), static_cast<int>(ids.size()));
        if (found.second)
        {
          model.nodes.push_back(p);
        }
        ring.nodes.push_back(found.first->second);
        ring.segmentCell.push_back(cell);
        region.bounds.add(p);
      }
      region.rings.push_back(ring);
      ++cell;
    }
    model.bounds.add(region.bounds);
    model.regions.push_back(region);
  }
  return model;
}

/// Brute-force references for one region: the standard crossing-number rule over all its
/// rings (a point is inside when a ray to +x crosses an odd number of edges), and the
/// distance to its nearest segment. The crossing test only looks at the edges of the
/// horizontal band that contains the point's y: an edge outside it cannot satisfy
/// (yi > py) != (yj > py), so the parity is that of the full scan.
class EvenOdd
{
public:
  explicit EvenOdd(const Region& region)
  {
    for (const Ring& ring : region.rings)
    {
      const std::size_t n = ring.points.size();
      for (std::size_t i = 0; i < n; ++i)
      {
        this->A.push_back(ring.points[i]);
        this->B.push_back(ring.points[(i + 1) % n]);
        this->Box.add(ring.points[i]);
      }
    }
    const std::size_t bands = std::max<std::size_t>(1, this->A.size() / 4);
    this->Bands.resize(bands);
    this->BandHeight = std::max(this->Box.height() / bands, 1e-300);
    for (std::size_t s = 0; s < this->A.size(); ++s)
    {
      const double y0 = std::min(this->A[s].y, this->B[s].y);
      const double y1 = std::max(this->A[s].y, this->B[s].y);
      for (std::size_t k = this->band(y0); k <= this->band(y1); ++k)
      {
        this->Bands[k].push_back(static_cast<int>(s));
      }
    }
  }

  bool inside(Vec2 p) const
  {
    if (this->A.empty() || p.y < this->Box.min.y || p.y > this->Box.max.y)
    {
      return false;
    }
    bool in = false;
    for (const int s : this->Bands[this->band(p.y)])
    {
      const Vec2 i = this->A[s];
      const Vec2 j = this->B[s];
      if ((i.y > p.y) != (j.y > p.y) && p.x < (j.x - i.x) * (p.y - i.y) / (j.y - i.y) + i.x)
      {
        in = !in;
      }
    }
    return in;
  }

  double distance(Vec2 p) const
  {
    return std::sqrt(strata_test::bruteForceDistance2(this->A, this->B, p));
  }

  const Box2& bounds() const { return this->Box; }

private:
  std::size_t band(double y) const
  {
    const double k = std::floor((y - this->Box.min.y) / this->BandHeight);
    return static_cast<std::size_t>(std::clamp(k, 0.0, double(this->Bands.size() - 1)));
  }

  std::vector<Vec2> A, B;
  Box2 Box;
  std::vector<std::vector<int>> Bands;
  double BandHeight = 1.0;
};

/// Checks the field's sign for region r at p against brute force; points on or within
/// rounding of the boundary (brute-force distance below 1e-12 of the model size, where the
/// crossing test's own division decides arbitrarily) are skipped. Returns false with a message
/// on a mismatch.
struct SignChecker
{
  SignChecker(const Model& model, const DistanceField& field)
    : Field(field)
    , Size(model.size())
  {
    for (const Region& region : model.regions)
    {
      this->Refs.emplace_back(region);
    }
  }

  bool check(std::size_t r,
    Vec2 p,
    DistanceField::Scratch& scratch,
    std::string& message,
    std::size_t* skipped = nullptr) const
  {
    const EvenOdd& ref = this->Refs[r];
    const double sd = this->Field.signedDistance(r, p, scratch);
    const bool in = this->Field.inside(r, p, scratch);
    const bool expected = ref.inside(p);
    if ((sd >= 0.0) == expected && in == expected)
    {
      return true;
    }
    const double bf = ref.distance(p);
    if (bf <= 1e-12 * this->Size)
    {
      if (skipped)
      {
        ++*skipped;
      }
      return true;
    }
    std::ostringstream out;
    out.precision(17);
    out << "region index " << r << ", p = (" << p.x << ", " << p.y << "): signedDistance " << sd
        << ", inside " << in << ", brute force inside " << expected << " at distance " << bf;
    message = out.str();
    return false;
  }

  const DistanceField& Field;
  double Size;
  std::vector<EvenOdd> Refs;
};

/// Runs check over many points, counting mismatches and keeping the first message.
struct Tally
{
  std::size_t checked = 0, failed = 0;
  std::string first;
  void add(bool ok, const std::string& message)
  {
    ++checked;
    if (!ok && failed++ == 0)
    {
      first = message;
    }
  }
};

Vec2 unit(Vec2 v)
{
  const double n = strata::norm(v);
  return n > 0.0 ? (1.0 / n) * v : v;
}

/// The brute-force containing region (index into model.regions), -1 for none, -2 when several
/// regions claim p (never for a valid partition).
int bruteForceRegion(const std::vector<EvenOdd>& refs, Vec2 p)
{
  int found = -1;
  for (std::size_t r = 0; r < refs.size(); ++r)
  {
    if (refs[r].inside(p))
    {
      found = found == -1 ? static_cast<int>(r) : -2;
    }
  }
  return found;
}

// The 8 compass directions.
const Vec2 kCompass[8] = { { 1, 0 },
  { 1, 1 },
  { 0, 1 },
  { -1, 1 },
  { -1, 0 },
  { -1, -1 },
  { 0, -1 },
  { 1, -1 } };

/// For every model of kModels, every ring vertex i: `around(model, ring, i, emit)` calls
/// emit(p) for the points to test near that vertex; every point's sign must match the
/// brute-force even-odd rule.
template<typename Around>
void expectSignsMatchAroundRingVertices(Around&& around)
{
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Model model = loadModel(name);
    const DistanceField field(model);
    const SignChecker checker(model, field);
    DistanceField::Scratch scratch;
    Tally tally;
    for (std::size_t r = 0; r < model.regions.size(); ++r)
    {
      for (const Ring& ring : model.regions[r].rings)
      {
        for (std::size_t i = 0; i < ring.points.size(); ++i)
        {
          around(model,
            ring,
            i,
            [&](Vec2 p)
            {
              std::string message;
              tally.add(checker.check(r, p, scratch, message), message);
            });
        }
      }
    }
    EXPECT_EQ(tally.failed, 0u) << tally.first;
  }
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Hand-made models (no buildModel involved).

TEST(DistanceFieldTest, square_with_hole_has_exact_signed_distances)
{
  // Region 0: square 0..10 with a square hole 4..6; region 1 fills the hole.
  const Model model = makeModel({
    { { { 0, 0 }, { 10, 0 }, { 10, 10 }, { 0, 10 } }, { { 4, 4 }, { 4, 6 }, { 6, 6 }, { 6, 4 } } },
    { { { 4, 4 }, { 6, 4 }, { 6, 6 }, { 4, 6 } } },
  });
  const DistanceField field(model);
  DistanceField::Scratch scratch;
  ASSERT_EQ(field.numberOfRegions(), 2u);
  EXPECT_EQ(field.regionId(1), 1);

  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 1, 5 }, scratch), 1.0);  // inside, near left
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 5, 5 }, scratch), -1.0); // in the hole
  EXPECT_DOUBLE_EQ(field.signedDistance(1, { 5, 5 }, scratch), 1.0);
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 13, 14 }, scratch), -5.0);         // outside, corner
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 3, 3 }, scratch), std::sqrt(2.0)); // hole corner
  EXPECT_DOUBLE_EQ(field.signedDistance(1, { 3, 3 }, scratch), -std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 10, 10 }, scratch), 0.0); // vertex
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 5, 0 }, scratch), 0.0);   // edge
  EXPECT_TRUE(field.inside(0, { 5, 0 }, scratch));
  EXPECT_TRUE(field.inside(0, { 4, 5 }, scratch)); // on the shared boundary: both
  EXPECT_TRUE(field.inside(1, { 4, 5 }, scratch));
  EXPECT_FALSE(field.inside(0, { 5, 5 }, scratch));
  EXPECT_FALSE(field.inside(1, { 20, 5 }, scratch));

  PointQuery q = field.query({ 5, 5.5 }, scratch);
  EXPECT_EQ(q.region, 1);
  EXPECT_DOUBLE_EQ(q.signedDistance, 0.5);
  EXPECT_DOUBLE_EQ(q.boundaryDistance, 0.5);
  EXPECT_EQ(q.nearestCurve, 1); // the hole ring (cell 1) comes before region 1's ring (cell 2)
  q = field.query({ 2, 5 }, scratch);
  EXPECT_EQ(q.region, 0);
  EXPECT_DOUBLE_EQ(q.signedDistance, 2.0);
  EXPECT_EQ(q.nearestCurve, 0);
  q = field.query({ -3, 5 }, scratch);
  EXPECT_EQ(q.region, -1);
  EXPECT_DOUBLE_EQ(q.signedDistance, -3.0);
  EXPECT_DOUBLE_EQ(q.boundaryDistance, 3.0);
  q = field.query({ 4, 5 }, scratch); // shared boundary: tie at 0, smallest id
  EXPECT_EQ(q.region, 0);
  EXPECT_EQ(q.signedDistance, 0.0);
  EXPECT_EQ(q.boundaryDistance, 0.0);
}

TEST(DistanceFieldTest, vertex_sector_rule_at_convex_and_reflex_corners)
{
  // An L-shaped region: reflex corner at (5,5), convex corners elsewhere. Points near every
  // vertex in 16 directions, at distances where the vertex is the closest boundary point.
  const Model model =
    makeModel({ { { { 0, 0 }, { 10, 0 }, { 10, 5 }, { 5, 5 }, { 5, 10 }, { 0, 10 } } } });
  const DistanceField field(model);
  const SignChecker checker(model, field);
  DistanceField::Scratch scratch;
  Tally tally;
  for (const Vec2 v : model.regions[0].rings[0].points)
  {
    for (int k = 0; k < 16; ++k)
    {
      const double angle = 2.0 * M_PI * (k + 0.5) / 16.0;
      for (const double eps : { 1e-9, 1e-3, 0.7 })
      {
        const Vec2 p = v + eps * Vec2{ std::cos(angle), std::sin(angle) };
        std::string message;
        tally.add(checker.check(0, p, scratch, message), message);
      }
    }
  }
  EXPECT_EQ(tally.failed, 0u) << tally.first;
  // The reflex corner: the quadrant x > 5, y > 5 is outside, the other three inside.
  EXPECT_LT(field.signedDistance(0, { 5.1, 5.1 }, scratch), 0.0);
  EXPECT_GT(field.signedDistance(0, { 4.9, 5.1 }, scratch), 0.0);
  EXPECT_GT(field.signedDistance(0, { 4.9, 4.9 }, scratch), 0.0);
  EXPECT_GT(field.signedDistance(0, { 5.1, 4.9 }, scratch), 0.0);
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 6, 6 }, scratch), -1.0);           // edge y = 5
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 5.5, 5.5 }, scratch), -0.5);       // both edges
  EXPECT_DOUBLE_EQ(field.signedDistance(0, { 4, 4 }, scratch), std::sqrt(2.0)); // the vertex
}

TEST(DistanceFieldTest, rings_of_one_region_touching_at_a_vertex_use_its_star)
{
  // Region 0 (even-odd): outer square 0..10 with a triangular hole whose vertex (10,5) lies on
  // the outer ring, plus an island square 12..14 touching a second island 14..16 at (14,14).
  // Region 1 fills the triangular hole. Around (10,5) region 0 has four edges: two of the
  // outer ring and two of the hole.
  const Model model = makeModel({
    {
      { { 0, 0 }, { 10, 0 }, { 10, 5 }, { 10, 10 }, { 0, 10 } },
      { { 10, 5 }, { 6, 3 }, { 6, 7 } }, // hole, clockwise
      { { 12, 12 }, { 14, 12 }, { 14, 14 }, { 12, 14 } },
      { { 14, 14 }, { 16, 14 }, { 16, 16 }, { 14, 16 } },
    },
    { { { 10, 5 }, { 6, 7 }, { 6, 3 } } },
  });
  const DistanceField field(model);
  const SignChecker checker(model, field);
  DistanceField::Scratch scratch;
  Tally tally;
  EXPECT_EQ(field.signedDistance(0, { 10, 5 }, scratch), 0.0);
  EXPECT_EQ(field.signedDistance(1, { 10, 5 }, scratch), 0.0);
  EXPECT_EQ(field.signedDistance(0, { 14, 14 }, scratch), 0.0);
  for (const Vec2 v : { Vec2{ 10, 5 }, Vec2{ 14, 14 } })
  {
    for (int k = 0; k < 64; ++k)
    {
      const double angle = 2.0 * M_PI * k / 64.0 + 1e-3;
      for (const double eps : { 1e-9, 1e-4, 0.3 })
      {
        const Vec2 p = v + eps * Vec2{ std::cos(angle), std::sin(angle) };
        for (std::size_t r = 0; r < 2; ++r)
        {
          std::string message;
          tally.add(checker.check(r, p, scratch, message), message);
        }
      }
    }
  }
  EXPECT_EQ(tally.failed, 0u) << tally.first;
  // Inside the hole's tip: region 1, not region 0.
  EXPECT_LT(field.signedDistance(0, { 9.5, 5.0 }, scratch), 0.0);
  EXPECT_GT(field.signedDistance(1, { 9.5, 5.0 }, scratch), 0.0);
  EXPECT_EQ(field.query({ 9.5, 5.0 }, scratch).region, 1);
  // Around the touching islands: NE and SW quadrants inside, NW and SE outside.
  EXPECT_GT(field.signedDistance(0, { 14.1, 14.1 }, scratch), 0.0);
  EXPECT_GT(field.signedDistance(0, { 13.9, 13.9 }, scratch), 0.0);
  EXPECT_LT(field.signedDistance(0, { 13.9, 14.1 }, scratch), 0.0);
  EXPECT_LT(field.signedDistance(0, { 14.1, 13.9 }, scratch), 0.0);
}

TEST(DistanceFieldTest, hole_with_a_reflex_vertex_on_a_reflex_corner_needs_the_star)
{
  // Region 0: an L (reflex corner at v = (5,5)) with a hole that touches v and is itself
  // reflex there (its interior spans the directions 120..330 degrees from v). Region 1 fills
  // the hole. Points at v + eps * d for d between 210 and 240 degrees are nearest to v, with
  // four segments of region 0 at the same distance; they are in the hole. The two edges of
  // the outer ring alone would say "inside" (v is a reflex corner of the L): only the star of
  // v (all four edges) gets them right, whichever segment the search returns.
  const double c = std::sqrt(3.0);
  const Vec2 v{ 5, 5 };
  const Vec2 e{ 5 + c, 4 }, a{ 4, 5 + c }; // at 330 and 120 degrees from v
  const Model model = makeModel({
    {
      { { 0, 0 }, { 10, 0 }, { 10, 5 }, v, { 5, 10 }, { 0, 10 } },
      { v, e, { 5, 1 }, { 1, 1 }, { 1, 5 }, a }, // the hole, clockwise
    },
    { { v, a, { 1, 5 }, { 1, 1 }, { 5, 1 }, e } },
  });
  const DistanceField field(model);
  const SignChecker checker(model, field);
  DistanceField::Scratch scratch;
  Tally tally;
  std::size_t inHole = 0;
  for (int k = 0; k <= 30; ++k)
  {
    const double angle = (210.0 + k) * M_PI / 180.0;
    for (const double eps : { 1e-9, 1e-5, 1e-2 })
    {
      const Vec2 p = v + eps * Vec2{ std::cos(angle), std::sin(angle) };
      for (std::size_t r = 0; r < 2; ++r)
      {
        std::string message;
        tally.add(checker.check(r, p, scratch, message), message);
      }
      EXPECT_NEAR(field.signedDistance(1, p, scratch), eps, 1e-15);
      EXPECT_NEAR(field.signedDistance(0, p, scratch), -eps, 1e-15);
      inHole += field.query(p, scratch).region == 1;
    }
  }
  EXPECT_EQ(tally.failed, 0u) << tally.first;
  EXPECT_EQ(inHole, 31u * 3u);
  // All around v, in 360 directions.
  for (int k = 0; k < 360; ++k)
  {
    const double angle = (k + 0.25) * M_PI / 180.0;
    for (const double eps : { 1e-7, 0.1 })
    {
      const Vec2 p = v + eps * Vec2{ std::cos(angle), std::sin(angle) };
      for (std::size_t r = 0; r < 2; ++r)
      {
        std::string message;
        tally.add(checker.check(r, p, scratch, message), message);
      }
    }
  }
  EXPECT_EQ(tally.failed, 0u) << tally.first;
}

TEST(DistanceFieldTest, empty_model_and_bad_region_index)
{
  const DistanceField field{ Model{} };
  DistanceField::Scratch scratch;
  EXPECT_EQ(field.numberOfRegions(), 0u);
  std::int64_t cell = 7;
  EXPECT_EQ(field.boundaryDistance({ 1, 2 }, scratch, &cell), HUGE_VAL);
  EXPECT_EQ(cell, -1);
  const PointQuery q = field.query({ 1, 2 }, scratch);
  EXPECT_EQ(q.region, -1);
  EXPECT_EQ(q.nearestCurve, -1);
  EXPECT_THROW(field.signedDistance(0, { 0, 0 }, scratch), strata::ParameterError);
  EXPECT_THROW(field.inside(3, { 0, 0 }, scratch), strata::ParameterError);
}

// ---------------------------------------------------------------------------------------------
// Models of Data/.

TEST(DistanceFieldTest, sign_matches_even_odd_on_random_points)
{
  // 1e5 points per model in its box grown by 5%. For each region whose box holds the point
  // the signed distance is checked; outside a region's box only inside() (which answers from
  // the box) and the brute force must agree.
  std::mt19937_64 rng(2024);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Model model = loadModel(name);
    const DistanceField field(model);
    const SignChecker checker(model, field);
    DistanceField::Scratch scratch;
    Tally tally;
    std::size_t skipped = 0;
    for (const Vec2 p : randomPoints(model.bounds, 0.05, 100000, rng))
    {
      for (std::size_t r = 0; r < model.regions.size(); ++r)
      {
        std::string message;
        if (checker.Refs[r].bounds().distance2(p) > 0.0)
        {
          const bool ok = !checker.Refs[r].inside(p) && !field.inside(r, p, scratch);
          tally.add(ok, ok ? "" : "outside the box of region index " + std::to_string(r));
          continue;
        }
        tally.add(checker.check(r, p, scratch, message, &skipped), message);
      }
    }
    EXPECT_EQ(tally.failed, 0u) << tally.first;
    EXPECT_LE(skipped, 10u);
  }
}

TEST(DistanceFieldTest, magnitude_equals_brute_force_distance_to_the_region_boundary)
{
  std::mt19937_64 rng(77);
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Model model = loadModel(name);
    const DistanceField field(model);
    DistanceField::Scratch scratch;
    std::vector<EvenOdd> refs(model.regions.begin(), model.regions.end());
    std::size_t bad = 0;
    std::string first;
    for (const Vec2 p : randomPoints(model.bounds, 0.5, 2000, rng))
    {
      for (std::size_t r = 0; r < refs.size(); ++r)
      {
        const double got = std::abs(field.signedDistance(r, p, scratch));
        const double expected = refs[r].distance(p);
        if (std::abs(got - expected) > 1e-12 * expected)
        {
          if (bad++ == 0)
          {
            first = "region index " + std::to_string(r) + ": " + std::to_string(got) + " vs " +
              std::to_string(expected);
          }
        }
      }
    }
    EXPECT_EQ(bad, 0u) << first;
  }
}

TEST(DistanceFieldTest, boundary_vertices_have_distance_zero_and_are_inside)
{
  for (const std::string& name : kModels)
  {
    SCOPED_TRACE(name);
    const Model model = loadModel(name);
    const DistanceField field(model);
    DistanceField::Scratch scratch;
    std::size_t bad = 0;
    std::string first;
    for (std::size_t r = 0; r < model.regions.size(); ++r)
    {
      for (const Ring& ring : model.regions[r].rings)
      {
        const std::size_t n = ring.points.size();
        for (std::size_t i = 0; i < n; ++i)
        {
          const Vec2 v = ring.points[i];
          const double sd = field.signedDistance(r, v, scratch);
          if (sd != 0.0 || !field.inside(r, v, scratch) ||
            field.boundaryDistance(v, scratch) != 0.0)
          {
            if (bad++ == 0)
            {
              first = "region index " + std::to_string(r) + " vertex " + std::to_string(i) +
                ": signed distance " + std::to_string(sd);
            }
          }
          // Axis-parallel edges have exactly representable midpoints: on the boundary too.
          const Vec2 w = ring.points[(i + 1) % n];
          if (v.x == w.x || v.y == w.y)
          {
            const Vec2 m = 0.5 * (v + w);
            if (field.signedDistance(r, m, scratch) != 0.0 || !field.inside(r, m, scratch))
            {
              if (bad++ == 0)
              {
                first = "midpoint of edge " + std::to_string(i);
              }
            }
          }
        }
      }
    }
    EXPECT_EQ(bad, 0u) << first;
  }
}

TEST(DistanceFieldTest, sign_matches_even_odd_on_segment_extensions)
{
  // Collinear points 0.5 and 2 segment lengths beyond both ends of every segment: the
  // closest boundary point is often the segment's end vertex, with p - v along the segment.
  expectSignsMatchAroundRingVertices(
    [](const Model&, const Ring& ring, std::size_t i, const auto& emit)
    {
      const std::size_t n = ring.points.size();
      const Vec2 a = ring.points[i];
      const Vec2 b = ring.points[(i + 1) % n];
      for (const double f : { 0.5, 2.0 })
      {
        for (const Vec2 p : { b + f * (b - a), a + f * (a - b) })
        {
          emit(p);
        }
      }
    });
}

TEST(DistanceFieldTest, sign_matches_even_odd_at_convex_and_reflex_corners)
{
  // p = v +- eps * (bisector of the corner at v), for eps small against the adjacent edges:
  // the closest boundary point is the vertex v itself.
  std::size_t convex = 0, reflex = 0;
  expectSignsMatchAroundRingVertices(
    [&](const Model&, const Ring& ring, std::size_t i, const auto& emit)
    {
      const std::size_t n = ring.points.size();
      const Vec2 u = ring.points[(i + n - 1) % n];
      const Vec2 v = ring.points[i];
      const Vec2 w = ring.points[(i + 1) % n];
      const double turn = strata::orient2d(u, v, w);
      (turn > 0.0 ? convex : reflex) += turn != 0.0;
      Vec2 bisector = unit(u - v) + unit(w - v);
      if (strata::norm(bisector) < 1e-9)
      {
        bisector = Vec2{ -(w - v).y, (w - v).x }; // straight: the normal
      }
      bisector = unit(bisector);
      const double edge = std::min(strata::norm(u - v), strata::norm(w - v));
      for (const double eps : { 1e-3 * edge, 1e-7 * edge })
      {
        for (const double side : { 1.0, -1.0 })
        {
          emit(v + (side * eps) * bisector);
        }
      }
    });
  EXPECT_GT(convex, 1000u);
  EXPECT_GT(reflex, 1000u);
}

TEST(DistanceFieldTest, sign_matches_even_odd_on_horizontal_rays_through_vertices)
{
  // Points with exactly the y of a vertex: the crossing test's degenerate case, and for the
  // field points whose nearest feature is often that vertex.
  std::mt19937_64 rng(31);
  expectSignsMatchAroundRingVertices(
    [&](const Model& model, const Ring& ring, std::size_t i, const auto& emit)
    {
      std::uniform_real_distribution<double> ux(model.bounds.min.x, model.bounds.max.x);
      const Vec2 v = ring.points[i];
      const double edge = strata::norm(ring.points[(i + 1) % ring.points.size()] - v);
      for (const double x :
        { v.x + 0.37 * edge, v.x - 0.37 * edge, v.x + 1.9 * edge, v.x - 1.9 * edge, ux(rng) })
      {
        emit({ x, v.y });
      }
    });
}

TEST(DistanceFieldTest, touching_loops_around_the_shared_vertex_in_eight_directions)
{
  const Model model = loadModel("touching_loops.vtp");
  const DistanceField field(model);
  const SignChecker checker(model, field);
  DistanceField::Scratch scratch;
  ASSERT_EQ(model.regions.size(), 2u);
  const Vec2 shared = Vec2{ 10, 10 } - model.origin;
  for (std::size_t r = 0; r < 2; ++r)
  {
    EXPECT_EQ(field.signedDistance(r, shared, scratch), 0.0);
    EXPECT_TRUE(field.inside(r, shared, scratch));
  }
  const std::vector<EvenOdd> refs(model.regions.begin(), model.regions.end());
  Tally tally;
  for (const double eps : { 1e-9, 1e-3, 1.0 })
  {
    for (const Vec2 d : kCompass)
    {
      const Vec2 p = shared + eps * d;
      for (std::size_t r = 0; r < 2; ++r)
      {
        std::string message;
        tally.add(checker.check(r, p, scratch, message), message);
      }
      // Along the axes p is on an edge of one square (distance 0 up to the rounding of the
      // projection, inside that square), on the diagonals strictly inside one square or
      // outside both, at distance eps from the nearest edge.
      const PointQuery q = field.query(p, scratch);
      if (d.x != 0.0 && d.y != 0.0)
      {
        const int expected = bruteForceRegion(refs, p);
        EXPECT_EQ(q.region, expected < 0 ? -1 : model.regions[expected].id)
          << "eps " << eps << " direction (" << d.x << ", " << d.y << ")";
        EXPECT_NEAR(std::abs(q.signedDistance), eps, 1e-15 * model.size());
        EXPECT_EQ(q.signedDistance > 0.0, q.region >= 0);
      }
      else
      {
        EXPECT_LE(q.boundaryDistance, 1e-15 * model.size());
        EXPECT_LE(std::abs(q.signedDistance), 1e-15 * model.size());
        const int owner = (d.x > 0.0 || d.y > 0.0) ? 1 : 0; // the square whose edge holds p
        EXPECT_EQ(q.region, model.regions[owner].id)
          << "eps " << eps << " direction (" << d.x << ", " << d.y << ")";
      }
    }
  }
  EXPECT_EQ(tally.failed, 0u) << tally.first;
  // North-east is the upper square, south-west the lower one, the other diagonals neither.
  EXPECT_EQ(field.query(shared + Vec2{ 0.5, 0.5 }, scratch).region, 1);
  EXPECT_EQ(field.query(shared + Vec2{ -0.5, -0.5 }, scratch).region, 0);
  EXPECT_EQ(field.query(shared + Vec2{ -0.5, 0.5 }, scratch).region, -1);
  EXPECT_EQ(field.query(shared + Vec2{ 0.5, -0.5 }, scratch).region, -1);
}

TEST(DistanceFieldTest, nested_holes_alternate_in_and_out)
{
  // nested_holes.vtp: one region, four nested loops. The depth of a point (how many loops
  // contain it) decides: depth 1 and 3 inside, 0, 2 and 4 outside. Every depth is sampled.
  const Model model = loadModel("nested_holes.vtp");
  ASSERT_EQ(model.regions.size(), 1u);
  ASSERT_EQ(model.regions[0].rings.size(), 4u);
  const DistanceField field(model);
  DistanceField::Scratch scratch;
  std::vector<EvenOdd> loops;
  for (const Ring& ring : model.regions[0].rings)
  {
    Region single;
    single.rings.push_back(ring);
    loops.emplace_back(single);
  }
  std::mt19937_64 rng(5);
  std::size_t perDepth[5] = { 0, 0, 0, 0, 0 };
  std::size_t wrong = 0;
  for (const Vec2 p : randomPoints(model.bounds, 0.05, 50000, rng))
  {
    int depth = 0;
    for (const EvenOdd& loop : loops)
    {
      depth += loop.inside(p);
    }
    ++perDepth[depth];
    wrong += field.inside(0, p, scratch) != (depth % 2 == 1);
    wrong += (field.query(p, scratch).region == model.regions[0].id) != (depth % 2 == 1);
  }
  EXPECT_EQ(wrong, 0u);
  for (int depth = 0; depth <= 4; ++depth)
  {
    EXPECT_GT(perDepth[depth], 50u) << "depth " << depth;
  }
}

TEST(DistanceFieldTest, query_region_matches_even_odd_on_multi_region_models)
{
  std::mt19937_64 rng(99);
  for (const std::string& name : { "gulf_section.vtp",
         "countries_westeurope.vtp",
         "countries_westeurope_loops.vtp",
         "geology_marmousi.vtp",
         "salt_dome.vtp" })
  {
    SCOPED_TRACE(name);
    const Model model = loadModel(name);
    const DistanceField field(model);
    DistanceField::Scratch scratch;
    const std::vector<EvenOdd> refs(model.regions.begin(), model.regions.end());
    std::vector<EvenOdd> all; // every boundary segment, for the boundary distance
    {
      Region everything;
      for (const Region& region : model.regions)
      {
        everything.rings.insert(everything.rings.end(), region.rings.begin(), region.rings.end());
      }
      all.emplace_back(everything);
    }
    std::size_t wrongRegion = 0, wrongDistance = 0, ambiguous = 0, inRegion = 0;
    std::string first;
    const std::vector<Vec2> points = randomPoints(model.bounds, 0.05, 100000, rng);
    for (std::size_t k = 0; k < points.size(); ++k)
    {
      const Vec2 p = points[k];
      const PointQuery q = field.query(p, scratch);
      const int expected = bruteForceRegion(refs, p);
      ambiguous += expected == -2;
      const int expectedId = expected < 0 ? -1 : model.regions[expected].id;
      inRegion += expectedId >= 0;
      if (q.region != expectedId && expected != -2)
      {
        if (wrongRegion++ == 0)
        {
          std::ostringstream out;
          out.precision(17);
          out << "p = (" << p.x << ", " << p.y << "): query " << q.region << ", brute force "
              << expectedId;
          first = out.str();
        }
      }
      if ((q.signedDistance >= 0.0) != (q.region >= 0))
      {
        ++wrongDistance;
      }
      wrongRegion += field.region(p, scratch) != q.region; // region() is query().region
      if (k % 20 == 0)
      {
        // Magnitudes: the boundary distance is exact; inside a region the signed distance is
        // the distance to its boundary.
        const double bd = all[0].distance(p);
        wrongDistance += std::abs(q.boundaryDistance - bd) > 1e-12 * bd;
        if (q.region >= 0)
        {
          const int r = model.regionIndex(q.region);
          const double rd = refs[r].distance(p);
          wrongDistance += std::abs(q.signedDistance - rd) > 1e-12 * rd;
        }
        else
        {
          wrongDistance += q.signedDistance != -q.boundaryDistance;
        }
      }
    }
    EXPECT_EQ(wrongRegion, 0u) << first;
    EXPECT_EQ(wrongDistance, 0u);
    EXPECT_EQ(ambiguous, 0u);
    EXPECT_GT(inRegion, points.size() / 4);
  }
}

TEST(DistanceFieldTest, nearest_curve_is_a_cell_at_the_boundary_distance)
{
  const Model model = loadModel("gulf_section.vtp");
  const DistanceField field(model);
  DistanceField::Scratch scratch;
  // Segments of each input cell, from the rings.
  std::map<std::int64_t, std::vector<std::pair<Vec2, Vec2>>> cells;
  for (const Region& region : model.regions)
  {
    for (const Ring& ring : region.rings)
    {
      for (std::size_t i = 0; i < ring.points.size(); ++i)
      {
        cells[ring.segmentCell[i]].emplace_back(
          ring.points[i], ring.points[(i + 1) % ring.points.size()]);
      }
    }
  }
  std::mt19937_64 rng(8);
  std::size_t bad = 0;
  for (const Vec2 p : randomPoints(model.bounds, 0.1, 5000, rng))
  {
    std::int64_t cell = -1;
    const double d = field.boundaryDistance(p, scratch, &cell);
    ASSERT_TRUE(cells.count(cell)) << cell;
    double best = HUGE_VAL;
    for (const auto& s : cells[cell])
    {
      best = std::min(best, strata::pointSegmentDistance2(p, s.first, s.second));
    }
    // The cell's segment may be stored reversed in another ring: equal up to rounding.
    bad += std::abs(std::sqrt(best) - d) > 1e-12 * d;
  }
  EXPECT_EQ(bad, 0u);
}

TEST(DistanceFieldTest, utm_offset_and_tiny_scale_give_the_reference_distances)
{
  // utm_offset_1e7.vtp is reference_ok.vtp shifted by +1e7 in x and y, tiny_scale_1e-6.vtp is
  // it scaled by 1e-6. Models are in local coordinates (input minus origin), so a point P of
  // the reference's input frame is P + 1e7 - origin in the shifted model and 1e-6 P - origin
  // in the scaled one. Signed distances agree within 1e-9 of the model size.
  const Model ref = loadModel("bad_inputs/reference_ok.vtp");
  const Model utm = loadModel("bad_inputs/utm_offset_1e7.vtp");
  const Model tiny = loadModel("bad_inputs/tiny_scale_1e-6.vtp");
  ASSERT_EQ(ref.regions.size(), utm.regions.size());
  ASSERT_EQ(ref.regions.size(), tiny.regions.size());
  const double offset = 1e7;
  const double scale = 1e-6;
  ASSERT_NEAR(utm.origin.x + utm.bounds.min.x, ref.origin.x + ref.bounds.min.x + offset, 1e-3);
  ASSERT_NEAR(tiny.bounds.width(), scale * ref.bounds.width(), 1e-9 * tiny.bounds.width());

  const DistanceField fRef(ref), fUtm(utm), fTiny(tiny);
  DistanceField::Scratch scratch;
  std::mt19937_64 rng(1234);
  std::size_t bad = 0;
  std::string first;
  const std::vector<Vec2> points = randomPoints(ref.bounds, 0.1, 20000, rng);
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    const Vec2 input = points[k] + ref.origin;
    const Vec2 pUtm = (input + Vec2{ offset, offset }) - utm.origin;
    const Vec2 pTiny = scale * input - tiny.origin;
    for (std::size_t r = 0; r < ref.regions.size(); ++r)
    {
      const double d = fRef.signedDistance(r, points[k], scratch);
      const int ru = utm.regionIndex(ref.regions[r].id);
      const int rt = tiny.regionIndex(ref.regions[r].id);
      ASSERT_GE(ru, 0);
      ASSERT_GE(rt, 0);
      const double du = fUtm.signedDistance(ru, pUtm, scratch);
      const double dt = fTiny.signedDistance(rt, pTiny, scratch) / scale;
      if (std::abs(du - d) > 1e-9 * ref.size() || std::abs(dt - d) > 1e-9 * ref.size())
      {
        if (bad++ == 0)
        {
          std::ostringstream out;
          out.precision(17);
          out << "region " << ref.regions[r].id << " at (" << input.x << ", " << input.y
              << "): reference " << d << ", shifted " << du << ", scaled (rescaled) " << dt;
          first = out.str();
        }
      }
    }
    const PointQuery q = fRef.query(points[k], scratch);
    bad += fUtm.query(pUtm, scratch).region != q.region;
    bad += fTiny.query(pTiny, scratch).region != q.region;
  }
  EXPECT_EQ(bad, 0u) << first;
}

TEST(DistanceFieldTest, warm_scratch_does_not_grow)
{
  const Model model = loadModel("lake_superior_full.vtp");
  const DistanceField field(model);
  std::mt19937_64 rng(3);
  const std::vector<Vec2> points = randomPoints(model.bounds, 0.1, 20000, rng);
  DistanceField::Scratch scratch;
  for (const Vec2 p : points)
  {
    field.query(p, scratch);
  }
  const std::size_t capacity = scratch.heap.capacity();
  const auto* data = scratch.heap.data();
  for (const Vec2 p : points)
  {
    field.query(p, scratch);
    field.signedDistance(0, p, scratch);
  }
  EXPECT_EQ(scratch.heap.capacity(), capacity);
  EXPECT_EQ(scratch.heap.data(), data);
}

TEST(DistanceFieldTest, concurrent_queries_with_own_scratch_agree_with_serial_ones)
{
  const Model model = loadModel("countries_westeurope.vtp");
  const DistanceField field(model);
  std::mt19937_64 rng(4);
  const std::vector<Vec2> points = randomPoints(model.bounds, 0.05, 20000, rng);
  std::vector<PointQuery> serial(points.size());
  DistanceField::Scratch scratch;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    serial[i] = field.query(points[i], scratch);
  }
  std::atomic<int> mismatches{ 0 };
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
  {
    threads.emplace_back(
      [&, t]()
      {
        DistanceField::Scratch own;
        for (std::size_t i = t; i < points.size(); i += 2)
        {
          const PointQuery q = field.query(points[i], own);
          if (q.region != serial[i].region || q.signedDistance != serial[i].signedDistance ||
            q.boundaryDistance != serial[i].boundaryDistance ||
            q.nearestCurve != serial[i].nearestCurve)
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
