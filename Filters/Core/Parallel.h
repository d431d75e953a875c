// StrataMesh core: two halves of a loop at once. The work is split by the caller into two
// halves fixed in advance (never by the number of cores), so results are the same on every
// machine; with two cores the second half runs on a second thread. No VTK.
#ifndef StrataMeshCore_Parallel_h
#define StrataMeshCore_Parallel_h

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

namespace detail
{
/// A short wait of a spinning thread (the other core's work is a few microseconds away).
inline void relax()
{
#if defined(__SSE2__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

/// The second thread of bothHalves(), one per process, started at its first call. After each
/// half it runs it spins for kSpin (the next half often follows within microseconds: a
/// sweep's next block, a simulation step's next loop), then sleeps until one is posted; a
/// half posted while it sleeps that it has not begun when the caller is done with its own,
/// the caller takes back. On the machines of issue 4 a thread started and joined for each
/// call cost 50-60 us alone and 120-140 us within a 1 M-triangle run (1383 calls: 164-192 ms
/// beyond the halves' own time); a half handed to the spinning worker costs about 1 us, one
/// that wakes it 80-90 us (the sleeping thread began some 300 us later: hence the spin, and
/// the taking back). That run spends 23-46 ms so, 83% of its halves finding it spinning.
class HalfWorker
{
public:
  static constexpr std::chrono::microseconds kSpin{ 200 };

  /// The worker, or nullptr when no thread could be started.
  static HalfWorker* get()
  {
    static HalfWorker worker;
    return worker.Thread.joinable() ? &worker : nullptr;
  }
  /// Posts task to the worker, unless another caller has it (then false: run it elsewhere).
  /// When true, finish() must be called before task goes out of scope.
  template<class Task>
  bool start(Task& task)
  {
    if (this->Busy.exchange(true))
    {
      return false;
    }
    this->Run = [](void* t) { (*static_cast<Task*>(t))(); };
    this->Arg = const_cast<void*>(static_cast<const void*>(&task));
    this->State.store(kPosted);
    if (this->Sleeping.load())
    {
      {
        const std::lock_guard<std::mutex> lock(this->Mutex); // (not between its check and wait)
      }
      this->Wake.notify_one();
    }
    return true;
  }
  /// Returns once the posted task is done: by the worker, or here when it has not begun it.
  /// The worker is free again.
  void finish()
  {
    int expected = kPosted;
    if (this->State.compare_exchange_strong(expected, kIdle))
    {
      void (*const run)(void*) = this->Run; // (taken back: the worker will not begin it)
      void* const arg = this->Arg;
      this->Busy.store(false);
      run(arg);
      return;
    }
    for (int spins = 0; this->State.load() != kDone; ++spins)
    {
      if (spins < 4096)
      {
        relax();
      }
      else
      {
        std::this_thread::yield(); // (a long half, or a busy machine)
      }
    }
    this->State.store(kIdle);
    this->Busy.store(false);
  }

  HalfWorker(const HalfWorker&) = delete;
  HalfWorker& operator=(const HalfWorker&) = delete;
  ~HalfWorker()
  {
    if (this->Thread.joinable())
    {
      this->Stop.store(true);
      {
        const std::lock_guard<std::mutex> lock(this->Mutex);
      }
      this->Wake.notify_one();
      this->Thread.join();
    }
  }

private:
  enum : int
  {
    kIdle,
    kPosted,
    kRunning,
    kDone
  };

  HalfWorker()
  {
    try
    {
      this->Thread = std::thread([this] { this->loop(); });
    }
    catch (const std::system_error&)
    {
      // No thread to be had: get() gives none.
    }
  }
  void loop()
  {
    for (;;)
    {
      const auto idle = std::chrono::steady_clock::now();
      for (int spins = 1; this->State.load() != kPosted && !this->Stop.load(); ++spins)
      {
        relax();
        if (spins % 64 == 0 && std::chrono::steady_clock::now() - idle > kSpin)
        {
          std::unique_lock<std::mutex> lock(this->Mutex);
          this->Sleeping.store(true);
          this->Wake.wait(
            lock, [this] { return this->State.load() == kPosted || this->Stop.load(); });
          this->Sleeping.store(false);
        }
      }
      if (this->Stop.load())
      {
        return;
      }
      int expected = kPosted;
      if (this->State.compare_exchange_strong(expected, kRunning))
      {
        this->Run(this->Arg); // (a half may not throw: as on a std::thread, it would terminate)
        this->State.store(kDone);
      }
    }
  }

  std::atomic<int> State{ kIdle };
  std::atomic<bool> Busy{ false }, Sleeping{ false }, Stop{ false };
  void (*Run)(void*) = nullptr;
  void* Arg = nullptr;
  std::mutex Mutex;
  std::condition_variable Wake;
  std::thread Thread;
};
} // namespace detail

/// Runs first() and second(): at once on two threads when the machine has two cores (second()
/// on the process's second thread, detail::HalfWorker, or when another caller has it on a
/// thread started for it), else one after the other. Neither may throw, and second() may not
/// report progress (it may run off the caller's thread).
template<class First, class Second>
void bothHalves(First&& first, Second&& second)
{
  if (twoCores())
  {
    if (detail::HalfWorker* worker = detail::HalfWorker::get())
    {
      if (worker->start(second))
      {
        struct Finish
        {
          detail::HalfWorker* W;
          ~Finish() { this->W->finish(); } // (also should first() throw after all)
        } finish{ worker };
        first();
        return;
      }
    }
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
/// progress, and may read only what the caller does not write until wait(). A task taking a
/// `const std::atomic<bool>&` is given a flag that turns true when the caller no longer wants
/// its result (the destructor before wait(), or wait(tick)'s tick threw): it may then return
/// at once, its result unread.
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
        if constexpr (std::is_invocable_v<decltype(task)&, const std::atomic<bool>&>)
        {
          task(static_cast<const std::atomic<bool>&>(this->Stop));
        }
        else
        {
          task();
        }
      }
      catch (...)
      {
        this->Error = std::current_exception();
      }
      this->Done.store(true, std::memory_order_release);
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
      this->Stop.store(true, std::memory_order_relaxed);
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
  /// wait(), calling tick() (a progress report) every kTickMilliseconds while the task runs:
  /// a task longer than the abort's bound does not hold the caller's reports back. When tick()
  /// throws (Aborted), the task is asked to stop and joined, and the exception goes on.
  template<class Tick>
  void wait(Tick&& tick)
  {
    while (this->Thread.joinable() && !this->Done.load(std::memory_order_acquire))
    {
      try
      {
        tick();
      }
      catch (...)
      {
        this->Stop.store(true, std::memory_order_relaxed);
        this->Thread.join();
        throw;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(kTickMilliseconds));
    }
    this->wait();
  }

private:
  static constexpr int kTickMilliseconds = 10;
  std::thread Thread;
  std::exception_ptr Error;
  std::atomic<bool> Stop{ false };
  std::atomic<bool> Done{ false };
};
/// Runs work(from, to, part) over [0, n) in blocks of at most `block` items, in order: each
/// block's two halves at once (bothHalves: part 0 on this thread, part 1 perhaps on another)
/// when n >= threaded, else the whole block as part 0. After each block, after() runs on this
/// thread, or after(done) with the items done so far (the block's end): it merges the parts'
/// results in order and may report progress (and throw Aborted); work() may not throw.
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
    if constexpr (std::is_invocable_v<After&, std::size_t>)
    {
      after(end);
    }
    else
    {
      after();
    }
  }
}

