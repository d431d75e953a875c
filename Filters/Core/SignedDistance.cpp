// The signed-distance stage: Model -> DistanceField -> samples. Queries are shifted into the
// model's local frame (input minus Model::origin) before they reach the distance field, so
// that UTM-sized coordinates keep their precision. Progress is reported, and abort honoured,
// every few thousand queries.
#include "SignedDistance.h"

#include "DistanceField.h"

namespace strata
{

SignedDistanceResult computeSignedDistance(const RawPolylines& input,
  const std::vector<Vec2>& queries, const SignedDistanceParams& params,
  const ProgressCallback& progress)
{
  const ProgressReporter reporter(progress);
  reporter.report(0.0, "reading the model");
  const Model model = buildModel(input, params.model);
  SignedDistanceResult result;
  result.warnings = model.warnings;
  if (model.empty())
  {
    return result;
  }
  reporter.report(0.05, "building strip trees");
  const DistanceField field(model);
  const ProgressReporter sampling = reporter.sub(0.1, 1.0);

  const std::size_t n = queries.size();
  result.signedDistance.resize(n);
  result.regionId.resize(n);
  result.nearestCurve.resize(n);
  DistanceField::Scratch scratch;
  constexpr std::size_t block = 4096;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (i % block == 0)
    {
      sampling.report(static_cast<double>(i) / static_cast<double>(n), "sampling the distance");
    }
    const PointQuery q = field.query(queries[i] - model.origin, scratch);
    result.signedDistance[i] = q.signedDistance;
    result.regionId[i] = q.region;
    result.nearestCurve[i] = q.nearestCurve;
  }
  reporter.report(1.0, "done");
  return result;
}

} // namespace strata
