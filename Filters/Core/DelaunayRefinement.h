// StrataMesh core: constrained Delaunay refinement of a region-tagged triangle mesh toward a
// minimum angle (beyond the paper: the last step of the optimization). No VTK.
#ifndef StrataMeshCore_DelaunayRefinement_h
#define StrataMeshCore_DelaunayRefinement_h

#include "Geometry.h"
#include "LargeArray.h"
#include "Progress.h"

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace strata
{

/// A region corner of the model sharper than RefinementParams::minimumAngle that is kept to its
/// apex (RefinementParams::keptCorners): the region's wedge between its two sides.
struct SharpCorner
{
  Vec2 apex;          ///< where a mesh vertex sits (a junction, or a feature point of the rails)
  int region = -1;    ///< the region whose corner it is
  double angle = 0.0; ///< the region's angle at the apex, degrees
  /// The region's two sides, each a polyline from the apex outward along the model's curves:
  /// `first` with the region on its left, `second` with the region on its right.
  std::vector<Vec2> first, second;
  /// RefinementParams::wedgeCorners: other regions (not only the exterior) beside its sides (a
  /// lens's tip, a layer's pinch-out at a junction); such a corner is not extended when that
  /// leaves a triangle below minimumAngle within twice its reach (the last pass is made again
  /// without it).
  bool amongRegions = false;
};

/// RefinementParams::regionsNear's answer for a point with no curve nearer than asked.
constexpr int kNoCurveNear = std::numeric_limits<int>::min();

/// The largest RefinementParams::minimumAngle, degrees. Delaunay refinement is known to end
/// in practice up to about 33 degrees and usually not above 34 (Shewchuk, Triangle's -q
/// switch). Here 34 was allowed until 2026-12-06: on 25 bundled models its runs cascaded
/// until their insertion budget, 7 not ending within 60 s and 17 of the other 18 ending below
/// 30 degrees (aliased_layers_section: 273 s, 23.4 degrees, 420 k triangles; 1.5 s at 30).
constexpr double kLargestMinimumAngle = 33.0;

/// Parameters of refineDelaunay().
struct RefinementParams
{
  /// Degrees. Triangles of a region whose smallest angle is below this are refined. Range
  /// [0, kLargestMinimumAngle]; 0 = no refinement (the mesh is still flipped to constrained
  /// Delaunay).
  double minimumAngle = 30.0;
  /// Model units (> 0 finite, or 0 for no floor). A bad triangle whose shortest edge is
  /// shorter than half this is left as it is, and a region boundary edge shorter than this is
  /// not split: the floor that ends the refinement where the input itself is finer (curves
  /// closer than this, small input angles). Within this of a region boundary edge shorter
  /// than 0.4 of it between two stop points (stopPoint: two junctions close together), the
  /// floor is half that edge instead (and at least a twentieth of this).
  double minimumEdgeLength = 0.0;
  /// Model units (> 0 finite, or 0 for none). A region edge longer than this is split: in
  /// its middle, or, for a region boundary edge, at the point the BoundarySplitter gives (on
  /// its curve), before the refinement's runs and once more after the last one.
  double maximumEdgeLength = 0.0;
  /// At most this many vertices are inserted per triangle of the input mesh (plus 1000), per
  /// pass. Range [0, 100].
  double insertionBudget = 4.0;
  /// Optional curve recovery, before the refinement (both set, or nothing happens): called with
  /// a triangle's corners (counter-clockwise), curvePoint returns true and a point of a model
  /// curve strictly inside the triangle where a curve runs through it (a layer the mesh lost
  /// between two of its region boundaries); that point is inserted and the triangles around
  /// it take the region regionAt gives at their centroid (a region id, -1 the exterior).
  /// Triangles whose shortest edge is below minimumEdgeLength are not probed. With the
  /// recovery, every triangle is first given the region at its centroid, the refinement runs
  /// twice (the second recovery probes the refined triangles), and region corners sharper
  /// than minimumAngle in small triangles are dissolved (see DelaunayRefinement.cpp).
  std::function<bool(Vec2 a, Vec2 b, Vec2 c, Vec2& at)> curvePoint;
  std::function<int(Vec2 p)> regionAt;
  /// With the curve recovery: whether a point lies on a model curve. A triangle keeps its
  /// region when the new one would give it a region boundary edge with an end off the
  /// curves. Empty: no such check.
  std::function<bool(Vec2 p)> onCurve;
  /// Optional smoothing of the vertices of the triangles still below minimumAngle (both set,
  /// or only free vertices move): curveSlide moves the vertex at `from`, on the curve that
  /// separates regions `left` and `right`, along that curve toward `toward` and returns true
  /// with the point reached in `at`, or returns false when the vertex may not move (a
  /// junction, a feature point, not on such a curve); curveDistance(p, within) is the distance
  /// from p to the nearest model curve when that is below `within`, else any value >= within
  /// (a slid vertex's boundary edges may not leave the curves; the curve recovery's retag
  /// skips triangles farther than their longest edge from every curve, and asks with that
  /// bound, which lets a far query stop early).
  std::function<bool(Vec2 from, Vec2 toward, int left, int right, Vec2& at)> curveSlide;
  std::function<double(Vec2 p, double within)> curveDistance;
  /// Optional, with the curve recovery and curveDistance: the answers of curveDistance and
  /// regionAt for many points at once (the recovery's first retag asks about every triangle's
  /// centroid), so that the caller may give them on two threads. For each i < n: region[i] =
  /// regionAt(p[i]) when curveDistance(p[i], within[i]) < within[i], else kNoCurveNear. Empty: the
  /// refinement asks curveDistance and regionAt one point at a time.
  std::function<void(const Vec2* p, const double* within, std::size_t n, int* region)> regionsNear;
  /// Optional, with the curve recovery: curvePoint for many triangles at once (the recovery's
  /// probes ask about most triangles near the curves), so that the caller may answer on two
  /// threads. For each i < n, with the corners corners[3i], corners[3i + 1], corners[3i + 2]:
  /// found[i] = curvePoint(corners..., at[i]). Empty: one triangle at a time.
  std::function<void(const Vec2* corners, std::size_t n, char* found, Vec2* at)> curvePoints;
  /// Optional, with the curve recovery: whether the model has a corner of region `region`
  /// sharper than about minimumAngle within `radius` of p. Where it has none, a sharp corner
  /// of a region's triangle between two triangles of one other region (or the outer border)
  /// is a spike of the mesh, not of the model (a peninsula's tip or a lens's end whose
  /// vertices do not reach its apex): 2c leaves it to the refinement instead of giving the
  /// triangle away. Empty: every such corner may be given away.
  std::function<bool(int region, Vec2 p, double radius)> sharpModelCorner;
  /// Optional curve fidelity, after the curve recovery's insertions (the mesher sets it with
  /// the recovery): for a region boundary edge from a to b (region `left` on its left,
  /// `right` on its right, -1 the outer border), returns true with the area between the edge
  /// and the stretch of the curve it stands for in `area` (model units squared; parts on both
  /// sides add up) and the point of that stretch farthest from the edge in `at`, or false
  /// when the edge does not stand for a curve between those regions. An edge at least
  /// minimumEdgeLength long that cuts off more than 0.05% of the smaller of its regions'
  /// (mesh) areas is split at `at` when both halves are at least half minimumEdgeLength long
  /// (the halves are checked in turn): small regions (islands, small countries) keep their
  /// area.
  std::function<bool(Vec2 a, Vec2 b, int left, int right, double& area, Vec2& at)> curveDeviation;
  /// With curveDeviation: a region whose boundary edges cut off more than this fraction of its
  /// area in all (each under the per-edge bound, a thin bending layer) also has each of its
  /// edges split that cuts off more than an even share of it (the fraction of its area over
  /// its number of boundary edges). 0 = off (the default); the mesher sets 0.25% with the
  /// automatic levels. Range [0, 1].
  double curveAreaBudget = 0.0;
  /// Optional, with curveDeviation: whether p, a point curveDeviation gave, is a corner of the
  /// model's curves (the mesher: sharper than the compression's FeatureAngle, not sharper than
  /// minimumAngle). A region boundary edge at least minimumEdgeLength long whose stretch's
  /// farthest point is such a corner, with no other corner on either side of it (each side's
  /// stretch within 5% of its length from straight), gets a vertex on it whatever the area it
  /// cuts off: split there when the corner lies more than a quarter of the edge's length from
  /// it (with the halves' bound above), else, or when the split is refused, the edge's nearer
  /// end slid onto it along its curve (with curveSlide, onCurve and curveDistance). The
  /// collapses of short edges keep such a corner's vertex. For chords the compression left
  /// across a corner of a section's box or a kink of a horizon. Empty: none of this.
  std::function<bool(Vec2 p)> modelCorner;
  /// Optional: whether p is a point of the model where a mesh vertex stays (a junction of
  /// three or more regions, a curve's end, a corner sharper than FeatureAngle). The local
  /// floors of step 3 are only beside short region boundary edges between two such points.
  /// Empty: beside every short region boundary edge.
  std::function<bool(Vec2 p)> stopPoint;
  /// Optional corners kept to their apex (with regionAt and onCurve; see DelaunayRefinement.cpp,
  /// step 7): in the last pass, before its refinement runs, the wedge of each between its apex
  /// and the nearest vertices of its region on its two sides is rebuilt as rungs of its region
  /// (vertices at equal distances from the apex on both sides, the sides made mesh edges). The
  /// wedge's triangles are not refined (their small angles are the input's); those below
  /// minimumAngle are counted in RefinementResult::keptCornerTriangles. A corner whose region
  /// has no vertex on one of its sides, or whose rebuilt wedge fails a check of step 7 (a
  /// boundary edge off the curves, a side that is not a region boundary, a nearly flat
  /// triangle, a wedge angle below a quarter of the corner's or above 150 degrees), is left as
  /// the refinement made it (not counted in RefinementResult::keptCorners).
  std::vector<SharpCorner> keptCorners;
  /// Optional corners whose wedge the last pass brings back (with regionAt and onCurve; see
  /// DelaunayRefinement.cpp, step 7'), before the kept corners:
  /// - a wedge of the exterior (region -1) sharper than minimumAngle (a coast's narrow inlet)
  ///   whose exterior triangles end before it is one minimumEdgeLength wide is made exterior
  ///   from there (vertices on its sides, the sides and the cut between them mesh edges; the
  ///   cut slanted: on one side a minimumEdgeLength nearer the apex than on the other); the
  ///   tip beyond the cut stays with the region around;
  /// - a spit of a region sharper than minimumAngle, with the exterior on both sides, whose
  ///   region's triangles end before it is one minimumEdgeLength wide is extended to there
  ///   (the same way; the tip beyond the cut stays exterior);
  /// - a region corner of at least minimumAngle whose tip the mesh lost (its region's
  ///   triangles end farther from the apex than where it is one minimumEdgeLength wide) is
  ///   rebuilt to its apex as rungs of its region (as a kept corner, but refined after).
  /// The refinement runs then mend the triangles beside them. The exterior's wedges of
  /// minimumAngle or more are ignored.
  std::vector<SharpCorner> wedgeCorners;
  /// Of wedgeCorners, how many have their lists of nearby triangles held at once (>= 1): each
  /// such chunk sweeps the mesh once for its lists, which on long zigzag curves hold thousands
  /// of triangles per corner. Memory against sweeps only: the mesh does not depend on it.
  std::size_t wedgeChunk = 4096;
  /// Model units (>= 0): how far from the curves a point that onCurve accepts may lie; a
  /// vertex within four times this (or 1e-7 of a kept corner's side length) of a side is on it.
  double curveTolerance = 0.0;
};

/// Throws ParameterError naming the parameter and its range.
void validate(const RefinementParams& params);

/// A region-tagged triangle mesh, refined in place. Triangles are counter-clockwise; an edge
/// belongs to at most two triangles. An edge between triangles of different regions, or with
/// one triangle, is a region boundary edge: it is never flipped, only split (on its curve).
/// Triangles of region < 0 (the exterior) are never refined, and triangles without positive
/// area are never touched (their edges count as boundary edges).
struct RegionMesh
{
  LargeVector<Vec2> points;
  LargeVector<std::array<int, 3>> triangles;
  LargeVector<int> region; ///< per triangle
  LargeVector<int> level;  ///< per triangle (any tag, e.g. the grid level); pieces inherit it
};

/// Where a region boundary edge from a to b (region `left` on its left, `right` on its right,
/// -1 the exterior or no triangle: the mesh's outer border) is split: sets `at` (normally the point
/// of the curve the edge stands for nearest to its middle) and returns true, or returns false to
/// keep the edge whole.
using BoundarySplitter = std::function<bool(Vec2 a, Vec2 b, int left, int right, Vec2& at)>;

struct RefinementResult
{
  std::size_t delaunayFlips = 0;    ///< edge flips (to constrained Delaunay, and after insertions)
  std::size_t interiorVertices = 0; ///< vertices inserted inside a region (off-centres)
  std::size_t boundaryVertices = 0; ///< vertices inserted on region boundary edges (splits)
  /// Region triangles still below minimumAngle at the end, and of those the ones whose
  /// smallest angle lies between two region boundary edges (a corner of the region, which no
  /// insertion can widen).
  std::size_t badTrianglesLeft = 0;
  std::size_t badTrianglesAtCorners = 0;
  bool budgetReached = false;     ///< insertionBudget stopped the refinement
  std::size_t curveVertices = 0;  ///< vertices inserted on curves by the curve recovery (2b, 2b')
  std::size_t fidelitySplits = 0; ///< of those, boundary edges split where their curve strays (2b')
  std::size_t smoothingMoves = 0; ///< vertex moves of the smoothing after the refinement
  std::size_t dissolvedCorners = 0; ///< triangles given a neighbour's region (sharp corners)
  std::size_t collapsedEdges = 0;   ///< short edges collapsed (their vertex merged into the other)
  std::size_t sizeVertices = 0;     ///< vertices splitting edges longer than maximumEdgeLength
  std::size_t keptCorners = 0;      ///< RefinementParams::keptCorners meshed to their apex
  std::size_t extendedWedges = 0;   ///< RefinementParams::wedgeCorners brought back (step 7')
  /// The smallest angle of the region triangles outside the kept corners' wedges after the
  /// last pass, degrees.
  double minimumAngle = 180.0;
  std::vector<Vec2> badCentroids; ///< the centroids of the badTrianglesLeft
  /// Triangles of the kept corners' wedges (see keptCornerOutline) below minimumAngle (left as
  /// the input forces them; not in badTrianglesLeft).
  std::size_t keptCornerTriangles = 0;
  /// Per entry of RefinementParams::keptCorners: the radius around its apex that its wedge
  /// reaches (0 when it was not kept), and the wedge's outline (apex, first side, second side
  /// back; empty when not kept): its region's triangles within the radius whose centroid lies
  /// inside the outline form the wedge.
  std::vector<double> keptCornerRadius;
  std::vector<std::vector<Vec2>> keptCornerOutline;
};

/// The triangles around each point of a triangle list: those around point v are
/// items[start[v]] .. items[start[v + 1] - 1], in increasing order. Point ids must lie in
/// [0, numberOfPoints). With `only` (numberOfPoints flags), the stars of the flagged points
/// alone (the others empty). With `tick` (a progress report, which may throw), it is called
/// every kStarsTick triangles of each of the two passes over them: at 2 M triangles the
/// stars' first writes take 0.1-0.3 s.
struct PointStars
{
  LargeVector<int> start; ///< numberOfPoints + 1 offsets
  LargeVector<int> items; ///< triangle ids
};
constexpr std::size_t kStarsTick = std::size_t(1) << 16;
PointStars pointStars(std::size_t numberOfPoints,
  const LargeVector<std::array<int, 3>>& triangles,
  const std::vector<char>* only = nullptr,
  const std::function<void()>& tick = {});

/// Answers of RefinementParams::regionsNear a caller already has for the centroids of a mesh's
/// triangles, each asked with its centroid and its longest edge as `within` (as the curve
/// recovery asks). A triangle of the mesh given to refineDelaunay() whose corners lie where
/// those of the known triangle of the same index lay, in the same order, takes that answer
/// instead of asking again (the mesher asks about every triangle just before the refinement,
/// for its snaps: 0.05 s saved at 1 M).
struct KnownCentroidRegions
{
  LargeVector<std::array<int, 3>> triangles; ///< the mesh asked about ...
  LargeVector<Vec2> points;
  LargeVector<int> region; ///< ... and the answer for each of its triangles
};

/// Ruppert / Ungor refinement restricted to the regions (see DelaunayRefinement.cpp): flips
/// the mesh to constrained Delaunay, then inserts the off-centre of every bad triangle, or,
/// when that point would encroach a region boundary edge (lie inside its diametral circle or
/// beyond it), splits that edge at the point `splitter` gives. Of a cautious run (no insertion
/// lowers a local smallest angle) and up to three bolder ones, the result with the largest
/// smallest angle (then the fewest triangles below minimumAngle) is kept: never below the
/// input mesh's (after the flips); then the vertices of the triangles still below the bound
/// are smoothed. The result's counts are those of the run kept (delaunayFlips included). Throws
/// ParameterError for parameters out of range or a mesh that breaks the preconditions of RegionMesh
/// (sizes, point ids, an edge in three triangles), Aborted when the progress callback asks to stop.
///
/// `known`, optional: the answers of params.regionsNear the caller already has (see
/// KnownCentroidRegions), taken by the first curve recovery: its arrays are moved from (no
/// copy of them at the run's peak). Throws ParameterError when its sizes differ or a known
/// triangle refers to a point it does not have.
RefinementResult refineDelaunay(RegionMesh& mesh,
  const BoundarySplitter& splitter,
  const RefinementParams& params = {},
  const ProgressReporter& progress = ProgressReporter(),
  KnownCentroidRegions* known = nullptr);

/// Step 6 of refineDelaunay() on its own (see DelaunayRefinement.cpp): the shortest edge uv of
/// a region triangle below minimumAngle, when shorter than half minimumEdgeLength (too short
/// for the refinement), is collapsed, v merged into u, when v is free or may slide on its
/// curve (curveSlide), u lies on the curves (onCurve), and the smallest angle around them
/// rises without an inverted triangle, a new junction or a boundary edge off the curves.
/// Returns the collapses; the vertices merged away stay in `points`, referenced by no
/// triangle. Does nothing (returns 0) without onCurve, curveSlide and curveDistance, or with
/// minimumAngle or minimumEdgeLength 0.
std::size_t collapseShortEdges(RegionMesh& mesh, const RefinementParams& params);

} // namespace strata

#endif
