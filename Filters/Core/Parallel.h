// StrataMesh core: two halves of a loop at once. The work is split by the caller into two
// halves fixed in advance (never by the number of cores), so results are the same on every
// machine; with two cores the second half runs on a second thread. No VTK.
#ifndef StrataMeshCore_Parallel_h
#define StrataMeshCore_Parallel_h

#include <system_error>
#include <thread>

namespace strata
{

/// Runs first() and second(): at once on two threads when the machine has two cores (and a
/// thread can be started), else one after the other. Neither may throw, and second() may not
/// report progress (it may run off the caller's thread).
template<class First, class Second>
void bothHalves(First&& first, Second&& second)
{
  static const bool twoCores = std::thread::hardware_concurrency() > 1;
  if (twoCores)
  {
    try
    {
      std::thread other(second);
      first();
      other.join();
      return;
    }
    catch (const std::system_error&)
    {
      // No thread to be had: both halves here.
    }
  }
  first();
  second();
}

} // namespace strata

#endif
