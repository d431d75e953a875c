/**
 * @class   vtkStrataMeshAlgorithm
 * @brief   base of the StrataMesh filters that mesh a polyline model
 *
 * Holds what every meshing stage shares: how the polyline model is read (Form and the names
 * of the region label arrays) and the parameters of the adaptive 4-8 grid (Marroquim,
 * Cavalcanti, Velho and Esperança, "Multi-Resolution Triangulations with Adaptation to the
 * Domain Based on Physical Compression", Sections 2 and 2.1). Input: a vtkPolyData of line
 * cells with region arrays (Loops: `RegionId`; Shared curves: `LeftRegion`/`RightRegion`).
 * Subclasses choose their outputs.
 *
 * Input 1 (optional, any vtkDataSet): a target edge length field, see
 * SetTargetEdgeLengthConnection.
 *
 * Property ranges: the setters keep the value given, even out of its documented range (they
 * do not clamp); the next update then fails with an error that names the property, its value
 * and the range, e.g. `MaxLevel = 99 is out of range [-1, 60]`, and produces empty outputs.
 *
 * @sa vtkAdaptive48Grid vtkClassify48Grid vtkPolylineSignedDistanceFilter
 */
#ifndef vtkStrataMeshAlgorithm_h
#define vtkStrataMeshAlgorithm_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <cstdint>    // for std::uint64_t
#include <functional> // for std::function
#include <string>     // for std::string

class vtkAlgorithmOutput;
class vtkDataSet;
namespace strata
{
struct Grid48Params;
}

