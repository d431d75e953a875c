// StrataMesh core: mass-spring particle system (paper Sections 6.1 and 6.2).
//
// The system holds one particle per mesh vertex (position, velocity, force accumulator, the
// same mass for all) and a list of spring sets. A step has the paper's three phases:
//  1. force accumulators: reset, then every spring set adds the force of each of its springs
//     to both ends (edge springs), or to the real vertex and, split by the projection
//     parameter, to the two ends of the opposite edge (projection springs: the auxiliary
//     particle at the projection exists only inside this loop);
//  2. derivatives: a = F / m for every free particle;
//  3. new velocities and positions by semi-implicit Euler (see SpringSystem.h for why).
// Spring sets are flat arrays indexed by edge id and by triangle corner; the loops read the
// positions and velocities through raw pointers and allocate nothing. Particles marked Driven
// or Fixed receive forces but are not integrated: the caller moves driven ones itself.
// With SSE2 both loops evaluate two springs (edges, or triangles corner by corner) at once,
// with the scalar kernels' operations in the same order, then add the forces one spring after
// the other as the scalar loop does: every particle's sums are bit for bit the same. The
// triangle loop prefetches the corners of the triangles eight pairs ahead (it waits on memory
// more than on its divisions).
// Large systems (SpringParams::splitSprings) split a step in two halves: the springs' forces
// into two accumulators, summed afterwards, and the particles' moves in two index halves,
// each moving only particles whose triangles lie in its half; those on the seam move after
// both, in index order. With particles in spatial order (the compression's are) the seam is a
// thin line. The halves run on two threads when the machine has two cores; the result does
// not depend on that.
#include "SpringSystem.h"

#include "Errors.h"
#include "Parallel.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace strata
{

namespace
{
const char* const kSpringStage = "building the spring system";
// Rest lengths written per block between two progress reports (2 MiB of doubles): at 1 M
// triangles the projection springs' 3 M took up to 0.075 s in one go, mostly first writes.
constexpr std::size_t kRestBlock = std::size_t(1) << 18;

// Sets `rest` to the rest lengths of `per` springs for each of `items` items (edges, triangles):
// written (for the first time) and filled, by fill(from, to) for the items [from, to), a block
// at a time, with a progress report after each.
template<class Fill>
void restInBlocks(LargeVector<double>& rest,
  std::size_t items,
  std::size_t per,
  const ProgressReporter& progress,
  Fill&& fill)
{
  rest.clear();
  rest.reserve(per * items);
  const std::size_t block = kRestBlock / per;
  for (std::size_t begin = 0; begin < items; begin += block)
  {
    const std::size_t end = std::min(items, begin + block);
    rest.resize(per * end, 0.0);
    fill(begin, end);
    progress.report(0.0, kSpringStage);
  }
}

void checkRange(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    throw ParameterError(
      std::string("SpringSystem: ") + name + " " + std::to_string(value) + " is not in " + range);
  }
}

} // namespace

void validate(const SpringParams& p)
{
  checkRange(p.configuration == SpringConfiguration::EdgeOnly ||
      p.configuration == SpringConfiguration::EdgeAndProjection,
    "SpringConfiguration",
    static_cast<double>(static_cast<int>(p.configuration)),
    "{0 (edge only), 1 (edge and projection)}");
  checkRange(p.stiffness > 0.0 && p.stiffness <= 1e3, "SpringStiffness", p.stiffness, "(0, 1e3]");
  checkRange(p.damping >= 0.0 && p.damping <= 1e3, "Damping", p.damping, "[0, 1e3]");
  checkRange(p.mass > 0.0 && p.mass <= 1e6, "Mass", p.mass, "(0, 1e6]");
  checkRange(p.maxStep > 0.0 && p.maxStep <= 1.0, "MaxStep", p.maxStep, "(0, 1]");
}

LargeVector<std::array<int, 2>> uniqueEdges(const LargeVector<std::array<int, 3>>& triangles)
{
  LargeVector<std::array<int, 2>> edges;
  edges.reserve(triangles.size() * 3);
  for (const std::array<int, 3>& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({ std::min(a, b), std::max(a, b) });
    }
  }
  sortUnique(edges);
  return edges;
}

Vec2 edgeSpringForce(Vec2 dx, Vec2 dv, double restLength, double ks, double kd)
{
  const double length = norm(dx);
  if (length == 0.0)
  {
    return {};
  }
  const double magnitude = ks * (length - restLength) + kd * dot(dv, dx) / length;
  return (-magnitude / length) * dx;
}

Vec2 projectionSpringForce(Vec2 dx, double restLength, double ks)
{
  const double length = norm(dx);
  if (length == 0.0 || !(restLength > 0.0))
  {
    return {};
  }
  const double r = length / restLength;
  const double magnitude = ks * restLength * (r - 1.0 / r);
  return (-magnitude / length) * dx;
}

double edgeSpringEnergy(double length, double restLength, double ks)
{
  const double d = length - restLength;
  return 0.5 * ks * d * d;
}

double projectionSpringEnergy(double length, double restLength, double ks)
{
  if (!(restLength > 0.0))
  {
    return 0.0;
  }
  if (length <= 0.0)
  {
    return HUGE_VAL;
  }
  // integral of ks x0 (s / x0 - x0 / s) ds from x0 to length
  return ks *
    (0.5 * (length * length - restLength * restLength) -
      restLength * restLength * std::log(length / restLength));
}

