// Tests of the mass-spring particle system (paper Sections 6.1 and 6.2).
#include "SpringSystem.h"
#include "Errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace
{
using strata::Vec2;

// A (n + 1) x (n + 1) lattice of unit squares split into counter-clockwise triangles; the
// border particles are fixed.
struct Lattice
{
  strata::LargeVector<Vec2> points;
  strata::LargeVector<std::array<int, 3>> triangles;
  strata::LargeVector<int> border;
};

Lattice lattice(int n)
{
  Lattice l;
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      l.points.push_back({ static_cast<double>(i), static_cast<double>(j) });
      if (i == 0 || j == 0 || i == n || j == n)
      {
        l.border.push_back(j * (n + 1) + i);
      }
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      l.triangles.push_back({ a, b, c });
      l.triangles.push_back({ a, c, d });
    }
  }
  return l;
}

strata::SpringSystem makeSystem(const Lattice& l,
  const strata::LargeVector<Vec2>& start,
  const strata::SpringParams& params = strata::SpringParams())
{
  strata::SpringMesh mesh;
  mesh.triangles = l.triangles;
  mesh.edges = strata::uniqueEdges(l.triangles);
  strata::SpringSystem s(mesh, start, l.points, params);
  for (int b : l.border)
  {
    s.setKind(b, strata::ParticleKind::Fixed);
  }
  return s;
}

// The lattice's points moved by up to 0.3 and velocities of up to 0.2, both varying from
// particle to particle.
void shaken(const Lattice& l, strata::LargeVector<Vec2>& x, strata::LargeVector<Vec2>& v)
{
  x = l.points;
  v.assign(x.size(), Vec2{});
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    const double s = static_cast<double>(i);
    x[i] = x[i] + Vec2{ 0.3 * std::sin(1.7 * s), 0.3 * std::cos(2.3 * s) };
    v[i] = Vec2{ 0.1 * std::cos(0.7 * s), -0.2 * std::sin(1.1 * s) };
  }
}

double totalEnergy(const strata::SpringSystem& s)
{
  return s.kineticEnergy() + s.potentialEnergy();
}
// Whether a split system's forces and stiffnesses are the serial one's up to rounding (the
// two halves' sums are added in another order); names the first particle that differs.
::testing::AssertionResult sameForces(const strata::SpringSystem& halves,
  const strata::SpringSystem& serial)
{
  for (std::size_t i = 0; i < serial.numberOfParticles(); ++i)
  {
    const double scale = 1.0 + strata::norm(serial.forces()[i]);
    const Vec2 d = halves.forces()[i] - serial.forces()[i];
    const double k = halves.stiffness(static_cast<int>(i)) - serial.stiffness(static_cast<int>(i));
    if (!(std::fabs(d.x) <= 1e-12 * scale && std::fabs(d.y) <= 1e-12 * scale &&
          std::fabs(k) <= 1e-12 * (1.0 + serial.stiffness(static_cast<int>(i)))))
    {
      return ::testing::AssertionFailure() << "particle " << i << ": force differs by (" << d.x
                                           << ", " << d.y << "), stiffness by " << k;
    }
  }
  return ::testing::AssertionSuccess();
}
} // namespace

TEST(SpringSystemTest, HookeSpringPullsStretchedAndPushesCompressedEnds)
{
  const Vec2 dx{ 2.0, 0.0 }; // a - b
  const Vec2 stretched = strata::edgeSpringForce(dx, {}, 1.0, 3.0, 0.0);
  EXPECT_NEAR(stretched.x, -3.0, 1e-12); // ks (|dx| - x0) toward b
  EXPECT_NEAR(stretched.y, 0.0, 1e-12);
  const Vec2 compressed = strata::edgeSpringForce({ 0.5, 0.0 }, {}, 1.0, 3.0, 0.0);
  EXPECT_NEAR(compressed.x, 1.5, 1e-12); // away from b
  const Vec2 rest = strata::edgeSpringForce({ 0.6, 0.8 }, {}, 1.0, 3.0, 0.0);
  EXPECT_NEAR(strata::norm(rest), 0.0, 1e-12);
}

TEST(SpringSystemTest, DampingOpposesTheRateOfStretching)
{
  const Vec2 dx{ 1.0, 0.0 };
  // At rest length: only damping acts. Ends separating (dv . dx > 0): force on a toward b.
  const Vec2 separating = strata::edgeSpringForce(dx, { 2.0, 0.0 }, 1.0, 1.0, 0.5);
  EXPECT_NEAR(separating.x, -1.0, 1e-12); // kd (dv . dx) / |dx|
  const Vec2 approaching = strata::edgeSpringForce(dx, { -2.0, 0.0 }, 1.0, 1.0, 0.5);
  EXPECT_NEAR(approaching.x, 1.0, 1e-12);
  // A sideways velocity does not change the length: no damping force.
  const Vec2 sideways = strata::edgeSpringForce(dx, { 0.0, 5.0 }, 1.0, 1.0, 0.5);
  EXPECT_NEAR(strata::norm(sideways), 0.0, 1e-12);
}

