// StrataMesh core: physical compression of the classified 4-8 grid onto the model's
// boundaries (paper Section 6), face classification (Section 5) and a quality pass.
//
// The algorithm
// -------------
// 0. Rails. The model's boundary becomes chains of segments between junctions (nodes where
//    the number of boundary segments is not two); closed chains have no junction. Chain points
//    whose angle is below featureAngle are features. One strip tree over all segments gives
//    the exact closest boundary point of any point (segment + parameter).
// 1. Candidates and push (6.3). Candidates are the end points of intersection edges. The push
//    criterion picks the vertices to push: all candidates; one side (OneSide: the exterior end
//    of an edge between a region and the exterior, the end in the region of larger id between
//    two regions, the end closer to the boundary when both ends lie in one region); or the end
//    closer to the boundary. A pushed vertex's target is its closest boundary point; it moves
//    straight toward it at pushVelocity, ignoring all forces, until it arrives. Vertices that
//    the classification found on a boundary are pushed too (they arrive in one step).
// 2. Junctions (6.4). Each junction gets exactly one vertex: the nearest candidate whose move
//    onto the junction keeps its triangles valid is snapped there before the simulation and
//    pinned; if none can move, the nearest one is pushed toward the junction and pinned on
//    arrival.
// 3. Simulated zone. Vertices within activeRings edge rings of a candidate or junction vertex
//    are simulated (the domain border never is); the triangles around them form a sub-mesh
//    with local flat arrays (triangles, neighbours across each edge, spring edge ids, a
//    vertex -> triangles table); every other vertex keeps its grid position.
// 4. Simulation (6.1, 6.2). A SpringSystem on the sub-mesh: edge springs and (by default)
//    projection springs with rest lengths from the grid positions; simulated vertices are
//    free particles, pushed and arrived ones are driven, the halo is fixed. Every step:
//    forces; free particles by semi-implicit Euler; pushed vertices one push step; once
//    every push is over (arrived or stuck for 30 steps), arrived vertices slide on their rail
//    (6.4): their velocity along the chain integrates the tangential force, the move follows
//    the polyline, and passing over a feature point stops them there for good. Every move of
//    any kind passes the restrain test (6.3): each triangle around the vertex must stay
//    counter-clockwise with at least 2% of its rest area (or not shrink if already below), so
//    no triangle ever inverts. Every flipInterval steps, triangles with less than 10% of their
//    rest area or an angle below 10 degrees get their longest edge flipped when the flip is
//    valid, improves the pair's smallest angle and keeps the region of the surrounding faces
//    (6.5). The loop stops after maxIterations or when every push is over and nothing moved
//    by 1e-3 h in 10 steps.
// 5. Faces (Section 5). Each triangle of the sub-mesh gets the region of its barycentre
//    (DistanceField::query); the others keep the classification's region (they did not move).
// 6. Optimization (beyond the paper, optional). (a) Snap: every vertex on the region boundary
//    (an edge between faces of different regions) that is not on a curve moves to its
//    closest boundary point if the restrain test allows, in halving steps otherwise. (b)
//    Flips: an edge between two faces of one region is flipped when both new triangles are
//    valid, keep that region (barycentres) and the pair's smallest angle grows. (c)
//    Smoothing: a free vertex moves to the centroid of its neighbours (or half-way) and a
//    curve vertex slides along its chain (not across stop points) when the smallest angle of
//    its triangles grows and no face changes region. Passes repeat optimizationPasses times.
//    Region boundaries are therefore left exactly as the compression made them, apart from
//    the snapped vertices, and no move or flip ever lowers the local smallest angle.
#include "Compression.h"

#include "Errors.h"
#include "Quality.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

namespace strata
{

namespace
{

constexpr double kCollapse = 0.02;        // restrain: keep at least 2% of the rest area
constexpr double kSmallArea = 0.1;        // degeneracy check: below 10% of the rest area
constexpr double kSmallAngle = 10.0;      // degeneracy check: an angle below 10 degrees
constexpr int kStuckSteps = 30;           // a push without progress for this long is over
constexpr int kMaxRetargets = 3;          // new targets for a stuck push
constexpr int kMaxWaves = 4;              // push phases after the first one
constexpr double kSettled = 1e-3;         // relative move below which a step is quiet
constexpr int kSettledSteps = 10;         // quiet steps that end the simulation
constexpr double kImprove = 1e-6;         // degrees: smallest meaningful angle improvement

void checkRange(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    throw ParameterError(std::string("Compression: ") + name + " " + std::to_string(value) +
      " is not in " + range);
  }
}

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

} // namespace

void validate(const CompressionParams& p)
{
  checkRange(p.springConfiguration == SpringConfiguration::EdgeOnly ||
      p.springConfiguration == SpringConfiguration::EdgeAndProjection,
    "SpringConfiguration", static_cast<double>(static_cast<int>(p.springConfiguration)),
    "{0 (edge only), 1 (edge and projection)}");
  checkRange(p.springStiffness > 0.0 && p.springStiffness <= 1e3, "SpringStiffness",
    p.springStiffness, "(0, 1e3]");
  checkRange(p.damping >= 0.0 && p.damping <= 1e3, "Damping", p.damping, "[0, 1e3]");
  checkRange(p.timeStep > 0.0 && p.timeStep <= 1.0, "TimeStep", p.timeStep, "(0, 1]");
  checkRange(p.maxIterations >= 0 && p.maxIterations <= 1000000, "MaxIterations",
    p.maxIterations, "[0, 1e6]");
  checkRange(p.pushCriterion == PushCriterion::AllCandidates ||
      p.pushCriterion == PushCriterion::OneSide || p.pushCriterion == PushCriterion::Closest,
    "PushCriterion", static_cast<double>(static_cast<int>(p.pushCriterion)),
    "{0 (all candidates), 1 (one side), 2 (closest)}");
  checkRange(p.pushVelocity > 0.0 && p.pushVelocity <= 10.0, "PushVelocity", p.pushVelocity,
    "(0, 10]");
  checkRange(p.featureAngle >= 0.0 && p.featureAngle <= 180.0, "FeatureAngle", p.featureAngle,
    "[0, 180]");
  checkRange(p.flipInterval >= 1 && p.flipInterval <= 1000000, "FlipInterval", p.flipInterval,
    "[1, 1e6]");
  checkRange(
    p.activeRings >= 1 && p.activeRings <= 16, "ActiveRings", p.activeRings, "[1, 16]");
  checkRange(p.optimizationPasses >= 0 && p.optimizationPasses <= 100, "OptimizationPasses",
    p.optimizationPasses, "[0, 100]");
}

//------------------------------------------------------------------------------
// Rails.
BoundaryRails::BoundaryRails(const Model& model, double featureAngle)
{
  // Distinct segments by node pair (lo < hi) with the regions left and right of lo -> hi.
  struct Seg
  {
    int lo, hi, left, right;
  };
  std::vector<Seg> raw;
  for (const Region& region : model.regions)
  {
    for (const Ring& ring : region.rings)
    {
      const std::size_t n = ring.nodes.size();
      for (std::size_t i = 0; i < n; ++i)
      {
        const int u = ring.nodes[i], v = ring.nodes[(i + 1) % n];
        if (u == v)
        {
          continue;
        }
        // The region lies left of u -> v.
        if (u < v)
        {
          raw.push_back({ u, v, region.id, -2 });
        }
        else
        {
          raw.push_back({ v, u, -2, region.id });
        }
      }
    }
  }
  std::sort(raw.begin(), raw.end(),
    [](const Seg& a, const Seg& b) { return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi; });
  std::vector<Seg> segs;
  for (const Seg& s : raw)
  {
    if (!segs.empty() && segs.back().lo == s.lo && segs.back().hi == s.hi)
    {
      if (s.left != -2)
      {
        segs.back().left = s.left;
      }
      if (s.right != -2)
      {
        segs.back().right = s.right;
      }
    }
    else
    {
      segs.push_back(s);
    }
  }
  for (Seg& s : segs)
  {
    s.left = s.left == -2 ? -1 : s.left;
    s.right = s.right == -2 ? -1 : s.right;
  }

  // Node -> incident segments.
  const std::size_t nn = model.nodes.size();
  std::vector<int> start(nn + 1, 0);
  for (const Seg& s : segs)
  {
    ++start[s.lo + 1];
    ++start[s.hi + 1];
  }
  for (std::size_t i = 0; i < nn; ++i)
  {
    start[i + 1] += start[i];
  }
  std::vector<int> incident(start.back());
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t s = 0; s < segs.size(); ++s)
    {
      incident[fill[segs[s].lo]++] = static_cast<int>(s);
      incident[fill[segs[s].hi]++] = static_cast<int>(s);
    }
  }
  auto degree = [&](int node) { return start[node + 1] - start[node]; };
  std::vector<std::uint8_t> used(segs.size(), 0);

  // Walks from `node` along segment s until a node of degree != 2 (or back to the start).
  auto walk = [&](int node, int s) {
    Chain c;
    const int first = node;
    c.nodes.push_back(node);
    const Seg& s0 = segs[s];
    c.left = node == s0.lo ? s0.left : s0.right;
    c.right = node == s0.lo ? s0.right : s0.left;
    while (true)
    {
      used[s] = 1;
      const int next = segs[s].lo == node ? segs[s].hi : segs[s].lo;
      if (next == first)
      {
        c.closed = true;
        break;
      }
      c.nodes.push_back(next);
      node = next;
      if (degree(node) != 2)
      {
        break;
      }
      int following = -1;
      for (int k = start[node]; k < start[node + 1]; ++k)
      {
        if (!used[incident[k]])
        {
          following = incident[k];
        }
      }
      if (following < 0)
      {
        break;
      }
      s = following;
    }
    return c;
  };
  for (std::size_t node = 0; node < nn; ++node)
  {
    if (degree(static_cast<int>(node)) == 2)
    {
      continue;
    }
    for (int k = start[node]; k < start[node + 1]; ++k)
    {
      if (!used[incident[k]])
      {
        this->Chains.push_back(walk(static_cast<int>(node), incident[k]));
      }
    }
  }
  for (std::size_t s = 0; s < segs.size(); ++s)
  {
    if (!used[s])
    {
      this->Chains.push_back(walk(segs[s].lo, static_cast<int>(s)));
    }
  }

  // Geometry, features, tree.
  const double cosLimit = std::cos(featureAngle * 3.14159265358979323846 / 180.0);
  std::vector<Vec2> a, b;
  for (std::size_t ci = 0; ci < this->Chains.size(); ++ci)
  {
    Chain& c = this->Chains[ci];
    const std::size_t n = c.nodes.size();
    c.points.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      c.points[i] = model.nodes[c.nodes[i]];
    }
    c.feature.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!c.closed && (i == 0 || i + 1 == n))
      {
        c.feature[i] = 1; // chain ends: junctions or dangling ends
        continue;
      }
      const Vec2 p = c.points[i];
      const Vec2 u = c.points[(i + n - 1) % n] - p;
      const Vec2 v = c.points[(i + 1) % n] - p;
      // angle(u, v) < featureAngle  <=>  cos(angle) > cos(featureAngle)
      const double cosAngle = dot(u, v) / (norm(u) * norm(v));
      if (featureAngle > 0.0 && cosAngle > cosLimit)
      {
        c.feature[i] = 1;
      }
    }
    for (std::size_t k = 0; k < c.numberOfSegments(); ++k)
    {
      a.push_back(c.points[k]);
      b.push_back(c.points[(k + 1) % n]);
      this->SegmentOf.push_back({ static_cast<int>(ci), static_cast<int>(k) });
    }
  }
  this->Tree = StripTree(std::move(a), std::move(b));
}

