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

private:
  vtkStrataMeshAlgorithm(const vtkStrataMeshAlgorithm&) = delete;
  void operator=(const vtkStrataMeshAlgorithm&) = delete;
};

#endif