TEST(SpringSystemTest, ProjectionSpringIsAtRestAtItsRestLength)
{
  EXPECT_NEAR(strata::norm(strata::projectionSpringForce({ 0.0, 2.0 }, 2.0, 1.0)), 0.0, 1e-12);
}

TEST(SpringSystemTest, ProjectionSpringRepelsWhenCompressedAndPullsWhenStretched)
{
  const Vec2 up{ 0.0, 1.0 };
  EXPECT_GT(strata::dot(strata::projectionSpringForce(0.5 * up, 1.0, 1.0), up), 0.0);
  EXPECT_LT(strata::dot(strata::projectionSpringForce(2.0 * up, 1.0, 1.0), up), 0.0);
}

TEST(SpringSystemTest, ProjectionSpringForceGrowsWithoutBoundAsLengthGoesToZero)
{
  const double ks = 2.0, x0 = 3.0;
  double previous = 0.0;
  for (double r : { 0.5, 1e-1, 1e-2, 1e-4, 1e-8 })
  {
    const double f = strata::norm(strata::projectionSpringForce({ r * x0, 0.0 }, x0, ks));
    // ks x0 (1 / r - r)
    EXPECT_NEAR(f, ks * x0 * (1.0 / r - r), 1e-9 * f);
    EXPECT_GT(f, previous);
    previous = f;
  }
  EXPECT_GT(previous, 1e8);
  EXPECT_GT(strata::projectionSpringEnergy(1e-6, 1.0, 1.0), 10.0);
}

TEST(SpringSystemTest, ForcesAreInternalSoTheySumToZero)
{
  // One triangle, deformed: edge and projection springs only exchange forces.
  strata::SpringMesh mesh;
  mesh.triangles = { { 0, 1, 2 } };
  mesh.edges = strata::uniqueEdges(mesh.triangles);
  const strata::LargeVector<Vec2> rest = { { 0, 0 }, { 1, 0 }, { 0, 1 } };
  strata::SpringSystem s(mesh, { { 0.1, 0.05 }, { 0.9, -0.1 }, { 0.3, 0.2 } }, rest);
  s.velocities() = { { 0.1, 0.0 }, { 0.0, -0.2 }, { 0.3, 0.1 } };
  s.computeForces();
  Vec2 sum{};
  for (const Vec2& f : s.forces())
  {
    sum = sum + f;
  }
  EXPECT_NEAR(strata::norm(sum), 0.0, 1e-12);
  EXPECT_GT(strata::norm(s.forces()[2]), 0.1); // the squeezed corner is pushed
}

TEST(SpringSystemTest, SystemAtRestStaysAtRest)
{
  const Lattice l = lattice(6);
  strata::SpringSystem s = makeSystem(l, l.points);
  for (int step = 0; step < 1000; ++step)
  {
    s.step(0.1);
  }
  for (std::size_t i = 0; i < l.points.size(); ++i)
  {
    EXPECT_NEAR(s.positions()[i].x, l.points[i].x, 1e-12);
    EXPECT_NEAR(s.positions()[i].y, l.points[i].y, 1e-12);
  }
  EXPECT_LT(s.kineticEnergy(), 1e-24);
}