double projectionParameter(Vec2 p, Vec2 a, Vec2 b)
{
  const Vec2 ab = b - a;
  const double len2 = norm2(ab);
  if (!(len2 > 0.0))
  {
    return 0.0;
  }
  return std::clamp(dot(p - a, ab) / len2, 0.0, 1.0);
}

//------------------------------------------------------------------------------
// Kernels of the force loops: the same laws as edgeSpringForce / projectionSpringForce with
// the square roots and divisions they can do without.
namespace
{
// Hooke + damping on end a; adds the stiffness ks to *k.
inline Vec2 edgeKernel(Vec2 dx, Vec2 dv, double x0, double ks, double kd)
{
  const double l2 = norm2(dx);
  if (l2 == 0.0)
  {
    return {};
  }
  const double inv = 1.0 / std::sqrt(l2);
  // -(ks (l - x0) + kd (dv . dx) / l) dx / l
  const double m = ks * (1.0 - x0 * inv) + kd * dot(dv, dx) * inv * inv;
  return { -m * dx.x, -m * dx.y };
}

// ks x0 (r - 1 / r) dx / |dx| with r = |dx| / x0 equals ks (1 - x0^2 / |dx|^2) dx.
inline Vec2 projectionKernel(Vec2 dx, double x02, double ks, double& stiffness)
{
  const double l2 = norm2(dx);
  if (l2 == 0.0)
  {
    stiffness = 0.0;
    return {};
  }
  const double q = x02 / l2;
  stiffness = ks * (1.0 + q);
  const double m = ks * (1.0 - q);
  return { -m * dx.x, -m * dx.y };
}

#if defined(__SSE2__)
// The kernels on two springs at once (lane 0 and lane 1): the same operations in the same
// order, so bit for bit the scalar results (the branches become selects).
inline __m128d selectPd(__m128d mask, __m128d x, __m128d y)
{
  return _mm_or_pd(_mm_and_pd(mask, x), _mm_andnot_pd(mask, y));
}

inline void edgeKernel2(__m128d dxx,
  __m128d dxy,
  __m128d dvx,
  __m128d dvy,
  __m128d x0,
  double ks,
  double kd,
  double fx[2],
  double fy[2])
{
  const __m128d l2 = _mm_add_pd(_mm_mul_pd(dxx, dxx), _mm_mul_pd(dxy, dxy));
  const __m128d zero = _mm_cmpeq_pd(l2, _mm_setzero_pd());
  const __m128d inv = _mm_div_pd(_mm_set1_pd(1.0), _mm_sqrt_pd(l2));
  const __m128d dvdx = _mm_add_pd(_mm_mul_pd(dvx, dxx), _mm_mul_pd(dvy, dxy));
  const __m128d m =
    _mm_add_pd(_mm_mul_pd(_mm_set1_pd(ks), _mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(x0, inv))),
      _mm_mul_pd(_mm_mul_pd(_mm_mul_pd(_mm_set1_pd(kd), dvdx), inv), inv));
  const __m128d negM = _mm_xor_pd(m, _mm_set1_pd(-0.0));
  _mm_storeu_pd(fx, _mm_andnot_pd(zero, _mm_mul_pd(negM, dxx)));
  _mm_storeu_pd(fy, _mm_andnot_pd(zero, _mm_mul_pd(negM, dxy)));
}
#endif
} // namespace

//------------------------------------------------------------------------------
// Edge springs.
void EdgeSprings::initialize(const SpringMesh& mesh, const LargeVector<Vec2>& rest)
{
  this->initializeWithProgress(mesh, rest, ProgressReporter());
}

void EdgeSprings::initializeWithProgress(const SpringMesh& mesh,
  const LargeVector<Vec2>& rest,
  const ProgressReporter& progress)
{
  restInBlocks(this->Rest,
    mesh.edges.size(),
    1,
    progress,
    [&](std::size_t from, std::size_t to)
    {
      for (std::size_t e = from; e < to; ++e)
      {
        this->Rest[e] = norm(rest[mesh.edges[e][0]] - rest[mesh.edges[e][1]]);
      }
    });
}

void EdgeSprings::flipped(const SpringMesh& mesh,
  const LargeVector<Vec2>& x,
  int edge,
  int /*t0*/,
  int /*t1*/)
{
  this->Rest[edge] = norm(x[mesh.edges[edge][0]] - x[mesh.edges[edge][1]]);
}

