// StrataMesh core, internal (not installed): the compressor's state, shared by
// Compression.cpp (set-up, simulation, faces) and Optimization.cpp (the quality pass after
// the simulation). No VTK.
#ifndef StrataMeshCore_Compressor_h
#define StrataMeshCore_Compressor_h

#include "Compression.h"
#include "LargeArray.h"
#include "Parallel.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace strata
{
namespace detail
{

constexpr double kCollapse = 0.02;         // restrain: keep at least 2% of the rest area
constexpr double kLastResort = 0.05;       // snap: then accept 5% of that (0.1% of the rest area)
constexpr double kSmallArea = 0.1;         // degeneracy check: below 10% of the rest area
constexpr double kSmallAngle = 10.0;       // degeneracy check: an angle below 10 degrees
constexpr int kStuckSteps = 20;            // a push blocked this long aims aside
constexpr int kMaxRetargets = 3;           // times a blocked push aims aside
constexpr int kMaxWaves = 4;               // push phases after the first one
constexpr double kSettled = 1e-3;          // relative move below which a step is quiet
constexpr int kSettledSteps = 10;          // quiet steps that end the simulation
constexpr int kWakeInterval = 10;          // steps between two updates of the awake particles
constexpr double kSleep = 3e-2;            // relative move in kWakeInterval steps that keeps awake
constexpr double kQuietFraction = 5e-3;    // fewer moving vertices than this fraction: stop
constexpr double kFewPushes = 1e-3;        // pushes left (share of the simulated) = a wave's tail
constexpr double kFewAwake = 1.0 / 128.0;  // awake particles (share) whose springs come from stars
constexpr double kGoodAngle = 30.0;        // optimization leaves stars and pairs above this alone
constexpr double kPoorAngle = 20.0;        // smoothing below this may leave the boundary tolerance
constexpr int kOnCurve = -2;               // vertex region of a vertex on a curve
constexpr std::size_t kQueryBlock = 16384; // queries per block of a two-thread query loop

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Sine of the smallest angle of abc (monotone in the angle, which is at most 60 degrees):
// twice the area over the product of the two longer edges.
inline double minAngleSine(Vec2 a, Vec2 b, Vec2 c)
{
  const double l0 = norm2(b - a), l1 = norm2(c - b), l2 = norm2(a - c);
  const double shortest = std::min({ l0, l1, l2 });
  const double product = l0 * l1 * l2 / (shortest > 0.0 ? shortest : 1.0);
  return shortest > 0.0 ? std::fabs(orient2d(a, b, c)) / std::sqrt(product) : 0.0;
}

// Vertex states during the simulation.
enum State : std::uint8_t
{
  Halo,    // fixed: in the sub-mesh only as a neighbour of simulated vertices
  Free,    // simulated particle
  Pushing, // driven toward its target
  Rail,    // on a curve
  Pinned   // on a junction or feature point
};

// The result's points, triangles, levels (0 without the grid's) and vertex states
// (VertexUntouched) as the grid has them, with room for the optimization's splits (when
// nothing is compressed; the compressor fills its result itself, Compressor::fillResult()).
void fillFromGrid(CompressionResult& result, const TriangleMesh& grid);

// The simulated sub-mesh and everything done to it.
class Compressor
{
public:
  // `spent`, when given, is `cls` itself, handed over: its edges go once the pushes are chosen.
  // `spentGrid`, when given, is `grid` itself, handed over: all but its points go once the
  // sub-mesh is built (keepOutside()).
  Compressor(const TriangleMesh& grid,
    const Classification& cls,
    const Model& model,
    const DistanceField& field,
    const CompressionParams& params,
    const ProgressReporter& progress,
    CompressionResult& result,
    Classification* spent = nullptr,
    TriangleMesh* spentGrid = nullptr)
    : Grid(grid)
    , Cls(cls)
    , Spent(spent)
    , SpentGrid(spentGrid)
    , TheModel(model)
    , Field(field)
    , Params(params)
    , Progress(progress)
    , Result(result)
    , Rails(model, params.featureAngle)
  {
    this->TheGuard.Self = this;
  }

  void run();

private:
  using Location = BoundaryRails::Location;

  // Progress (and abort) inside long loops: every 4096 items, at the current fraction.
  void poll(std::size_t i) const
  {
    if ((i & 4095) == 0)
    {
      this->Progress.report(this->At, this->Stage);
    }
  }
  // For loops whose items are heavier (a flip search, a smoothing move, a collapse, a split
  // around one bad face or vertex): tens of microseconds each at 1e6 triangles.
  void pollEach(std::size_t i) const
  {
    if ((i & 255) == 0)
    {
      this->Progress.report(this->At, this->Stage);
    }
  }
  double At = 0.0;
  const char* Stage = "compressing the grid";

  // --- set-up
  void buildGlobalStars();
  bool isBorderVertex(int g) const;
  // The queries below with the compressor's own scratch, or with a caller's (another
  // thread's: see pushNewCrossings).
  double gridDistance(int g) { return this->gridDistance(g, this->RailScratch); }
  double gridDistance(int g, StripTreeScratch& rail);
  bool movedLessThanGridDistance(int g, double moved)
  {
    return this->movedLessThanGridDistance(g, moved, this->RailScratch);
  }
  bool movedLessThanGridDistance(int g, double moved, StripTreeScratch& rail);
  void buildCurveCells();
  void choosePushes();
  void placeJunctions();
  void buildSubMesh();
  void keepOutside();
  void rebuildStars();
  void updateStars();
  void claimStopPoints();
  void spreadTargets();
  bool nearClaimedStop(const Location& l, double reach) const;
  void startPush(int i, const Location& target);
  void setBudget(int i);
  void retarget(int i);
  bool junctionBound(int i) const { return this->JunctionTarget[this->Global[i]] >= 0; }
  // --- simulation
  void simulate();
  void pushStep(int i, double dt);
  void railStep(int i, double dt);
  std::size_t pushNewCrossings();
  std::size_t refreshAwake(LargeVector<Vec2>& windowStart,
    const std::vector<int>& pushed,
    bool tail = false);
  double lowerDistance(int i) const
  {
    const int g = this->Global[i];
    const double d = this->Distance[g];
    return std::isnan(d) ? 0.0 : d - norm(this->positions()[i] - this->Grid.points[g]);
  }
  std::size_t flipDegenerate();
  std::size_t unblockPushes();
  // --- faces and optimization
  int regionAt(Vec2 p) { return this->Field.region(p, this->FieldScratch); }
  int vertexRegion(int i) { return this->vertexRegion(i, this->RailScratch, this->FieldScratch); }
  int vertexRegion(int i, StripTreeScratch& rail, DistanceField::Scratch& field);
  int faceTag(int a, int b, int c, Vec2 pa, Vec2 pb, Vec2 pc);
  int faceTag(int a, int b, int c, Vec2 pa, Vec2 pb, Vec2 pc, DistanceField::Scratch& field);
  int faceTag(int t);
  int faceTag(int t, DistanceField::Scratch& field);
  void classifyFaces();
  int neighbourTag(int t, int k) const
  {
    const int u = this->Nbr[t][k];
    return u >= 0 ? this->Tag[u] : (u == -1 ? -1 : this->Result.triangleRegion[-2 - u]);
  }
  std::vector<int> offCurveBoundaryVertices() const;
  bool placeOnCurve(int i, const Location& target, double minFraction);
  std::size_t snapBoundaryVertices();
  std::size_t optimizeFlips();
  std::size_t smooth();
  double starMinAngle(int i, Vec2 p) const;
  // boundary refinement
  struct ChainPiece
  {
    int chain = -1;
    double from = 0.0, to = 0.0; // chain parameters (segment + t) of the two ends
    bool forward = true;         // walk direction from `from` to `to`
    double deviation = -1.0;     // largest distance of a chain point between them to the edge
    int farthest = -1;           // that chain point
  };
  // Calls f(location) for each location of curve vertex i on the chains: its own, or at a
  // model node, the node's on every chain through it (without a list in the usual case).
  template<typename F>
  void forEachLocation(int i, F&& f) const;
  ChainPiece boundaryPiece(int t, int k) const;
  Location pieceMiddle(const ChainPiece& piece) const;
  // The two faces across edge k of face t: t = (a, b, c) and u = Nbr[t][k] = (b, a, d), the
  // edge being edge j of u (u >= 0).
  struct Quad
  {
    int u, j, a, b, c, d;
  };
  Quad quadOf(int t, int k) const
  {
    Quad q;
    q.u = this->Nbr[t][k];
    q.a = this->Tri[t][k];
    q.b = this->Tri[t][(k + 1) % 3];
    q.c = this->Tri[t][(k + 2) % 3];
    q.j = this->Tri[q.u][0] == q.b ? 0 : (this->Tri[q.u][1] == q.b ? 1 : 2);
    q.d = this->Tri[q.u][(q.j + 2) % 3];
    return q;
  }
  // The four faces made by splitting that edge at w: (a, w, c), (w, b, c), (b, w, d), (w, a, d).
  std::array<std::array<Vec2, 3>, 4> splitFaces(const Quad& q, Vec2 w) const
  {
    const auto& x = this->positions();
    return {
      { { x[q.a], w, x[q.c] }, { w, x[q.b], x[q.c] }, { x[q.b], w, x[q.d] }, { w, x[q.a], x[q.d] } }
    };
  }
  bool canSplit(int t, int k, Vec2 w) const;
  bool splitBoundaryEdge(int t, int k, const Location& at, bool pin);
  void splitEdge(int t, int k, Vec2 w, std::uint8_t state, const Location& at, int region);
  void detach();
  std::size_t refineAngles();
  bool collapseInto(int i, int v);
  bool insidePiece(const ChainPiece& piece, const Location& l) const;
  std::size_t collapseSqueezed();
  void collectBad();
  bool pullIntoBulge(int t, int k, const Location& far);
  Location farthestLocation(const ChainPiece& piece) const;
  bool deviatingEdge(int t, int k, int nt, ChainPiece& piece) const;
  // forEachDeviatingEdge's blocks of faces tested ahead: after a change, doubled up to the
  // last while none changes; on two threads from kTwoThreadAhead faces.
  static constexpr int kFirstAhead = 256, kLastAhead = 16384, kTwoThreadAhead = 2048;
  // Calls act(t, k, piece) for every boundary edge out of tolerance among the faces present
  // at the call (each edge once); act returns true when it changed face t, whose other edges
  // are then skipped. Returns how many calls returned true. `found` (kept by the caller
  // between calls) holds which faces had such an edge when the mesh was last seen unchanged:
  // filled here when empty (on two threads for a large mesh: deviatingEdge only reads),
  // emptied when an act changes the mesh (returns true, or flips edges and returns false).
  // Only the faces found are looked at until the first change; from there on, every face
  // (the change may put later faces' edges out of tolerance). So the faces visited and the
  // edges acted on are those of a sweep over every face. From the first change on, the faces
  // ahead are tested in blocks (on two threads from kTwoThreadAhead faces), each block when
  // it is reached, so with the mesh as the sweep finds it there; a change within a block
  // ends it (the next block starts at the next face), its blocks growing from kFirstAhead
  // faces while there is none. (So an act may change the mesh only as said: returning true,
  // or by flips, which Flips counts.)
  template<typename Act>
  std::size_t forEachDeviatingEdge(LargeVector<std::uint8_t>& found, Act&& act)
  {
    std::size_t changed = 0;
    const int nt = static_cast<int>(this->Tri.size());
    const auto deviates = [&](int t, ChainPiece& scratch)
    {
      return this->deviatingEdge(t, 0, nt, scratch) || this->deviatingEdge(t, 1, nt, scratch) ||
        this->deviatingEdge(t, 2, nt, scratch);
    };
    if (found.size() != static_cast<std::size_t>(nt))
    {
      found.assign(static_cast<std::size_t>(nt), 0);
      blockwise(
        static_cast<std::size_t>(nt),
        kTwoThreadBlock,
        kTwoThreadItems,
        [&](std::size_t from, std::size_t to, int)
        {
          ChainPiece scratch;
          for (std::size_t t = from; t < to; ++t)
          {
            found[t] = deviates(static_cast<int>(t), scratch);
          }
        },
        [&] { this->Progress.report(this->At, this->Stage); });
    }
    bool every = false;
    ChainPiece piece;
    std::vector<std::uint8_t> ahead;  // per face of [aheadBegin, aheadEnd): a deviating edge
    int aheadBegin = 0, aheadEnd = 0; // (nothing changed since they were tested)
    int aheadSize = kFirstAhead;
    const auto testAhead = [&](int from)
    {
      aheadBegin = from;
      aheadEnd = std::min(nt, from + aheadSize);
      aheadSize = std::min(2 * aheadSize, kLastAhead);
      ahead.assign(static_cast<std::size_t>(aheadEnd - aheadBegin), 0);
      blockwise(
        ahead.size(),
        ahead.size(),
        kTwoThreadAhead,
        [&](std::size_t begin, std::size_t end, int)
        {
          ChainPiece scratch;
          for (std::size_t i = begin; i < end; ++i)
          {
            ahead[i] = deviates(aheadBegin + static_cast<int>(i), scratch);
          }
        },
        [] {});
    };
    for (int t = 0; t < nt; ++t)
    {
      this->poll(static_cast<std::size_t>(t));
      if (!every && !found[static_cast<std::size_t>(t)])
      {
        continue;
      }
      if (every)
      {
        if (t >= aheadEnd)
        {
          testAhead(t);
        }
        if (!ahead[static_cast<std::size_t>(t - aheadBegin)])
        {
          continue;
        }
      }
      for (int k = 0; k < 3; ++k)
      {
        if (!this->deviatingEdge(t, k, nt, piece))
        {
          continue;
        }
        const std::size_t flipsBefore = this->Flips;
        const bool acted = act(t, k, piece);
        if (acted || this->Flips != flipsBefore)
        {
          every = true;
          aheadEnd = 0; // (the faces ahead are tested again from the next one)
          aheadSize = kFirstAhead;
        }
        if (acted)
        {
          ++changed;
          break;
        }
      }
    }
    if (every)
    {
      found.clear();
    }
    return changed;
  }
  bool followsCurves(int i, Vec2 p, const Location& l);
  std::size_t refineBoundary();
  bool active(int i) const { return i < this->NumActive || i >= this->FirstAdded; }
  // --- shared
  bool flipValid(int t, int k) const;
  bool tryFlip(int t, int k, bool degenerate);
  void flip(int t, int k);
  void retagStar(int i);
  bool accepts(int i, Vec2 to) const
  {
    const int s0 = this->StarStart[i];
    return restrainAccepts(this->positions(),
      this->Tri,
      this->StarItems.data() + s0,
      this->StarStart[i + 1] - s0,
      i,
      to,
      this->RestTwice.data(),
      kCollapse);
  }
  double twiceArea(int t) const
  {
    const auto& x = this->positions();
    return orient2d(x[this->Tri[t][0]], x[this->Tri[t][1]], x[this->Tri[t][2]]);
  }
  bool onCurve(int i) const { return this->St[i] == Rail || this->St[i] == Pinned; }
  double triMinAngleSine(int t) const
  {
    const auto& x = this->positions();
    return minAngleSine(x[this->Tri[t][0]], x[this->Tri[t][1]], x[this->Tri[t][2]]);
  }
  void writeBack();

  struct Guard : MoveGuard
  {
    const Compressor* Self = nullptr;
    bool accept(int i, Vec2, Vec2 to) override { return this->Self->accepts(i, to); }
  };

  const TriangleMesh& Grid;
  const Classification& Cls;
  Classification* Spent; // Cls, when the caller handed it over (compress(Classification&&))
  TriangleMesh* SpentGrid; // Grid, when the caller handed it over (compressHandedOver())
  // Once the sub-mesh is built (keepOutside()): the grid's triangle count, and its triangles
  // outside the sub-mesh (the sub-mesh's own are written back from it).
  struct OutsideTriangle
  {
    int id;
    std::array<int, 3> corners;
    int level;
  };
  std::size_t GridTriangles = 0;
  LargeVector<OutsideTriangle> Outside;
  const Model& TheModel;
  const DistanceField& Field;
  const CompressionParams& Params;
  const ProgressReporter& Progress;
  CompressionResult& Result;
  BoundaryRails Rails;
  StripTreeScratch RailScratch;
  std::unique_ptr<SegmentGrid> CurveCells; // the rails' segments (for vertexRegion), when asked
  double CurveCell = 0.0;                  // ... the cell size asked for
  DistanceField::Scratch FieldScratch;
  Guard TheGuard;

  // Global mesh (grid ids).
  // The set-up's (freed at its end): the positions before the simulation (junctions snapped)
  // and the grid's vertex stars.
  LargeVector<Vec2> Points;
  LargeVector<int> GStarStart, GStarItems;
  LargeVector<std::uint8_t> Candidate, Push;
  LargeVector<double> Distance; // boundary distance (NaN: not computed)
  // pushNewCrossings' answers of its last call: the region of a vertex off the curves at the
  // position it had (NaN: none), and of the barycentres of the faces it asked about (by face
  // id, increasing); a wave asks again only where a position moved.
  LargeVector<Vec2> WaveVertexAt;
  LargeVector<int> WaveVertexRegion;
  struct FaceAnswer
  {
    int face;
    int region;
    Vec2 at;
  };
  LargeVector<FaceAnswer> WaveFaces;
  LargeVector<int> JunctionOf;     // junction node a vertex was placed on, or -1
  LargeVector<int> JunctionTarget; // junction node a vertex is pushed to, or -1

  // Sub-mesh (local ids).
  LargeVector<int> Global;  // local vertex -> grid vertex
  LargeVector<int> LocalOf; // grid vertex -> local vertex, -1
  int NumActive = 0;        // local ids below are simulated
  LargeVector<std::array<int, 3>> Tri, Nbr, TriEdge;
  LargeVector<int> TriGlobal, Level, Tag;
  LargeVector<double> RestTwice; // twice the rest area (restrain: keep kCollapse of it)
  LargeVector<int> StarStart, StarItems;
  // Since the stars were built: the triangles whose corners flip(), splitEdge() and
  // collapseInto() changed (with repeats), the scratch of updateStars() (marks, and the buffer
  // the new items are written to, swapped with StarItems) and the triangle count they cover.
  LargeVector<int> Flipped;
  LargeVector<std::uint8_t> FlippedMark;
  LargeVector<int> StarScratch;
  // flipDegenerate()'s marks per triangle: kDegenerate as tested, kChanged once flipped. Since
  // its last test: the vertices that may have moved (every one when MovedAll; each awake set's
  // particles, MovedMark against repeats) and the triangles flip() changed (with repeats). The
  // marks of the other triangles still hold (a sleeping particle does not move).
  static constexpr std::uint8_t kDegenerate = 1, kChanged = 2;
  LargeVector<std::uint8_t> DegenerateMarks;
  bool MovedAll = true;
  LargeVector<int> Moved;
  LargeVector<std::uint8_t> MovedMark;
  LargeVector<int> FlippedSinceTest;
  void noteMoved(); // the awake set's particles may have moved since flipDegenerate's test
  std::size_t StarTriangles = 0;
  std::unique_ptr<SpringSystem> Sys; // (none once detached: the positions are taken to X)
  LargeVector<Vec2> X;               // the positions once detached
  // The positions: the spring system's until detach(), then X.
  LargeVector<Vec2>& positions() { return this->Sys ? this->Sys->positions() : this->X; }
  const LargeVector<Vec2>& positions() const
  {
    return this->Sys ? this->Sys->positions() : this->X;
  }

  // Per local vertex.
  LargeVector<std::uint8_t> St;
  LargeVector<Location> Loc; // push target, then position on the rail
  LargeVector<std::uint8_t> PinOnArrival;
  // A push's own state, kept for the vertices that were pushed only (at 1 M 81 k of the 470 k
  // simulated: 18 MB less than per vertex through the simulation, one of the run's two
  // memory peaks). A vertex pushed again in a later wave starts its record anew.
  struct PushRecord
  {
    Vec2 target;       // where it goes
    Location first;    // its closest point when the push started
    int stuck = 0;     // steps in a row its move was refused
    int retargets = 0; // times it aimed aside
    int steps = 0;     // steps taken
    int budget = 0;    // steps it may take
  };
  LargeVector<int> PushOf; // the vertex's record in Pushes, or -1 (never pushed)
  LargeVector<PushRecord> Pushes;
  // The record of vertex i, made (all zero) when it has none.
  PushRecord& pushRecord(int i)
  {
    if (this->PushOf[i] < 0)
    {
      this->PushOf[i] = static_cast<int>(this->Pushes.size());
      this->Pushes.emplace_back();
    }
    return this->Pushes[this->PushOf[i]];
  }
  // The record of vertex i (all zero when it has none).
  const PushRecord& pushed(int i) const
  {
    static const PushRecord none{};
    return this->PushOf[i] < 0 ? none : this->Pushes[this->PushOf[i]];
  }
  LargeVector<int> VRegion;          // region of vertices off the curves, kOnCurve for the others
  LargeVector<std::uint8_t> Claimed; // per model node: a vertex is (going) there
  LargeVector<std::pair<int, int>> Blocked; // (triangle, edge) blocking a push
  LargeVector<Vec2> Candidates;             // smoothing scratch
  // After the simulation (optimization): local edge length per vertex, and the first local id
  // of the vertices inserted by the boundary refinement (they are simulated ones too).
  LargeVector<double> H;
  LargeVector<int> StuckVertices; // pushes that never arrived (free during the optimization)
  // Faces with an angle below kGoodAngle at the start of an optimization round, and their
  // corners (ascending): the rounds only look at these.
  LargeVector<int> BadFaces, BadVertices;
  // collectBad()'s test per face (1: bad), kept through the optimization's rounds, and while
  // it is (not empty) the faces whose shape the rounds changed since its last call (with
  // repeats: flips, moves, collapses, splits), which are all its next call tests again, with
  // the faces added since.
  LargeVector<std::uint8_t> BadMark;
  LargeVector<int> Changed;
  void noteChanged(int t)
  {
    if (!this->BadMark.empty())
    {
      this->Changed.push_back(t);
    }
  }
  void noteStar(int i) // (the faces around vertex i, before i moves or goes)
  {
    if (!this->BadMark.empty())
    {
      this->Changed.insert(this->Changed.end(),
        this->StarItems.begin() + this->StarStart[i],
        this->StarItems.begin() + this->StarStart[i + 1]);
    }
  }
  int FirstAdded = std::numeric_limits<int>::max();
  bool Detached = false; // springs no longer follow the mesh (no more simulation)
  // Result's points, triangles, levels and vertex states are copied from the grid only when
  // needed (fillResult(): at detach() or writeBack(), on memory the spring system left) and
  // updated there; its triangle regions from the start (neighbourTag()).
  void fillResult();
  bool ResultFilled = false;
  std::size_t Flips = 0; // flip() calls so far
};

} // namespace detail
} // namespace strata

#endif