BoundaryRails::Location BoundaryRails::closest(
  Vec2 p, StripTreeScratch& scratch, double* distance) const
{
  const NearestSegment s = this->Tree.nearest(p, scratch);
  Location l;
  if (s.segment >= 0)
  {
    l.chain = this->SegmentOf[s.segment][0];
    l.segment = this->SegmentOf[s.segment][1];
    l.t = s.t;
  }
  if (distance)
  {
    *distance = std::sqrt(s.distance2);
  }
  return l;
}

Vec2 BoundaryRails::position(const Location& l) const
{
  const Chain& c = this->Chains[l.chain];
  const Vec2 a = c.points[l.segment];
  const Vec2 b = c.points[(l.segment + 1) % c.points.size()];
  if (l.t == 0.0)
  {
    return a;
  }
  if (l.t == 1.0)
  {
    return b;
  }
  return a + l.t * (b - a);
}

Vec2 BoundaryRails::tangent(const Location& l) const
{
  const Chain& c = this->Chains[l.chain];
  const Vec2 d = c.points[(l.segment + 1) % c.points.size()] - c.points[l.segment];
  const double len = norm(d);
  return len > 0.0 ? (1.0 / len) * d : Vec2{ 1.0, 0.0 };
}

int BoundaryRails::pointAt(const Location& l) const
{
  if (l.t == 0.0)
  {
    return l.segment;
  }
  if (l.t == 1.0)
  {
    return static_cast<int>((l.segment + 1) % this->Chains[l.chain].points.size());
  }
  return -1;
}

bool BoundaryRails::isStop(int chain, int point) const
{
  return this->Chains[chain].feature[point] != 0;
}

std::vector<BoundaryRails::Location> BoundaryRails::locationsOfNode(int node) const
{
  std::vector<Location> out;
  for (std::size_t ci = 0; ci < this->Chains.size(); ++ci)
  {
    const Chain& c = this->Chains[ci];
    for (std::size_t i = 0; i < c.nodes.size(); ++i)
    {
      if (c.nodes[i] == node)
      {
        Location l;
        l.chain = static_cast<int>(ci);
        if (i < c.numberOfSegments())
        {
          l.segment = static_cast<int>(i);
          l.t = 0.0;
        }
        else
        {
          l.segment = static_cast<int>(i) - 1;
          l.t = 1.0;
        }
        out.push_back(l);
      }
    }
  }
  return out;
}

BoundaryRails::Slide BoundaryRails::slide(const Location& from, double s) const
{
  Slide out;
  out.location = from;
  const Chain& c = this->Chains[from.chain];
  const int np = static_cast<int>(c.points.size());
  const int ns = static_cast<int>(c.numberOfSegments());
  Location& l = out.location;
  // Leaving the chain point the location is at: step onto the segment in the direction of
  // motion (that point is not passed over, so it does not stop the slide).
  if (s > 0.0 && l.t == 1.0 && (c.closed || l.segment + 1 < ns))
  {
    l.segment = (l.segment + 1) % ns;
    l.t = 0.0;
  }
  else if (s < 0.0 && l.t == 0.0 && (c.closed || l.segment > 0))
  {
    l.segment = (l.segment + ns - 1) % ns;
    l.t = 1.0;
  }
  // Each turn consumes a segment; a closed chain without stops could be walked around for
  // ever with a huge s, so bound the turns.
  for (int turn = 0; turn <= 2 * ns + 2 && s != 0.0; ++turn)
  {
    const Vec2 a = c.points[l.segment];
    const Vec2 b = c.points[(l.segment + 1) % np];
    const double len = norm(b - a);
    if (s > 0.0)
    {
      const double avail = (1.0 - l.t) * len;
      if (s < avail)
      {
        l.t += s / len;
        return out;
      }
      s -= avail;
      l.t = 1.0;
      const int end = (l.segment + 1) % np;
      if (this->isStop(from.chain, end) || (!c.closed && l.segment + 1 >= ns))
      {
        out.stopped = true;
        return out;
      }
      l.segment = (l.segment + 1) % ns;
      l.t = 0.0;
    }
    else
    {
      const double avail = l.t * len;
      if (-s < avail)
      {
        l.t += s / len;
        return out;
      }
      s += avail;
      l.t = 0.0;
      if (this->isStop(from.chain, l.segment) || (!c.closed && l.segment == 0))
      {
        out.stopped = true;
        return out;
      }
      l.segment = (l.segment + ns - 1) % ns;
      l.t = 1.0;
    }
  }
  return out;
}

//------------------------------------------------------------------------------
bool restrainAccepts(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
  const int* star, int starSize, int i, Vec2 to, const double* minTwiceArea)
{
  for (int s = 0; s < starSize; ++s)
  {
    const int t = star[s];
    const std::array<int, 3>& tri = triangles[t];
    const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
    const Vec2 a = points[tri[(k + 1) % 3]];
    const Vec2 b = points[tri[(k + 2) % 3]];
    // Two cross products: the side of the opposite edge ab the vertex is on now and after.
    const double after = cross(b - a, to - a);
    if (!(after > 0.0))
    {
      return false;
    }
    if (minTwiceArea && after < minTwiceArea[t])
    {
      const double before = cross(b - a, points[i] - a);
      if (after < before)
      {
        return false;
      }
    }
  }
  return true;
}

namespace
{

// Vertex states during the simulation.
enum State : std::uint8_t
{
  Halo,    // fixed: in the sub-mesh only as a neighbour
  Free,    // simulated particle
  Pushing, // driven toward its target
  Rail,    // on a curve
  Pinned   // on a junction or feature point
};

// The simulated sub-mesh and everything done to it.
class Compressor
{
public:
  Compressor(const TriangleMesh& grid, const Classification& cls, const Model& model,
    const DistanceField& field, const CompressionParams& params, const ProgressReporter& progress,
    CompressionResult& result)
    : Grid(grid)
    , Cls(cls)
    , TheModel(model)
    , Field(field)
    , Params(params)
    , Progress(progress)
    , Result(result)
    , Rails(model, params.featureAngle)
  {
  }

  void run();

private:
  // --- set-up
  void buildGlobalStars();
  bool isBorderVertex(int g) const;
  double boundaryDistance(int g);
  void choosePushes();
  void placeJunctions();
  void buildSubMesh();
  void rebuildStars();
  // --- simulation
  void simulate();
  bool pushStep(int i, double dt);
  void claimStopPoints();
  std::size_t pushNewCrossings();
  void startPush(int i, const BoundaryRails::Location& target);
  bool JunctionTargetLocal(int i) const { return this->JunctionTarget[this->Global[i]] >= 0; }
  void retarget(int i);
  bool nearClaimedStop(const BoundaryRails::Location& l, double reach) const;
  BoundaryRails::Location sideTarget(int i, const BoundaryRails::Location& from, double s) const;
  void railStep(int i, double dt);
  std::size_t flipDegenerate();
  std::size_t unblockPushes();
  bool flipValid(int t, int k) const;
  // --- faces and optimization
  void classifyFaces();
  int tagAt(Vec2 p) { return this->Field.query(p, this->FieldScratch).region; }
  int outsideTag(int code) const
  {
    return code == -1 ? -1 : this->Result.triangleRegion[-2 - code];
  }
  int neighbourTag(int t, int k) const
  {
    const int u = this->Nbr[t][k];
    return u >= 0 ? this->Tag[u] : this->outsideTag(u);
  }
  std::size_t snapBoundaryVertices();
  bool moveTowards(int i, const BoundaryRails::Location& target);
  std::size_t optimizeFlips();
  std::size_t smooth();
  bool starTagsKept(int i, Vec2 p);
  double starMinAngle(int i, Vec2 p) const;
  // --- shared
  bool tryFlip(int t, int k, bool degenerateMode);
  void flip(int t, int k);
  bool accepts(int i, Vec2 to) const
  {
    return restrainAccepts(this->Sys->positions(), this->Tri, this->StarItems.data() + this->StarStart[i],
      this->StarStart[i + 1] - this->StarStart[i], i, to, this->MinTwice.data());
  }
  double twiceArea(int t) const
  {
    const std::vector<Vec2>& x = this->Sys->positions();
    return orient2d(x[this->Tri[t][0]], x[this->Tri[t][1]], x[this->Tri[t][2]]);
  }
  double triMinAngle(int t) const
  {
    const std::vector<Vec2>& x = this->Sys->positions();
    return minimumAngle(x[this->Tri[t][0]], x[this->Tri[t][1]], x[this->Tri[t][2]]);
  }
  void writeBack();

