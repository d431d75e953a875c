// StrataMesh core: physical compression of a classified grid onto the model's boundaries
// (paper Section 6: push, restrain, rails, junctions, flips; Section 5: face classification),
// followed by an optional quality pass beyond the paper. No VTK.
#ifndef StrataMeshCore_Compression_h
#define StrataMeshCore_Compression_h

#include "Classification.h"
#include "DistanceField.h"
#include "Grid48.h"
#include "Model.h"
#include "Progress.h"
#include "SpringSystem.h"
#include "StripTree.h"

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace strata
{

/// Which end points of the intersection edges are pushed onto the boundary (paper 6.3).
enum class PushCriterion : int
{
  AllCandidates = 0, ///< both end points of every intersection edge
  OneSide = 1,       ///< the exterior end against a region, the end in the region of larger id
                     ///< between two regions; the closer end when both are in one region
  Closest = 2        ///< the end point closer to the boundary
};

/// Parameters of compress(). Lengths are relative to the local edge length h (the mean rest
/// length of a vertex's grid edges), times are in the particle system's dimensionless time
/// (see SpringParams), so the defaults fit every model whatever its units and size.
struct CompressionParams
{
  /// Springs per edge only, or edge + projection springs (paper 6.1). Default: both.
  SpringConfiguration springConfiguration = SpringConfiguration::EdgeAndProjection;
  /// ks. Range (0, 1e3].
  double springStiffness = 1.0;
  /// kd of the edge springs. Range [0, 1e3].
  double damping = 0.5;
  /// Duration of one step. Range (0, 1]. With the default stiffness a spring's period is
  /// about 44 steps.
  double timeStep = 0.1;
  /// Steps of the simulation (push, then scattering) at most; it stops earlier when every
  /// push is over and fewer than 0.5% of the simulated vertices still move (by more than
  /// 0.03 h in 10 steps; the others sleep, see SpringSystem::setAwake), or nothing moves by
  /// 1e-3 h for 10 steps. Range [0, 1e6]; 0 skips
  /// the simulation (boundary vertices are then only placed by the optimization's snap).
  int maxIterations = 600;
  /// Default: OneSide (the paper's best).
  PushCriterion pushCriterion = PushCriterion::OneSide;
  /// Speed of pushed vertices in local edge lengths per unit time: with the default time step
  /// a pushed vertex moves 0.05 h per step. Range (0, 10].
  double pushVelocity = 0.5;
  /// Degrees. A boundary point whose angle (between its two segments, 180 = straight) is
  /// smaller than this is a feature: a vertex sliding over it stops there for good (paper
  /// 6.4). Range [0, 180]; 0 means no features.
  double featureAngle = 140.0;
  /// Flip the longest edge of collapsed or very small triangles when that is valid and
  /// improves them (paper 6.5), every flipInterval steps and at the end.
  bool flipDegenerate = true;
  /// Steps between two degeneracy checks. Range [1, 1e6].
  int flipInterval = 10;
  /// Vertices within this many edge rings of a candidate (an end point of an intersection
  /// edge or a junction vertex) are simulated; the rest of the grid is fixed. Range [1, 16].
  int activeRings = 2;
  /// Springs from which a simulation step is split in two halves on two threads
  /// (SpringParams::splitSprings; a larger mesh's result does not depend on the machine).
  std::size_t splitSprings = SpringParams{}.splitSprings;
  /// Beyond the paper: after the simulation, snap boundary vertices that are off the curves
  /// onto them, refine the boundary (boundaryTolerance), then flip edges, smooth vertices
  /// (free ones in the plane, curve ones along their curve), collapse squeezed vertices and
  /// split the longest edge of faces (angle refinement) where an angle is below 30 degrees,
  /// toward larger minimum angles, never changing a face's region and never lowering the
  /// smallest angle around the vertex or edge touched.
  bool optimize = true;
  /// Rounds of (flip pass, smoothing pass, angle refinement) of the optimization; they stop
  /// earlier when a round changes nothing. Range [0, 100].
  int optimizationPasses = 12;
  /// Beyond the paper, part of the optimization: an edge of the approximated boundary whose
  /// curve (the part of the chain between its two end vertices) lies farther than this times
  /// the local edge length h from it is split at the curve's farthest point (a corner the
  /// compression cut, a bulge between two vertices), until every boundary edge follows its
  /// curve within this distance or cannot be split (the new triangles would be inverted).
  /// Relative to h. Range [0, 10]; 0 = no boundary refinement.
  double boundaryTolerance = 0.25;
};

/// Validates params (ParameterError naming the parameter and its range).
void validate(const CompressionParams& params);

/// The model's boundary as rails: the distinct boundary segments chained through the nodes
/// where exactly two of them meet; chains end at junctions (nodes of any other degree, the
/// Model::junctions) and closed chains have none. Each chain knows the regions on its left and
/// right (-1 exterior) and which of its points are features.
class BoundaryRails
{
public:
  struct Chain
  {
    std::vector<Vec2> points;          ///< local coordinates; closed chains do not repeat
    std::vector<int> nodes;            ///< Model node id of each point
    std::vector<std::uint8_t> feature; ///< per point: 1 = a vertex sliding over it stops there
    bool closed = false;
    int left = -1, right = -1; ///< region ids on both sides (-1 exterior)
    std::size_t numberOfSegments() const
    {
      return this->closed ? this->points.size() : this->points.size() - 1;
    }
  };
  /// A point on a rail: chain, segment of the chain (from points[segment] to the next point)
  /// and parameter t in [0, 1] along it.
  struct Location
  {
    int chain = -1;
    int segment = -1;
    double t = 0.0;
  };
  struct Slide
  {
    Location location;
    bool stopped = false; ///< stopped at a feature point or a chain end
  };

  /// featureAngle in degrees (see CompressionParams::featureAngle). Chain ends are always
  /// stop points.
  BoundaryRails(const Model& model, double featureAngle);

  std::size_t numberOfChains() const { return this->Chains.size(); }
  const Chain& chain(int i) const { return this->Chains[i]; }
  std::size_t numberOfSegments() const { return this->Tree.numberOfSegments(); }

  /// Closest boundary point to p (distance in *distance when given). With maxDistance, only
  /// points nearer than it are looked for (chain -1 and *distance maxDistance when there is
  /// none; much faster for far points).
  Location closest(Vec2 p,
    StripTreeScratch& scratch,
    double* distance = nullptr,
    double maxDistance = HUGE_VAL) const;
  /// The rails' segments (chain by chain, the order of the segment ids closest() works with)
  /// in a SegmentGrid of cells cellSize wide, at most maxCells (see SegmentGrid).
  SegmentGrid segmentGrid(double cellSize, std::size_t maxCells) const;
  /// The location of parameter t on segment `segment` of that order.
  Location location(int segment, double t) const;
  Vec2 position(const Location& l) const;
  /// Unit direction of the location's segment (chain direction).
  Vec2 tangent(const Location& l) const;
  /// Moves along the chain by the signed arc length s; stops on reaching a feature point or
  /// a chain end (the returned location is then exactly that point).
  Slide slide(const Location& from, double s) const;
  /// Index of the chain point the location is exactly at (t = 0 or 1), or -1.
  int pointAt(const Location& l) const;
  /// Whether chain point `point` stops sliding vertices (a feature or a chain end).
  bool isStop(int chain, int point) const;
  /// Locations of the chain points at model node `node` (several for a junction).
  std::vector<Location> locationsOfNode(int node) const;

private:
  std::vector<Chain> Chains;
  StripTree Tree;
  std::vector<std::array<int, 2>> SegmentOf; // tree segment -> (chain, segment)
  /// The chain points at each model node: NodeLocations[NodeStart[node] .. NodeStart[node + 1]).
  std::vector<int> NodeStart;
  std::vector<Location> NodeLocations;
};

/// Vertex states at the end of compress().
enum CompressedVertex : std::int8_t
{
  VertexUntouched = 0, ///< outside the simulated zone: still at its grid position
  VertexFree = 1,      ///< simulated, moved by the springs (and the optimization)
  VertexOnCurve = 2,   ///< on a boundary curve (arrived there, slides along it)
  VertexPinned = 3,    ///< exactly on a junction or a feature point, never moves again
  VertexStuck = 4      ///< was pushed but could not reach the boundary
};

struct CompressionResult
{
  LargeVector<Vec2> points;                  ///< final positions (local coordinates)
  LargeVector<std::array<int, 3>> triangles; ///< counter-clockwise (after flips)
  LargeVector<int> triangleLevel;            ///< grid level (a flipped pair: the finer of both)
  /// Section 5 face classification: region of each triangle's barycentre (-1 exterior).
  LargeVector<int> triangleRegion;
  LargeVector<std::int8_t> vertexState; ///< CompressedVertex per point
  int iterations = 0;                   ///< simulation steps run
  std::size_t simulatedVertices = 0;    ///< vertices in the simulated zone
  std::size_t pushedVertices = 0;       ///< vertices marked to be pushed
  std::size_t arrivedVertices = 0;      ///< of those, reached the boundary in the simulation
  std::size_t snappedVertices = 0;      ///< moved onto a curve after the simulation
  std::size_t junctionVertices = 0;     ///< vertices placed on junctions
  std::size_t flips = 0;                ///< degeneracy flips (6.5)
  std::size_t optimizationFlips = 0;    ///< flips of the quality pass
  std::size_t smoothingMoves = 0;       ///< accepted smoothing moves
  std::size_t boundarySplits = 0;       ///< boundary edges split onto their curve
  std::size_t angleVertices = 0;        ///< free vertices inserted to mend small angles
  /// Free vertices collapsed into a neighbour (squeezed ones); they stay in points, used by
  /// no triangle.
  std::size_t collapsedVertices = 0;
  std::size_t bulgeVertices = 0; ///< free vertices moved onto a curve that bulged past them
  /// Points [firstInsertedPoint, points.size()) were inserted by the optimization (boundary
  /// and angle refinement; they have no grid position); the others are the grid's points.
  std::size_t firstInsertedPoint = 0;
  std::size_t offCurveBoundaryVertices = 0; ///< vertices of the region boundary not on a curve
  std::size_t degenerateTriangles = 0;      ///< triangles of zero or negative area left (0)
  std::vector<std::pair<std::string, double>> secondsPerStage;
  std::vector<std::string> warnings;
};

/// Compresses the grid mesh `grid` (as extracted from a Grid48, classified by classify() with
/// the same model and field) onto the model's boundaries and classifies its faces. Throws
/// ParameterError for parameters out of range or a classification of another mesh, Aborted
/// when the progress callback asks to stop (checked at least every simulation step).
CompressionResult compress(const TriangleMesh& grid,
  const Classification& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params = {},
  const ProgressReporter& progress = ProgressReporter());

/// As above, with the classification handed over: the arrays the compression reads no more go
/// as soon as it is done with them (`cellRegion` once copied into the result, `edges` and
/// `edgeClass` once the pushes are chosen), so that the compression's own arrays take their
/// memory. Same result; the classification is left with its vertex arrays only (and its
/// edges, when the mesh or the model is empty: nothing is compressed). At 1 M triangles 17 MB
/// less at the run's peak.
CompressionResult compress(const TriangleMesh& grid,
  Classification&& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params = {},
  const ProgressReporter& progress = ProgressReporter());

/// As above, with the grid handed over as well, but for its points: its other arrays (the
/// triangles, their levels, the points' boundary distances and any other) go once the
/// compression's set-up has read them, instead of staying through the simulation, and the
/// points stay for the caller (the displacements). Same result. The grid is left with its
/// points only, or as it was when nothing is compressed (an empty mesh or model). At 1 M
/// triangles 21 MB less through the simulation, one of the run's two memory peaks (the other
/// is the refinement's).
CompressionResult compressHandedOver(TriangleMesh& grid,
  Classification&& classification,
  const Model& model,
  const DistanceField& field,
  const CompressionParams& params = {},
  const ProgressReporter& progress = ProgressReporter());

/// Drops the triangles a collapse removed (all three corners the same vertex) from `r`'s
/// triangles, levels and regions, keeping the others in order; the collapsed vertices stay in
/// `r.points`, used by no triangle. Returns how many were dropped.
std::size_t dropCollapsedTriangles(CompressionResult& r);

/// Paper 6.5 on a plain counter-clockwise triangle list: every triangle with an angle below
/// smallAngle degrees gets its longest edge flipped when both new triangles are
/// counter-clockwise and the smaller of the two triangles' smallest angles grows; repeated
/// until nothing changes or `passes` passes. Returns the number of flips. The simulation
/// applies the same rule to its sub-mesh (also to triangles below 10% of their rest area).
std::size_t flipDegenerateTriangles(const LargeVector<Vec2>& points,
  LargeVector<std::array<int, 3>>& triangles,
  double smallAngle = 10.0,
  int passes = 8);

/// Whether moving vertex `i` of a counter-clockwise triangle list to `to` keeps every
/// triangle of `star` (ids of triangles containing i) counter-clockwise with twice-area at
/// least min(minFraction * minTwiceArea[t], its current twice-area) and > 0: the paper's
/// restrain test (6.3), with two cross products per (vertex, opposite edge) pair. (With
/// minTwiceArea the rest twice-areas and minFraction the share of them to keep, no array of
/// the bounds is needed.)
bool restrainAccepts(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles,
  const int* star,
  int starSize,
  int i,
  Vec2 to,
  const double* minTwiceArea = nullptr,
  double minFraction = 1.0);

} // namespace strata

#endif