void EdgeSprings::addForces(const SpringMesh& mesh,
  const ParticleState& s,
  const SpringParams& params) const
{
  const double ks = params.stiffness, kd = params.damping;
  const std::size_t n = s.edgeEnd;
  const int* subset = s.edgeIds;
  const std::array<int, 2>* edges = mesh.edges.data();
  const double* rest = this->Rest.data();
  std::size_t i = s.edgeBegin;
#if defined(__SSE2__)
  // Two springs at a time, their forces added in order as below.
  for (; i + 1 < n; i += 2)
  {
    const std::size_t e0 = subset ? static_cast<std::size_t>(subset[i]) : i;
    const std::size_t e1 = subset ? static_cast<std::size_t>(subset[i + 1]) : i + 1;
    const int a0 = edges[e0][0], b0 = edges[e0][1], a1 = edges[e1][0], b1 = edges[e1][1];
    const Vec2 dx0 = s.x[a0] - s.x[b0], dx1 = s.x[a1] - s.x[b1];
    const Vec2 dv0 = s.v[a0] - s.v[b0], dv1 = s.v[a1] - s.v[b1];
    double fx[2], fy[2];
    edgeKernel2(_mm_set_pd(dx1.x, dx0.x),
      _mm_set_pd(dx1.y, dx0.y),
      _mm_set_pd(dv1.x, dv0.x),
      _mm_set_pd(dv1.y, dv0.y),
      _mm_set_pd(rest[e1], rest[e0]),
      ks,
      kd,
      fx,
      fy);
    const Vec2 f0{ fx[0], fy[0] }, f1{ fx[1], fy[1] };
    s.f[a0] = s.f[a0] + f0;
    s.f[b0] = s.f[b0] - f0;
    if (s.k)
    {
      s.k[a0] += ks;
      s.k[b0] += ks;
    }
    s.f[a1] = s.f[a1] + f1;
    s.f[b1] = s.f[b1] - f1;
    if (s.k)
    {
      s.k[a1] += ks;
      s.k[b1] += ks;
    }
  }
#endif
  for (; i < n; ++i)
  {
    const std::size_t e = subset ? static_cast<std::size_t>(subset[i]) : i;
    const int a = edges[e][0], b = edges[e][1];
    const Vec2 f = edgeKernel(s.x[a] - s.x[b], s.v[a] - s.v[b], rest[e], ks, kd);
    s.f[a] = s.f[a] + f;
    s.f[b] = s.f[b] - f;
    if (s.k)
    {
      s.k[a] += ks;
      s.k[b] += ks;
    }
  }
}

double EdgeSprings::energy(const SpringMesh& mesh,
  const LargeVector<Vec2>& x,
  const SpringParams& params) const
{
  double sum = 0.0;
  for (std::size_t e = 0; e < mesh.edges.size(); ++e)
  {
    sum += edgeSpringEnergy(
      norm(x[mesh.edges[e][0]] - x[mesh.edges[e][1]]), this->Rest[e], params.stiffness);
  }
  return sum;
}

//------------------------------------------------------------------------------
// Projection springs.
void ProjectionSprings::restOf(const SpringMesh& mesh, const LargeVector<Vec2>& x, int t)
{
  const std::array<int, 3>& tri = mesh.triangles[t];
  for (int k = 0; k < 3; ++k)
  {
    const Vec2 p = x[tri[k]], a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
    const double u = projectionParameter(p, a, b);
    this->Rest[3 * t + k] = norm(p - (a + u * (b - a)));
  }
}

void ProjectionSprings::initialize(const SpringMesh& mesh, const LargeVector<Vec2>& rest)
{
  this->initializeWithProgress(mesh, rest, ProgressReporter());
}

void ProjectionSprings::initializeWithProgress(const SpringMesh& mesh,
  const LargeVector<Vec2>& rest,
  const ProgressReporter& progress)
{
  // (The two halves of a large block at once.)
  const auto some = [&](std::size_t from, std::size_t to)
  {
    for (std::size_t t = from; t < to; ++t)
    {
      this->restOf(mesh, rest, static_cast<int>(t));
    }
  };
  restInBlocks(this->Rest,
    mesh.triangles.size(),
    3,
    progress,
    [&](std::size_t from, std::size_t to)
    {
      const std::size_t middle = from + (to - from) / 2;
      if (to - from < kTwoThreadItems)
      {
        some(from, to);
      }
      else
      {
        bothHalves([&] { some(from, middle); }, [&] { some(middle, to); });
      }
    });
}

void ProjectionSprings::flipped(const SpringMesh& mesh,
  const LargeVector<Vec2>& x,
  int /*edge*/,
  int t0,
  int t1)
{
  this->restOf(mesh, x, t0);
  this->restOf(mesh, x, t1);
}