  struct Guard : MoveGuard
  {
    const Compressor* self = nullptr;
    bool accept(int i, Vec2, Vec2 to) override { return self->accepts(i, to); }
  };

  const TriangleMesh& Grid;
  const Classification& Cls;
  const Model& TheModel;
  const DistanceField& Field;
  const CompressionParams& Params;
  const ProgressReporter& Progress;
  CompressionResult& Result;
  BoundaryRails Rails;
  StripTreeScratch RailScratch;
  DistanceField::Scratch FieldScratch;

  // Global mesh.
  std::vector<Vec2> Points; // current positions (global ids)
  std::vector<int> GStarStart, GStarItems;
  std::vector<std::uint8_t> Candidate, Push;
  std::vector<double> Distance; // boundary distance of candidates (NaN unknown)
  std::vector<int> JunctionOf;  // global vertex -> junction node it was placed on, or -1
  std::vector<int> JunctionTarget; // global vertex -> junction node it is pushed to, or -1
  std::vector<std::uint8_t> SnappedToJunction;

  // Sub-mesh (local ids).
  std::vector<int> Global;       // local vertex -> global vertex
  std::vector<int> LocalOf;      // global vertex -> local, -1
  int NumActive = 0;             // local ids < NumActive are simulated
  std::vector<std::array<int, 3>> Tri, Nbr, TriEdge;
  std::vector<int> TriGlobal, Level, Tag;
  std::vector<double> RestTwice, MinTwice;
  std::vector<int> StarStart, StarItems;
  std::unique_ptr<SpringSystem> Sys;
  Guard TheGuard;

  // Per local vertex.
  std::vector<std::uint8_t> St;
  std::vector<Vec2> Target;
  std::vector<BoundaryRails::Location> Loc; // push target, then rail position
  std::vector<std::uint8_t> PinOnArrival;
  std::vector<double> Speed; // along the rail
  std::vector<int> Stuck;
  std::vector<int> Retargets;
  std::vector<std::uint8_t> Claimed; // model node taken by a vertex (junction, feature)
  std::vector<BoundaryRails::Location> FirstTarget; // closest point when the push started
  std::vector<std::pair<int, int>> Blocked; // (triangle, edge) blocking a push this step
};

void Compressor::buildGlobalStars()
{
  const std::size_t np = this->Grid.points.size();
  this->GStarStart.assign(np + 1, 0);
  for (const std::array<int, 3>& t : this->Grid.triangles)
  {
    for (int v : t)
    {
      ++this->GStarStart[v + 1];
    }
  }
  for (std::size_t i = 0; i < np; ++i)
  {
    this->GStarStart[i + 1] += this->GStarStart[i];
  }
  this->GStarItems.resize(this->GStarStart.back());
  std::vector<int> fill(this->GStarStart.begin(), this->GStarStart.end() - 1);
  for (std::size_t t = 0; t < this->Grid.triangles.size(); ++t)
  {
    for (int v : this->Grid.triangles[t])
    {
      this->GStarItems[fill[v]++] = static_cast<int>(t);
    }
  }
}

// A vertex whose triangles do not close around it lies on the mesh border.
bool Compressor::isBorderVertex(int g) const
{
  for (int s = this->GStarStart[g]; s < this->GStarStart[g + 1]; ++s)
  {
    const std::array<int, 3>& t = this->Grid.triangles[this->GStarItems[s]];
    const int k = t[0] == g ? 0 : (t[1] == g ? 1 : 2);
    const int next = t[(k + 1) % 3];
    bool found = false;
    for (int r = this->GStarStart[g]; r < this->GStarStart[g + 1] && !found; ++r)
    {
      const std::array<int, 3>& u = this->Grid.triangles[this->GStarItems[r]];
      const int j = u[0] == g ? 0 : (u[1] == g ? 1 : 2);
      found = u[(j + 2) % 3] == next;
    }
    if (!found)
    {
      return true;
    }
  }
  return false;
}

double Compressor::boundaryDistance(int g)
{
  double& d = this->Distance[g];
  if (std::isnan(d))
  {
    if (this->Grid.pointBoundaryDistance.size() == this->Grid.points.size() &&
      !std::isnan(this->Grid.pointBoundaryDistance[g]))
    {
      d = this->Grid.pointBoundaryDistance[g];
    }
    else
    {
      this->Rails.closest(this->Grid.points[g], this->RailScratch, &d);
    }
  }
  return d;
}

void Compressor::choosePushes()
{
  const std::size_t np = this->Grid.points.size();
  this->Candidate.assign(np, 0);
  this->Push.assign(np, 0);
  this->Distance.assign(np, std::numeric_limits<double>::quiet_NaN());
  const PushCriterion criterion = this->Params.pushCriterion;
  for (std::size_t e = 0; e < this->Cls.edges.size(); ++e)
  {
    if (this->Cls.edgeClass[e] != EdgeIntersection)
    {
      continue;
    }
    const int a = this->Cls.edges[e][0], b = this->Cls.edges[e][1];
    this->Candidate[a] = this->Candidate[b] = 1;
    const bool onA = this->Cls.vertexClass[a] == VertexBoundary;
    const bool onB = this->Cls.vertexClass[b] == VertexBoundary;
    if (onA || onB)
    {
      this->Push[a] |= onA;
      this->Push[b] |= onB;
      continue;
    }
    const int ra = this->Cls.vertexRegion[a], rb = this->Cls.vertexRegion[b];
    auto closer = [&]() { return this->boundaryDistance(a) <= this->boundaryDistance(b) ? a : b; };
    switch (criterion)
    {
      case PushCriterion::AllCandidates:
        this->Push[a] = this->Push[b] = 1;
        break;
      case PushCriterion::OneSide:
        if (ra != rb)
        {
          const int pushed = ra == -1 ? a : (rb == -1 ? b : (ra > rb ? a : b));
          this->Push[pushed] = 1;
        }
        else
        {
          this->Push[closer()] = 1;
        }
        break;
      case PushCriterion::Closest:
        this->Push[closer()] = 1;
        break;
    }
  }
}

void Compressor::placeJunctions()
{
  const std::size_t np = this->Grid.points.size();
  this->JunctionOf.assign(np, -1);
  this->JunctionTarget.assign(np, -1);
  if (this->TheModel.junctions.empty())
  {
    return;
  }
  // Bucket grid over the candidate vertices.
  std::vector<int> cand;
  Box2 box;
  for (std::size_t i = 0; i < np; ++i)
  {
    if (this->Candidate[i])
    {
      cand.push_back(static_cast<int>(i));
      box.add(this->Points[i]);
    }
  }
  if (cand.empty())
  {
    this->Result.warnings.push_back("no intersection edges: junctions were not placed");
    return;
  }
  const int cells = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(cand.size()))), 1, 2048);
  const double side = std::max(box.width(), box.height()) * (1.0 + 1e-9) + 1e-300;
  const double cellSize = side / cells;
  auto cellOf = [&](double v, double lo) {
    return std::clamp(static_cast<int>((v - lo) / cellSize), 0, cells - 1);
  };
  std::vector<int> start(static_cast<std::size_t>(cells) * cells + 1, 0);
  for (int v : cand)
  {
    ++start[cellOf(this->Points[v].y, box.min.y) * cells + cellOf(this->Points[v].x, box.min.x) + 1];
  }
  for (std::size_t i = 1; i < start.size(); ++i)
  {
    start[i] += start[i - 1];
  }
  std::vector<int> items(cand.size());
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int v : cand)
    {
      items[fill[cellOf(this->Points[v].y, box.min.y) * cells +
        cellOf(this->Points[v].x, box.min.x)]++] = v;
    }
  }
  std::vector<double> minTwice(this->Grid.triangles.size());
  for (std::size_t t = 0; t < minTwice.size(); ++t)
  {
    const std::array<int, 3>& tri = this->Grid.triangles[t];
    minTwice[t] = kCollapse *
      orient2d(this->Grid.points[tri[0]], this->Grid.points[tri[1]], this->Grid.points[tri[2]]);
  }

  std::size_t unplaced = 0;
  for (int node : this->TheModel.junctions)
  {
    const Vec2 p = this->TheModel.nodes[node];
    // Nearest candidates: grow rings of cells until the ring is beyond 3x the nearest found.
    std::vector<std::pair<double, int>> near;
    const int cx = cellOf(p.x, box.min.x), cy = cellOf(p.y, box.min.y);
    double best = HUGE_VAL;
    for (int r = 0; r < cells; ++r)
    {
      for (int y = cy - r; y <= cy + r; ++y)
      {
        for (int x = cx - r; x <= cx + r; ++x)
        {
          if (x < 0 || y < 0 || x >= cells || y >= cells ||
            (std::abs(x - cx) != r && std::abs(y - cy) != r))
          {
            continue;
          }
          const int c = y * cells + x;
          for (int k = start[c]; k < start[c + 1]; ++k)
          {
            const int v = items[k];
            if (this->JunctionOf[v] >= 0 || this->JunctionTarget[v] >= 0)
            {
              continue;
            }
            const double d = norm(this->Points[v] - p);
            near.push_back({ d, v });
            best = std::min(best, d);
          }
        }
      }
      // Cells of ring r + 1 are at least r * cellSize away.
      if (best < HUGE_VAL && r * cellSize > 3.0 * best)
      {
        break;
      }
    }
    if (near.empty())
    {
      ++unplaced;
      continue;
    }
    std::sort(near.begin(), near.end());
    bool placed = false;
    for (std::size_t k = 0; k < near.size() && k < 12 && near[k].first <= 3.0 * best; ++k)
    {
      const int v = near[k].second;
      if (restrainAccepts(this->Points, this->Grid.triangles,
            this->GStarItems.data() + this->GStarStart[v],
            this->GStarStart[v + 1] - this->GStarStart[v], v, p, minTwice.data()))
      {
        this->Points[v] = p;
        this->JunctionOf[v] = node;
        placed = true;
        break;
      }
    }
    if (!placed)
    {
      this->JunctionTarget[near[0].second] = node;
    }
  }
  if (unplaced > 0)
  {
    this->Result.warnings.push_back(
      std::to_string(unplaced) + " junction(s) found no grid vertex to take them");
  }
}