TEST(SpringSystemTest, LargeSystemReportsProgressWhileItSetsItsRestLengths)
{
  // 300 x 300 squares: 270 k edge springs and 540 k projection springs, more than one block
  // of rest lengths each (a block between two reports); 10 x 10: one each. Interior particles
  // are moved off their rest positions (in the large lattice one in each block's triangles):
  // with every rest length set, the springs pull each back alike.
  const auto build = [](int n, const std::vector<Vec2>& at, int& reports)
  {
    const Lattice l = lattice(n);
    strata::SpringMesh mesh;
    mesh.triangles = l.triangles;
    mesh.edges = strata::uniqueEdges(l.triangles);
    reports = 0;
    const strata::ProgressReporter progress(
      [&reports](double, const char* stage)
      {
        EXPECT_STREQ(stage, "building the spring system");
        ++reports;
        return true;
      });
    strata::LargeVector<Vec2> start = l.points;
    std::vector<int> moved;
    for (const Vec2 a : at)
    {
      moved.push_back(static_cast<int>(a.y) * (n + 1) + static_cast<int>(a.x));
      start[moved.back()] = start[moved.back()] + Vec2{ 0.3, 0.1 };
    }
    strata::SpringSystem s(mesh, start, l.points, strata::SpringParams(), progress);
    s.computeForces();
    std::vector<Vec2> forces;
    for (const int i : moved)
    {
      forces.push_back(s.forces()[i]);
    }
    return forces;
  };
  int small = 0, large = 0;
  const Vec2 expected = build(10, { { 5, 5 } }, small)[0];
  const std::vector<Vec2> got = build(300, { { 150, 50 }, { 150, 200 }, { 150, 298 } }, large);
  EXPECT_GE(large, small + 3); // one more block of edges, two more of projections
  EXPECT_LT(expected.x, -0.1); // pulled back
  for (const Vec2 f : got)
  {
    EXPECT_NEAR(f.x, expected.x, 1e-9 * std::fabs(expected.x));
    EXPECT_NEAR(f.y, expected.y, 1e-9 * std::fabs(expected.x));
  }
  // An abort asked while the rest lengths are set stops the construction.
  const Lattice l = lattice(300);
  strata::SpringMesh mesh;
  mesh.triangles = l.triangles;
  mesh.edges = strata::uniqueEdges(l.triangles);
  int calls = 0;
  const int limit = small + 2; // (a report among the projection springs' blocks)
  const strata::ProgressReporter stop(
    [&calls, limit](double, const char*) { return ++calls < limit; });
  EXPECT_THROW(
    strata::SpringSystem(mesh, l.points, l.points, strata::SpringParams(), stop), strata::Aborted);
}

TEST(SpringSystemTest, EnergyDecaysWithDamping)
{
  for (strata::SpringConfiguration c :
    { strata::SpringConfiguration::EdgeOnly, strata::SpringConfiguration::EdgeAndProjection })
  {
    const Lattice l = lattice(6);
    strata::LargeVector<Vec2> start = l.points;
    start[3 * 7 + 3] = start[3 * 7 + 3] + Vec2{ 0.3, 0.2 }; // an inner particle displaced
    strata::SpringParams p;
    p.configuration = c;
    strata::SpringSystem s = makeSystem(l, start, p);
    const double e0 = totalEnergy(s);
    ASSERT_GT(e0, 0.0);
    double highest = e0;
    for (int step = 0; step < 600; ++step)
    {
      s.step(0.1);
      highest = std::max(highest, totalEnergy(s));
    }
    EXPECT_LE(highest, 1.02 * e0); // never gains energy (beyond symplectic wobble)
    EXPECT_LT(totalEnergy(s), 1e-3 * e0);
  }
}

TEST(SpringSystemTest, UndampedEnergyStaysBoundedWithSymplecticEuler)
{
  const Lattice l = lattice(5);
  strata::LargeVector<Vec2> start = l.points;
  start[2 * 6 + 2] = start[2 * 6 + 2] + Vec2{ 0.2, -0.1 };
  strata::SpringParams p;
  p.damping = 0.0;
  strata::SpringSystem s = makeSystem(l, start, p);
  const double e0 = totalEnergy(s);
  double lowest = e0, highest = e0;
  for (int step = 0; step < 5000; ++step)
  {
    s.step(0.1);
    lowest = std::min(lowest, totalEnergy(s));
    highest = std::max(highest, totalEnergy(s));
  }
  // Bounded (the stable mass varies a little with the configuration, so the energy is not
  // exactly conserved, but it neither blows up nor dies out).
  EXPECT_GT(lowest, 0.5 * e0);
  EXPECT_LT(highest, 1.5 * e0);
}

TEST(SpringSystemTest, NearlyCollapsedTriangleDoesNotThrowParticlesAway)
{
  // A corner squeezed to 1% of its height: its projection spring is 1e4 times stiffer; the
  // stable mass keeps the step bounded, and no coordinate becomes NaN.
  strata::SpringMesh mesh;
  mesh.triangles = { { 0, 1, 2 } };
  mesh.edges = strata::uniqueEdges(mesh.triangles);
  const strata::LargeVector<Vec2> rest = { { 0, 0 }, { 1, 0 }, { 0.5, 1 } };
  strata::SpringSystem s(mesh, { { 0, 0 }, { 1, 0 }, { 0.5, 0.01 } }, rest);
  s.setKind(0, strata::ParticleKind::Fixed);
  s.setKind(1, strata::ParticleKind::Fixed);
  for (int step = 0; step < 2000; ++step)
  {
    const Vec2 before = s.positions()[2];
    s.step(0.1);
    ASSERT_TRUE(std::isfinite(s.positions()[2].x) && std::isfinite(s.positions()[2].y));
    EXPECT_LE(
      strata::norm(s.positions()[2] - before), s.params().maxStep * s.localLength(2) + 1e-12);
  }
  EXPECT_NEAR(s.positions()[2].y, 1.0, 1e-3); // back at rest
}

