// StrataMesh core: two halves of a loop at once. The work is split by the caller into two
// halves fixed in advance (never by the number of cores), so results are the same on every
// machine; with two cores the second half runs on a second thread. No VTK.
#ifndef StrataMeshCore_Parallel_h
#define StrataMeshCore_Parallel_h

#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace strata
{

/// Items (triangles, points) from which a loop over a whole mesh runs in two halves at once
/// (below it a thread's start costs more than it saves), and the items per block of such a
/// loop between two progress reports (blockwise).
constexpr std::size_t kTwoThreadItems = 65536;
constexpr std::size_t kTwoThreadBlock = 65536;

/// Whether the machine has two cores or more (asked once).
inline bool twoCores()
{
  static const bool two = std::thread::hardware_concurrency() > 1;
  return two;
}

/// Runs first() and second(): at once on two threads when the machine has two cores (and a
/// thread can be started), else one after the other. Neither may throw, and second() may not
/// report progress (it may run off the caller's thread).
template<class First, class Second>
void bothHalves(First&& first, Second&& second)
{
  if (twoCores())
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

/// A task that runs while the caller goes on: on a second thread when the machine has two cores
/// (and a thread can be started), else at once, in the constructor. wait() returns when it is
/// done and rethrows what it threw; the destructor waits too (dropping what it threw), so an
/// exception of the caller's (Aborted) leaves no thread behind. The task may not report
/// progress, and may read only what the caller does not write until wait().
class Background
{
public:
  template<class Task>
  explicit Background(Task&& task)
  {
    auto run = [this, task]() mutable
    {
      try
      {
        task();
      }
      catch (...)
      {
        this->Error = std::current_exception();
      }
    };
    if (twoCores())
    {
      try
      {
        this->Thread = std::thread(run);
        return;
      }
      catch (const std::system_error&)
      {
        // No thread to be had: the task here.
      }
    }
    run();
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  ~Background()
  {
    if (this->Thread.joinable())
    {
      this->Thread.join();
    }
  }
  void wait()
  {
    if (this->Thread.joinable())
    {
      this->Thread.join();
    }
    if (this->Error)
    {
      std::exception_ptr error = this->Error;
      this->Error = nullptr;
      std::rethrow_exception(error);
    }
  }

private:
  std::thread Thread;
  std::exception_ptr Error;
};
/// Runs work(from, to, part) over [0, n) in blocks of at most `block` items, in order: each
/// block's two halves at once (bothHalves: part 0 on this thread, part 1 perhaps on another)
/// when n >= threaded, else the whole block as part 0. After each block, after() runs on this
/// thread: it merges the parts' results in order and may report progress (and throw Aborted);
/// work() may not throw.
template<class Work, class After>
void blockwise(std::size_t n, std::size_t block, std::size_t threaded, Work&& work, After&& after)
{
  for (std::size_t begin = 0; begin < n; begin += block)
  {
    const std::size_t end = begin + block < n ? begin + block : n;
    if (n < threaded)
    {
      work(begin, end, 0);
    }
    else
    {
      const std::size_t middle = begin + (end - begin) / 2;
      bothHalves([&] { work(begin, middle, 0); }, [&] { work(middle, end, 1); });
    }
    after();
  }
}

/// blockwise() for a loop that gathers items: pick(i, list) may append items of i to its
/// part's list; after each block the parts' items go to take(item) in order (part 0's, then
/// part 1's: in order of i, as one pass would give them), then after() runs. Each part's list
/// sits on cache lines of its own (the threads write them at every item).
template<class T, class Pick, class Take, class After>
void gatherInOrder(std::size_t n,
  std::size_t block,
  std::size_t threaded,
  Pick&& pick,
  Take&& take,
  After&& after)
{
  struct alignas(64) Part
  {
    std::vector<T> items;
  };
  Part parts[2];
  blockwise(
    n,
    block,
    threaded,
    [&](std::size_t from, std::size_t to, int which)
    {
      for (std::size_t i = from; i < to; ++i)
      {
        pick(i, parts[which].items);
      }
    },
    [&]
    {
      for (Part& part : parts)
      {
        for (const T& item : part.items)
        {
          take(item);
        }
        part.items.clear();
      }
      after();
    });
}

} // namespace strata

#endif
