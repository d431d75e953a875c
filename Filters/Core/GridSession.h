// StrataMesh core: the grid stages of the pipeline as a session that keeps its hierarchy, so a
// filter can re-extract another level, or resume refinement after a parameter change,
// without starting over (the paper's multi-resolution). No VTK.
#ifndef StrataMeshCore_GridSession_h
#define StrataMeshCore_GridSession_h

#include "Classification.h"
#include "DistanceField.h"
#include "Grid48.h"
#include "Model.h"
#include "Progress.h"

#include <memory>
#include <string>
#include <vector>

namespace strata
{

/// A model, its distance field and its 4-8 grid. Create one per input model; call refine()
/// with the grid parameters (again when they change), then extract meshes of any level.
/// Holds no state beyond that: a filter resets it by creating a new one.
class GridSession
{
public:
  /// Builds and validates the model (InputError) and its distance field.
  explicit GridSession(const RawPolylines& input, const ModelParams& params = {});
  ~GridSession();

  const Model& model() const { return this->Core; }
  const DistanceField& field() const { return *this->Field; }
  const std::vector<std::string>& warnings() const { return this->Core.warnings; }
  bool empty() const { return this->Core.empty(); }

  /// Brings the grid to `params`: resumes refinement when the resolved parameters are all at
  /// least as fine as the current grid's, rebuilds otherwise. Returns true when it resumed
  /// (or had nothing to do). With a target edge length field it resumes only when the field
  /// is the same (Grid48Params::targetEdgeLengthId equal and non-zero), else it rebuilds.
  /// Throws ParameterError, Aborted.
  bool refine(const Grid48Params& params, const ProgressReporter& progress = ProgressReporter());

  /// The grid (valid after refine()).
  const Grid48& grid() const { return *this->Grid; }

  /// The conforming mesh of `level` (-1: finest), in local coordinates.
  TriangleMesh extract(int level = -1) const;

  /// Classification of a mesh extracted from this session.
  Classification classify(const TriangleMesh& mesh,
    const ClassificationParams& params = {},
    const ProgressReporter& progress = ProgressReporter()) const;

private:
  Model Core;
  std::unique_ptr<DistanceField> Field;
  std::unique_ptr<Grid48> Grid;
};

} // namespace strata

#endif