TEST(SpringSystemTest, GuardCanVetoAMove)
{
  struct NoUp : strata::MoveGuard
  {
    bool accept(int, Vec2 from, Vec2 to) override { return to.y <= from.y; }
  };
  strata::SpringMesh mesh;
  mesh.triangles = { { 0, 1, 2 } };
  mesh.edges = strata::uniqueEdges(mesh.triangles);
  const strata::LargeVector<Vec2> rest = { { 0, 0 }, { 1, 0 }, { 0.5, 1 } };
  strata::SpringSystem s(mesh, { { 0, 0 }, { 1, 0 }, { 0.5, 0.5 } }, rest);
  s.setKind(0, strata::ParticleKind::Fixed);
  s.setKind(1, strata::ParticleKind::Fixed);
  NoUp guard;
  for (int step = 0; step < 100; ++step)
  {
    s.step(0.1, &guard);
  }
  EXPECT_EQ(s.positions()[2].y, 0.5);
  EXPECT_EQ(strata::norm(s.velocities()[2]), 0.0);
}

TEST(SpringSystemTest, DrivenAndFixedParticlesAreNotIntegrated)
{
  const Lattice l = lattice(3);
  strata::LargeVector<Vec2> start = l.points;
  start[5] = start[5] + Vec2{ 0.2, 0.2 };
  strata::SpringSystem s = makeSystem(l, start);
  s.setKind(5, strata::ParticleKind::Driven);
  s.step(0.1);
  EXPECT_EQ(s.positions()[5], start[5]);
  EXPECT_GT(strata::norm(s.forces()[5]), 0.0); // but its force is known
}

TEST(SpringSystemTest, ConfigurationsArePluggable)
{
  const Lattice l = lattice(2);
  strata::SpringParams edgeOnly;
  edgeOnly.configuration = strata::SpringConfiguration::EdgeOnly;
  EXPECT_EQ(makeSystem(l, l.points, edgeOnly).numberOfSpringSets(), 1u);
  strata::SpringSystem s = makeSystem(l, l.points);
  EXPECT_EQ(s.numberOfSpringSets(), 2u);
  // A new set: a constant pull on particle 4 (the centre).
  struct Pull : strata::SpringSet
  {
    const char* name() const override { return "pull"; }
    void initialize(const strata::SpringMesh&, const strata::LargeVector<Vec2>&) override {}
    void flipped(const strata::SpringMesh&,
      const strata::LargeVector<Vec2>&,
      int,
      int,
      int) override
    {
    }
    void addForces(const strata::SpringMesh&,
      const strata::ParticleState& st,
      const strata::SpringParams&) const override
    {
      st.f[4] = st.f[4] + Vec2{ 1.0, 0.0 };
    }
    double energy(const strata::SpringMesh&,
      const strata::LargeVector<Vec2>&,
      const strata::SpringParams&) const override
    {
      return 0.0;
    }
  };
  s.addSpringSet(std::make_unique<Pull>());
  s.computeForces();
  EXPECT_NEAR(s.forces()[4].x, 1.0, 1e-12);
  for (int step = 0; step < 500; ++step)
  {
    s.step(0.1);
  }
  EXPECT_GT(s.positions()[4].x, 1.05); // pulled right, held by the springs
  EXPECT_LT(s.positions()[4].x, 1.9);
}

// Released rest positions change no force or step (the sets have their rest lengths), and a
// set added afterwards is refused rather than read from freed memory.
TEST(SpringSystemTest, ReleasedRestPositionsChangeNoStepAndRefuseANewSet)
{
  const Lattice l = lattice(3);
  strata::LargeVector<Vec2> start = l.points;
  start[5] = start[5] + Vec2{ 0.2, -0.1 };
  start[10] = start[10] + Vec2{ -0.15, 0.05 };
  strata::SpringSystem kept = makeSystem(l, start);
  strata::SpringSystem released = makeSystem(l, start);
  released.releaseRestPositions();
  for (int step = 0; step < 20; ++step)
  {
    kept.step(0.1);
    released.step(0.1);
  }
  EXPECT_FALSE(kept.positions()[5] == start[5]); // (the springs moved it back)
  for (std::size_t i = 0; i < kept.positions().size(); ++i)
  {
    EXPECT_EQ(released.positions()[i], kept.positions()[i]) << "particle " << i;
  }
  auto sets = strata::makeSpringSets(strata::SpringConfiguration::EdgeOnly);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_THROW(released.addSpringSet(std::move(sets[0])), strata::ParameterError);
  EXPECT_EQ(released.numberOfSpringSets(), kept.numberOfSpringSets());
}