class STRATAMESHFILTERS_EXPORT vtkStrataMeshAlgorithm : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkStrataMeshAlgorithm, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Input form of the model: 0 Auto (default: Shared curves when both label arrays exist,
   * else Loops), 1 Loops, 2 Shared curves. Range [0, 2].
   */
  vtkSetMacro(Form, int);
  vtkGetMacro(Form, int);
  ///@}

  ///@{
  /**
   * Names of the cell arrays with the region labels. Defaults: `RegionId` (Loops form),
   * `LeftRegion` and `RightRegion` (Shared curves form). An empty name means the default.
   */
  vtkSetStringMacro(RegionArrayName);
  vtkGetStringMacro(RegionArrayName);
  vtkSetStringMacro(LeftRegionArrayName);
  vtkGetStringMacro(LeftRegionArrayName);
  vtkSetStringMacro(RightRegionArrayName);
  vtkGetStringMacro(RightRegionArrayName);
  ///@}

  ///@{
  /**
   * Global refinement level (paper Section 2): edges are bisected up to this level while they
   * are longer than their midpoint's distance to the boundary. -1 (default) is automatic:
   * the level whose hypotenuse is about four median boundary segments long, in [10, 20].
   * Range [-1, 60].
   */
  vtkSetMacro(MaxLevel, int);
  vtkGetMacro(MaxLevel, int);
  ///@}

  ///@{
  /**
   * Local refinement level (paper Section 2.1, and thin regions): triangles holding two or
   * more model vertices, or crossed by two or more boundary curves, or by one curve twice,
   * are bisected up to this level. -1 (default) is MaxLevel + 4. Range [-1, 60]; when both are
   * set it must not be below MaxLevel.
   */
  vtkSetMacro(LocalMaxLevel, int);
  vtkGetMacro(LocalMaxLevel, int);
  ///@}

  ///@{
  /**
   * Global criterion tolerance (model units): an edge whose midpoint is closer than this to
   * the boundary is not bisected further. 0 (default) is automatic: 1e-3 of the hypotenuse
   * of a MaxLevel triangle. Range [0, inf) (finite).
   */
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /**
   * Sizes in model units, which choose the levels (0, the default: automatic levels).
   * A level's triangles have their longest edge, the hypotenuse, of D / 2^(level / 2), with D
   * the side of the grid's square (the model's larger side plus 5% on every side).
   *
   * MaximumEdgeLength > 0: every triangle of the grid is refined at least to the coarsest
   * level L whose hypotenuse is <= MaximumEdgeLength, so no grid edge is longer than it
   * anywhere; MaxLevel becomes L when automatic (-1) and the finer of MaxLevel and L when set,
   * and the automatic LocalMaxLevel follows (L + 4). Range 0 or [D / 2048, inf) (at most
   * 4 * 2^22 triangles of uniform refinement). The mesh of the triangulator moves vertices
   * onto the curves, which stretches some edges; its refinement then splits every region edge
   * still longer than MaximumEdgeLength, so no mesh edge is longer (with MinimumAngle > 0,
   * the default; with MinimumAngle 0 or Optimization off, up to 2.0 times measured).
   *
   * MinimumEdgeLength > 0 caps the refinement: MaxLevel, LocalMaxLevel and the junction
   * refinement, automatic or set, stop at the finest level whose hypotenuse is >=
   * MinimumEdgeLength (the coarser wins), so no grid triangle's hypotenuse is shorter than it
   * (when both lengths are set and within a factor sqrt(2) of each other, MaximumEdgeLength
   * wins, and hypotenuses stay above MinimumEdgeLength / sqrt(2)). Range [0, inf), not above
   * MaximumEdgeLength when both are > 0.
   */
  vtkSetMacro(MaximumEdgeLength, double);
  vtkGetMacro(MaximumEdgeLength, double);
  vtkSetMacro(MinimumEdgeLength, double);
  vtkGetMacro(MinimumEdgeLength, double);
  ///@}

  ///@{
  /**
   * Beyond the paper, thin layers (default off): also bisect grid triangles from MaxLevel
   * down to the junction refinement's level (16 times shorter edges than at LocalMaxLevel),
   * where a layer thinner than the triangle's legs but at least as thick as that level's legs
   * (the finest edge) crosses them (two boundary curves, or one curve twice) or lies beside
   * them (one curve twice: one side crossing the triangle, the other within a leg of it, as a
   * comb's tooth along a grid line), so that the compression gets cells about as wide as the
   * layer and keeps it. Curves meeting at a junction at 30 degrees or more are not a layer; a
   * pinch-out's tip, thinner than the finest edge, is not refined. Physical Compression
   * Triangulation keeps the mesh made with it only when it meets MinimumAngle (30 at most)
   * and the 0.5% region area bound; otherwise it also meshes without it and keeps the better
   * of the two (field `ThinLayerMesh`, a warning). Without it, that filter still uses it as a
   * second try for a mesh that misses those bounds (its ThinLayerRetry, on by default). The
   * README gives what it brings and costs.
   */
  vtkSetMacro(ThinLayerRefinement, vtkTypeBool);
  vtkGetMacro(ThinLayerRefinement, vtkTypeBool);
  vtkBooleanMacro(ThinLayerRefinement, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Target edge length field (input 1, optional; default: none): any vtkDataSet whose point
   * array TargetEdgeLengthArray gives the wanted length of the grid triangles' longest edge,
   * in model units, in the plane of the model (x, y; a flat dataset off z = 0 is read in its
   * own plane). Grid triangles are refined while their longest edge is longer than the
   * smallest target at their corners and centroid, down to a floor (MinimumEdgeLength when
   * set, otherwise 4 levels finer than LocalMaxLevel, or than its usual automatic value when
   * the field coarsened MaxLevel). With MaxLevel automatic (and no MaximumEdgeLength) the
   * field can also coarsen: MaxLevel becomes the coarser of the usual automatic level and
   * the coarsest level whose longest edge is not longer than the field's largest value.
   * Neighbouring grid triangles differ by at most one level, so their longest edges differ
   * by at most a factor 1.41 (the grading); the compression stretches that a little.
   *
   * - A dataset with 2-D (or 3-D) cells, e.g. an image or a triangulated surface, is
   *   interpolated linearly inside its cells; outside them there is no wish.
   * - A dataset without such cells (points, vertex cells, lines: e.g. well locations) gives
   *   h(x) = min over its points p of (h_p + TargetEdgeLengthGrading * |x - p|), distances
   *   in the xy plane: the size grows linearly away from every point.
   *
   * Values must be finite and > 0 (the request fails naming the first point at fault).
   * SetTargetEdgeLengthConnection is the pipeline way, SetTargetEdgeLengthData the
   * data way; a null argument removes the field.
   */
  void SetTargetEdgeLengthConnection(vtkAlgorithmOutput* output);
  void SetTargetEdgeLengthData(vtkDataSet* data);
  ///@}

  ///@{
  /**
   * Point array of the target edge length field. Default `TargetEdgeLength`; when the
   * dataset has no array of that name but exactly one point array, of one component, that
   * array is used.
   */
  vtkSetStringMacro(TargetEdgeLengthArray);
  vtkGetStringMacro(TargetEdgeLengthArray);
  ///@}

  ///@{
  /**
   * Grading of a points-only target edge length field, dimensionless: the size grows by this
   * many model units per model unit of distance from a point. Default 0.5; range (0, 10].
   * Ignored for a field with 2-D cells (interpolated).
   */
  vtkSetMacro(TargetEdgeLengthGrading, double);
  vtkGetMacro(TargetEdgeLengthGrading, double);
  ///@}

protected:
  vtkStrataMeshAlgorithm();
  ~vtkStrataMeshAlgorithm() override;

  /// Input 0: vtkPolyData (the model); input 1: vtkDataSet, optional (the target field).
  int FillInputPortInformation(int port, vtkInformation* info) override;

  /// The grid parameters of the properties (levels, tolerance, edge lengths) and the target
  /// edge length field of `target` (input 1, may be null) into `params`. Reports an error
  /// (vtkErrorMacro, naming the array or the point at fault) and returns false when the
  /// field is unusable.
  bool FillGridParams(vtkDataSet* target, strata::Grid48Params& params);

  /// Progress and abort wiring for the core: UpdateProgress, and false once CheckAbort().
  std::function<bool(double, const char*)> ProgressCallback();

  /// Checks every property against its documented range, reports each one out of range
  /// (vtkErrorMacro: "<Property> = <value> is out of range [<min>, <max>]") and returns
  /// whether all are valid. RequestData calls it first; subclasses add their properties.
  virtual bool CheckProperties();

  int Form = 0;
  char* RegionArrayName = nullptr;
  char* LeftRegionArrayName = nullptr;
  char* RightRegionArrayName = nullptr;
  int MaxLevel = -1;
  int LocalMaxLevel = -1;
  double Tolerance = 0.0;
  double MaximumEdgeLength = 0.0;
  double MinimumEdgeLength = 0.0;
  vtkTypeBool ThinLayerRefinement = 0;
  char* TargetEdgeLengthArray = nullptr;
  double TargetEdgeLengthGrading = 0.5;

private:
  vtkStrataMeshAlgorithm(const vtkStrataMeshAlgorithm&) = delete;
  void operator=(const vtkStrataMeshAlgorithm&) = delete;

  // Identifies the target field for resumable grids: incremented whenever the key (the
  // dataset, its MTime, the array name and the grading) changes.
  std::string TargetKey;
  std::uint64_t TargetId = 0;
};

#endif