void Compressor::buildSubMesh()
{
  const std::size_t np = this->Grid.points.size();
  const std::size_t nt = this->Grid.triangles.size();
  // Breadth-first rings from the candidates and junction vertices.
  std::vector<int> ring(np, -1);
  std::vector<int> frontier;
  std::vector<std::uint8_t> border(np, 2); // 2 = unknown
  auto isBorder = [&](int g) {
    if (border[g] == 2)
    {
      border[g] = this->isBorderVertex(g) ? 1 : 0;
    }
    return border[g] == 1;
  };
  std::size_t stuckOnBorder = 0;
  for (std::size_t i = 0; i < np; ++i)
  {
    if (this->Candidate[i] || this->JunctionOf[i] >= 0 || this->JunctionTarget[i] >= 0)
    {
      if (isBorder(static_cast<int>(i)))
      {
        stuckOnBorder += this->Push[i] || this->JunctionOf[i] >= 0;
        continue;
      }
      ring[i] = 0;
      frontier.push_back(static_cast<int>(i));
    }
  }
  if (stuckOnBorder > 0)
  {
    this->Result.warnings.push_back(std::to_string(stuckOnBorder) +
      " boundary vertices lie on the border of the grid and cannot move");
  }
  std::vector<int> active = frontier;
  for (int r = 1; r <= this->Params.activeRings; ++r)
  {
    std::vector<int> next;
    for (int g : frontier)
    {
      for (int s = this->GStarStart[g]; s < this->GStarStart[g + 1]; ++s)
      {
        for (int v : this->Grid.triangles[this->GStarItems[s]])
        {
          if (ring[v] < 0 && !isBorder(v))
          {
            ring[v] = r;
            next.push_back(v);
          }
        }
      }
    }
    active.insert(active.end(), next.begin(), next.end());
    frontier.swap(next);
  }
  // Local vertices: active first, then the halo.
  this->LocalOf.assign(np, -1);
  this->Global.clear();
  for (int g : active)
  {
    this->LocalOf[g] = static_cast<int>(this->Global.size());
    this->Global.push_back(g);
  }
  this->NumActive = static_cast<int>(this->Global.size());
  std::vector<int> localTri(nt, -1);
  this->TriGlobal.clear();
  for (int g : active)
  {
    for (int s = this->GStarStart[g]; s < this->GStarStart[g + 1]; ++s)
    {
      const int t = this->GStarItems[s];
      if (localTri[t] >= 0)
      {
        continue;
      }
      localTri[t] = static_cast<int>(this->TriGlobal.size());
      this->TriGlobal.push_back(t);
      for (int v : this->Grid.triangles[t])
      {
        if (this->LocalOf[v] < 0)
        {
          this->LocalOf[v] = static_cast<int>(this->Global.size());
          this->Global.push_back(v);
        }
      }
    }
  }
  const std::size_t nl = this->TriGlobal.size();
  this->Tri.resize(nl);
  this->Level.resize(nl);
  for (std::size_t t = 0; t < nl; ++t)
  {
    const std::array<int, 3>& g = this->Grid.triangles[this->TriGlobal[t]];
    this->Tri[t] = { this->LocalOf[g[0]], this->LocalOf[g[1]], this->LocalOf[g[2]] };
    this->Level[t] = this->Grid.triangleLevel.size() == nt ? this->Grid.triangleLevel[this->TriGlobal[t]] : 0;
  }
  // Neighbours across each edge: local id, -1 for the domain border, -2 - global id outside.
  this->Nbr.assign(nl, { -1, -1, -1 });
  for (std::size_t t = 0; t < nl; ++t)
  {
    const int gt = this->TriGlobal[t];
    const std::array<int, 3>& g = this->Grid.triangles[gt];
    for (int k = 0; k < 3; ++k)
    {
      const int a = g[k], b = g[(k + 1) % 3];
      int across = -1;
      for (int s = this->GStarStart[b]; s < this->GStarStart[b + 1] && across < 0; ++s)
      {
        const int u = this->GStarItems[s];
        if (u == gt)
        {
          continue;
        }
        const std::array<int, 3>& h = this->Grid.triangles[u];
        const int j = h[0] == b ? 0 : (h[1] == b ? 1 : 2);
        if (h[(j + 1) % 3] == a)
        {
          across = u;
        }
      }
      this->Nbr[t][k] = across < 0 ? -1 : (localTri[across] >= 0 ? localTri[across] : -2 - across);
    }
  }
  // Spring edges.
  std::vector<std::array<int, 2>> edges;
  this->TriEdge.assign(nl, { -1, -1, -1 });
  for (std::size_t t = 0; t < nl; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int u = this->Nbr[t][k];
      if (u >= 0 && u < static_cast<int>(t))
      {
        const int a = this->Tri[t][k];
        for (int j = 0; j < 3; ++j)
        {
          if (this->Tri[u][j] == this->Tri[t][(k + 1) % 3] && this->Tri[u][(j + 1) % 3] == a)
          {
            this->TriEdge[t][k] = this->TriEdge[u][j];
          }
        }
      }
      else
      {
        this->TriEdge[t][k] = static_cast<int>(edges.size());
        edges.push_back({ std::min(this->Tri[t][k], this->Tri[t][(k + 1) % 3]),
          std::max(this->Tri[t][k], this->Tri[t][(k + 1) % 3]) });
      }
    }
  }
  // Positions, rest positions, areas.
  const std::size_t nv = this->Global.size();
  std::vector<Vec2> x(nv), rest(nv);
  for (std::size_t i = 0; i < nv; ++i)
  {
    x[i] = this->Points[this->Global[i]];
    rest[i] = this->Grid.points[this->Global[i]];
  }
  this->RestTwice.resize(nl);
  this->MinTwice.resize(nl);
  for (std::size_t t = 0; t < nl; ++t)
  {
    this->RestTwice[t] = orient2d(rest[this->Tri[t][0]], rest[this->Tri[t][1]], rest[this->Tri[t][2]]);
    this->MinTwice[t] = kCollapse * this->RestTwice[t];
  }
  SpringParams sp;
  sp.configuration = this->Params.springConfiguration;
  sp.stiffness = this->Params.springStiffness;
  sp.damping = this->Params.damping;
  SpringMesh sm;
  sm.triangles = this->Tri;
  sm.edges = std::move(edges);
  this->Sys = std::make_unique<SpringSystem>(std::move(sm), std::move(x), rest, sp);
  this->TheGuard.self = this;
  this->rebuildStars();

  // States.
  this->St.assign(nv, Halo);
  this->Target.assign(nv, Vec2{});
  this->Loc.assign(nv, BoundaryRails::Location{});
  this->PinOnArrival.assign(nv, 0);
  this->Speed.assign(nv, 0.0);
  this->Stuck.assign(nv, 0);
  this->Retargets.assign(nv, 0);
  this->FirstTarget.assign(nv, BoundaryRails::Location{});
  for (std::size_t i = 0; i < nv; ++i)
  {
    const int g = this->Global[i];
    if (static_cast<int>(i) >= this->NumActive)
    {
      this->Sys->setKind(static_cast<int>(i), ParticleKind::Fixed);
      continue;
    }
    if (this->JunctionOf[g] >= 0)
    {
      this->St[i] = Pinned;
      this->Loc[i] = this->Rails.locationsOfNode(this->JunctionOf[g]).front();
      this->Sys->setKind(static_cast<int>(i), ParticleKind::Fixed);
      ++this->Result.junctionVertices;
    }
    else if (this->JunctionTarget[g] >= 0)
    {
      this->St[i] = Pushing;
      this->Loc[i] = this->Rails.locationsOfNode(this->JunctionTarget[g]).front();
      this->Target[i] = this->TheModel.nodes[this->JunctionTarget[g]];
      this->PinOnArrival[i] = 1;
      this->Sys->setKind(static_cast<int>(i), ParticleKind::Driven);
      ++this->Result.pushedVertices;
    }
    else if (this->Push[g])
    {
      this->St[i] = Pushing;
      this->Loc[i] = this->Rails.closest(this->Sys->positions()[i], this->RailScratch);
      this->Target[i] = this->Rails.position(this->Loc[i]);
      const int point = this->Rails.pointAt(this->Loc[i]);
      this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(this->Loc[i].chain, point);
      this->Sys->setKind(static_cast<int>(i), ParticleKind::Driven);
      ++this->Result.pushedVertices;
    }
    else
    {
      this->St[i] = Free;
    }
  }
  this->Result.simulatedVertices = static_cast<std::size_t>(this->NumActive);
  this->FirstTarget = this->Loc;
  this->claimStopPoints();
}

