/**
 * @class   vtkPhysicalCompressionTriangulator
 * @brief   triangulates a multi-region polyline model by physical compression of a 4-8 grid
 *
 * StrataMesh's main filter, after Marroquim, Cavalcanti, Velho and Esperança,
 * "Multi-Resolution Triangulations with Adaptation to the Domain Based on Physical
 * Compression": an adaptive 4-8 grid refined toward the model's boundaries (Sections 2, 2.1)
 * is classified with a strip-tree signed distance (Sections 3-5), then compressed onto the
 * boundaries by a mass-spring particle system (Section 6): vertices next to a boundary are
 * pushed onto it, slide along it as on rails, stop at sharp points, one vertex sits on every
 * junction, degenerate triangles get their longest edge flipped, and every triangle is tagged
 * with the region of its barycentre. An optional pass beyond the paper (Optimization) then
 * refines the boundary onto the curves, flips edges, smooths, merges squeezed vertices and
 * splits bad triangles toward larger angles, and ends with a constrained Delaunay refinement
 * (Ruppert 1995, with Ungor's off-centres) toward MinimumAngle whose new boundary vertices lie
 * on the input curves.
 *
 * Input: a vtkPolyData of line cells in either StrataMesh form (Loops with `RegionId`, or
 * Shared curves with `LeftRegion`/`RightRegion`).
 *
 * Output port 0: a vtkUnstructuredGrid of counter-clockwise triangles (exterior dropped)
 * with cell arrays `RegionId`, `MinimumAngle`, `MaximumAngle` (degrees), `RadiusRatio`
 * (2 r / R, 1 for equilateral), `Area`, `Level` (4-8 level of origin); point arrays
 * `VertexClass` (0 exterior, 1 boundary, 2 interior) and `Displacement` (from the grid
 * position); field data `NumberOfTriangles`, `NumberOfVertices`, `MinimumAngle`,
 * `MaximumAngle`, `PercentAngles30To60` (of all angles), `PercentTriangles30To60` (of
 * triangles whose smallest angle lies in [30, 60]), `MaxBoundaryDeviation` (model units),
 * `MaxRelativeBoundaryDeviation` (the largest deviation in local edge lengths, outside
 * regions narrower than the finest edge: above 0.5, a piece of a region is lost or added),
 * `MaxBoundaryVertexDistance` (model units: the farthest vertex of output port 1 from the
 * input curves; above 1e-9 of the model's size a warning says where it is),
 * `MaxRegionAreaError` (relative: the largest |mesh area - model area| over a region's model
 * area), `MaxRegionMisplacedArea` (relative: the largest misplaced area, lost plus added,
 * over a region's model area; the symmetric difference of the region's triangles and its
 * model region, which a loss at one place and a gain at another do not cancel; at least
 * `MaxRegionAreaError`; ThinLayerRetry makes a mesh again when either is above 0.5%),
 * `FinestEdgeLength` (model units: MinimumEdgeLength when set, else the automatic finest edge),
 * `Iterations`, `BoundarySplits`, `RefinementVertices` (vertices the Delaunay refinement inserted),
 * `CurveVertices` (the curve recovery's), `RegionIds`, `RegionModelArea`, `RegionMeshArea` and
 * `RegionMisplacedArea` (one tuple per region of the model, in its order: the region's id, its
 * area in the model and in the mesh and its misplaced area, lost plus added, model units
 * squared), `UnresolvedRegions` (ids of the regions keeping less than
 * half their area, also named in a warning), `BrokenRegions` (ids of the regions the mesh cuts into
 * more pieces than the model has, where a layer is thinner than the finest triangles, or leaves
 * with fewer; also named in a warning), `TrianglesAtSharpCorners` (triangles below 25 degrees at an
 * input corner sharper than that), `TrianglesBelowMinimumAngle` (with Optimization: triangles below
 * MinimumAngle by more than 0.05 degrees that neither an input corner nor a kept one forces; a
 * warning names the worst one's angle, region and place), `MinimumAngleUnforced` (degrees: the
 * smallest angle of the other triangles, neither an input corner nor a kept one forcing them; 180
 * without any), `LocalMaxLevel` (the level the mesh was made with), with KeepSharpCorners
 * `KeptCorners` and `KeptCornerTriangles`, `ThinLayerMesh` (1 when the mesh was made with the
 * grid's thin layer refinement: ThinLayerRefinement on, or ThinLayerRetry's second mesh kept; when
 * a second mesh was made, `SecondsDiscardedRun` times the one not kept), and `Seconds<Stage>` per
 * stage. `Displacement` is 0 at vertices the optimization inserted.
 *
 * Output port 1: the approximated boundary (edges whose two triangles have different
 * regions, and the outer border) as polylines in the Shared curves form, with cell arrays
 * `LeftRegion` and `RightRegion`, so it can be fed back in as a model.
 *
 * Every numeric property has a documented range. The setters keep the value given (no
 * clamping); an update with a value out of range fails with an error naming the property,
 * its value and the range (e.g. `SpringStiffness = 0 is out of range (0, 1000]`) and leaves
 * the outputs empty.
 *
 * @sa vtkAdaptive48Grid vtkClassify48Grid vtkPolylineSignedDistanceFilter
 */
