// Tests of the triangle quality measures.
#include "Quality.h"
#include "Errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace
{
using strata::Vec2;
constexpr double kPi = 3.14159265358979323846;
} // namespace

TEST(QualityTest, EquilateralTriangleIsPerfect)
{
  const strata::TriangleQuality q =
    strata::triangleQuality({ 0, 0 }, { 1, 0 }, { 0.5, std::sqrt(3.0) / 2 });
  EXPECT_NEAR(q.minAngle, 60.0, 1e-12);
  EXPECT_NEAR(q.maxAngle, 60.0, 1e-12);
  EXPECT_NEAR(q.radiusRatio, 1.0, 1e-12);
  EXPECT_NEAR(q.area, std::sqrt(3.0) / 4, 1e-15);
}

TEST(QualityTest, GridTriangleHas45And90Degrees)
{
  const strata::TriangleQuality q = strata::triangleQuality({ 0, 0 }, { 1, 0 }, { 0, 1 });
  EXPECT_NEAR(q.minAngle, 45.0, 1e-12);
  EXPECT_NEAR(q.maxAngle, 90.0, 1e-12);
  EXPECT_NEAR(q.radiusRatio, 2.0 * (std::sqrt(2.0) - 1.0), 1e-12); // 0.828...
  EXPECT_NEAR(q.area, 0.5, 1e-15);
  const std::array<double, 3> a = strata::triangleAngles({ 0, 0 }, { 1, 0 }, { 0, 1 });
  EXPECT_NEAR(a[0], 90.0, 1e-12);
  EXPECT_NEAR(a[1] + a[2], 90.0, 1e-12);
}

TEST(QualityTest, ClockwiseTriangleHasNegativeArea)
{
  EXPECT_NEAR(strata::triangleQuality({ 0, 0 }, { 0, 1 }, { 1, 0 }).area, -0.5, 1e-15);
}

TEST(QualityTest, CollinearAndCoincidentPointsAreDegenerate)
{
  const strata::TriangleQuality flat = strata::triangleQuality({ 0, 0 }, { 1, 0 }, { 3, 0 });
  EXPECT_EQ(flat.minAngle, 0.0);
  EXPECT_EQ(flat.maxAngle, 180.0);
  EXPECT_EQ(flat.radiusRatio, 0.0);
  EXPECT_EQ(flat.area, 0.0);
  const std::array<double, 3> a = strata::triangleAngles({ 0, 0 }, { 0, 0 }, { 1, 1 });
  EXPECT_NEAR(a[0] + a[1] + a[2], 180.0, 1e-12);
  EXPECT_EQ(strata::minimumAngle({ 0, 0 }, { 0, 0 }, { 1, 1 }), 0.0);
}

TEST(QualityTest, NeedleAnglesAreAccurate)
{
  // Apex angle 2 atan(1e-9): acos-based formulas lose it entirely.
  const double h = 1e-9;
  const double expected = 2.0 * std::atan(h) * 180.0 / kPi;
  const double m = strata::minimumAngle({ 1, -h }, { 1, h }, { 0, 0 });
  EXPECT_NEAR(m / expected, 1.0, 1e-9);
  EXPECT_NEAR(
    strata::triangleQuality({ 1, -h }, { 1, h }, { 0, 0 }).minAngle / expected, 1.0, 1e-9);
}

TEST(QualityTest, MinimumAngleAgreesWithTheFullComputation)
{
  const Vec2 a{ 0.3, -1.2 }, b{ 4.1, 0.7 }, c{ -0.5, 2.2 };
  const std::array<double, 3> all = strata::triangleAngles(a, b, c);
  EXPECT_NEAR(strata::minimumAngle(a, b, c), std::min({ all[0], all[1], all[2] }), 1e-12);
  EXPECT_NEAR(all[0] + all[1] + all[2], 180.0, 1e-12);
}