// A stop point (junction or feature) takes one vertex: a pinned junction vertex, else the
// pushed vertex closest to it; the others aim beside it.
void Compressor::claimStopPoints()
{
  this->Claimed.assign(this->TheModel.nodes.size(), 0);
  std::vector<std::uint8_t>& claimed = this->Claimed;
  std::vector<std::pair<double, int>> order;
  const std::vector<Vec2>& x = this->Sys->positions();
  for (int i = 0; i < this->NumActive; ++i)
  {
    if (this->St[i] == Pinned || (this->St[i] == Pushing && this->JunctionTargetLocal(i)))
    {
      const BoundaryRails::Chain& c = this->Rails.chain(this->Loc[i].chain);
      claimed[c.nodes[this->Rails.pointAt(this->Loc[i])]] = 1;
    }
    else if (this->St[i] == Pushing)
    {
      order.push_back({ norm(this->Target[i] - x[i]), i });
    }
  }
  std::sort(order.begin(), order.end());
  for (const auto& item : order)
  {
    const int i = item.second;
    const int point = this->Rails.pointAt(this->Loc[i]);
    if (this->nearClaimedStop(this->Loc[i], 0.3 * this->Sys->localLength(i)))
    {
      this->retarget(i);
    }
    else if (point >= 0 && this->PinOnArrival[i])
    {
      claimed[this->Rails.chain(this->Loc[i].chain).nodes[point]] = 1;
    }
  }
}

// Whether a claimed stop point (a junction or feature with its vertex) is within arc length
// `reach` of l along its segment.
bool Compressor::nearClaimedStop(const BoundaryRails::Location& l, double reach) const
{
  const BoundaryRails::Chain& c = this->Rails.chain(l.chain);
  const int np = static_cast<int>(c.points.size());
  const int p0 = l.segment, p1 = (l.segment + 1) % np;
  const double len = norm(c.points[p1] - c.points[p0]);
  return (this->Claimed[c.nodes[p0]] && l.t * len <= reach) ||
    (this->Claimed[c.nodes[p1]] && (1.0 - l.t) * len <= reach);
}

void Compressor::startPush(int i, const BoundaryRails::Location& target)
{
  this->St[i] = Pushing;
  this->Loc[i] = target;
  this->FirstTarget[i] = target;
  this->Retargets[i] = 0;
  this->Target[i] = this->Rails.position(target);
  const int point = this->Rails.pointAt(target);
  this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(target.chain, point);
  this->Stuck[i] = 0;
  this->Speed[i] = 0.0;
  this->Sys->setKind(i, ParticleKind::Driven);
  ++this->Result.pushedVertices;
  if (this->nearClaimedStop(target, 0.3 * this->Sys->localLength(i)))
  {
    this->retarget(i);
  }
  else if (point >= 0 && this->PinOnArrival[i])
  {
    this->Claimed[this->Rails.chain(target.chain).nodes[point]] = 1;
  }
}

// A new push wave: the compression moved free vertices, so edges between two free vertices
// may now cross a boundary. Such an edge can only cross when the boundary distances of its
// ends add up to at most its length; then the regions of its ends decide, and the push
// criterion picks the end(s) to push.
std::size_t Compressor::pushNewCrossings()
{
  const std::vector<Vec2>& x = this->Sys->positions();
  const std::size_t nv = x.size();
  std::vector<double> dist(nv, -1.0);
  std::vector<BoundaryRails::Location> near(nv);
  std::vector<int> region(nv, -2);
  auto distance = [&](int v) {
    if (dist[v] < 0.0)
    {
      near[v] = this->Rails.closest(x[v], this->RailScratch, &dist[v]);
    }
    return dist[v];
  };
  auto regionOf = [&](int v) {
    if (region[v] == -2)
    {
      region[v] = this->tagAt(x[v]);
    }
    return region[v];
  };
  std::vector<std::uint8_t> push(nv, 0);
  for (const std::array<int, 2>& e : this->Sys->mesh().edges)
  {
    const int a = e[0], b = e[1];
    const bool freeA = a < this->NumActive && this->St[a] == Free;
    const bool freeB = b < this->NumActive && this->St[b] == Free;
    if (!(freeA || freeB) || !((freeA || this->St[a] == Halo) && (freeB || this->St[b] == Halo)))
    {
      continue;
    }
    if (distance(a) + distance(b) > norm(x[a] - x[b]))
    {
      continue;
    }
    const int ra = regionOf(a), rb = regionOf(b);
    if (ra == rb)
    {
      continue;
    }
    int pushed = -1;
    switch (this->Params.pushCriterion)
    {
      case PushCriterion::AllCandidates:
        push[a] |= freeA;
        push[b] |= freeB;
        break;
      case PushCriterion::OneSide:
        pushed = ra == -1 ? a : (rb == -1 ? b : (ra > rb ? a : b));
        break;
      case PushCriterion::Closest:
        pushed = dist[a] <= dist[b] ? a : b;
        break;
    }
    if (pushed >= 0)
    {
      const int other = pushed == a ? b : a;
      push[(pushed < this->NumActive && this->St[pushed] == Free) ? pushed : other] = 1;
    }
  }
  // A free vertex near the boundary whose faces' barycentres lie in different regions would
  // end on the approximated boundary: push it as well.
  std::vector<int> faceRegion(this->Tri.size(), -2);
  for (int i = 0; i < this->NumActive; ++i)
  {
    if (this->St[i] != Free || push[i])
    {
      continue;
    }
    const int s0 = this->StarStart[i], s1 = this->StarStart[i + 1];
    double reach = 0.0;
    for (int s = s0; s < s1; ++s)
    {
      for (int v : this->Tri[this->StarItems[s]])
      {
        reach = std::max(reach, norm(x[v] - x[i]));
      }
    }
    if (distance(i) > reach)
    {
      continue;
    }
    int first = -2;
    for (int s = s0; s < s1; ++s)
    {
      const int t = this->StarItems[s];
      if (faceRegion[t] == -2)
      {
        const std::array<int, 3>& tri = this->Tri[t];
        faceRegion[t] = this->tagAt((1.0 / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]));
      }
      if (first == -2)
      {
        first = faceRegion[t];
      }
      else if (faceRegion[t] != first)
      {
        push[i] = 1;
        break;
      }
    }
  }
  std::size_t count = 0;
  for (int i = 0; i < this->NumActive; ++i)
  {
    if (push[i] && this->St[i] == Free)
    {
      distance(i);
      this->startPush(i, near[i]);
      ++count;
    }
  }
  return count;
}

// The rail location at arc length s from `from` (not beyond a stop point).
BoundaryRails::Location Compressor::sideTarget(
  int, const BoundaryRails::Location& from, double s) const
{
  return this->Rails.slide(from, s).location;
}

// Aims a pushed vertex beside its target: half a local edge length along the chain, on the
// side nearer to the vertex.
void Compressor::retarget(int i)
{
  const std::vector<Vec2>& x = this->Sys->positions();
  // Half an edge length beside the first closest point, then one edge length.
  const double h = 0.5 * this->Sys->localLength(i) * (1 + this->Retargets[i] / 2);
  const BoundaryRails::Location a = this->sideTarget(i, this->FirstTarget[i], h);
  const BoundaryRails::Location b = this->sideTarget(i, this->FirstTarget[i], -h);
  const Vec2 pa = this->Rails.position(a), pb = this->Rails.position(b);
  const double tiny = 0.05 * h;
  const bool aMoved = norm(pa - this->Target[i]) > tiny && !this->nearClaimedStop(a, 0.3 * h);
  const bool bMoved = norm(pb - this->Target[i]) > tiny && !this->nearClaimedStop(b, 0.3 * h);
  if (!aMoved && !bMoved)
  {
    return;
  }
  const bool useA = aMoved && (!bMoved || norm2(pa - x[i]) <= norm2(pb - x[i]));
  this->Loc[i] = useA ? a : b;
  this->Target[i] = useA ? pa : pb;
  const int point = this->Rails.pointAt(this->Loc[i]);
  this->PinOnArrival[i] = point >= 0 && this->Rails.isStop(this->Loc[i].chain, point);
  ++this->Retargets[i];
}

void Compressor::rebuildStars()
{
  const std::size_t nv = this->Global.size();
  this->StarStart.assign(nv + 1, 0);
  for (const std::array<int, 3>& t : this->Tri)
  {
    for (int v : t)
    {
      ++this->StarStart[v + 1];
    }
  }
  for (std::size_t i = 0; i < nv; ++i)
  {
    this->StarStart[i + 1] += this->StarStart[i];
  }
  this->StarItems.resize(this->StarStart.back());
  std::vector<int> fill(this->StarStart.begin(), this->StarStart.end() - 1);
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    for (int v : this->Tri[t])
    {
      this->StarItems[fill[v]++] = static_cast<int>(t);
    }
  }
}

//------------------------------------------------------------------------------
// Simulation.
bool Compressor::pushStep(int i, double dt)
{
  std::vector<Vec2>& x = this->Sys->positions();
  const Vec2 d = this->Target[i] - x[i];
  const double remaining = norm(d);
  const double stepLength = this->Params.pushVelocity * dt * this->Sys->localLength(i);
  const bool arrive = remaining <= stepLength;
  const Vec2 to = arrive ? this->Target[i] : x[i] + (stepLength / remaining) * d;
  if (!this->accepts(i, to))
  {
    ++this->Stuck[i];
    this->Sys->velocities()[i] = Vec2{};
    if (this->Stuck[i] == kStuckSteps / 2 && this->Params.flipDegenerate)
    {
      // Blocked by the opposite edge of some triangle (typically a chord between two vertices
      // already on the curve, which bulges beyond it): ask for that edge to be flipped.
      for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
      {
        const int t = this->StarItems[s];
        const std::array<int, 3>& tri = this->Tri[t];
        const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
        const Vec2 a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
        if (cross(b - a, to - a) < this->MinTwice[t])
        {
          this->Blocked.push_back({ t, (k + 1) % 3 });
        }
      }
    }
    if (this->Stuck[i] == kStuckSteps && this->Retargets[i] < kMaxRetargets &&
      !this->JunctionTargetLocal(i))
    {
      this->retarget(i);
      this->Stuck[i] = 0;
    }
    return false;
  }
  this->Stuck[i] = 0;
  x[i] = to;
  this->Sys->velocities()[i] = arrive ? Vec2{} : (this->Params.pushVelocity * this->Sys->localLength(i) / remaining) * d;
  if (arrive)
  {
    this->St[i] = this->PinOnArrival[i] ? Pinned : Rail;
    if (this->St[i] == Pinned)
    {
      this->Sys->setKind(i, ParticleKind::Fixed);
    }
    ++this->Result.arrivedVertices;
  }
  return true;
}

