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

#include <functional> // for std::function

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
   * onto the curves, which stretches some edges: its longest edges stay below 2
   * MaximumEdgeLength (at most 1.6 times measured on the bundled models).
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

protected:
  vtkStrataMeshAlgorithm();
  ~vtkStrataMeshAlgorithm() override;

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

private:
  vtkStrataMeshAlgorithm(const vtkStrataMeshAlgorithm&) = delete;
  void operator=(const vtkStrataMeshAlgorithm&) = delete;
};

#endif
