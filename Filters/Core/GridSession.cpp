// The grid stages as a session: Model -> DistanceField once, then Grid48 built or resumed as
// parameters change, and any level extracted and classified on demand. Resuming is only
// correct when no criterion got coarser (Grid48::refine's contract), so the resolved new
// parameters are compared with the grid's before choosing between resuming and rebuilding.
#include "GridSession.h"

namespace strata
{
namespace
{

/// The target edge length criterion of `next` is at least as fine as `current`'s: no field
/// before, or the same field (same non-zero id) with a floor not coarser. A field removed, or
/// one that may have changed, makes the grid rebuild.
bool sameOrFinerField(const Grid48Params& next, const Grid48Params& current)
{
  if (!current.targetEdgeLength)
  {
    return true;
  }
  return next.targetEdgeLength && next.targetEdgeLengthId != 0 &&
    next.targetEdgeLengthId == current.targetEdgeLengthId &&
    next.targetMaxLevel >= current.targetMaxLevel;
}

/// True when every criterion of `next` is at least as fine as `current`'s (both resolved).
bool atLeastAsFine(const Grid48Params& next, const Grid48Params& current)
{
  return next.maxLevel >= current.maxLevel && next.localMaxLevel >= current.localMaxLevel &&
    next.junctionMaxLevel >= current.junctionMaxLevel && next.minLevel >= current.minLevel &&
    next.tolerance <= current.tolerance &&
    (next.junctionRefinement || !current.junctionRefinement) &&
    (next.thinLayerRefinement || !current.thinLayerRefinement) &&
    next.featurePointAngle >= current.featurePointAngle &&
    (next.localRefinement || !current.localRefinement) &&
    (next.thinRegionRefinement || !current.thinRegionRefinement) && next.margin == current.margin &&
    sameOrFinerField(next, current);
}

} // namespace

GridSession::GridSession(const RawPolylines& input, const ModelParams& params)
  : Core(buildModel(input, params))
  , Field(std::make_unique<DistanceField>(this->Core))
{
}

GridSession::~GridSession() = default;

bool GridSession::refine(const Grid48Params& params, const ProgressReporter& progress)
{
  const Grid48Params resolved = Grid48::resolveParams(this->Core, params);
  if (this->Grid && atLeastAsFine(resolved, this->Grid->params()))
  {
    this->Grid->refine(this->Core, *this->Field, params, progress);
    return true;
  }
  this->Grid.reset(); // free the old hierarchy before building the new one
  this->Grid = std::make_unique<Grid48>(Grid48::build(this->Core, *this->Field, params, progress));
  return false;
}

TriangleMesh GridSession::extract(int level) const
{
  return this->Grid->extract(level);
}

Classification GridSession::classify(const TriangleMesh& mesh,
  const ClassificationParams& params,
  const ProgressReporter& progress) const
{
  return strata::classify(mesh, this->Core, *this->Field, params, progress);
}

} // namespace strata