void ProjectionSprings::addForces(const SpringMesh& mesh,
  const ParticleState& s,
  const SpringParams& params) const
{
  const double ks = params.stiffness;
  const std::size_t n = s.triangleEnd;
  const int* subset = s.triangleIds;
  const std::array<int, 3>* tris = mesh.triangles.data();
  const double* rest = this->Rest.data();
  std::size_t j = s.triangleBegin;
#if defined(__SSE2__)
  // Two triangles at a time (lane 0 and lane 1), corner by corner; the forces are added in
  // order as below, those of the first triangle first.
  const __m128d ksv = _mm_set1_pd(ks), one = _mm_set1_pd(1.0), zero = _mm_setzero_pd();
  for (; j + 1 < n; j += 2)
  {
    if (j + 16 < n)
    {
      // The memory of the triangles a few pairs ahead (the loop waits on it, not on the
      // arithmetic): their corners' positions and forces, then further ahead their corners.
      const std::size_t ahead = subset ? static_cast<std::size_t>(subset[j + 16]) : j + 16;
      prefetch(tris + ahead);
      prefetch(rest + 3 * ahead);
      const std::size_t near = subset ? static_cast<std::size_t>(subset[j + 8]) : j + 8;
      for (int k = 0; k < 3; ++k)
      {
        prefetch(s.x + tris[near][k]);
        prefetch(s.f + tris[near][k]);
        if (s.k)
        {
          prefetch(s.k + tris[near][k]);
        }
      }
    }
    const std::size_t t0 = subset ? static_cast<std::size_t>(subset[j]) : j;
    const std::size_t t1 = subset ? static_cast<std::size_t>(subset[j + 1]) : j + 1;
    const int v[2][3] = { { tris[t0][0], tris[t0][1], tris[t0][2] },
      { tris[t1][0], tris[t1][1], tris[t1][2] } };
    __m128d px[3], py[3];
    for (int k = 0; k < 3; ++k)
    {
      const Vec2 q0 = s.x[v[0][k]], q1 = s.x[v[1][k]];
      px[k] = _mm_set_pd(q1.x, q0.x);
      py[k] = _mm_set_pd(q1.y, q0.y);
    }
    double u[3][2], fx[3][2], fy[3][2], stiffness[3][2];
    int valid[3];
    for (int k = 0; k < 3; ++k)
    {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      // Edge a -> b is opposite corner k.
      const __m128d ex = _mm_sub_pd(px[b], px[a]), ey = _mm_sub_pd(py[b], py[a]);
      const __m128d x0 = _mm_set_pd(rest[3 * t1 + k], rest[3 * t0 + k]);
      const __m128d len2 = _mm_add_pd(_mm_mul_pd(ex, ex), _mm_mul_pd(ey, ey));
      valid[k] = _mm_movemask_pd(_mm_and_pd(_mm_cmpgt_pd(x0, zero), _mm_cmpgt_pd(len2, zero)));
      const __m128d rx = _mm_sub_pd(px[k], px[a]), ry = _mm_sub_pd(py[k], py[a]);
      __m128d w = _mm_div_pd(_mm_add_pd(_mm_mul_pd(rx, ex), _mm_mul_pd(ry, ey)), len2);
      // std::clamp(w, 0, 1): 0 below, 1 above, else w (NaN included).
      w = selectPd(_mm_cmplt_pd(w, zero), zero, w);
      w = selectPd(_mm_cmplt_pd(one, w), one, w);
      const __m128d dx = _mm_sub_pd(rx, _mm_mul_pd(w, ex));
      const __m128d dy = _mm_sub_pd(ry, _mm_mul_pd(w, ey));
      const __m128d l2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
      const __m128d isZero = _mm_cmpeq_pd(l2, zero);
      const __m128d q = _mm_div_pd(_mm_mul_pd(x0, x0), l2);
      const __m128d m = _mm_mul_pd(ksv, _mm_sub_pd(one, q));
      const __m128d negM = _mm_xor_pd(m, _mm_set1_pd(-0.0));
      _mm_storeu_pd(u[k], w);
      _mm_storeu_pd(stiffness[k], _mm_andnot_pd(isZero, _mm_mul_pd(ksv, _mm_add_pd(one, q))));
      _mm_storeu_pd(fx[k], _mm_andnot_pd(isZero, _mm_mul_pd(negM, dx)));
      _mm_storeu_pd(fy[k], _mm_andnot_pd(isZero, _mm_mul_pd(negM, dy)));
    }
    for (int lane = 0; lane < 2; ++lane)
    {
      for (int k = 0; k < 3; ++k)
      {
        if (!(valid[k] >> lane & 1))
        {
          continue;
        }
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        const int* w = v[lane];
        const double uk = u[k][lane];
        const Vec2 f{ fx[k][lane], fy[k][lane] };
        s.f[w[k]] = s.f[w[k]] + f;
        s.f[w[a]] = s.f[w[a]] - (1.0 - uk) * f;
        s.f[w[b]] = s.f[w[b]] - uk * f;
        if (s.k)
        {
          const double sk = stiffness[k][lane];
          s.k[w[k]] += sk;
          s.k[w[a]] += (1.0 - uk) * sk;
          s.k[w[b]] += uk * sk;
        }
      }
    }
  }
#endif
  for (; j < n; ++j)
  {
    const std::size_t t = subset ? static_cast<std::size_t>(subset[j]) : j;
    const int v[3] = { tris[t][0], tris[t][1], tris[t][2] };
    const Vec2 p[3] = { s.x[v[0]], s.x[v[1]], s.x[v[2]] };
    // Edge k + 1 -> k + 2 is opposite corner k.
    const Vec2 e[3] = { p[2] - p[1], p[0] - p[2], p[1] - p[0] };
    for (int k = 0; k < 3; ++k)
    {
      const double x0 = rest[3 * t + k];
      const double len2 = norm2(e[k]);
      if (!(x0 > 0.0) || !(len2 > 0.0))
      {
        continue;
      }
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const Vec2 rel = p[k] - p[a];
      const double u = std::clamp(dot(rel, e[k]) / len2, 0.0, 1.0);
      double stiffness = 0.0;
      const Vec2 f = projectionKernel(rel - u * e[k], x0 * x0, ks, stiffness);
      s.f[v[k]] = s.f[v[k]] + f;
      s.f[v[a]] = s.f[v[a]] - (1.0 - u) * f;
      s.f[v[b]] = s.f[v[b]] - u * f;
      if (s.k)
      {
        s.k[v[k]] += stiffness;
        s.k[v[a]] += (1.0 - u) * stiffness;
        s.k[v[b]] += u * stiffness;
      }
    }
  }
}