#ifndef vtkPhysicalCompressionTriangulator_h
#define vtkPhysicalCompressionTriangulator_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkStrataMeshAlgorithm.h"

class vtkUnstructuredGrid;

class STRATAMESHFILTERS_EXPORT vtkPhysicalCompressionTriangulator : public vtkStrataMeshAlgorithm
{
public:
  static vtkPhysicalCompressionTriangulator* New();
  vtkTypeMacro(vtkPhysicalCompressionTriangulator, vtkStrataMeshAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Spring configurations (paper Section 6.1).
  enum SpringConfigurations
  {
    EDGE_SPRINGS = 0,
    EDGE_AND_PROJECTION_SPRINGS = 1
  };

  /// Which vertices are pushed onto the boundary (paper Section 6.3).
  enum PushCriteria
  {
    PUSH_ALL_CANDIDATES = 0,
    PUSH_ONE_SIDE = 1,
    PUSH_CLOSEST = 2
  };

  ///@{
  /**
   * The triangle mesh (output port 0). These hide vtkPolyDataAlgorithm::GetOutput, whose
   * type is not this filter's output type: through a vtkPolyDataAlgorithm pointer,
   * GetOutput() is null; use GetOutputDataObject(0). GetOutput(1) is null too (port 1 is
   * polydata: GetBoundaryOutput()).
   */
  vtkUnstructuredGrid* GetOutput();
  vtkUnstructuredGrid* GetOutput(int port);
  ///@}

  /// The approximated boundary as Shared curves (output port 1).
  vtkPolyData* GetBoundaryOutput();

  ///@{
  /**
   * Springs: one per edge (EDGE_SPRINGS), or per edge plus one projection spring per
   * triangle corner (EDGE_AND_PROJECTION_SPRINGS, default), which keeps triangles from
   * collapsing. Range [0, 1].
   */
  vtkSetMacro(SpringConfiguration, int);
  vtkGetMacro(SpringConfiguration, int);
  ///@}

  ///@{
  /**
   * Spring stiffness ks (dimensionless: forces are relative to edge lengths). Default 1;
   * range (0, 1000].
   */
  vtkSetMacro(SpringStiffness, double);
  vtkGetMacro(SpringStiffness, double);
  ///@}

  ///@{
  /**
   * Damping kd of the edge springs (dimensionless). Default 0.5; range [0, 1000].
   */
  vtkSetMacro(Damping, double);
  vtkGetMacro(Damping, double);
  ///@}

  ///@{
  /**
   * Duration of one simulation step (dimensionless time; an undamped spring's period is
   * about 44 steps with the defaults). Default 0.1; range (0, 1].
   */
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  ///@}

  ///@{
  /**
   * Most simulation steps; the simulation stops earlier when it has settled. Default 600;
   * range [0, 1000000].
   */
  vtkSetMacro(MaxIterations, int);
  vtkGetMacro(MaxIterations, int);
  ///@}

  ///@{
  /**
   * Which end points of the edges crossing a boundary are pushed onto it:
   * PUSH_ALL_CANDIDATES, PUSH_ONE_SIDE (default: the exterior side of an outer boundary,
   * one region's side between two regions) or PUSH_CLOSEST (the end closer to the boundary).
   * Range [0, 2].
   */
  vtkSetMacro(PushCriterion, int);
  vtkGetMacro(PushCriterion, int);
  ///@}

  ///@{
  /**
   * Speed of pushed vertices, in local edge lengths per unit time. Default 0.5; range
   * (0, 10].
   */
  vtkSetMacro(PushVelocity, double);
  vtkGetMacro(PushVelocity, double);
  ///@}

  ///@{
  /**
   * Degrees: a boundary point whose angle (180 = straight) is below this is a feature; a
   * vertex sliding along the boundary stops there (and stays exactly on it); with
   * CurveRecovery, features not sharper than MinimumAngle that a probed triangle holds are
   * inserted (a corner the compression cut). Default 140; range [0, 180] (0: no features).
   */
  vtkSetMacro(FeatureAngle, double);
  vtkGetMacro(FeatureAngle, double);
  ///@}

  ///@{
  /**
   * Flip the longest edge of collapsed or very small triangles (paper Section 6.5). Default
   * on.
   */
  vtkSetMacro(FlipDegenerate, vtkTypeBool);
  vtkGetMacro(FlipDegenerate, vtkTypeBool);
  vtkBooleanMacro(FlipDegenerate, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Beyond the paper: after the compression, refine the boundary (BoundaryTolerance), then
   * flip edges, smooth vertices (boundary ones along their curve), merge squeezed vertices
   * and split the longest edge of bad triangles, toward larger minimum angles, never changing
   * a triangle's region. Default on; off reproduces the paper's method.
   */
  vtkSetMacro(Optimization, vtkTypeBool);
  vtkGetMacro(Optimization, vtkTypeBool);
  vtkBooleanMacro(Optimization, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Beyond the paper, part of the Optimization: an edge of the approximated boundary whose
   * curve lies farther from it than BoundaryTolerance times the edge's length (a corner the
   * compression cut, a bulge between two vertices) is split at the curve's farthest point,
   * when the new triangles keep angles in [15, 140] degrees. The number of splits is in the
   * field data (BoundarySplits). Range [0, 10], dimensionless; default 0.25; 0 = off.
   */
  vtkSetMacro(BoundaryTolerance, double);
  vtkGetMacro(BoundaryTolerance, double);
  ///@}

  ///@{
  /**
   * Beyond the paper, the last step of the Optimization: constrained Delaunay refinement
   * (Ruppert's algorithm with Ungor's off-centres) of every triangle whose smallest angle is
   * below this. The mesh is first flipped to constrained Delaunay (region boundaries are never
   * flipped); then the off-centre of each bad triangle is inserted, or, when it would encroach
   * a region boundary edge, that edge is split at its curve point (new boundary vertices lie on
   * the input curves). Triangles whose shortest edge is below half the grid's finest edge
   * (MinimumEdgeLength when set) are left, boundary edges shorter than it are not split, and
   * insertions never leave the region; the corners of a region sharper than this stay. Of
   * a bold and a cautious run (the latter never lowers any local smallest angle) the one with
   * the larger smallest angle is kept, so the refinement never makes the mesh worse (the curve
   * recovery before it can, where it brings back a layer); then the vertices of the triangles
   * still below this are smoothed (boundary ones slide on their curves). The field data
   * RefinementVertices counts the vertices inserted. Above 30 the bound is reached less
   * often, with several times the triangles; a mesh that then misses a bound of the meshes
   * at 30 (a triangle below 30 degrees that no input corner forces, a region's area off by
   * more than 0.5%, a region cut, the boundary more than half a local edge off, a vertex of
   * the approximated boundary off the curves) is made again with the refinement toward 30
   * degrees, and the one missing fewer kept (a warning says which; TrianglesBelowMinimumAngle
   * still counts against this). Delaunay refinement is known to end in practice only up to
   * about 33 degrees (Shewchuk's Triangle), hence the range's end: at 34 it ran for minutes
   * into worse meshes. Degrees, range [0, 33]; default 30; 0 turns the refinement off.
   */
  vtkSetMacro(MinimumAngle, double);
  vtkGetMacro(MinimumAngle, double);
  ///@}

  ///@{
  /**
   * Beyond the paper, with the Delaunay refinement (MinimumAngle > 0): curve recovery first.
   * Every triangle takes the region of its centroid; where an input curve runs through a
   * triangle (a layer or island the compression lost, a boundary cut short) and no layer
   * thinner than twice the recovery margin lies beside it, a curve point is inserted (a model
   * corner between MinimumAngle and FeatureAngle when one lies inside: a lost peninsula's tip
   * comes back with its apex) and the triangles around it take the region of their centroid,
   * never putting a region boundary through a vertex off the curves; the refinement then runs
   * twice, and region corners
   * sharper than MinimumAngle in small triangles (where a recovered layer ends) go to a
   * neighbour. A region boundary edge that cuts off more than 0.05% of the smaller of its
   * regions' areas from its curve is split at the curve point farthest from it (small
   * countries and islands keep their area); with the automatic sizes, a region whose edges cut
   * off more than 0.25% of its area in all (a thin bending layer) also has each edge split that
   * cuts off more than an even share of that. A mesh with a triangle below MinimumAngle or a
   * region's area off by more than 0.05% is made once more with half the recovery margin (thinner
   * layers, smaller regions), and the better kept (larger smallest angle, then smaller area error;
   * a retry that halves an area error above 0.5% is kept if its smallest angle is at most 5
   * degrees below MinimumAngle). In the last pass, wedges sharper than MinimumAngle that the
   * mesh ends early (a coast's narrow bay, a spit, a lens's tip, a layer's pinch-out at a
   * junction) are extended to where they are one finest edge wide, ended by a slanted cut (a
   * finest edge nearer the apex on one side), whose middle lies within half the local edge of
   * the curves (those among regions only when no triangle is left below MinimumAngle near
   * them).
   * Region areas within 0.5% on every bundled model (README, Measured). The field data
   * CurveVertices counts the vertices inserted on curves. Default on; off keeps the compressed
   * mesh's regions.
   */
  vtkSetMacro(CurveRecovery, vtkTypeBool);
  vtkGetMacro(CurveRecovery, vtkTypeBool);
  vtkBooleanMacro(CurveRecovery, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Beyond the paper, with CurveRecovery and MinimumAngle above 0: keep the input's region
   * corners sharper than MinimumAngle (pinch-outs, sharp junctions) to their apex, where the
   * apex is a junction or sharper than FeatureAngle. Each such region's wedge, from its apex to
   * where the refined mesh has the region on both sides, is given to the region with both
   * sides as mesh edges, as rungs across it (vertices on both sides at the same distances from
   * the apex, about one finest edge apart); its triangles keep the input's small angle, are not
   * refined, and have no angle above 150 degrees. A corner that cannot be kept so is left as
   * with the option off and named in a warning. Field data: `KeptCorners` (corners kept) and
   * `KeptCornerTriangles` (triangles below MinimumAngle within a kept corner's reach: its wedge
   * and the few beside it the refinement could not mend). Default off: every such corner ends
   * where its layer is about one finest edge thick and every triangle keeps MinimumAngle.
   * Without CurveRecovery, Optimization or a MinimumAngle it does nothing (with a warning).
   */
  vtkSetMacro(KeepSharpCorners, vtkTypeBool);
  vtkGetMacro(KeepSharpCorners, vtkTypeBool);
  vtkBooleanMacro(KeepSharpCorners, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Beyond the paper, with Optimization: a mesh that misses a bound is made again another
   * way and the better one kept. Default on; off: one mesh, as made.
   * - A smallest angle below min(MinimumAngle, 30) by more than 0.05 degrees (not checked
   *   with KeepSharpCorners), a region's area off by more than 0.5% (`MaxRegionAreaError`, or
   *   its misplaced area, lost plus added: `MaxRegionMisplacedArea`), a vertex of the
   *   approximated boundary off the curves, or, with no level set (no MaxLevel or
   *   LocalMaxLevel; sizes in model units allowed), the boundary more
   *   than half the local edge off the curves where the region is at least a finest edge wide
   *   (`MaxRelativeBoundaryDeviation` above 0.5): the mesh is made again with
   *   ThinLayerRefinement toggled (for the boundary alone, around the misses first, then
   *   everywhere; of equals on the hard bounds below, the smaller deviation is kept when the
   *   smallest angle, the area and the regions cut are no worse). Field `ThinLayerMesh` says
   *   how the kept one was made.
   * - Then, with the automatic levels (LocalMaxLevel -1, no MinimumEdgeLength, no edge length
   *   field), CurveRecovery and MinimumAngle 25 or more: still below 25 degrees where no input
   *   corner forces it, a region's area still off by more than 0.5%, or, with MaxLevel
   *   automatic too, a region with more or fewer pieces than the model has (`BrokenRegions`), a
   *   `MaxRelativeBoundaryDeviation` above 0.5 or triangles still below min(MinimumAngle, 30)
   *   (by more than 0.05 degrees) where no input corner forces them: made again with
   *   LocalMaxLevel 4 levels finer and, while the mesh kept still misses any of these (the
   *   finer one kept or not; refined toward 30 degrees or less), 2 levels finer again; when that
   *   third one is kept and still cuts a region, or the one kept is still more than one local
   *   edge off (`MaxRelativeBoundaryDeviation` above 1; toward 30 or less), 2 levels
   *   finer once more; a finer mesh not kept that cuts a region as the kept one does leads to
   *   the next step too (field `LocalMaxLevel`).
   * - Of two meshes, the one that misses fewer of issue 5's hard bounds (smallest angle 25
   *   degrees, or MinimumAngle when lower, away from kept corners; areas within 0.5%; with
   *   the automatic sizes, no region cut or lost; every vertex of the approximated boundary
   *   on a curve) and, with the automatic sizes, issue 4's boundary bound
   *   (`MaxRelativeBoundaryDeviation` at most 1) is kept. Between equals: the larger smallest angle
   *   (up to 30 degrees), or for an area miss the smaller area error, for the pieces fewer
   *   regions cut, for the boundary the smaller deviation, none of the others worse.
   * A warning gives every mesh's figures. In the finer levels' steps the smallest angle is that
   * of the triangles no input corner forces (field `MinimumAngleUnforced`; with
   * KeepSharpCorners no kept corner either): a triangle at a sharp input corner does not hide
   * the misses beside it. With KeepSharpCorners the thin layer step judges it so too.
   */
  vtkSetMacro(ThinLayerRetry, vtkTypeBool);
  vtkGetMacro(ThinLayerRetry, vtkTypeBool);
  vtkBooleanMacro(ThinLayerRetry, vtkTypeBool);
  ///@}

protected:
  vtkPhysicalCompressionTriangulator();
  ~vtkPhysicalCompressionTriangulator() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  bool CheckProperties() override;

  // Defaults come from the core's strata::CompressionParams (set in the constructor).
  int SpringConfiguration;
  double SpringStiffness;
  double Damping;
  double TimeStep;
  int MaxIterations;
  int PushCriterion;
  double PushVelocity;
  double FeatureAngle;
  vtkTypeBool FlipDegenerate;
  vtkTypeBool Optimization;
  double BoundaryTolerance;
  double MinimumAngle;          // default from strata::RefinementParams
  vtkTypeBool CurveRecovery;    // default from strata::MesherParams
  vtkTypeBool KeepSharpCorners; // default from strata::MesherParams
  vtkTypeBool ThinLayerRetry;   // default from strata::MesherParams

private:
  vtkPhysicalCompressionTriangulator(const vtkPhysicalCompressionTriangulator&) = delete;
  void operator=(const vtkPhysicalCompressionTriangulator&) = delete;
};

#endif
