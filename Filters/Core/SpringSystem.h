// StrataMesh core: a mass-spring particle system on a triangle mesh (paper Sections 6.1 and
// 6.2). It computes spring forces and integrates particles; it knows nothing about why a
// particle is pushed: callers mark particles as driven (moved by them) or fixed. No VTK.
#ifndef StrataMeshCore_SpringSystem_h
#define StrataMeshCore_SpringSystem_h

#include "Geometry.h"
#include "LargeArray.h"
#include "Progress.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace strata
{

/// Spring configurations of paper Section 6.1 (more can be added as SpringSet subclasses).
enum class SpringConfiguration : int
{
  EdgeOnly = 0,         ///< one Hooke spring per edge
  EdgeAndProjection = 1 ///< plus one non-linear projection spring per triangle corner
};

/// Global coefficients of the springs and particles. All quantities are model-independent:
/// forces are proportional to lengths, so with unit masses the motion of a mesh scaled by any
/// factor is the same motion scaled; time is dimensionless (an undamped edge spring between
/// two unit masses oscillates with period 2 pi / sqrt(2 stiffness)).
struct SpringParams
{
  SpringConfiguration configuration = SpringConfiguration::EdgeAndProjection;
  /// ks of both laws. Range (0, 1e3].
  double stiffness = 1.0;
  /// kd of the edge springs (damping of the relative velocity along the spring). Range
  /// [0, 1e3].
  double damping = 0.5;
  /// Mass of every particle. Range (0, 1e6].
  double mass = 1.0;
  /// Largest displacement of a free particle in one step, as a fraction of its local length
  /// (mean rest length of its edges). Bounds the jump a stiff, nearly collapsed projection
  /// spring can cause in one explicit step. Range (0, 1].
  double maxStep = 0.25;
  /// Springs (edges plus triangles) from which a step is split in two halves computed by two
  /// threads (SpringSystem::computeForces and integrate). The split depends on this number
  /// only, never on the machine's cores (one core computes both halves in turn), so results
  /// are the same everywhere; below it one serial loop. Range [0, inf).
  std::size_t splitSprings = 131072;
};

/// The triangles the springs live on and their unique edges. Springs are indexed by edge and
/// by triangle corner, so ids stay valid through edge flips (SpringSystem::flip).
struct SpringMesh
{
  LargeVector<std::array<int, 3>> triangles; ///< counter-clockwise
  LargeVector<std::array<int, 2>> edges;     ///< each undirected edge once
};

/// Unique edges of a triangle list (sorted end points, ordered).
LargeVector<std::array<int, 2>> uniqueEdges(const LargeVector<std::array<int, 3>>& triangles);

/// Paper 6.1, edge spring (Hooke's law with damping): the force on end a of a spring with
/// dx = xa - xb, dv = va - vb and rest length x0:
///   F_a = -(ks (|dx| - x0) + kd (dv . dx) / |dx|) dx / |dx|,  F_b = -F_a.
/// A stretched spring pulls its ends together; damping opposes the rate of stretching. Zero
/// for |dx| = 0 (no direction).
Vec2 edgeSpringForce(Vec2 dx, Vec2 dv, double restLength, double ks, double kd);

/// Paper 6.1, projection (repulsion) spring between a vertex and its projection on the
/// opposite edge, with dx = vertex - projection and rest length x0. The paper writes
/// F = ks (|dx| - x0 / |dx|) dx / |dx|, whose rest point is |dx| = sqrt(x0) and depends on the
/// units; measured in units of the rest length (r = |dx| / x0) the same law reads
///   F_vertex = -ks x0 (r - 1 / r) dx / |dx|,
/// which is at rest at r = 1, pulls back when stretched and grows without bound as r -> 0.
/// Zero for |dx| = 0 or x0 <= 0.
Vec2 projectionSpringForce(Vec2 dx, double restLength, double ks);

/// Potential energies of the two laws (zero at rest).
double edgeSpringEnergy(double length, double restLength, double ks);
double projectionSpringEnergy(double length, double restLength, double ks);

/// Closest point to p on segment ab: parameter t in [0, 1] (0 at a).
double projectionParameter(Vec2 p, Vec2 a, Vec2 b);

/// The particle state a spring set reads and the force array it adds to.
struct ParticleState
{
  const Vec2* x = nullptr;
  const Vec2* v = nullptr;
  Vec2* f = nullptr;
  /// Stiffness accumulator (may be null): each spring adds its current stiffness along its
  /// direction (dF/dlength) to the particles it acts on, for the stable mass of step().
  double* k = nullptr;
  /// The springs to add: edges [edgeBegin, edgeEnd) (for edge-indexed sets) and triangles
  /// [triangleBegin, triangleEnd) (for triangle-indexed sets) of the lists edgeIds and
  /// triangleIds, or of the mesh's own when they are null (then every spring, unless the
  /// ranges say otherwise). The lists are the springs touching an awake particle.
  const int* edgeIds = nullptr;
  std::size_t edgeBegin = 0, edgeEnd = 0;
  const int* triangleIds = nullptr;
  std::size_t triangleBegin = 0, triangleEnd = 0;
  /// Which part of a split computation this is (0 or 1; see SpringSystem::computeForces).
  int part = 0;
};

/// A set of springs defined on a SpringMesh. Subclass to add a configuration.
class SpringSet
{
public:
  virtual ~SpringSet() = default;
  virtual const char* name() const = 0;
  /// Rest lengths of every spring from the rest positions.
  virtual void initialize(const SpringMesh& mesh, const LargeVector<Vec2>& rest) = 0;
  /// initialize(), telling `progress` (fraction 0, stage "building the spring system")
  /// between parts of the work: a set with a spring per edge or per triangle corner takes
  /// 0.02-0.07 s at a million triangles, most of it the first writes to its rest lengths. By
  /// default initialize() in one go.
  virtual void initializeWithProgress(const SpringMesh& mesh,
    const LargeVector<Vec2>& rest,
    const ProgressReporter& progress)
  {
    (void)progress;
    this->initialize(mesh, rest);
  }
  /// After SpringSystem::flip: new rest lengths (the current ones) of the springs of edge
  /// `edge` and of triangles t0 and t1.
  virtual void flipped(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    int edge,
    int t0,
    int t1) = 0;
  /// Adds the forces (and stiffnesses) of the springs in s's edge and triangle ranges to
  /// s.f (and s.k). computeForces may split the springs in two parts, each with its own
  /// ranges and accumulators, and compute them at once on two threads: an implementation
  /// reads the shared state and writes only s.f and s.k, and only the entries of the
  /// particles of the springs in its ranges (edge ends, triangle corners: while some particles
  /// sleep, computeForces resets those entries only); springs that are neither edge- nor
  /// triangle-indexed are added in part 0.
  virtual void addForces(const SpringMesh& mesh,
    const ParticleState& s,
    const SpringParams& params) const = 0;
  /// Potential energy of all springs.
  virtual double energy(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    const SpringParams& params) const = 0;
};

/// One Hooke spring per edge (paper 6.1).
class EdgeSprings : public SpringSet
{
public:
  const char* name() const override { return "edge"; }
  void initialize(const SpringMesh& mesh, const LargeVector<Vec2>& rest) override;
  void initializeWithProgress(const SpringMesh& mesh,
    const LargeVector<Vec2>& rest,
    const ProgressReporter& progress) override;
  void flipped(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    int edge,
    int t0,
    int t1) override;
  void addForces(const SpringMesh& mesh,
    const ParticleState& s,
    const SpringParams& params) const override;
  double energy(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    const SpringParams& params) const override;

private:
  LargeVector<double> Rest;
};

/// One projection spring per triangle corner (paper 6.1, Figure 8): the corner against an
/// auxiliary particle at its projection on the opposite edge (clamped to the edge). The
/// auxiliary particle exists only while the force is computed; its reaction goes to the
/// edge's end points in proportion to the projection parameter (1 - t to the first, t to the
/// second).
class ProjectionSprings : public SpringSet
{
public:
  const char* name() const override { return "projection"; }
  void initialize(const SpringMesh& mesh, const LargeVector<Vec2>& rest) override;
  void initializeWithProgress(const SpringMesh& mesh,
    const LargeVector<Vec2>& rest,
    const ProgressReporter& progress) override;
  void flipped(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    int edge,
    int t0,
    int t1) override;
  void addForces(const SpringMesh& mesh,
    const ParticleState& s,
    const SpringParams& params) const override;
  double energy(const SpringMesh& mesh,
    const LargeVector<Vec2>& x,
    const SpringParams& params) const override;

private:
  void restOf(const SpringMesh& mesh, const LargeVector<Vec2>& x, int t);
  LargeVector<double> Rest; // 3 per triangle
};

/// How a particle is treated by SpringSystem::step.
enum class ParticleKind : std::uint8_t
{
  Free,   ///< integrated from its spring forces
  Driven, ///< moved by the caller (its force is computed, step() leaves it alone)
  Fixed   ///< never moves
};

/// Lets a caller veto a particle's move (e.g. one that would invert a triangle).
class MoveGuard
{
public:
  virtual ~MoveGuard() = default;
  /// Whether particle i may move from `from` to `to` (all other particles where they are now).
  /// A split step (SpringParams::splitSprings) asks from two threads at once, for particles
  /// that share no triangle: an implementation reads the corners of i's triangles only.
  virtual bool accept(int i, Vec2 from, Vec2 to) = 0;
};

/// Particles (position, velocity, force, mass) on the vertices of a SpringMesh, with the spring
/// sets of a configuration. Rest lengths are the lengths in the rest positions.
///
/// Integration: semi-implicit (symplectic) Euler, v += dt F(x, v) / m, then x += dt v. The
/// paper's scheme (add the derivative vector (v, F / m) dt to the state) is explicit Euler,
/// which multiplies the energy of an undamped spring by (1 + (w dt)^2) every step and so blows
/// up without enough damping; symplectic Euler keeps the energy of an undamped oscillator
/// bounded for w dt < 2 at the same cost (one force evaluation per step) and, with damping,
/// decays it. With the defaults (ks = m = 1, dt = 0.1) w dt is about 0.3 at rest, but a
/// projection spring compressed to a fraction r of its rest length is (1 + 1 / r^2) times
/// stiffer, which would break that bound in the squeezed triangles compression produces. So
/// each step uses for particle i the mass m_i = max(m, 2 dt^2 K_i), K_i the summed current
/// stiffness of its springs (mass scaling, as in explicit finite elements): then
/// w_i^2 <= 2 K_i / m_i <= 1 / dt^2, i.e. w_i dt <= 1 everywhere. Equilibria do not depend on
/// the masses, so stiff spots just move slower; at rest nothing changes with the defaults.
/// The step bound SpringParams::maxStep is a last safeguard.
class SpringSystem
{
public:
  /// Rest lengths from `rest` (same size as positions). Throws ParameterError for
  /// parameters out of range, sizes that differ or indices out of range. `progress` is told
  /// (fraction 0, stage "building the spring system") between the construction's passes over
  /// the particles and the springs and between blocks of rest lengths
  /// (SpringSet::initializeWithProgress), which take 0.02-0.05 s each at a million triangles.
  SpringSystem(SpringMesh mesh,
    LargeVector<Vec2> positions,
    LargeVector<Vec2> rest,
    const SpringParams& params = {},
    const ProgressReporter& progress = ProgressReporter());
  /// Rest lengths from the initial positions.
  SpringSystem(SpringMesh mesh, LargeVector<Vec2> positions, const SpringParams& params = {});

  /// Adds a spring set (initialised from the rest positions given at construction; `progress`
  /// is told between parts of that, see SpringSet::initializeWithProgress).
  void addSpringSet(std::unique_ptr<SpringSet> set,
    const ProgressReporter& progress = ProgressReporter());
  /// Frees the rest positions, which only addSpringSet() reads after the construction (for a
  /// caller done adding sets: 8 MB at a million triangles). addSpringSet() throws
  /// ParameterError afterwards.
  void releaseRestPositions();
  std::size_t numberOfSpringSets() const { return this->Sets.size(); }

  std::size_t numberOfParticles() const { return this->X.size(); }
  std::size_t numberOfTriangles() const { return this->Mesh.triangles.size(); }
  const SpringParams& params() const { return this->Params; }
  const SpringMesh& mesh() const { return this->Mesh; }

  LargeVector<Vec2>& positions() { return this->X; }
  const LargeVector<Vec2>& positions() const { return this->X; }
  LargeVector<Vec2>& velocities() { return this->V; }
  const LargeVector<Vec2>& velocities() const { return this->V; }
  const LargeVector<Vec2>& forces() const { return this->F; }
  ParticleKind kind(int i) const { return static_cast<ParticleKind>(this->Kind[i]); }
  void setKind(int i, ParticleKind kind);
  /// Mean rest length of the particle's edges (1 for a particle without edges).
  double localLength(int i) const { return this->Local[i]; }
  /// Summed stiffness of the particle's springs at the last computeForces().
  double stiffness(int i) const { return this->K[i]; }
  /// The mass step(dt) uses for particle i: max(mass, 2 dt^2 stiffness(i)).
  double stableMass(int i, double dt) const
  {
    return std::max(this->Params.mass, 2.0 * dt * dt * this->K[i]);
  }

  /// Sleeping: only awake particles are integrated, and only springs touching an awake
  /// particle are evaluated (the forces on awake particles are then complete; a sleeping
  /// particle has the forces of the live springs that touch it, none when no live spring
  /// does). An empty mask wakes every particle. What the last mask's springs wrote is reset
  /// there only; the live springs are found by one pass over the edges and one over the
  /// triangles (on two threads for large meshes).
  void setAwake(LargeVector<std::uint8_t> awake);
  /// The awake particles and their live springs, as a caller with the mesh's adjacency finds
  /// them for a few awake particles: each list increasing, without repeats.
  struct AwakeSets
  {
    LargeVector<int> particles; ///< those with a nonzero mask entry
    LargeVector<int> edges;     ///< the edges with an awake end
    LargeVector<int> triangles; ///< the triangles with an awake corner
  };
  /// setAwake(awake) with the lists given, not found by passes over every spring: the same
  /// state, at the cost of the lists (a wave's tail refreshes a few awake particles at every
  /// step). Preconditions: `awake` has an entry per particle; each list is increasing, in
  /// range, and the particles' entries are nonzero (ParameterError otherwise); that the lists
  /// hold every awake particle and live spring is the caller's (a pass over the springs to
  /// check it would cost what this spares).
  void setAwake(LargeVector<std::uint8_t> awake, AwakeSets&& sets);
  bool awake(int i) const { return this->Awake.empty() || this->Awake[i]; }
  /// The awake particles, increasing; null when every particle is awake.
  const LargeVector<int>* awakeParticles() const
  {
    return this->Awake.empty() ? nullptr : &this->AwakeList;
  }

  /// Phase 1: resets the force accumulators and adds the contribution of every spring.
  void computeForces();
  /// Phases 2 and 3 for the free particles: acceleration F / m_i, then v += dt a and
  /// x += dt v (displacement clamped to maxStep local lengths). When `guard` rejects a move
  /// the particle stays and its velocity is zeroed. Particles move one after the other, in
  /// index order, each guarded against the others' new positions; a split step moves two
  /// index halves at once (the particles with triangles in both halves last). Call
  /// computeForces() first. Returns the largest displacement of a free particle divided by
  /// its local length.
  double integrate(double dt, MoveGuard* guard = nullptr);
  /// computeForces() then integrate().
  double step(double dt, MoveGuard* guard = nullptr);

  double kineticEnergy() const;
  double potentialEnergy() const;

  /// Replaces the edge `edge` shared by triangles t0 and t1 by newEdge and the triangles by
  /// n0 and n1 (an edge flip done by the caller, who checked it); the springs of the edge and
  /// of both triangles take their current lengths as rest lengths.
  void flip(int edge,
    std::array<int, 2> newEdge,
    int t0,
    std::array<int, 3> n0,
    int t1,
    std::array<int, 3> n1);

private:
  SpringParams Params;
  SpringMesh Mesh;
  LargeVector<Vec2> X, V, F, Rest;
  LargeVector<double> K;
  LargeVector<Vec2> F1;   // the second half's forces (computeForces)
  LargeVector<double> K1; // and stiffnesses
  // integrate's halves: [0, SplitAt) and [SplitAt, n); Seam marks the particles with a
  // triangle in both, moved after the halves (empty until a split step).
  std::size_t SplitAt = 0;
  LargeVector<std::uint8_t> Seam;
  bool splits() const; // whether a step is split (SpringParams::splitSprings)
  double moveParticle(std::size_t i, double dt, MoveGuard* guard);
  void findSeam();
  void markSeam(const std::array<int, 3>& t);
  LargeVector<std::uint8_t> Awake;
  LargeVector<int> AwakeList; // the awake particles, increasing (integrate's loops)
  LargeVector<int> LiveEdges, LiveTriangles;
  LargeVector<std::uint8_t> LiveEdge, LiveTriangle;
  // The particles of the live springs (the only forces computeForces writes while some
  // particles sleep), so that it resets those entries only.
  LargeVector<int> Touched;
  LargeVector<std::uint8_t> IsTouched;
  // Marks the particles `ends` touched, appending those not yet touched to `into` (Touched,
  // or a thread's list that becomes it).
  template<std::size_t N>
  void touch(const std::array<int, N>& ends, LargeVector<int>& into)
  {
    for (const int i : ends)
    {
      if (!this->IsTouched[i])
      {
        this->IsTouched[i] = 1;
        into.push_back(i);
      }
    }
  }
  template<std::size_t N>
  void touch(const std::array<int, N>& ends)
  {
    this->touch(ends, this->Touched);
  }
  void resetAccumulators(Vec2* f, double* k) const;
  // Back to no live spring before a new awake mask (`none`: an empty one).
  void resetLive(bool none);
  // Whether computeForces resets (and sums) the touched particles' accumulators only, and
  // setAwake resets those entries only: some particles sleep and at most a quarter of them are
  // touched (IsTouched is then sized: a nonempty awake mask sizes it).
  bool sparseReset() const
  {
    return !this->Awake.empty() && 4 * this->Touched.size() <= this->X.size();
  }
  LargeVector<std::uint8_t> Kind;
  LargeVector<double> Local;
  std::vector<std::unique_ptr<SpringSet>> Sets;
};

/// The spring sets of a configuration (for SpringSystem::addSpringSet).
std::vector<std::unique_ptr<SpringSet>> makeSpringSets(SpringConfiguration configuration);

/// Validates params (ParameterError naming the parameter and its range).
void validate(const SpringParams& params);

} // namespace strata

#endif