double ProjectionSprings::energy(const SpringMesh& mesh,
  const LargeVector<Vec2>& x,
  const SpringParams& params) const
{
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
  {
    const std::array<int, 3>& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
    {
      const Vec2 p = x[tri[k]], a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
      const double u = projectionParameter(p, a, b);
      sum += projectionSpringEnergy(
        norm(p - (a + u * (b - a))), this->Rest[3 * t + k], params.stiffness);
    }
  }
  return sum;
}

std::vector<std::unique_ptr<SpringSet>> makeSpringSets(SpringConfiguration configuration)
{
  std::vector<std::unique_ptr<SpringSet>> sets;
  sets.push_back(std::make_unique<EdgeSprings>());
  if (configuration == SpringConfiguration::EdgeAndProjection)
  {
    sets.push_back(std::make_unique<ProjectionSprings>());
  }
  return sets;
}

//------------------------------------------------------------------------------
SpringSystem::SpringSystem(SpringMesh mesh,
  LargeVector<Vec2> positions,
  LargeVector<Vec2> rest,
  const SpringParams& params,
  const ProgressReporter& progress)
  : Params(params)
  , Mesh(std::move(mesh))
  , X(std::move(positions))
  , Rest(std::move(rest))
{
  validate(params);
  const std::size_t n = this->X.size();
  if (this->Rest.size() != n)
  {
    throw ParameterError("SpringSystem: " + std::to_string(n) + " positions but " +
      std::to_string(this->Rest.size()) + " rest positions");
  }
  const int ni = static_cast<int>(n);
  for (const std::array<int, 3>& t : this->Mesh.triangles)
  {
    for (int v : t)
    {
      if (v < 0 || v >= ni)
      {
        throw ParameterError("SpringSystem: a triangle refers to particle " + std::to_string(v) +
          ", not in [0, " + std::to_string(n) + ")");
      }
    }
  }
  for (const std::array<int, 2>& e : this->Mesh.edges)
  {
    if (e[0] < 0 || e[0] >= ni || e[1] < 0 || e[1] >= ni)
    {
      throw ParameterError("SpringSystem: an edge refers to a particle out of range");
    }
  }
  const char* stage = kSpringStage;
  progress.report(0.0, stage);
  this->V.assign(n, Vec2{});
  this->F.assign(n, Vec2{});
  progress.report(0.0, stage); // (between first writes: 0.02-0.05 s each at 1 M)
  this->K.assign(n, 0.0);
  this->Kind.assign(n, static_cast<std::uint8_t>(ParticleKind::Free));
  this->Local.assign(n, 0.0);
  LargeVector<int> count(n, 0);
  progress.report(0.0, stage);
  for (const std::array<int, 2>& e : this->Mesh.edges)
  {
    const double l = norm(this->Rest[e[0]] - this->Rest[e[1]]);
    this->Local[e[0]] += l;
    this->Local[e[1]] += l;
    ++count[e[0]];
    ++count[e[1]];
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    this->Local[i] = count[i] > 0 && this->Local[i] > 0.0 ? this->Local[i] / count[i] : 1.0;
  }
  for (std::unique_ptr<SpringSet>& set : makeSpringSets(params.configuration))
  {
    progress.report(0.0, stage);
    this->addSpringSet(std::move(set), progress);
  }
  progress.report(0.0, stage);
}

SpringSystem::SpringSystem(SpringMesh mesh, LargeVector<Vec2> positions, const SpringParams& params)
  : SpringSystem(std::move(mesh), positions, positions, params)
{
}

void SpringSystem::addSpringSet(std::unique_ptr<SpringSet> set, const ProgressReporter& progress)
{
  if (this->Rest.size() != this->X.size())
  {
    throw ParameterError("SpringSystem::addSpringSet: the rest positions were released");
  }
  set->initializeWithProgress(this->Mesh, this->Rest, progress);
  this->Sets.push_back(std::move(set));
}

void SpringSystem::releaseRestPositions()
{
  LargeVector<Vec2>().swap(this->Rest);
}

// Back to no live spring: what the last awake set made nonzero is reset (every accumulator
// and flag when all springs may have written: before the first set, or with none). With
// `none` (every particle awake next) the flags go.
void SpringSystem::resetLive(bool none)
{
  const auto resetTouched = [this](LargeVector<Vec2>& f, LargeVector<double>& k)
  {
    if (f.size() != this->X.size())
    {
      return;
    }
    for (const int i : this->Touched)
    {
      f[i] = Vec2{};
      k[i] = 0.0;
    }
  };
  if (this->sparseReset())
  {
    resetTouched(this->F, this->K);
    resetTouched(this->F1, this->K1);
    for (const int i : this->Touched)
    {
      this->IsTouched[i] = 0;
    }
    for (const int e : this->LiveEdges)
    {
      this->LiveEdge[e] = 0;
    }
    for (const int t : this->LiveTriangles)
    {
      this->LiveTriangle[t] = 0;
    }
  }
  else
  {
    std::fill(this->F.begin(), this->F.end(), Vec2{});
    std::fill(this->K.begin(), this->K.end(), 0.0);
    std::fill(this->F1.begin(), this->F1.end(), Vec2{});
    std::fill(this->K1.begin(), this->K1.end(), 0.0);
    this->IsTouched.assign(none ? 0 : this->X.size(), 0);
    this->LiveEdge.assign(none ? 0 : this->Mesh.edges.size(), 0);
    this->LiveTriangle.assign(none ? 0 : this->Mesh.triangles.size(), 0);
  }
}