TEST(QualityTest, SummaryCountsAnglesAndTrianglesIn30To60)
{
  // Angles (35, 50, 95): two in range, smallest in range. A grid triangle (90, 45, 45): two,
  // smallest in range. A needle (15, 82.5, 82.5): none.
  const double ac = std::sin(50.0 * kPi / 180.0) / std::sin(95.0 * kPi / 180.0);
  const strata::LargeVector<Vec2> p = { { 0, 0 },
    { 1, 0 },
    { ac * std::cos(35.0 * kPi / 180.0), ac * std::sin(35.0 * kPi / 180.0) },
    { 0, 1 },
    { 10, 0 },
    { 11, 0 },
    { 10.5, 0.5 / std::tan(7.5 * kPi / 180.0) } };
  const strata::LargeVector<std::array<int, 3>> t = { { 0, 1, 2 }, { 0, 1, 3 }, { 4, 5, 6 } };
  const strata::QualitySummary s = strata::summarizeQuality(p, t);
  EXPECT_EQ(s.triangles, 3u);
  EXPECT_NEAR(s.minAngle, 15.0, 1e-9);
  EXPECT_NEAR(s.maxAngle, 95.0, 1e-9);
  EXPECT_NEAR(s.percentAngles30to60, 100.0 * 4.0 / 9.0, 1e-9);
  EXPECT_NEAR(s.percentTriangles30to60, 100.0 * 2.0 / 3.0, 1e-9);
  EXPECT_EQ(s.minAngleHistogram[1], 1u); // the needle: [10, 20)
  EXPECT_EQ(s.minAngleHistogram[3], 1u); // [30, 40)
  EXPECT_EQ(s.minAngleHistogram[4], 1u); // the grid triangle: [40, 50)
  EXPECT_EQ(s.inverted, 0u);
  EXPECT_EQ(s.degenerate, 0u);
}

TEST(QualityTest, SummaryOfNothingIsZero)
{
  const strata::QualitySummary s = strata::summarizeQuality({}, {});
  EXPECT_EQ(s.triangles, 0u);
  EXPECT_EQ(s.minAngle, 0.0);
}

TEST(QualityTest, SummaryCountsInvertedAndDegenerateTriangles)
{
  const strata::LargeVector<Vec2> p = { { 0, 0 }, { 1, 0 }, { 0, 1 }, { 2, 0 } };
  const strata::QualitySummary s = strata::summarizeQuality(p, { { 0, 2, 1 }, { 0, 1, 3 } });
  EXPECT_EQ(s.inverted, 1u);
  EXPECT_EQ(s.degenerate, 1u);
}

TEST(QualityTest, LargeMeshIsMeasuredInBlocksBetweenProgressReports)
{
  // 400 x 400 unit squares, each split into two right triangles: 320 k triangles.
  const int n = 400;
  strata::LargeVector<Vec2> p;
  strata::LargeVector<std::array<int, 3>> t;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      p.push_back({ static_cast<double>(i), static_cast<double>(j) });
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const int a = j * (n + 1) + i;
      t.push_back({ a, a + 1, a + n + 2 });
      t.push_back({ a, a + n + 2, a + n + 1 });
    }
  }
  std::vector<double> fractions;
  const strata::LargeVector<strata::TriangleQuality> q = strata::triangleQualities(p,
    t,
    strata::ProgressReporter(
      [&fractions](double f, const char* stage)
      {
        EXPECT_STREQ(stage, "measuring");
        fractions.push_back(f);
        return true;
      }),
    "measuring");
  ASSERT_EQ(q.size(), t.size());
  ASSERT_GE(fractions.size(), 2u); // more than one block
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  // Every triangle of every block measured: 45, 45 and 90 degrees, area 1/2.
  for (const strata::TriangleQuality& tq : q)
  {
    ASSERT_NEAR(tq.minAngle, 45.0, 1e-9);
    ASSERT_NEAR(tq.maxAngle, 90.0, 1e-9);
    ASSERT_NEAR(tq.area, 0.5, 1e-12);
  }
  // An abort asked between blocks stops the measure.
  int calls = 0;
  EXPECT_THROW(
    strata::triangleQualities(
      p, t, strata::ProgressReporter([&calls](double, const char*) { return ++calls < 1; })),
    strata::Aborted);
  EXPECT_EQ(calls, 1);
}

TEST(QualityTest, RejectsIndicesOutOfRange)
{
  EXPECT_THROW(strata::triangleQualities({ { 0, 0 } }, { { 0, 1, 2 } }), strata::ParameterError);
}
