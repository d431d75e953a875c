// StrataMesh core: the whole triangulation pipeline (Model -> DistanceField -> Grid48 ->
// Classification -> Compression -> faces, quality, approximated boundary). No VTK.
#ifndef StrataMeshCore_Mesher_h
#define StrataMeshCore_Mesher_h

#include "Classification.h"
#include "Compression.h"
#include "DelaunayRefinement.h"
#include "Geometry.h"
#include "Grid48.h"
#include "Model.h"
#include "Progress.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace strata
{

/// Parameters of every stage (each documented with its unit).
struct MesherParams
{
  ModelParams model;
  Grid48Params grid;
  ClassificationParams classification;
  CompressionParams compression;
  /// Delaunay refinement toward refinement.minimumAngle, run after the compression when
  /// compression.optimize is on. refinement.minimumEdgeLength 0 (default) means
  /// grid.minEdgeLength when that is set, else the grid's finest leg (the hypotenuse at
  /// Grid48Params::junctionMaxLevel over sqrt(2)). Above 30 degrees (with the optimization), a
  /// mesh that misses a bound of the meshes refined toward 30 (its smallest angle 30 degrees
  /// where no input or kept corner forces it, the regions' areas within 0.5%, with the automatic
  /// sizes the regions whole and the boundary within half a local edge, the boundary vertices on
  /// the curves) is made again with the refinement toward 30 degrees, and that one is kept when it
  /// misses fewer of them, or as many with a larger smallest angle (up to 30) or as large a one
  /// with a smaller area error; a warning says which. The triangles below refinement.minimumAngle
  /// are counted against it in either.
  RefinementParams refinement;
  /// Beyond the paper, with the refinement: curve recovery first (RefinementParams::curvePoint
  /// and regionAt, from the model's curves and distance field): every triangle takes the
  /// region of its centroid, and where an input curve runs through a triangle, a point of it
  /// is inserted and the triangles around take the region of their centroid; that brings back
  /// layers and islands the compression lost and pulls the boundary onto the curves. Off-curve
  /// vertices that keep a triangle from its region are snapped onto their curve first; the
  /// refinement then runs twice and dissolves the spikes where a recovered layer ends
  /// (DelaunayRefinement.cpp). A region boundary edge that cuts off more than 0.05% of the
  /// smaller of its regions' areas from its curve is split at the curve point farthest from it
  /// (small countries and islands keep their area). A mesh with a triangle below
  /// refinement.minimumAngle or a region's area off by more than 0.05% is refined once more from
  /// the compressed mesh with half the recovery margin (thinner layers, smaller regions), and the
  /// better is kept: the larger smallest angle (up to minimumAngle), then the smaller area error
  /// (a retry that halves an area error above 0.5% is kept if its smallest angle is at most 5
  /// degrees below minimumAngle).
  /// Region areas within 0.5% on every bundled model (README, Measured). Default on; off gives the
  /// compressed mesh's regions, only refined.
  bool curveRecovery = true;
  /// Beyond the paper, with the refinement and curveRecovery: keep the model's region corners
  /// sharper than refinement.minimumAngle to their apex (pinch-outs, sharp junctions) where a
  /// mesh vertex sits exactly (every junction; other corners when sharper than
  /// compression.featureAngle). Each such region's wedge, from its apex to where the refined
  /// mesh has the region on both sides, is given to the region with its two sides as mesh
  /// edges; its triangles keep the input's small angles (MesherResult::keptCorners,
  /// Summary::keptCornerTriangles). Default off: such corners end where the layer is about one
  /// finest edge thick, and every triangle meets minimumAngle.
  bool keepSharpCorners = false;
  /// Beyond the paper, with compression.optimize: when the mesh's smallest angle is below
  /// min(refinement.minimumAngle, 30) by more than 0.05 degrees (not checked with
  /// keepSharpCorners), or a region's area is off by more than 0.5% (Summary::maxRegionAreaError,
  /// or its misplaced area: Summary::maxRegionMisplacedArea, lost plus added, which a loss at
  /// one place and a gain at another do not cancel; the comparisons below are of the net area
  /// error), or a vertex of the approximated boundary lies off the curves
  /// (Summary::maxBoundaryVertexDistance above 1e-9 of the model's size), it is made again with
  /// grid.thinLayerRefinement (layers thinner than the cells get cells as wide as they are)
  /// and the better of the two is kept: the larger smallest angle (up to that bound), then the
  /// smaller area error (Summary::thinLayerMesh, a warning). With no level set (maxLevel and
  /// localMaxLevel automatic; sizes in model units allowed), a mesh whose
  /// Summary::maxRelativeDeviation is above 0.5 (a piece of a region at least a finest edge
  /// wide lost to its neighbour) is made again with the thin layer refinement around
  /// MesherResult::boundaryMisses (grid.thinLayerZones) and, when that one still misses,
  /// everywhere; the one with the smallest deviation is kept as long as its smallest angle
  /// (up to that bound), its area error (beyond 0.5%) and its regions cut are not worse. Of
  /// two meshes, the one that misses fewer of the hard bounds (hardMisses() in Mesher.cpp; with
  /// the automatic sizes, since 2026-12-07, a boundary more than one local edge off too) is
  /// kept first, here and in the finer levels below. Meshes that meet the bounds
  /// are made once, as without it. With grid.thinLayerRefinement on, its mesh is the first one and
  /// the mesh without it the second, whatever this says. Then, with the automatic levels
  /// (grid.localMaxLevel -1, no grid.minEdgeLength or targetEdgeLength), curveRecovery, a
  /// minimumAngle of 25 or more: a mesh whose triangles that no input corner forces
  /// (Summary::minAngleUnforced) are still below 25 degrees (layers about a finest edge thick;
  /// a triangle at a sharp input corner does not hide them since 2026-12-07), or with a
  /// region's area still off by more than 0.5%, or (with grid.maxLevel automatic too) with a
  /// region cut into more pieces than the model has or left with fewer
  /// (MesherResult::brokenRegions) or its Summary::maxRelativeDeviation still above 0.5, or
  /// triangles still below min(refinement.minimumAngle, 30) (by more than 0.05 degrees), is
  /// made again with grid.localMaxLevel 4 levels finer than the automatic one, and kept when
  /// its smallest angle is larger, or when it mends the area, the pieces or the deviation
  /// without a smaller smallest angle (up to 30 degrees) (a warning gives both;
  /// Summary::localMaxLevel); while the mesh kept still misses any of these (that last one
  /// too), the finer one kept or not (since 2026-12-07's sixty-third session; toward
  /// refinement.minimumAngle 30 or less), the mesh is made once more 2 levels finer again,
  /// kept by the same rule, and when that third one is kept and still cuts a region, or the
  /// one kept is still more than one local edge off (Summary::maxRelativeDeviation above 1;
  /// toward 30 degrees or less), 2 levels finer once more. A finer mesh not kept that cuts a
  /// region as the kept one does (a neck narrower than both meshes' triangles) leads to the
  /// next of these steps too, compared with the kept one. These smallest angles are
  /// Summary::minAngleUnforced: off the input's sharp corners and, with keepSharpCorners, off the
  /// kept corners (the wedges keep the input's). Default on.
  bool thinLayerRetry = true;
};

/// The triangulation of a model, everything in local coordinates (add `origin`).
struct MesherResult
{
  Vec2 origin;                               ///< add to local coordinates for input ones
  LargeVector<Vec2> points;                  ///< local; only points used by triangles
  LargeVector<std::array<int, 3>> triangles; ///< counter-clockwise, exterior triangles dropped
  LargeVector<int> regionId;                 ///< per triangle: region id (>= 0)
  LargeVector<int> level;                    ///< per triangle: grid level
  LargeVector<double> minAngle, maxAngle;    ///< per triangle, degrees
  LargeVector<double> radiusRatio;           ///< per triangle, 2 r / R (1 equilateral)
  LargeVector<double> area;                  ///< per triangle, model units^2 (> 0)
  LargeVector<std::int8_t> vertexClass;      ///< per point: 0 exterior, 1 boundary, 2 interior
  LargeVector<Vec2> displacement; ///< per point: final minus grid position (0 if inserted)

  /// A piece of the approximated boundary (edges whose two faces have different regions, and
  /// the outer border of the kept triangles) in the Shared curves form: `left` lies to the
  /// left walking along `points`, `right` to the right (-1 exterior). Pieces are chained
  /// between mesh vertices where the boundary branches or the pair of regions changes;
  /// closed pieces repeat their first point at the end.
  struct BoundaryCurve
  {
    std::vector<Vec2> points; ///< local coordinates
    int left = -1;
    int right = -1;
  };
  std::vector<BoundaryCurve> boundary;

  /// Area of a region in the model (from its rings) and in the mesh, and its misplaced area:
  /// what its triangles cover that the model gives another region or the exterior, plus what of
  /// its model area other triangles cover (the symmetric difference of the two, which the
  /// independent checker measures; the net difference mesh - model may hide it, a loss in one
  /// place making up for a gain in another). model units^2. The misplaced area is estimated
  /// from the approximated boundary, as the largest of three lower bounds: the pieces between
  /// each boundary edge with both ends on a curve of its two regions and the stretch of the
  /// curve it stands for, plus what these leave unexplained of the net difference (a layer's
  /// tip cut off by an edge across it, a piece lost whole); the net differences in slabs across
  /// x, and across y, about two finest edges wide, added up without their signs.
  struct RegionArea
  {
    int id = -1;
    double model = 0.0;
    double mesh = 0.0;
    double misplaced = 0.0;
  };
  std::vector<RegionArea> regionAreas;
  /// Ids of the regions whose triangles cover less than half of their model area (regions
  /// thinner or smaller than the finest triangles); each is also named in `warnings`.
  std::vector<int> unresolvedRegions;
  /// Ids of the regions the mesh cuts into more pieces than the model has, or leaves with
  /// fewer than it has apart (pieces of at least 4 median boundary edge lengths squared counted
  /// on both sides, as the independent checker counts them; mesh pieces joined across edges;
  /// model pieces touching at a node count as one for `fewer`): a layer broken where it is
  /// thinner than the finest triangles, or a piece lost (its tip cut off and the rest below
  /// that floor). Each is also named in `warnings`, with both counts.
  std::vector<int> brokenRegions;
  /// The corners MesherParams::keepSharpCorners kept: the region `region`'s corner of `angle`
  /// degrees at `apex` (local); its wedge reaches `radius` from the apex, and its triangles are
  /// the region's within that radius whose centroid lies inside `outline` (apex, first side,
  /// second side back; local).
  struct KeptCorner
  {
    Vec2 apex;
    int region = -1;
    double angle = 0.0;
    double radius = 0.0;
    std::vector<Vec2> outline;
  };
  std::vector<KeptCorner> keptCorners;
  /// Where the approximated boundary lies more than half the local edge off the input curves
  /// (the samples of Summary::maxRelativeDeviation above 0.5, a few local edges apart; local
  /// coordinates), with the local edge there: MesherParams::thinLayerRetry refines the grid's
  /// thin layers around them.
  struct BoundaryMiss
  {
    Vec2 at;
    double edge = 0.0;
  };
  std::vector<BoundaryMiss> boundaryMisses;

  struct Summary
  {
    std::size_t triangles = 0, vertices = 0;
    double minAngle = 0.0, maxAngle = 0.0; ///< degrees
    double percentAngles30to60 = 0.0;      ///< percent of all angles in [30, 60]
    double percentTriangles30to60 = 0.0;   ///< percent of triangles, smallest angle in [30, 60]
    /// Largest distance (model units) between the approximated boundary and the input curves,
    /// both ways (Hausdorff; the boundary sampled every eighth of an edge, the curves at five
    /// points per segment at least).
    double maxBoundaryDeviation = 0.0;
    /// The largest of the deviations above, each divided by the local edge there (the mean
    /// edge length of the triangles beside the approximated boundary's nearest edge), the
    /// input curves sampled every quarter finest edge and the approximated boundary every
    /// eighth of an edge (and, where a deviation above 0.5 may lie between two samples,
    /// between them down to 0.001 local edges, and, since 2026-12-07's sixty-third session, on
    /// past a point above 0.5 wherever a point between may be above 1, issue 4's bound: the
    /// figure tells exactly on which side of 0.5 and of 1 the boundary lies; within those
    /// ranges it is the largest of the points measured, which a peak between them may
    /// exceed up to the range's end), leaving out the
    /// curve points beside a region narrower than finestEdgeLength (issue 5's exemption:
    /// another curve within it along the curve's normal, or the disc of that diameter
    /// touching the point, shrunk by 10%, cut by a curve) and the points of the approximated
    /// boundary whose nearest curve point is beside such a region; 0 when there is none.
    /// Above 0.5 (issue 5's bound is half the local edge) a piece of a region that the finest
    /// edges could represent is lost to its neighbour (or one is added).
    double maxRelativeDeviation = 0.0;
    /// The local edge (model units) where maxRelativeDeviation is reached (0 when it is 0).
    double relativeDeviationEdge = 0.0;
    /// Largest distance (model units) of a vertex of the approximated boundary from the input
    /// curves (0 up to rounding when every boundary vertex was placed on a curve).
    double maxBoundaryVertexDistance = 0.0;
    /// Largest |mesh area - model area| / model area over the regions.
    double maxRegionAreaError = 0.0;
    /// Largest misplaced area (RegionArea::misplaced) / model area over the regions: at least
    /// maxRegionAreaError. MesherParams::thinLayerRetry makes a mesh again when either is above
    /// issue 5's 0.5%.
    double maxRegionMisplacedArea = 0.0;
    /// The finest edge length the mesh aims at (model units): the refinement's
    /// minimumEdgeLength when set, else grid.minEdgeLength (the user's MinimumEdgeLength), else
    /// the grid's finest leg at its junction level. Regions narrower than this cannot be
    /// represented: there the boundary may lie farther than half an edge from its curve.
    double finestEdgeLength = 0.0;
    /// The grid's LocalMaxLevel the mesh was made with (grid.localMaxLevel, or its automatic
    /// value; MesherParams::thinLayerRetry may have raised it).
    int localMaxLevel = 0;
    int iterations = 0; ///< simulation steps
    /// Edges of the approximated boundary split onto their curve by the boundary refinement.
    std::size_t boundarySplits = 0;
    /// Vertices inserted by the Delaunay refinement (inside regions and on boundary edges).
    std::size_t refinementVertices = 0;
    /// Vertices the curve recovery inserted on input curves (MesherParams::curveRecovery).
    std::size_t curveVertices = 0;
    /// Triangles with a smallest angle below 25 degrees at a model corner sharper than 25
    /// degrees (a region's angle there): the input forces them, they are kept, not mended.
    std::size_t trianglesAtSharpCorners = 0;
    /// With the optimization (compression.optimize): the triangles whose smallest angle is
    /// below refinement.minimumAngle by more than 0.05 degrees, not counting those of
    /// trianglesAtSharpCorners and keptCornerTriangles (which the input or the user's choice
    /// forces): where the mesh missed the bound, mostly in layers about a finest edge thick. A
    /// warning names the worst one's angle, region and place. 0 without the optimization.
    std::size_t trianglesBelowMinimumAngle = 0;
    /// With MesherParams::keepSharpCorners: the model's corners it applies to (kept or not;
    /// MesherResult::keptCorners lists those kept, a warning names the others).
    std::size_t sharpCorners = 0;
    /// With MesherParams::keepSharpCorners: the triangles below refinement.minimumAngle with a
    /// vertex within a kept corner's radius (its wedge's, and those beside it the refinement
    /// could not mend): what keeping the corners costs. Some also count in
    /// trianglesAtSharpCorners.
    std::size_t keptCornerTriangles = 0;
    /// The smallest angle (degrees; 180 without any) of the triangles neither
    /// trianglesAtSharpCorners nor keptCornerTriangles count: what the mesh reached where
    /// neither the input nor the kept corners force it (thinLayerRetry's finer level judges
    /// meshes with kept corners by it).
    double minAngleUnforced = 180.0;
    /// Whether the mesh was made with the grid's thin layer refinement: grid.thinLayerRefinement
    /// and its mesh kept, or thinLayerRetry's second mesh kept (a warning then gives both
    /// meshes' figures, and secondsPerStage starts with the discarded run's "discarded run"; the
    /// finer level's retry puts "discarded level run" before it).
    bool thinLayerMesh = false;
    /// Wall-clock seconds of each stage, in order (a mesh made again refined toward 30
    /// degrees, MinimumAngle being above, puts "discarded angle run" first).
    std::vector<std::pair<std::string, double>> secondsPerStage;
    double totalSeconds = 0.0;
  } summary;

  std::vector<std::string> warnings;
};

/// Triangulates a model given as raw polylines (either form of Data/FORMAT.md). Throws
/// InputError for a malformed model, ParameterError for parameters out of range, Aborted when
/// the progress callback returns false (progress is reported per stage and at least every
/// simulation step, so an abort is honoured within a few milliseconds on large meshes).
MesherResult triangulate(const RawPolylines& input,
  const MesherParams& params = {},
  const ProgressCallback& progress = {});

/// What triangulate() does with a MinimumAngle above 30 degrees (MesherParams::refinement):
/// how many of the bounds of the meshes at 30 degrees mesh r misses. They are its smallest angle
/// at 30 degrees (by 0.05) where no input or kept corner forces it (Summary::minAngleUnforced),
/// every region's area within 0.5%, every vertex of the approximated boundary within `offCurve`
/// of the curves and, with the `automatic` sizes, every region whole (no brokenRegions or
/// unresolvedRegions) and the boundary within half a local edge (maxRelativeDeviation).
int boundsMissedAtThirty(const MesherResult& r, bool automatic, double offCurve);

/// Whether triangulate() keeps `towardThirty`, the mesh made again with the refinement toward
/// 30 degrees, over `asked`, the one toward a MinimumAngle above 30 that missed a bound
/// (boundsMissedAtThirty): when it misses fewer, or as many with a larger smallest angle (up to
/// 30, by more than 0.05 degrees), or as large a one with a smaller area error.
bool keepsTheMeshTowardThirty(const MesherResult& asked,
  const MesherResult& towardThirty,
  bool automatic,
  double offCurve);

/// The approximated boundary of a region-tagged triangle mesh (see MesherResult::boundary):
/// triangles with region -1 count as absent. With `vertices`, also the ids of each curve's
/// points. With `stop`, returns early (what it has, to be dropped) once *stop is true (a caller
/// aborted while this ran on another thread).
std::vector<MesherResult::BoundaryCurve> approximatedBoundary(const LargeVector<Vec2>& points,
  const LargeVector<std::array<int, 3>>& triangles,
  const LargeVector<int>& region,
  std::vector<std::vector<int>>* vertices = nullptr,
  const std::atomic<bool>* stop = nullptr);

} // namespace strata

#endif