void SpringSystem::setAwake(LargeVector<std::uint8_t> mask, AwakeSets&& sets)
{
  if (mask.size() != this->X.size())
  {
    throw ParameterError("SpringSystem::setAwake: " + std::to_string(mask.size()) +
      " mask entries for " + std::to_string(this->X.size()) + " particles");
  }
  const auto check = [](const LargeVector<int>& ids, std::size_t n, const char* what)
  {
    for (std::size_t j = 0; j < ids.size(); ++j)
    {
      if (ids[j] < 0 || static_cast<std::size_t>(ids[j]) >= n || (j > 0 && ids[j] <= ids[j - 1]))
      {
        throw ParameterError(std::string("SpringSystem::setAwake: the awake ") + what +
          " are not increasing in [0, " + std::to_string(n) + "): " + std::to_string(ids[j]) +
          " at " + std::to_string(j));
      }
    }
  };
  check(sets.particles, this->X.size(), "particles");
  check(sets.edges, this->Mesh.edges.size(), "edges");
  check(sets.triangles, this->Mesh.triangles.size(), "triangles");
  for (const int i : sets.particles)
  {
    if (!mask[i])
    {
      throw ParameterError(
        "SpringSystem::setAwake: particle " + std::to_string(i) + " is listed but asleep");
    }
  }
  this->resetLive(false);
  this->Awake = std::move(mask);
  this->AwakeList.swap(sets.particles);
  this->LiveEdges.swap(sets.edges);
  this->LiveTriangles.swap(sets.triangles);
  this->Touched.clear();
  // (In the order of the pass over the edges below: the same touched list.)
  for (const int e : this->LiveEdges)
  {
    this->LiveEdge[e] = 1;
    this->touch(this->Mesh.edges[e]);
  }
  for (const int t : this->LiveTriangles)
  {
    this->LiveTriangle[t] = 1;
  }
}

void SpringSystem::setAwake(LargeVector<std::uint8_t> mask)
{
  this->resetLive(mask.empty());
  this->Awake = std::move(mask);
  this->AwakeList.clear();
  this->LiveEdges.clear();
  this->LiveTriangles.clear();
  this->Touched.clear();
  if (this->Awake.empty())
  {
    this->IsTouched.clear();
    return;
  }
  // (Each list reserved for all it may hold: grown by doubling, the first refresh at 1 M wrote
  // about twice its lists' memory, new to the process, and copied them on the way.)
  this->AwakeList.reserve(this->Awake.size());
  for (std::size_t i = 0; i < this->Awake.size(); ++i)
  {
    if (this->Awake[i])
    {
      this->AwakeList.push_back(static_cast<int>(i));
    }
  }
  // Only the particles of live springs get forces from here on, and computeForces resets
  // those entries only. The edges' and the triangles' lists are independent: one thread each
  // (for large meshes), both in order. The live edges' ends are all the touched particles: a
  // live triangle has an awake corner, whose edges to the other two corners are live.
  // (Each thread appends to a list of its own, the member's buffer swapped in and out: the
  // members' ends share a cache line, which the two threads' appends took from each other.)
  const LargeVector<std::uint8_t>& awake = this->Awake;
  const auto liveEdges = [&]
  {
    LargeVector<int> live, touched;
    live.swap(this->LiveEdges);
    touched.swap(this->Touched);
    live.reserve(this->Mesh.edges.size());
    touched.reserve(this->X.size());
    for (std::size_t e = 0; e < this->Mesh.edges.size(); ++e)
    {
      if (awake[this->Mesh.edges[e][0]] || awake[this->Mesh.edges[e][1]])
      {
        this->LiveEdge[e] = 1;
        live.push_back(static_cast<int>(e));
        this->touch(this->Mesh.edges[e], touched);
      }
    }
    live.swap(this->LiveEdges);
    touched.swap(this->Touched);
  };
  const auto liveTriangles = [&]
  {
    LargeVector<int> live;
    live.swap(this->LiveTriangles);
    live.reserve(this->Mesh.triangles.size());
    for (std::size_t t = 0; t < this->Mesh.triangles.size(); ++t)
    {
      const std::array<int, 3>& tri = this->Mesh.triangles[t];
      if (awake[tri[0]] || awake[tri[1]] || awake[tri[2]])
      {
        this->LiveTriangle[t] = 1;
        live.push_back(static_cast<int>(t));
      }
    }
    live.swap(this->LiveTriangles);
  };
  if (this->Mesh.triangles.size() < kTwoThreadItems)
  {
    liveEdges();
    liveTriangles();
    return;
  }
  bothHalves(liveEdges, liveTriangles);
}