void Compressor::railStep(int i, double dt)
{
  std::vector<Vec2>& x = this->Sys->positions();
  const Vec2 tangent = this->Rails.tangent(this->Loc[i]);
  const double h = this->Sys->localLength(i);
  double u = this->Speed[i] + dt * dot(this->Sys->forces()[i], tangent) / this->Sys->stableMass(i, dt);
  double s = dt * u;
  const double limit = this->Sys->params().maxStep * h;
  if (std::fabs(s) > limit)
  {
    s = s > 0.0 ? limit : -limit;
    u = s / dt;
  }
  if (s == 0.0)
  {
    return;
  }
  BoundaryRails::Slide slide = this->Rails.slide(this->Loc[i], s);
  if (!slide.stopped && slide.location.segment != this->Loc[i].segment &&
    dot(this->Sys->forces()[i], this->Rails.tangent(slide.location)) * s < 0.0)
  {
    // The force pulls back on the next segment: the bend is an equilibrium, rest on it
    // instead of chattering around it.
    slide.location = this->Loc[i];
    slide.location.t = s > 0.0 ? 1.0 : 0.0;
    u = 0.0;
  }
  const Vec2 to = this->Rails.position(slide.location);
  if (!this->accepts(i, to))
  {
    this->Speed[i] = 0.0;
    this->Sys->velocities()[i] = Vec2{};
    return;
  }
  x[i] = to;
  this->Loc[i] = slide.location;
  if (slide.stopped)
  {
    const int point = this->Rails.pointAt(slide.location);
    const BoundaryRails::Chain& c = this->Rails.chain(slide.location.chain);
    const bool chainEnd = !c.closed && (point == 0 || point + 1 == static_cast<int>(c.points.size()));
    this->Speed[i] = 0.0;
    this->Sys->velocities()[i] = Vec2{};
    if (!chainEnd)
    {
      this->Claimed[c.nodes[point]] = 1;
      this->St[i] = Pinned; // passed over a feature point: stays there (6.4)
      this->Sys->setKind(i, ParticleKind::Fixed);
    }
    return;
  }
  // Crossing a chain point, keep only the part of the velocity along the new segment.
  const Vec2 newTangent = this->Rails.tangent(slide.location);
  this->Speed[i] = u * std::max(0.0, dot(tangent, newTangent));
  this->Sys->velocities()[i] = this->Speed[i] * newTangent;
}

void Compressor::flip(int t, int k)
{
  const int u = this->Nbr[t][k];
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3], c = this->Tri[t][(k + 2) % 3];
  int j = 0;
  while (this->Tri[u][j] != b)
  {
    ++j;
  }
  const int d = this->Tri[u][(j + 2) % 3];
  const int nBC = this->Nbr[t][(k + 1) % 3], nCA = this->Nbr[t][(k + 2) % 3];
  const int nAD = this->Nbr[u][(j + 1) % 3], nDB = this->Nbr[u][(j + 2) % 3];
  const int eAB = this->TriEdge[t][k], eBC = this->TriEdge[t][(k + 1) % 3];
  const int eCA = this->TriEdge[t][(k + 2) % 3];
  const int eAD = this->TriEdge[u][(j + 1) % 3], eDB = this->TriEdge[u][(j + 2) % 3];
  // t = (c, a, d), u = (d, b, c)
  this->Tri[t] = { c, a, d };
  this->Nbr[t] = { nCA, nAD, u };
  this->TriEdge[t] = { eCA, eAD, eAB };
  this->Tri[u] = { d, b, c };
  this->Nbr[u] = { nDB, nBC, t };
  this->TriEdge[u] = { eDB, eBC, eAB };
  auto relink = [&](int n, int from, int to) {
    if (n >= 0)
    {
      for (int m = 0; m < 3; ++m)
      {
        if (this->Nbr[n][m] == from)
        {
          this->Nbr[n][m] = to;
        }
      }
    }
  };
  relink(nAD, u, t);
  relink(nBC, t, u);
  this->Sys->flip(eAB, { c, d }, t, this->Tri[t], u, this->Tri[u]);
  this->RestTwice[t] = this->twiceArea(t);
  this->RestTwice[u] = this->twiceArea(u);
  this->MinTwice[t] = kCollapse * this->RestTwice[t];
  this->MinTwice[u] = kCollapse * this->RestTwice[u];
  this->Level[t] = this->Level[u] = std::max(this->Level[t], this->Level[u]);
}

// Flips edge k of t if valid, improving and region-preserving. degenerateMode: t is a
// collapsed triangle whose own region does not count.
bool Compressor::tryFlip(int t, int k, bool degenerateMode)
{
  const int u = this->Nbr[t][k];
  if (u < 0)
  {
    return false;
  }
  const std::vector<Vec2>& x = this->Sys->positions();
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3], c = this->Tri[t][(k + 2) % 3];
  int j = 0;
  while (this->Tri[u][j] != b)
  {
    ++j;
  }
  const int d = this->Tri[u][(j + 2) % 3];
  if (c == d)
  {
    return false;
  }
  const double area0 = orient2d(x[c], x[a], x[d]);
  const double area1 = orient2d(x[d], x[b], x[c]);
  const double scale = norm2(x[c] - x[d]);
  if (!(area0 > 1e-12 * scale) || !(area1 > 1e-12 * scale))
  {
    return false;
  }
  const double before = std::min(this->triMinAngle(t), this->triMinAngle(u));
  const double after = std::min(minimumAngle(x[c], x[a], x[d]), minimumAngle(x[d], x[b], x[c]));
  if (!(after > before + kImprove))
  {
    return false;
  }
  if (degenerateMode)
  {
    // Paper 6.5: valid and improving is enough; faces are classified afterwards.
    this->flip(t, k);
    if (!this->Tag.empty())
    {
      this->Tag[t] = this->tagAt((1.0 / 3.0) * (x[c] + x[a] + x[d]));
      this->Tag[u] = this->tagAt((1.0 / 3.0) * (x[d] + x[b] + x[c]));
    }
    return true;
  }
  // Optimization: the flip must not move a region boundary: both new faces keep the region
  // of the two faces they replace.
  if (this->Tag[t] != this->Tag[u] ||
    this->tagAt((1.0 / 3.0) * (x[c] + x[a] + x[d])) != this->Tag[t] ||
    this->tagAt((1.0 / 3.0) * (x[d] + x[b] + x[c])) != this->Tag[t])
  {
    return false;
  }
  this->flip(t, k);
  return true;
}

// Whether flipping edge k of t gives two counter-clockwise triangles (a convex quad).
bool Compressor::flipValid(int t, int k) const
{
  const int u = this->Nbr[t][k];
  if (u < 0)
  {
    return false;
  }
  const std::vector<Vec2>& x = this->Sys->positions();
  const int a = this->Tri[t][k], b = this->Tri[t][(k + 1) % 3], c = this->Tri[t][(k + 2) % 3];
  int j = 0;
  while (this->Tri[u][j] != b)
  {
    ++j;
  }
  const int d = this->Tri[u][(j + 2) % 3];
  if (c == d)
  {
    return false;
  }
  const double scale = norm2(x[c] - x[d]);
  return orient2d(x[c], x[a], x[d]) > 1e-12 * scale && orient2d(x[d], x[b], x[c]) > 1e-12 * scale;
}

// Flips the edges that blocked pushes (when valid), so the pushed vertices can go on.
std::size_t Compressor::unblockPushes()
{
  std::size_t flips = 0;
  for (const std::pair<int, int>& b : this->Blocked)
  {
    // Earlier flips of this batch may have changed the triangle: re-find the edge.
    const int t = b.first;
    if (this->flipValid(t, b.second))
    {
      this->flip(t, b.second);
      ++flips;
    }
  }
  this->Blocked.clear();
  if (flips > 0)
  {
    this->rebuildStars();
  }
  this->Result.flips += flips;
  return flips;
}

std::size_t Compressor::flipDegenerate()
{
  if (!this->Params.flipDegenerate)
  {
    return 0;
  }
  std::size_t flips = 0;
  const std::vector<Vec2>& x = this->Sys->positions();
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    const int ti = static_cast<int>(t);
    const bool small = this->twiceArea(ti) < kSmallArea * this->RestTwice[t] ||
      this->triMinAngle(ti) < kSmallAngle;
    if (!small)
    {
      continue;
    }
    // Longest edge.
    int longest = 0;
    double best = -1.0;
    for (int k = 0; k < 3; ++k)
    {
      const double l = norm2(x[this->Tri[t][k]] - x[this->Tri[t][(k + 1) % 3]]);
      if (l > best)
      {
        best = l;
        longest = k;
      }
    }
    flips += this->tryFlip(ti, longest, true);
  }
  if (flips > 0)
  {
    this->rebuildStars();
  }
  this->Result.flips += flips;
  return flips;
}

