// StrataMesh core: the "Polyline Signed Distance" stage of the pipeline: build the model, build
// the distance field, sample it at given points. No VTK.
#ifndef StrataMeshCore_SignedDistance_h
#define StrataMeshCore_SignedDistance_h

#include "Model.h"
#include "Progress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace strata
{

struct SignedDistanceParams
{
  ModelParams model; ///< how the input is read into a model
};

struct SignedDistanceResult
{
  std::vector<std::string> warnings;      ///< repairs made while reading the model
  std::vector<double> signedDistance;     ///< one per query: + inside a region, - outside all
  std::vector<int> regionId;              ///< containing region id, -1 for none
  std::vector<std::int64_t> nearestCurve; ///< input cell id of the nearest boundary segment
};

/// Samples the model's signed distance at `queries` (input coordinates; see DistanceField for
/// the definitions). Throws InputError for an invalid model, Aborted when the progress
/// callback asks to stop. An empty model gives empty results and a warning.
SignedDistanceResult computeSignedDistance(const RawPolylines& input,
  const std::vector<Vec2>& queries, const SignedDistanceParams& params = {},
  const ProgressCallback& progress = {});

} // namespace strata

#endif
