/**
 * @class   vtkPolylineSignedDistanceFilter
 * @brief   samples the signed distance to a multi-region polyline model
 *
 * Input 0 (optional) is the dataset to probe; input 1 (`Source`) is the polyline model, in
 * either StrataMesh input form (Loops with `RegionId`, or Shared curves with
 * `LeftRegion`/`RightRegion`; see Data/FORMAT.md). The output is a shallow copy of input 0
 * with three point arrays:
 * - `SignedDistance` (double): + the distance to the boundary of the region that contains
 *   the point, or - the distance to the nearest boundary when no region contains it;
 * - `RegionId` (int): the containing region, -1 for none (even-odd rule per region);
 * - `NearestCurve` (vtkIdType): id of the input cell nearest to the point.
 *
 * When no dataset to probe is given (input 0 unconnected, or the same data as the source, as
 * happens when a script passes only the model), the filter samples a vtkImageData of
 * SampleDimensions points over the model's bounds padded by 5% on each side.
 *
 * Distances are exact: one strip tree per region searched best-first (Marroquim,
 * Cavalcanti, Velho and Esperança, "Multi-Resolution Triangulations with Adaptation to the
 * Domain Based on Physical Compression", Sections 3-4). Invalid models fail the request with
 * an error naming the cell, point or location at fault; repairs (duplicate points,
 * zero-length cells) are reported as warnings. An empty model gives an empty output.
 *
 * Property ranges are checked when the filter executes, not clamped by the setters: a value
 * out of range fails the request with an error naming the property, its value and the range
 * (e.g. `Form = 3 is out of range [0, 2]`).
 *
 * @sa vtkPolylineSignedDistance vtkPhysicalCompressionTriangulator
 */
#ifndef vtkPolylineSignedDistanceFilter_h
#define vtkPolylineSignedDistanceFilter_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkDataSetAlgorithm.h"

class vtkPolyData;

class STRATAMESHFILTERS_EXPORT vtkPolylineSignedDistanceFilter : public vtkDataSetAlgorithm
{
public:
  static vtkPolylineSignedDistanceFilter* New();
  vtkTypeMacro(vtkPolylineSignedDistanceFilter, vtkDataSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The polyline model (input 1). SetSourceConnection is the pipeline way.
   */
  void SetSourceConnection(vtkAlgorithmOutput* output);
  void SetSourceData(vtkPolyData* source);
  ///@}

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
   * Points of the sampled image along x and y when no dataset to probe is given.
   * Default 256 x 256; each in [2, 16384].
   */
  vtkSetVector2Macro(SampleDimensions, int);
  vtkGetVector2Macro(SampleDimensions, int);
  ///@}

protected:
  vtkPolylineSignedDistanceFilter();
  ~vtkPolylineSignedDistanceFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestDataObject(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Form = 0;
  char* RegionArrayName = nullptr;
  char* LeftRegionArrayName = nullptr;
  char* RightRegionArrayName = nullptr;
  int SampleDimensions[2] = { 256, 256 };

private:
  vtkPolylineSignedDistanceFilter(const vtkPolylineSignedDistanceFilter&) = delete;
  void operator=(const vtkPolylineSignedDistanceFilter&) = delete;

  /// The dataset to probe, or nullptr when an image is to be sampled.
  static vtkDataSet* GetProbe(vtkInformationVector** inputVector);
  /// Checks Form, and SampleDimensions when an image is sampled, reporting each value out of
  /// range (vtkErrorMacro); returns whether all are valid.
  bool CheckProperties(bool sampling);
};

#endif