void Compressor::simulate()
{
  const double dt = this->Params.timeStep;
  const int maxIt = this->Params.maxIterations;
  int settled = 0;
  int it = 0;
  int waves = 0;
  bool wasPushing = true;
  for (; it < maxIt; ++it)
  {
    if (it % 4 == 0)
    {
      this->Progress.report(0.1 + 0.6 * static_cast<double>(it) / maxIt, "compressing the grid");
    }
    this->Sys->computeForces();
    double largest = this->Sys->integrate(dt, &this->TheGuard);
    bool pushing = false;
    const int n = this->NumActive;
    for (int i = 0; i < n; ++i)
    {
      if (this->St[i] == Pushing)
      {
        const Vec2 before = this->Sys->positions()[i];
        this->pushStep(i, dt);
        largest = std::max(largest, norm(this->Sys->positions()[i] - before) / this->Sys->localLength(i));
        pushing |= this->St[i] == Pushing && this->Stuck[i] < kStuckSteps;
      }
    }
    if (!this->Blocked.empty())
    {
      this->unblockPushes();
    }
    if (!pushing && wasPushing && waves < kMaxWaves)
    {
      ++waves;
      pushing = this->pushNewCrossings() > 0;
    }
    wasPushing = pushing;
    double largestRail = 0.0;
    if (!pushing)
    {
      for (int i = 0; i < n; ++i)
      {
        if (this->St[i] == Rail)
        {
          const Vec2 before = this->Sys->positions()[i];
          this->railStep(i, dt);
          largestRail = std::max(largestRail, norm(this->Sys->positions()[i] - before) / this->Sys->localLength(i));
        }
      }
    }
    if (std::getenv("STRATA_DEBUG") && it % 50 == 0)
    {
      static std::vector<Vec2> snap;
      double net = 0.0; int arg = -1;
      const std::vector<Vec2>& x = this->Sys->positions();
      if (snap.size() == x.size())
        for (int i = 0; i < n; ++i)
        {
          const double d = norm(x[i] - snap[i]) / this->Sys->localLength(i);
          if (d > net) { net = d; arg = i; }
        }
      snap = x;
      std::fprintf(stderr, "  free %g rail %g net50 %g (vertex %d state %d)\n", largest, largestRail, net, arg, arg >= 0 ? this->St[arg] : -1);
    }
    largest = std::max(largest, largestRail);
    if ((it + 1) % this->Params.flipInterval == 0)
    {
      this->flipDegenerate();
    }
    settled = (!pushing && largest < kSettled) ? settled + 1 : 0;
    if (std::getenv("STRATA_DEBUG") && it % 50 == 0)
    {
      int np = 0, ns = 0, nr = 0, npin = 0;
      for (int i = 0; i < n; ++i)
      {
        np += this->St[i] == Pushing;
        ns += this->St[i] == Pushing && this->Stuck[i] >= kStuckSteps;
        nr += this->St[i] == Rail;
        npin += this->St[i] == Pinned;
      }
      std::fprintf(stderr, "it %d pushing %d stuck %d rail %d pinned %d largest %g flips %zu\n", it, np, ns, nr, npin, largest, this->Result.flips);
    }
    if (settled >= kSettledSteps)
    {
      ++it;
      break;
    }
  }
  this->Result.iterations = it;
  this->flipDegenerate();
  if (std::getenv("STRATA_DEBUG"))
  {
    const std::vector<Vec2>& x = this->Sys->positions();
    for (int i = 0; i < this->NumActive; ++i)
    {
      if (this->St[i] != Pushing)
        continue;
      std::fprintf(stderr, "stuck %d at (%.1f %.1f) target (%.1f %.1f)\n", i, x[i].x + this->TheModel.origin.x, x[i].y + this->TheModel.origin.y, this->Target[i].x + this->TheModel.origin.x, this->Target[i].y + this->TheModel.origin.y);
      for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
      {
        const int t = this->StarItems[s];
        const std::array<int, 3>& tri = this->Tri[t];
        const int k = tri[0] == i ? 0 : (tri[1] == i ? 1 : 2);
        const Vec2 a = x[tri[(k + 1) % 3]], b = x[tri[(k + 2) % 3]];
        std::fprintf(stderr, "   tri %d others (%.1f %.1f) [%d] (%.1f %.1f) [%d] area-after %.3g min %.3g nbr-opp %d minang %.2f\n", t, a.x + this->TheModel.origin.x, a.y + this->TheModel.origin.y, this->St[tri[(k + 1) % 3]], b.x + this->TheModel.origin.x, b.y + this->TheModel.origin.y, this->St[tri[(k + 2) % 3]], cross(b - a, this->Target[i] - a), this->MinTwice[t], this->Nbr[t][(k + 1) % 3], this->triMinAngle(t));
      }
    }
  }
}

//------------------------------------------------------------------------------
// Faces and optimization.
void Compressor::classifyFaces()
{
  const std::vector<Vec2>& x = this->Sys->positions();
  this->Tag.resize(this->Tri.size());
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    if (t % 4096 == 0)
    {
      this->Progress.report(0.7 + 0.1 * static_cast<double>(t) / this->Tri.size(), "classifying faces");
    }
    const std::array<int, 3>& tri = this->Tri[t];
    this->Tag[t] = this->tagAt((1.0 / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]));
  }
}

// Moves vertex i as far as the restrain test allows toward the rail location `target`
// (halving the step on refusal); true when it got there.
bool Compressor::moveTowards(int i, const BoundaryRails::Location& target)
{
  std::vector<Vec2>& x = this->Sys->positions();
  const Vec2 goal = this->Rails.position(target);
  for (int attempt = 0; attempt < 4; ++attempt)
  {
    if (this->accepts(i, goal))
    {
      x[i] = goal;
      return true;
    }
    double f = 0.5;
    bool moved = false;
    for (int h = 0; h < 8 && !moved; ++h, f *= 0.5)
    {
      const Vec2 to = x[i] + f * (goal - x[i]);
      if (this->accepts(i, to))
      {
        x[i] = to;
        moved = true;
      }
    }
    if (!moved)
    {
      return false;
    }
  }
  return false;
}

std::size_t Compressor::snapBoundaryVertices()
{
  std::size_t snapped = 0;
  for (int round = 0; round < 3; ++round)
  {
    std::vector<int> off;
    for (std::size_t t = 0; t < this->Tri.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        if (this->neighbourTag(static_cast<int>(t), k) == this->Tag[t])
        {
          continue;
        }
        for (int v : { this->Tri[t][k], this->Tri[t][(k + 1) % 3] })
        {
          if (v < this->NumActive && (this->St[v] == Free || this->St[v] == Pushing))
          {
            off.push_back(v);
          }
        }
      }
    }
    std::sort(off.begin(), off.end());
    off.erase(std::unique(off.begin(), off.end()), off.end());
    if (off.empty())
    {
      break;
    }
    std::size_t moved = 0;
    for (int v : off)
    {
      const BoundaryRails::Location target = this->St[v] == Pushing
        ? this->Loc[v]
        : this->Rails.closest(this->Sys->positions()[v], this->RailScratch);
      if (!this->moveTowards(v, target))
      {
        if (std::getenv("STRATA_DEBUG"))
        {
          const Vec2 p = this->Sys->positions()[v] + this->TheModel.origin;
          const Vec2 q = this->Rails.position(target) + this->TheModel.origin;
          std::fprintf(stderr, "snap failed round %d vertex %d state %d at (%.1f %.1f) target (%.1f %.1f)\n", round, v, this->St[v], p.x, p.y, q.x, q.y);
        }
        continue;
      }
      const int point = this->Rails.pointAt(target);
      const bool pin = (this->St[v] == Pushing && this->PinOnArrival[v]) ||
        (point >= 0 && this->Rails.isStop(target.chain, point));
      this->St[v] = pin ? Pinned : Rail;
      this->Loc[v] = target;
      this->Sys->setKind(v, pin ? ParticleKind::Fixed : ParticleKind::Driven);
      ++moved;
      const std::vector<Vec2>& x = this->Sys->positions();
      for (int s = this->StarStart[v]; s < this->StarStart[v + 1]; ++s)
      {
        const std::array<int, 3>& tri = this->Tri[this->StarItems[s]];
        this->Tag[this->StarItems[s]] = this->tagAt((1.0 / 3.0) * (x[tri[0]] + x[tri[1]] + x[tri[2]]));
      }
    }
    snapped += moved;
    if (moved == 0)
    {
      break;
    }
  }
  return snapped;
}

std::size_t Compressor::optimizeFlips()
{
  std::size_t flips = 0;
  for (int pass = 0; pass < 8; ++pass)
  {
    std::size_t now = 0;
    for (std::size_t t = 0; t < this->Tri.size(); ++t)
    {
      for (int k = 0; k < 3; ++k)
      {
        const int u = this->Nbr[t][k];
        if (u < 0 || this->Tag[u] != this->Tag[t])
        {
          continue;
        }
        if (this->tryFlip(static_cast<int>(t), k, false))
        {
          ++now;
          break;
        }
      }
    }
    flips += now;
    if (now == 0)
    {
      break;
    }
  }
  if (flips > 0)
  {
    this->rebuildStars();
  }
  return flips;
}

double Compressor::starMinAngle(int i, Vec2 p) const
{
  const std::vector<Vec2>& x = this->Sys->positions();
  double m = 180.0;
  for (int s = this->StarStart[i]; s < this->StarStart[i + 1]; ++s)
  {
    const std::array<int, 3>& tri = this->Tri[this->StarItems[s]];
    const Vec2 a = tri[0] == i ? p : x[tri[0]];
    const Vec2 b = tri[1] == i ? p : x[tri[1]];
    const Vec2 c = tri[2] == i ? p : x[tri[2]];
    m = std::min(m, minimumAngle(a, b, c));
  }
  return m;
}

