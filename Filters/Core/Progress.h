// StrataMesh core: the one progress and abort channel of the core.
#ifndef StrataMeshCore_Progress_h
#define StrataMeshCore_Progress_h

#include "Errors.h"

#include <functional>

namespace strata
{

/// Called by long-running core code with the fraction done (0..1) of the whole run and the
/// name of the current stage. Return false to abort: the core then throws strata::Aborted.
/// The VTK adapters wire it to vtkAlgorithm::UpdateProgress and vtkAlgorithm::CheckAbort.
using ProgressCallback = std::function<bool(double fraction, const char* stage)>;

/// Reports progress through an optional callback and throws Aborted when asked to stop.
class ProgressReporter
{
public:
  explicit ProgressReporter(ProgressCallback callback = {}, double begin = 0.0, double end = 1.0)
    : Callback(std::move(callback))
    , Begin(begin)
    , End(end)
  {
  }

  /// Report the fraction (0..1) of this reporter's share; throws Aborted on request.
  void report(double fraction, const char* stage) const
  {
    if (this->Callback && !this->Callback(this->Begin + fraction * (this->End - this->Begin), stage))
    {
      throw Aborted();
    }
  }

  /// A reporter for the sub-range [from, to] of this one's share.
  ProgressReporter sub(double from, double to) const
  {
    const double w = this->End - this->Begin;
    return ProgressReporter(this->Callback, this->Begin + from * w, this->Begin + to * w);
  }

private:
  ProgressCallback Callback;
  double Begin;
  double End;
};

} // namespace strata

#endif