TEST(SpringSystemTest, FlipTakesTheCurrentLengthsAsRest)
{
  // Two triangles forming a square; flip the diagonal at a deformed state: the new diagonal
  // and both new triangles are at rest, so only the unchanged edges act.
  strata::SpringMesh mesh;
  mesh.triangles = { { 0, 1, 2 }, { 0, 2, 3 } };
  mesh.edges = strata::uniqueEdges(mesh.triangles);
  const strata::LargeVector<Vec2> rest = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
  strata::SpringSystem s(mesh, rest, rest);
  int diagonal = -1;
  for (std::size_t e = 0; e < s.mesh().edges.size(); ++e)
  {
    if (s.mesh().edges[e] == std::array<int, 2>{ 0, 2 })
    {
      diagonal = static_cast<int>(e);
    }
  }
  ASSERT_GE(diagonal, 0);
  s.flip(diagonal, { 1, 3 }, 0, { 3, 0, 1 }, 1, { 1, 2, 3 });
  s.computeForces();
  for (const Vec2& f : s.forces())
  {
    EXPECT_NEAR(strata::norm(f), 0.0, 1e-12);
  }
  EXPECT_EQ(s.mesh().edges[diagonal], (std::array<int, 2>{ 1, 3 }));
}

TEST(SpringSystemTest, RejectsParametersOutOfRangeNamingThem)
{
  const Lattice l = lattice(1);
  const auto message = [&](strata::SpringParams p)
  {
    try
    {
      makeSystem(l, l.points, p);
    }
    catch (const strata::ParameterError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  strata::SpringParams p;
  p.stiffness = 0.0;
  EXPECT_NE(message(p).find("SpringStiffness"), std::string::npos);
  p = {};
  p.damping = -1.0;
  EXPECT_NE(message(p).find("Damping"), std::string::npos);
  p = {};
  p.mass = 0.0;
  EXPECT_NE(message(p).find("Mass"), std::string::npos);
  p = {};
  p.maxStep = 2.0;
  EXPECT_NE(message(p).find("MaxStep"), std::string::npos);
  EXPECT_THROW(strata::SpringSystem(
                 strata::SpringMesh{ { { 0, 1, 5 } }, {} }, { { 0, 0 }, { 1, 0 }, { 0, 1 } }),
    strata::ParameterError);
}

TEST(SpringSystemTest, ForcesAndStiffnessesAreBitForBitTheScalarLaws)
{
  // The force loops work on two springs at a time; each particle's sums must be those of the
  // plain loop below (same operations, springs in order), with coincident particles (a spring
  // of length 0) and a corner on its opposite edge (a projection of length 0), all particles
  // awake and only some.
  const Lattice l = lattice(9);
  strata::LargeVector<Vec2> x, v;
  shaken(l, x, v);
  x[12] = x[13];                          // an edge of length 0
  x[25] = 0.5 * (x[24] + x[35]);          // near or on an opposite edge
  x[47] = x[46] + 0.25 * (x[58] - x[46]); // on edge 46-58's line
  strata::SpringParams params;
  params.damping = 0.7;
  params.stiffness = 1.3;
  for (const bool some : { false, true })
  {
    SCOPED_TRACE(some ? "some awake" : "all awake");
    strata::SpringSystem s = makeSystem(l, x, params);
    s.velocities() = v;
    strata::LargeVector<std::uint8_t> awake(x.size(), 1);
    if (some)
    {
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        awake[i] = (i * 7) % 5 != 0;
      }
      s.setAwake(awake);
    }
    s.computeForces();
    // The plain loops (edges, then the three corners of each triangle).
    const strata::SpringMesh& mesh = s.mesh();
    strata::LargeVector<Vec2> f(x.size());
    strata::LargeVector<double> k(x.size(), 0.0);
    const double ks = params.stiffness, kd = params.damping;
    for (const auto& e : mesh.edges)
    {
      if (!awake[e[0]] && !awake[e[1]])
      {
        continue;
      }
      const double x0 = strata::norm(l.points[e[0]] - l.points[e[1]]);
      const Vec2 dx = x[e[0]] - x[e[1]], dv = v[e[0]] - v[e[1]];
      const double l2 = strata::norm2(dx);
      Vec2 force;
      if (l2 != 0.0)
      {
        const double inv = 1.0 / std::sqrt(l2);
        const double m = ks * (1.0 - x0 * inv) + kd * strata::dot(dv, dx) * inv * inv;
        force = { -m * dx.x, -m * dx.y };
      }
      f[e[0]] = f[e[0]] + force;
      f[e[1]] = f[e[1]] - force;
      k[e[0]] += ks;
      k[e[1]] += ks;
    }
    for (const auto& t : mesh.triangles)
    {
      if (!awake[t[0]] && !awake[t[1]] && !awake[t[2]])
      {
        continue;
      }
      for (int c = 0; c < 3; ++c)
      {
        const int a = t[(c + 1) % 3], b = t[(c + 2) % 3];
        const Vec2 r0 = l.points[t[c]], ra = l.points[a], rb = l.points[b];
        const double x0 =
          strata::norm(r0 - (ra + strata::projectionParameter(r0, ra, rb) * (rb - ra)));
        const Vec2 e = x[b] - x[a];
        const double len2 = strata::norm2(e);
        if (!(x0 > 0.0) || !(len2 > 0.0))
        {
          continue;
        }
        const Vec2 rel = x[t[c]] - x[a];
        const double u = std::clamp(strata::dot(rel, e) / len2, 0.0, 1.0);
        const Vec2 dx = rel - u * e;
        const double l2 = strata::norm2(dx);
        Vec2 force;
        double stiffness = 0.0;
        if (l2 != 0.0)
        {
          const double q = x0 * x0 / l2;
          stiffness = ks * (1.0 + q);
          const double m = ks * (1.0 - q);
          force = { -m * dx.x, -m * dx.y };
        }
        f[t[c]] = f[t[c]] + force;
        f[a] = f[a] - (1.0 - u) * force;
        f[b] = f[b] - u * force;
        k[t[c]] += stiffness;
        k[a] += (1.0 - u) * stiffness;
        k[b] += u * stiffness;
      }
    }
    std::size_t differ = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      const double stiffness = s.stiffness(i);
      differ += std::memcmp(&f[i], &s.forces()[i], sizeof(Vec2)) != 0 ||
        std::memcmp(&k[i], &stiffness, sizeof(double)) != 0;
    }
    EXPECT_EQ(differ, 0u);
  }
}