/// blockwise() with after() also within each block, for loops whose items differ much in cost:
/// each block's halves are worked through in `slices` steps (about block / (2 slices) items of
/// each half), after() running on this thread after each step. Each part is given the same
/// items in the same order as blockwise(n, block, threaded, ...) gives it, so that what a part
/// carries from item to item comes out the same; after() must not merge the parts' results
/// (it may report progress, and throw Aborted). slices < 1 counts as 1.
template<class Work, class After>
void blockwiseInSlices(std::size_t n,
  std::size_t block,
  std::size_t threaded,
  std::size_t slices,
  Work&& work,
  After&& after)
{
  slices = slices < 1 ? 1 : slices;
  const auto step = [slices](std::size_t items) { return (items + slices - 1) / slices; };
  for (std::size_t begin = 0; begin < n; begin += block)
  {
    const std::size_t end = begin + block < n ? begin + block : n;
    if (n < threaded)
    {
      const std::size_t each = step(end - begin);
      for (std::size_t from = begin; from < end; from += each)
      {
        work(from, from + each < end ? from + each : end, 0);
        after();
      }
      continue;
    }
    const std::size_t middle = begin + (end - begin) / 2;
    const std::size_t each0 = step(middle - begin), each1 = step(end - middle);
    for (std::size_t k = 0; k < slices; ++k)
    {
      const auto range = [k](std::size_t from, std::size_t to, std::size_t each)
      {
        const std::size_t a = from + k * each < to ? from + k * each : to;
        return std::make_pair(a, a + each < to ? a + each : to);
      };
      const auto first = range(begin, middle, each0), second = range(middle, end, each1);
      if (first.first == first.second && second.first == second.second)
      {
        break;
      }
      bothHalves(
        [&] { work(first.first, first.second, 0); }, [&] { work(second.first, second.second, 1); });
      after();
    }
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