void SpringSystem::resetAccumulators(Vec2* f, double* k) const
{
  // A few particles touched: their entries; many: all of them (sequential writes).
  if (!this->sparseReset())
  {
    std::fill(f, f + this->X.size(), Vec2{});
    std::fill(k, k + this->X.size(), 0.0);
    return;
  }
  for (const int i : this->Touched)
  {
    f[i] = Vec2{};
    k[i] = 0.0;
  }
}

void SpringSystem::computeForces()
{
  ParticleState s{ this->X.data(), this->V.data(), this->F.data(), this->K.data() };
  const bool live = !this->Awake.empty();
  s.edgeIds = live ? this->LiveEdges.data() : nullptr;
  s.edgeEnd = live ? this->LiveEdges.size() : this->Mesh.edges.size();
  s.triangleIds = live ? this->LiveTriangles.data() : nullptr;
  s.triangleEnd = live ? this->LiveTriangles.size() : this->Mesh.triangles.size();
  const auto add = [this](const ParticleState& part)
  {
    this->resetAccumulators(part.f, part.k);
    for (const std::unique_ptr<SpringSet>& set : this->Sets)
    {
      set->addForces(this->Mesh, part, this->Params);
    }
  };
  if (!this->splits())
  {
    // The second half's accumulators go while the steps are not split (made again, zero, when
    // one is): at 1 M 12 MB that the compression's waves of new pushes take instead of new
    // memory (see LargeArray.h).
    LargeVector<Vec2>().swap(this->F1);
    LargeVector<double>().swap(this->K1);
    add(s);
    return;
  }
  // Two halves of the springs, each into its own accumulators (reset by its own thread), then
  // summed, in two halves too: the second half on a second thread.
  if (this->F1.size() != this->F.size())
  {
    this->F1.assign(this->F.size(), Vec2{});
    this->K1.assign(this->K.size(), 0.0);
  }
  ParticleState second = s;
  second.f = this->F1.data();
  second.k = this->K1.data();
  second.part = 1;
  s.edgeEnd = second.edgeBegin = s.edgeEnd / 2;
  s.triangleEnd = second.triangleBegin = s.triangleEnd / 2;
  bothHalves([&] { add(s); }, [&] { add(second); });
  // Summed where the second half may have written: every particle, or the touched ones when
  // the accumulators are reset there only (the others' entries are zero in F1 and K1).
  const int* touched = this->sparseReset() ? this->Touched.data() : nullptr;
  const auto sum = [this, touched](std::size_t from, std::size_t to)
  {
    for (std::size_t j = from; j < to; ++j)
    {
      const std::size_t i = touched ? static_cast<std::size_t>(touched[j]) : j;
      this->F[i] = this->F[i] + this->F1[i];
      this->K[i] += this->K1[i];
    }
  };
  const std::size_t n = touched ? this->Touched.size() : this->F.size();
  bothHalves([&] { sum(0, n / 2); }, [&] { sum(n / 2, n); });
}

double SpringSystem::moveParticle(std::size_t i, double dt, MoveGuard* guard)
{
  const double m = std::max(this->Params.mass, 2.0 * dt * dt * this->K[i]);
  Vec2 v = this->V[i] + (dt / m) * this->F[i];
  Vec2 d = dt * v;
  const double limit = this->Params.maxStep * this->Local[i];
  const double length = norm(d);
  if (length > limit)
  {
    d = (limit / length) * d;
    v = (limit / length) * v;
  }
  const Vec2 to = this->X[i] + d;
  if (guard && !guard->accept(static_cast<int>(i), this->X[i], to))
  {
    this->V[i] = Vec2{};
    return 0.0;
  }
  this->X[i] = to;
  this->V[i] = v;
  return std::min(length, limit) / this->Local[i];
}

double SpringSystem::integrate(double dt, MoveGuard* guard)
{
  const std::size_t n = this->X.size();
  const auto free = [this](std::size_t i)
  { return this->Kind[i] == static_cast<std::uint8_t>(ParticleKind::Free); };
  // The particles that may move, in index order: all, or the awake ones.
  const bool all = this->Awake.empty();
  const std::size_t count = all ? n : this->AwakeList.size();
  const auto particle = [&](std::size_t j)
  { return all ? j : static_cast<std::size_t>(this->AwakeList[j]); };
  if (!this->splits())
  {
    double largest = 0.0;
    for (std::size_t j = 0; j < count; ++j)
    {
      const std::size_t i = particle(j);
      if (free(i))
      {
        largest = std::max(largest, this->moveParticle(i, dt, guard));
      }
    }
    return largest;
  }
  // Two index halves, each moving the particles whose triangles lie in it (a move reads the
  // corners of the particle's triangles only), then the seam's in index order.
  if (this->Seam.size() != n)
  {
    this->findSeam();
  }
  const std::size_t splitAt = all
    ? this->SplitAt
    : static_cast<std::size_t>(
        std::lower_bound(this->AwakeList.begin(), this->AwakeList.end(), this->SplitAt) -
        this->AwakeList.begin());
  double largest[2] = { 0.0, 0.0 };
  const auto half = [&](int h)
  {
    const std::size_t begin = h == 0 ? 0 : splitAt, end = h == 0 ? splitAt : count;
    double most = 0.0; // (a local: the two threads' results share a cache line)
    for (std::size_t j = begin; j < end; ++j)
    {
      const std::size_t i = particle(j);
      if (!this->Seam[i] && free(i))
      {
        most = std::max(most, this->moveParticle(i, dt, guard));
      }
    }
    largest[h] = most;
  };
  bothHalves([&] { half(0); }, [&] { half(1); });
  double result = std::max(largest[0], largest[1]);
  for (std::size_t j = 0; j < count; ++j)
  {
    const std::size_t i = particle(j);
    if (this->Seam[i] && free(i))
    {
      result = std::max(result, this->moveParticle(i, dt, guard));
    }
  }
  return result;
}