TEST(SpringSystemTest, ASplitStepHasTheSerialForcesAndMovesEveryParticleOnce)
{
  // A large system's step is split in two halves (forces summed from two accumulators,
  // particles moved by index halves, the seam between them last): the forces are those of one
  // loop up to rounding, every free awake particle is moved exactly once, and without a veto
  // the moves are the serial ones.
  const Lattice l = lattice(40);
  strata::LargeVector<Vec2> x, v;
  shaken(l, x, v);
  struct Counting : strata::MoveGuard
  {
    strata::LargeVector<int> asked;
    bool accept(int i, Vec2, Vec2) override
    {
      ++this->asked[i]; // each index from one thread only, or the test fails on a count
      return true;
    }
  };
  for (const bool some : { false, true })
  {
    SCOPED_TRACE(some ? "some awake" : "all awake");
    strata::SpringParams split;
    split.splitSprings = 0;
    strata::SpringSystem serial = makeSystem(l, x), halves = makeSystem(l, x, split);
    strata::LargeVector<std::uint8_t> awake(x.size(), 1);
    for (std::size_t i = 0; some && i < x.size(); ++i)
    {
      awake[i] = (i * 7) % 5 != 0;
    }
    for (strata::SpringSystem* s : { &serial, &halves })
    {
      s->velocities() = v;
      s->setKind(l.border[3], strata::ParticleKind::Free); // a fixed particle freed
      if (some)
      {
        s->setAwake(awake);
      }
      s->computeForces();
    }
    EXPECT_TRUE(sameForces(halves, serial));
    // Two steps; before the second another fixed particle is freed (it may join the halves).
    for (const int freed : { l.border[3], l.border[7] })
    {
      if (freed == l.border[7])
      {
        for (strata::SpringSystem* s : { &serial, &halves })
        {
          s->setKind(freed, strata::ParticleKind::Free);
          s->computeForces();
        }
      }
      Counting guard;
      guard.asked.assign(x.size(), 0);
      serial.integrate(0.1);
      halves.integrate(0.1, &guard);
      std::size_t wrong = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        const bool moves = halves.kind(static_cast<int>(i)) == strata::ParticleKind::Free &&
          halves.awake(static_cast<int>(i));
        wrong += guard.asked[i] != (moves ? 1 : 0);
        EXPECT_NEAR(halves.positions()[i].x, serial.positions()[i].x, 1e-12) << i;
        EXPECT_NEAR(halves.positions()[i].y, serial.positions()[i].y, 1e-12) << i;
      }
      EXPECT_EQ(wrong, 0u);
      EXPECT_EQ(guard.asked[freed], some && !awake[freed] ? 0 : 1);
    }
  }
}

