/**
 * @class   vtkClassify48Grid
 * @brief   the adaptive 4-8 grid with its vertices, edges and cells classified by region
 *
 * Second stage of StrataMesh's physical compression triangulation (Marroquim, Cavalcanti,
 * Velho and Esperança, "Multi-Resolution Triangulations with Adaptation to the Domain Based
 * on Physical Compression", Section 5): the grid of vtkAdaptive48Grid (same properties),
 * classified against the model's regions with the strip-tree distance.
 *
 * Output port 0: the grid (vtkUnstructuredGrid of triangles) with point arrays
 * `VertexClass` (0 exterior, 1 boundary: within BoundaryTolerance of a boundary, 2 interior)
 * and `VertexRegion` (region containing the vertex, -1 for none), and cell arrays
 * `CellRegion` (region of the triangle's barycentre) and `Level`.
 * Output port 1: the grid's edges as lines (vtkPolyData) with cell arrays `EdgeClass`
 * (0 exterior, 1 interior to a region, 2 intersection: crosses or touches a boundary) and
 * `EdgeRegion` (the region of an interior edge; for an intersection edge the region of its
 * first endpoint inside a region; -1 for exterior edges).
 *
 * @sa vtkAdaptive48Grid vtkStrataMeshAlgorithm
 */
#ifndef vtkClassify48Grid_h
#define vtkClassify48Grid_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkAdaptive48Grid.h"

class STRATAMESHFILTERS_EXPORT vtkClassify48Grid : public vtkAdaptive48Grid
{
public:
  static vtkClassify48Grid* New();
  vtkTypeMacro(vtkClassify48Grid, vtkAdaptive48Grid);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The grid's edges (output port 1).
  vtkPolyData* GetEdgesOutput();

  ///@{
  /**
   * A vertex within this distance (model units) of a boundary is a boundary vertex, and an
   * edge that comes this close to a boundary is an intersection edge. 0 (default) is
   * automatic: 1e-6 of the grid's shortest edge. Range [0, inf) (finite; not clamped: a value
   * out of range fails the update with an error naming it).
   */
  vtkSetMacro(BoundaryTolerance, double);
  vtkGetMacro(BoundaryTolerance, double);
  ///@}

protected:
  vtkClassify48Grid();
  ~vtkClassify48Grid() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  bool CheckProperties() override;

  double BoundaryTolerance = 0.0;

private:
  vtkClassify48Grid(const vtkClassify48Grid&) = delete;
  void operator=(const vtkClassify48Grid&) = delete;
};

#endif