bool SpringSystem::splits() const
{
  const std::size_t springs = this->Awake.empty()
    ? this->Mesh.edges.size() + this->Mesh.triangles.size()
    : this->LiveEdges.size() + this->LiveTriangles.size();
  return springs >= this->Params.splitSprings;
}

void SpringSystem::setKind(int i, ParticleKind kind)
{
  if (kind != ParticleKind::Fixed &&
    this->Kind[i] == static_cast<std::uint8_t>(ParticleKind::Fixed))
  {
    this->Seam.clear(); // a fixed particle that moves again may join the halves: find it anew
  }
  this->Kind[i] = static_cast<std::uint8_t>(kind);
}

void SpringSystem::findSeam()
{
  // The split halves the particles that are not fixed.
  const std::size_t n = this->X.size();
  std::size_t movable = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    movable += this->Kind[i] != static_cast<std::uint8_t>(ParticleKind::Fixed);
  }
  this->SplitAt = 0;
  for (std::size_t below = 0; this->SplitAt < n && 2 * below < movable; ++this->SplitAt)
  {
    below += this->Kind[this->SplitAt] != static_cast<std::uint8_t>(ParticleKind::Fixed);
  }
  this->Seam.assign(n, 0);
  for (const std::array<int, 3>& t : this->Mesh.triangles)
  {
    this->markSeam(t);
  }
}

void SpringSystem::markSeam(const std::array<int, 3>& t)
{
  // Fixed particles never move: reading them from either half is safe.
  bool low = false, high = false;
  for (const int i : t)
  {
    if (this->Kind[i] != static_cast<std::uint8_t>(ParticleKind::Fixed))
    {
      (static_cast<std::size_t>(i) < this->SplitAt ? low : high) = true;
    }
  }
  if (low && high)
  {
    for (const int i : t)
    {
      this->Seam[i] = this->Kind[i] != static_cast<std::uint8_t>(ParticleKind::Fixed);
    }
  }
}

double SpringSystem::step(double dt, MoveGuard* guard)
{
  this->computeForces();
  return this->integrate(dt, guard);
}

double SpringSystem::kineticEnergy() const
{
  double sum = 0.0;
  for (std::size_t i = 0; i < this->X.size(); ++i)
  {
    if (this->Kind[i] != static_cast<std::uint8_t>(ParticleKind::Fixed))
    {
      sum += 0.5 * this->Params.mass * norm2(this->V[i]);
    }
  }
  return sum;
}

double SpringSystem::potentialEnergy() const
{
  double sum = 0.0;
  for (const std::unique_ptr<SpringSet>& set : this->Sets)
  {
    sum += set->energy(this->Mesh, this->X, this->Params);
  }
  return sum;
}

void SpringSystem::flip(int edge,
  std::array<int, 2> newEdge,
  int t0,
  std::array<int, 3> n0,
  int t1,
  std::array<int, 3> n1)
{
  this->Mesh.edges[edge] = { std::min(newEdge[0], newEdge[1]), std::max(newEdge[0], newEdge[1]) };
  this->Mesh.triangles[t0] = n0;
  this->Mesh.triangles[t1] = n1;
  if (!this->Seam.empty())
  {
    // The new triangles may join the halves (the seam only grows).
    this->markSeam(n0);
    this->markSeam(n1);
  }
  for (std::unique_ptr<SpringSet>& set : this->Sets)
  {
    set->flipped(this->Mesh, this->X, edge, t0, t1);
  }
  if (!this->Awake.empty())
  {
    // The flipped springs now touch other particles: make them live if one is awake.
    const std::array<int, 2>& e = this->Mesh.edges[edge];
    if (!this->LiveEdge[edge] && (this->Awake[e[0]] || this->Awake[e[1]]))
    {
      this->LiveEdge[edge] = 1;
      this->LiveEdges.push_back(edge);
    }
    if (this->LiveEdge[edge])
    {
      this->touch(e);
    }
    for (int t : { t0, t1 })
    {
      const std::array<int, 3>& tri = this->Mesh.triangles[t];
      if (!this->LiveTriangle[t] &&
        (this->Awake[tri[0]] || this->Awake[tri[1]] || this->Awake[tri[2]]))
      {
        this->LiveTriangle[t] = 1;
        this->LiveTriangles.push_back(t);
      }
      if (this->LiveTriangle[t])
      {
        this->touch(tri); // (a live triangle's new corner)
      }
    }
  }
}

} // namespace strata