// Split steps, then steps too small to split (whose second-half accumulators are let go),
// then split steps again: the forces stay those of one loop at every step.
TEST(SpringSystemTest, SplitStepsAfterUnsplitOnesStillHaveTheSerialForces)
{
  const Lattice l = lattice(40);
  strata::LargeVector<Vec2> x, v;
  shaken(l, x, v);
  strata::SpringParams split;
  split.splitSprings = 4000; // every spring live: split; a tenth of the particles awake: not
  strata::SpringSystem serial = makeSystem(l, x), halves = makeSystem(l, x, split);
  strata::LargeVector<std::uint8_t> all(x.size(), 1), few(x.size(), 0);
  for (std::size_t i = 0; i < x.size(); i += 10)
  {
    few[i] = 1;
  }
  int step = 0;
  for (const strata::LargeVector<std::uint8_t>* awake : { &all, &few, &few, &all, &few, &all })
  {
    SCOPED_TRACE("step " + std::to_string(step++));
    for (strata::SpringSystem* s : { &serial, &halves })
    {
      s->velocities() = v;
      s->setAwake(*awake);
      s->computeForces();
    }
    ASSERT_TRUE(sameForces(halves, serial));
    serial.integrate(0.05);
    halves.integrate(0.05);
  }
}

TEST(SpringSystemTest, ASplitStepKeepsAGuardedMeshEmbedded)
{
  // A lattice squeezed toward its centre line relaxes with a guard that refuses any move
  // inverting a triangle: split in halves as in one loop, no triangle ever inverts.
  const Lattice l = lattice(40);
  strata::LargeVector<Vec2> x = l.points;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    if (std::find(l.border.begin(), l.border.end(), static_cast<int>(i)) == l.border.end())
    {
      x[i].y = 20.0 + 0.05 * (x[i].y - 20.0); // squeezed
    }
  }
  struct Embedded : strata::MoveGuard
  {
    const strata::SpringSystem* system = nullptr;
    strata::LargeVector<strata::LargeVector<int>> star;
    bool accept(int i, Vec2, Vec2 to) override
    {
      const strata::LargeVector<Vec2>& p = this->system->positions();
      for (const int t : this->star[i])
      {
        std::array<Vec2, 3> c;
        for (int k = 0; k < 3; ++k)
        {
          const int j = this->system->mesh().triangles[t][k];
          c[k] = j == i ? to : p[j];
        }
        if (!(strata::orient2d(c[0], c[1], c[2]) > 0.0))
        {
          return false;
        }
      }
      return true;
    }
  };
  for (const std::size_t splitSprings : { strata::SpringParams{}.splitSprings, std::size_t(0) })
  {
    strata::SpringParams params;
    params.splitSprings = splitSprings;
    strata::SpringSystem s = makeSystem(l, x, params);
    Embedded guard;
    guard.system = &s;
    guard.star.resize(x.size());
    for (std::size_t t = 0; t < l.triangles.size(); ++t)
    {
      for (const int v : l.triangles[t])
      {
        guard.star[v].push_back(static_cast<int>(t));
      }
    }
    for (int step = 0; step < 300; ++step)
    {
      s.step(0.1, &guard);
    }
    std::size_t inverted = 0;
    double spread = 0.0;
    for (const auto& t : l.triangles)
    {
      const strata::LargeVector<Vec2>& p = s.positions();
      inverted += !(strata::orient2d(p[t[0]], p[t[1]], p[t[2]]) > 0.0);
    }
    for (const Vec2& p : s.positions())
    {
      spread = std::max(spread, std::abs(p.y - 20.0));
    }
    EXPECT_EQ(inverted, 0u) << splitSprings;
    EXPECT_GT(spread, 15.0) << splitSprings; // it did relax
  }
}

