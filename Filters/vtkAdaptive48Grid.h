/**
 * @class   vtkAdaptive48Grid
 * @brief   the adaptive 4-8 grid that subdivides the space around a polyline model
 *
 * First stage of StrataMesh's physical compression triangulation (Marroquim, Cavalcanti,
 * Velho and Esperança, "Multi-Resolution Triangulations with Adaptation to the Domain Based
 * on Physical Compression", Sections 2 and 2.1): a square covering the model (5% margin) is
 * split into four right isosceles triangles and refined by newest-vertex bisection toward the
 * model's boundaries, conformingly (no hanging vertex, neighbours at most one level apart),
 * on an exact lattice so every triangle has angles of 45, 45 and 90 degrees.
 *
 * Output: a vtkUnstructuredGrid of triangles with the cell array `Level` (bisection level)
 * and the point array `Level` (level at which the vertex appeared), and field data
 * `MaxLevel`, `LocalMaxLevel`, `Tolerance` (the values used, automatic ones resolved),
 * `GridMemoryBytes`. The hierarchy is kept between updates: changing only OutputLevel
 * extracts another nested level without refining again, and raising a level resumes the
 * refinement. Input 1 (optional): a target edge length field (see vtkStrataMeshAlgorithm);
 * the field data then also holds `TargetMaxLevel` (the level of its floor), and a new or
 * modified field rebuilds the grid.
 *
 * @sa vtkClassify48Grid vtkStrataMeshAlgorithm
 */
#ifndef vtkAdaptive48Grid_h
#define vtkAdaptive48Grid_h

#include "StrataMeshFiltersModule.h" // for export macro
#include "vtkStrataMeshAlgorithm.h"

#include <functional> // for std::function
#include <memory>     // for std::shared_ptr
#include <string>     // for std::string

class vtkUnstructuredGrid;
namespace strata
{
class GridSession;
struct Grid48Params;
struct TriangleMesh;
}

class STRATAMESHFILTERS_EXPORT vtkAdaptive48Grid : public vtkStrataMeshAlgorithm
{
public:
  static vtkAdaptive48Grid* New();
  vtkTypeMacro(vtkAdaptive48Grid, vtkStrataMeshAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The grid (output port 0). These hide vtkPolyDataAlgorithm::GetOutput, whose type is not
   * this filter's output type.
   */
  vtkUnstructuredGrid* GetOutput();
  vtkUnstructuredGrid* GetOutput(int port);
  ///@}

  ///@{
  /**
   * Level of the output mesh: -1 (default) for the finest (all leaves); otherwise the nested
   * conforming mesh of that level (coarser levels of the same hierarchy). Range [-1, 60]
   * (not clamped: a value out of range fails the update with an error naming it).
   */
  vtkSetMacro(OutputLevel, int);
  vtkGetMacro(OutputLevel, int);
  ///@}

protected:
  vtkAdaptive48Grid();
  ~vtkAdaptive48Grid() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  bool CheckProperties() override;

  /// The session for this input and these parameters, reused when possible (throws what the
  /// core throws, after dropping the session). `params`: from FillGridParams. Shared with
  /// vtkClassify48Grid.
  std::shared_ptr<strata::GridSession> UpdateSession(vtkPolyData* input,
    const strata::Grid48Params& params);

  /// The common part of RequestData, shared with vtkClassify48Grid: checks the properties
  /// and the target edge length field (input 1, `target`, may be null), updates the session and,
  /// unless the model is empty, extracts the mesh of OutputLevel into `mesh` and runs `more` on it
  /// (further core work, under the same error handling); then reports the session's warnings.
  /// Returns the session (empty for an empty model), or null after reporting an error.
  std::shared_ptr<strata::GridSession> ExtractMesh(vtkPolyData* input,
    vtkDataSet* target,
    strata::TriangleMesh& mesh,
    const std::function<void(strata::GridSession&, const strata::TriangleMesh&)>& more = nullptr);

  int OutputLevel = -1;

private:
  vtkAdaptive48Grid(const vtkAdaptive48Grid&) = delete;
  void operator=(const vtkAdaptive48Grid&) = delete;

  std::shared_ptr<strata::GridSession> Session;
  std::string SessionKey; // the input (address, MTime) and the model-reading settings
};

#endif
