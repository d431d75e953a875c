/**
 * @class   vtkPolylineSignedDistance
 * @brief   implicit function: signed distance to the regions of a polyline model
 *
 * Evaluates, at any point of the plane z = 0 (z is ignored), the signed distance to a
 * multi-region polyline model in either input form of StrataMesh (Loops with `RegionId`, or
 * Shared curves with `LeftRegion`/`RightRegion`). The distance is exact and computed with one
 * strip tree per region, searched best-first, as in Marroquim, Cavalcanti, Velho and
 * Esperança, "Multi-Resolution Triangulations with Adaptation to the Domain Based on
 * Physical Compression", Sections 3-4. Region membership follows the even-odd rule per
 * region, so holes and islands are handled.
 *
 * Sign convention (the paper's, not vtkImplicitFunction's usual one): the value is
 * **positive inside** and negative outside. With `Region` = -1 (the default, "any region")
 * the value is + the distance to the boundary of the region containing the point, or - the
 * distance to the nearest boundary when no region contains it. With `Region` = r >= 0 it is
 * the signed distance to region r's boundary. The gradient is computed by central
 * differences with a step of 1e-7 of the model's size.
 *
 * The model is read when it is set (SetModel) and again whenever it is modified. An invalid
 * model, or a Region or Form out of range (the setters do not clamp), is reported through
 * vtkErrorMacro and the function then evaluates to NaN. Thread safe for evaluation (as
 * vtkSampleFunction does it).
 *
 * @sa vtkPolylineSignedDistanceFilter vtkSampleFunction vtkImplicitFunction
 */
#ifndef vtkPolylineSignedDistance_h
#define vtkPolylineSignedDistance_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkImplicitFunction.h"

#include <memory> // for std::unique_ptr

class vtkPolyData;

class STRATAMESHFILTERS_EXPORT vtkPolylineSignedDistance : public vtkImplicitFunction
{
public:
  static vtkPolylineSignedDistance* New();
  vtkTypeMacro(vtkPolylineSignedDistance, vtkImplicitFunction);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  using vtkImplicitFunction::EvaluateFunction;
  double EvaluateFunction(double x[3]) override;
  void EvaluateGradient(double x[3], double g[3]) override;

  ///@{
  /**
   * The polyline model (line cells with region arrays). Default: none (evaluates to NaN).
   */
  void SetModel(vtkPolyData* model);
  vtkPolyData* GetModel();
  ///@}

  ///@{
  /**
   * Region whose signed distance is evaluated; -1 (default) means any region: the distance to
   * the boundary of the containing region, negative outside all regions. Range [-1, max int];
   * a region the model does not have is an error too.
   */
  vtkSetMacro(Region, int);
  vtkGetMacro(Region, int);
  ///@}

  ///@{
  /**
   * Input form of the model: 0 Auto (default: Shared curves when both label arrays exist,
   * else Loops), 1 Loops, 2 Shared curves (range [0, 2]); and the names of the label arrays
   * (defaults `RegionId`, `LeftRegion`, `RightRegion`).
   */
  vtkSetMacro(Form, int);
  vtkGetMacro(Form, int);
  vtkSetStringMacro(RegionArrayName);
  vtkGetStringMacro(RegionArrayName);
  vtkSetStringMacro(LeftRegionArrayName);
  vtkGetStringMacro(LeftRegionArrayName);
  vtkSetStringMacro(RightRegionArrayName);
  vtkGetStringMacro(RightRegionArrayName);
  ///@}

  /// Includes the model's modification time.
  vtkMTimeType GetMTime() override;

  /// Reads the model now if it changed; returns false (after vtkErrorMacro) when it is
  /// invalid. Evaluation calls this itself; call it to learn about errors early.
  bool UpdateModel();

protected:
  vtkPolylineSignedDistance();
  ~vtkPolylineSignedDistance() override;

  int Region = -1;
  int Form = 0;
  char* RegionArrayName = nullptr;
  char* LeftRegionArrayName = nullptr;
  char* RightRegionArrayName = nullptr;

private:
  vtkPolylineSignedDistance(const vtkPolylineSignedDistance&) = delete;
  void operator=(const vtkPolylineSignedDistance&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