TEST(SpringSystemTest, AwakeListsGivenMakeTheSameStepsAsThePassesOverTheSprings)
{
  // A caller with the mesh's adjacency gives the awake particles and their live springs
  // (the compression's wave tail, from its stars): the forces and the moves are bit for bit
  // those of the masks alone, over awake sets that shrink and grow; malformed lists are
  // refused.
  const Lattice l = lattice(12);
  strata::LargeVector<Vec2> x, v;
  shaken(l, x, v);
  strata::SpringSystem passes = makeSystem(l, x), given = makeSystem(l, x);
  passes.velocities() = v;
  given.velocities() = v;
  for (const double reach : { 9.0, 3.0, 6.0, 1.5 })
  {
    SCOPED_TRACE(reach);
    strata::LargeVector<std::uint8_t> awake(x.size(), 0);
    strata::SpringSystem::AwakeSets sets;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      awake[i] = strata::norm(l.points[i] - Vec2{ 2.0, 3.0 }) < reach;
      if (awake[i])
      {
        sets.particles.push_back(static_cast<int>(i));
      }
    }
    const strata::SpringMesh& mesh = given.mesh();
    for (std::size_t e = 0; e < mesh.edges.size(); ++e)
    {
      if (awake[mesh.edges[e][0]] || awake[mesh.edges[e][1]])
      {
        sets.edges.push_back(static_cast<int>(e));
      }
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    {
      const auto& tri = mesh.triangles[t];
      if (awake[tri[0]] || awake[tri[1]] || awake[tri[2]])
      {
        sets.triangles.push_back(static_cast<int>(t));
      }
    }
    ASSERT_FALSE(sets.particles.empty());
    passes.setAwake(awake);
    given.setAwake(awake, std::move(sets));
    ASSERT_EQ(*passes.awakeParticles(), *given.awakeParticles());
    for (int step = 0; step < 3; ++step)
    {
      passes.step(0.1);
      given.step(0.1);
    }
    passes.computeForces();
    given.computeForces();
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      ASSERT_EQ(std::memcmp(&passes.positions()[i], &given.positions()[i], sizeof(Vec2)), 0) << i;
      ASSERT_EQ(std::memcmp(&passes.forces()[i], &given.forces()[i], sizeof(Vec2)), 0) << i;
    }
  }
  strata::LargeVector<std::uint8_t> awake(x.size(), 0);
  awake[5] = awake[7] = 1;
  strata::SpringSystem::AwakeSets backwards;
  backwards.particles = { 7, 5 };
  EXPECT_THROW(given.setAwake(awake, std::move(backwards)), strata::ParameterError);
  strata::SpringSystem::AwakeSets asleep;
  asleep.particles = { 5, 6 };
  EXPECT_THROW(given.setAwake(awake, std::move(asleep)), strata::ParameterError);
  EXPECT_THROW(given.setAwake(strata::LargeVector<std::uint8_t>(3, 1), {}), strata::ParameterError);
}

TEST(SpringSystemTest, SleepersAwayFromTheAwakeHaveNoForceAndTheAwakeHaveEverySpring)
{
  // While some particles sleep, only the springs touching an awake particle are evaluated and
  // only their particles' accumulators are reset: an awake particle's force and stiffness are
  // those of all its springs (bit for bit), a particle no live spring touches has none, also
  // after a wider awake set gave it some, and an awake set that shrinks step after step keeps
  // it so.
  const Lattice l = lattice(12);
  strata::LargeVector<Vec2> x, v;
  shaken(l, x, v);
  strata::SpringSystem sleeping = makeSystem(l, x);
  sleeping.velocities() = v;
  for (const int corner : { 0, 1, 2 })
  {
    SCOPED_TRACE(corner);
    // Awake: the particles within `reach` of (0, 0), fewer each time.
    const double reach = 9.0 - 3.0 * corner;
    strata::LargeVector<std::uint8_t> awake(x.size(), 0);
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      awake[i] = strata::norm(l.points[i]) < reach;
    }
    sleeping.setAwake(awake);
    sleeping.step(0.1);
    sleeping.computeForces();
    strata::SpringSystem all = makeSystem(l, sleeping.positions());
    all.velocities() = sleeping.velocities();
    all.computeForces();
    std::size_t awakeDiffer = 0, touched = 0, untouched = 0, untouchedWithForce = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
      if (awake[i])
      {
        const double k = sleeping.stiffness(i), kAll = all.stiffness(i);
        awakeDiffer += std::memcmp(&sleeping.forces()[i], &all.forces()[i], sizeof(Vec2)) != 0 ||
          std::memcmp(&k, &kAll, sizeof(double)) != 0;
        continue;
      }
      // A sleeper is touched when a live spring reaches it: it shares a triangle with an
      // awake particle.
      bool near = false;
      for (const auto& t : l.triangles)
      {
        const bool has =
          t[0] == static_cast<int>(i) || t[1] == static_cast<int>(i) || t[2] == static_cast<int>(i);
        near = near || (has && (awake[t[0]] || awake[t[1]] || awake[t[2]]));
      }
      ++(near ? touched : untouched);
      untouchedWithForce +=
        !near && (sleeping.forces()[i] != Vec2{} || sleeping.stiffness(static_cast<int>(i)) != 0.0);
    }
    EXPECT_EQ(awakeDiffer, 0u);
    EXPECT_GT(touched, 0u);
    EXPECT_GT(untouched, 0u);
    EXPECT_EQ(untouchedWithForce, 0u);
  }
}