// Whether every triangle around i keeps its region when i moves to p.
bool Compressor::starTagsKept(int i, Vec2 p)
{
  const std::vector<Vec2>& x = this->Sys->positions();
  const int s0 = this->StarStart[i], s1 = this->StarStart[i + 1];
  bool uniform = true;
  double reach = 0.0;
  for (int s = s0; s < s1; ++s)
  {
    const int t = this->StarItems[s];
    uniform &= this->Tag[t] == this->Tag[this->StarItems[s0]];
    for (int v : this->Tri[t])
    {
      reach = std::max(reach, norm2(x[v] - p));
    }
  }
  if (uniform)
  {
    // No boundary within the disk around p that holds the new star: one region, the same as
    // before (the old star shares the ring vertices with the new one).
    double d = 0.0;
    this->Rails.closest(p, this->RailScratch, &d);
    const double dOld = [&] {
      double e = 0.0;
      this->Rails.closest(x[i], this->RailScratch, &e);
      return e;
    }();
    double reachOld = 0.0;
    for (int s = s0; s < s1; ++s)
    {
      for (int v : this->Tri[this->StarItems[s]])
      {
        reachOld = std::max(reachOld, norm2(x[v] - x[i]));
      }
    }
    if (d * d > reach && dOld * dOld > reachOld)
    {
      return true;
    }
  }
  for (int s = s0; s < s1; ++s)
  {
    const std::array<int, 3>& tri = this->Tri[this->StarItems[s]];
    const Vec2 a = tri[0] == i ? p : x[tri[0]];
    const Vec2 b = tri[1] == i ? p : x[tri[1]];
    const Vec2 c = tri[2] == i ? p : x[tri[2]];
    if (this->tagAt((1.0 / 3.0) * (a + b + c)) != this->Tag[this->StarItems[s]])
    {
      return false;
    }
  }
  return true;
}

std::size_t Compressor::smooth()
{
  std::size_t moves = 0;
  std::vector<Vec2>& x = this->Sys->positions();
  for (int i = 0; i < this->NumActive; ++i)
  {
    const int s0 = this->StarStart[i], s1 = this->StarStart[i + 1];
    if (s1 == s0 || !(this->St[i] == Free || this->St[i] == Rail))
    {
      continue;
    }
    if (this->St[i] == Free)
    {
      // A free vertex between faces of different regions is on the region boundary: moving it
      // would move the boundary off the curves.
      bool uniform = true;
      for (int s = s0 + 1; s < s1 && uniform; ++s)
      {
        uniform = this->Tag[this->StarItems[s]] == this->Tag[this->StarItems[s0]];
      }
      if (!uniform)
      {
        continue;
      }
    }
    const double m0 = this->starMinAngle(i, x[i]);
    if (m0 >= 44.0)
    {
      continue;
    }
    Vec2 bestP = x[i];
    double bestM = m0;
    BoundaryRails::Location bestLoc = this->Loc[i];
    if (this->St[i] == Free)
    {
      Vec2 c{};
      int count = 0;
      for (int s = s0; s < s1; ++s)
      {
        for (int v : this->Tri[this->StarItems[s]])
        {
          if (v != i)
          {
            c = c + x[v];
            ++count;
          }
        }
      }
      c = (1.0 / count) * c;
      for (double f : { 1.0, 0.5, 0.25 })
      {
        const Vec2 p = x[i] + f * (c - x[i]);
        const double m = this->starMinAngle(i, p);
        if (m > bestM + kImprove && this->accepts(i, p))
        {
          bestM = m;
          bestP = p;
        }
      }
    }
    else
    {
      const double h = this->Sys->localLength(i);
      for (double f : { 0.3, -0.3, 0.15, -0.15, 0.05, -0.05 })
      {
        const BoundaryRails::Slide sl = this->Rails.slide(this->Loc[i], f * h);
        if (sl.stopped)
        {
          continue;
        }
        const Vec2 p = this->Rails.position(sl.location);
        const double m = this->starMinAngle(i, p);
        if (m > bestM + kImprove && this->accepts(i, p))
        {
          bestM = m;
          bestP = p;
          bestLoc = sl.location;
        }
      }
    }
    if (bestM > m0 && this->starTagsKept(i, bestP))
    {
      x[i] = bestP;
      this->Loc[i] = bestLoc;
      ++moves;
    }
  }
  return moves;
}

void Compressor::writeBack()
{
  const std::vector<Vec2>& x = this->Sys->positions();
  for (std::size_t i = 0; i < this->Global.size(); ++i)
  {
    this->Result.points[this->Global[i]] = x[i];
  }
  for (std::size_t t = 0; t < this->Tri.size(); ++t)
  {
    const int g = this->TriGlobal[t];
    this->Result.triangles[g] = { this->Global[this->Tri[t][0]], this->Global[this->Tri[t][1]],
      this->Global[this->Tri[t][2]] };
    this->Result.triangleLevel[g] = this->Level[t];
    this->Result.triangleRegion[g] = this->Tag[t];
  }
  for (int i = 0; i < this->NumActive; ++i)
  {
    std::int8_t s = VertexFree;
    switch (this->St[i])
    {
      case Rail:
        s = VertexOnCurve;
        break;
      case Pinned:
        s = VertexPinned;
        break;
      case Pushing:
        s = VertexStuck;
        break;
      default:
        break;
    }
    this->Result.vertexState[this->Global[i]] = s;
  }
}

void Compressor::run()
{
  Clock::time_point t0 = Clock::now();
  this->Points = this->Grid.points;
  this->Progress.report(0.0, "compressing the grid");
  this->buildGlobalStars();
  this->choosePushes();
  this->placeJunctions();
  this->buildSubMesh();
  this->Result.secondsPerStage.push_back({ "compression set-up", secondsSince(t0) });
  this->Progress.report(0.1, "compressing the grid");

  t0 = Clock::now();
  this->simulate();
  this->Result.secondsPerStage.push_back({ "simulation", secondsSince(t0) });

  t0 = Clock::now();
  this->classifyFaces();
  this->Result.secondsPerStage.push_back({ "face classification", secondsSince(t0) });

  t0 = Clock::now();
  if (this->Params.optimize)
  {
    this->Progress.report(0.8, "optimizing the mesh");
    this->Result.snappedVertices += this->snapBoundaryVertices();
    for (int pass = 0; pass < this->Params.optimizationPasses; ++pass)
    {
      this->Progress.report(0.8 + 0.2 * pass / this->Params.optimizationPasses, "optimizing the mesh");
      const std::size_t flips = this->optimizeFlips();
      const std::size_t moves = this->smooth();
      this->Result.optimizationFlips += flips;
      this->Result.smoothingMoves += moves;
      if (flips == 0 && moves == 0)
      {
        break;
      }
    }
    this->Result.secondsPerStage.push_back({ "optimization", secondsSince(t0) });
  }
  // Off-curve vertices of the region boundary, degenerate triangles.
  {
    std::vector<std::uint8_t> off(this->Global.size(), 0);
    for (std::size_t t = 0; t < this->Tri.size(); ++t)
    {
      if (!(this->twiceArea(static_cast<int>(t)) > 0.0))
      {
        ++this->Result.degenerateTriangles;
      }
      for (int k = 0; k < 3; ++k)
      {
        if (this->neighbourTag(static_cast<int>(t), k) == this->Tag[t])
        {
          continue;
        }
        for (int v : { this->Tri[t][k], this->Tri[t][(k + 1) % 3] })
        {
          off[v] |= !(this->St[v] == Rail || this->St[v] == Pinned);
        }
      }
    }
    this->Result.offCurveBoundaryVertices = static_cast<std::size_t>(std::count(off.begin(), off.end(), 1));
  }
  this->writeBack();
  this->Progress.report(1.0, "compressing the grid");
}

} // namespace

CompressionResult compress(const TriangleMesh& grid, const Classification& classification,
  const Model& model, const DistanceField& field, const CompressionParams& params,
  const ProgressReporter& progress)
{
  validate(params);
  const std::size_t np = grid.points.size();
  const std::size_t nt = grid.triangles.size();
  if (classification.vertexClass.size() != np || classification.vertexRegion.size() != np ||
    classification.cellRegion.size() != nt ||
    classification.edgeClass.size() != classification.edges.size())
  {
    throw ParameterError("compress: the classification does not belong to this mesh (" +
      std::to_string(classification.vertexClass.size()) + " vertex classes for " +
      std::to_string(np) + " points, " + std::to_string(classification.cellRegion.size()) +
      " face regions for " + std::to_string(nt) + " triangles)");
  }
  for (std::size_t t = 0; t < nt; ++t)
  {
    for (int v : grid.triangles[t])
    {
      if (v < 0 || static_cast<std::size_t>(v) >= np)
      {
        throw ParameterError("compress: triangle " + std::to_string(t) + " refers to point " +
          std::to_string(v) + ", not in [0, " + std::to_string(np) + ")");
      }
    }
  }
  CompressionResult result;
  result.points = grid.points;
  result.triangles = grid.triangles;
  result.triangleLevel = grid.triangleLevel.size() == nt ? grid.triangleLevel : std::vector<int>(nt, 0);
  result.triangleRegion = classification.cellRegion;
  result.vertexState.assign(np, VertexUntouched);
  if (nt == 0 || model.empty())
  {
    result.warnings.push_back("compress: nothing to compress (empty mesh or model)");
    return result;
  }
  Compressor compressor(grid, classification, model, field, params, progress, result);
  compressor.run();
  if (result.degenerateTriangles > 0)
  {
    result.warnings.push_back(std::to_string(result.degenerateTriangles) +
      " triangles have zero or negative area after compression");
  }
  if (result.offCurveBoundaryVertices > 0)
  {
    result.warnings.push_back(std::to_string(result.offCurveBoundaryVertices) +
      " vertices of the approximated boundary could not be placed on a curve");
  }
  return result;
}

} // namespace strata
