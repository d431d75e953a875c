// Core tests: the two-thread helpers of Parallel.h.
#include "Parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{

struct Stop : std::runtime_error
{
  Stop()
    : std::runtime_error("stop")
  {
  }
};

// Runs blockwise over n items and returns what it saw: every item's part, the items merged in
// order after each block, the blocks' ends.
struct Seen
{
  std::vector<int> part;         // per item, the part that visited it (-1: none, -2: twice)
  std::vector<int> merged;       // the items, in the order the merges appended them
  std::vector<std::size_t> ends; // per block, how many items were merged after it
};

Seen run(std::size_t n, std::size_t block, std::size_t threaded)
{
  Seen seen;
  seen.part.assign(n, -1);
  std::vector<int> parts[2];
  strata::blockwise(
    n,
    block,
    threaded,
    [&](std::size_t from, std::size_t to, int part)
    {
      for (std::size_t i = from; i < to; ++i)
      {
        seen.part[i] = seen.part[i] == -1 ? part : -2;
        parts[part].push_back(static_cast<int>(i));
      }
    },
    [&]
    {
      for (std::vector<int>& p : parts)
      {
        seen.merged.insert(seen.merged.end(), p.begin(), p.end());
        p.clear();
      }
      seen.ends.push_back(seen.merged.size());
    });
  return seen;
}

} // namespace

TEST(ParallelTest, BlockwiseVisitsEveryItemOnceAndMergesInOrder)
{
  for (const std::size_t threaded : { std::size_t(0), std::size_t(1000000) })
  {
    SCOPED_TRACE(threaded);
    const Seen seen = run(1000, 64, threaded);
    std::vector<int> order(1000);
    for (int i = 0; i < 1000; ++i)
    {
      order[i] = i;
      EXPECT_GE(seen.part[i], 0) << "item " << i;
    }
    EXPECT_EQ(seen.merged, order);
    // 15 blocks of 64 and one of 40, each merged before the next.
    ASSERT_EQ(seen.ends.size(), 16u);
    for (std::size_t b = 0; b < seen.ends.size(); ++b)
    {
      EXPECT_EQ(seen.ends[b], std::min<std::size_t>(1000, 64 * (b + 1)));
    }
    // Split blocks: each half its own part (the first 32 of a block part 0); whole blocks
    // below the threshold: part 0 only.
    for (int i = 0; i < 1000; ++i)
    {
      const int expected = threaded == 0 && i % 64 >= (i < 960 ? 32 : 20) ? 1 : 0;
      EXPECT_EQ(seen.part[i], expected) << "item " << i;
    }
  }
  EXPECT_TRUE(run(0, 64, 0).ends.empty());
}

TEST(ParallelTest, BlockwiseTellsAnAfterThatTakesACountTheItemsDoneSoFar)
{
  // after(done) gets each block's end: 15 blocks of 64 and one of 40, with or without threads.
  for (const std::size_t threaded : { std::size_t(0), std::size_t(1000000) })
  {
    SCOPED_TRACE(threaded);
    std::atomic<std::size_t> visited{ 0 };
    std::vector<std::size_t> done, seen;
    strata::blockwise(
      1000,
      64,
      threaded,
      [&](std::size_t from, std::size_t to, int) { visited += to - from; },
      [&](std::size_t items)
      {
        done.push_back(items);
        seen.push_back(visited.load());
      });
    ASSERT_EQ(done.size(), 16u);
    for (std::size_t b = 0; b < done.size(); ++b)
    {
      EXPECT_EQ(done[b], std::min<std::size_t>(1000, 64 * (b + 1)));
    }
    EXPECT_EQ(done, seen);
  }
}

TEST(ParallelTest, AnExceptionBetweenBlocksLeavesNoThreadRunning)
{
  // The merge after a block may throw (a progress report's abort): the block's threads have
  // been joined by then, so the exception reaches the caller (no std::terminate) and no
  // further block runs.
  std::atomic<int> blocks{ 0 };
  EXPECT_THROW(strata::blockwise(
                 1000,
                 100,
                 0,
                 [&](std::size_t from, std::size_t, int) { blocks += from % 100 == 0; },
                 [&]
                 {
                   if (blocks == 3)
                   {
                     throw Stop();
                   }
                 }),
    Stop);
  EXPECT_EQ(blocks.load(), 3);
}

TEST(ParallelTest, BlockwiseInSlicesGivesEachPartTheItemsOfBlockwiseWithMoreAftersBetween)
{
  // Each part sees the same items in the same order as blockwise gives it (what a part carries
  // from item to item, as the boundary measure's samples do, comes out the same); after() runs
  // after each slice of each block, with no slice longer than its share of the block's half.
  for (const std::size_t threaded : { std::size_t(0), std::size_t(1000000) })
  {
    for (const std::size_t slices :
      { std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(8), std::size_t(200) })
    {
      SCOPED_TRACE(std::to_string(threaded) + " threaded, " + std::to_string(slices) + " slices");
      std::vector<int> byBlockwise[2], bySlices[2];
      std::size_t blocks = 0;
      strata::blockwise(
        1000,
        64,
        threaded,
        [&](std::size_t from, std::size_t to, int part)
        {
          for (std::size_t i = from; i < to; ++i)
          {
            byBlockwise[part].push_back(static_cast<int>(i));
          }
        },
        [&] { ++blocks; });
      std::size_t afters = 0, pending = 0, longest = 0;
      strata::blockwiseInSlices(
        1000,
        64,
        threaded,
        slices,
        [&](std::size_t from, std::size_t to, int part)
        {
          for (std::size_t i = from; i < to; ++i)
          {
            bySlices[part].push_back(static_cast<int>(i));
          }
          pending += to - from;
        },
        [&]
        {
          ++afters;
          longest = std::max(longest, pending);
          pending = 0;
        });
      EXPECT_EQ(bySlices[0], byBlockwise[0]);
      EXPECT_EQ(bySlices[1], byBlockwise[1]);
      EXPECT_EQ(bySlices[0].size() + bySlices[1].size(), 1000u);
      EXPECT_EQ(pending, 0u) << "items after the last after()";
      // Blocks of 64 (15, and one of 40), each in two halves of 32 (20) items, or whole with
      // one part: each half (or block) in steps of ceil(items / slices), slices with no
      // items left out.
      const std::size_t n = std::max<std::size_t>(slices, 1);
      const auto steps = [n](std::size_t items)
      {
        const std::size_t each = (items + n - 1) / n;
        return (items + each - 1) / each;
      };
      const std::size_t perBlock = threaded == 0 ? steps(32) : steps(64);
      const std::size_t lastBlock = threaded == 0 ? steps(20) : steps(40);
      EXPECT_EQ(afters, 15 * perBlock + lastBlock);
      EXPECT_LE(afters, 16 * n);
      const std::size_t each = ((threaded == 0 ? 32 : 64) + n - 1) / n;
      EXPECT_LE(longest, threaded == 0 ? 2 * each : each);
      EXPECT_EQ(blocks, 16u);
    }
  }
}

TEST(ParallelTest, GatherInOrderGivesEachItemOnceInOrderOfItsIndex)
{
  // Items 0..999, blocks of 64, each block's halves on two threads: the multiples of 3 give
  // themselves, the multiples of 5 also their negation after; take() sees them as one pass
  // over the indices would give them, and after() runs once per block, after its items.
  std::vector<int> expected, taken;
  for (int i = 0; i < 1000; ++i)
  {
    if (i % 3 == 0)
    {
      expected.push_back(i);
    }
    if (i % 5 == 0)
    {
      expected.push_back(-i);
    }
  }
  std::vector<std::size_t> takenAtBlockEnd;
  strata::gatherInOrder<int>(
    1000,
    64,
    0,
    [](std::size_t i, std::vector<int>& items)
    {
      if (i % 3 == 0)
      {
        items.push_back(static_cast<int>(i));
      }
      if (i % 5 == 0)
      {
        items.push_back(-static_cast<int>(i));
      }
    },
    [&](int item) { taken.push_back(item); },
    [&] { takenAtBlockEnd.push_back(taken.size()); });
  EXPECT_EQ(taken, expected);
  ASSERT_EQ(takenAtBlockEnd.size(), 16u); // ceil(1000 / 64)
  EXPECT_EQ(takenAtBlockEnd.back(), expected.size());
  // After the first block (items 0..63): 22 multiples of 3 and 13 of 5.
  EXPECT_EQ(takenAtBlockEnd.front(), 35u);
}

TEST(ParallelTest, ABackgroundTaskIsDoneAtWaitAndItsExceptionReachesTheCaller)
{
  // The task's writes are all seen after wait().
  std::vector<int> squares;
  {
    strata::Background task(
      [&]
      {
        for (int i = 0; i < 100000; ++i)
        {
          squares.push_back(i % 1000 * (i % 1000));
        }
      });
    task.wait();
    ASSERT_EQ(squares.size(), 100000u);
    EXPECT_EQ(squares[99999], 999 * 999);
    task.wait(); // (a second wait returns at once)
  }
  // What the task throws is rethrown by wait(), once.
  strata::Background failing([] { throw Stop(); });
  EXPECT_THROW(failing.wait(), Stop);
  EXPECT_NO_THROW(failing.wait());
}

TEST(ParallelTest, AnExceptionOfTheCallerWaitsForTheBackgroundTask)
{
  // The caller throws (a progress report's abort) while the task runs: the task's destructor
  // joins it (no std::terminate), and the task ran to its end before the exception arrives.
  std::atomic<int> done{ 0 };
  const auto caller = [&]
  {
    strata::Background task(
      [&]
      {
        volatile double x = 0.0;
        for (int i = 0; i < 2000000; ++i)
        {
          x = x + 1.0;
        }
        done = 1;
      });
    throw Stop();
  };
  EXPECT_THROW(caller(), Stop);
  EXPECT_EQ(done.load(), 1);
}

namespace
{
// A background task that runs for 10 s unless asked to stop, and records whether it was.
auto untilAskedToStop(std::atomic<bool>& sawStop)
{
  return [&sawStop](const std::atomic<bool>& stop)
  {
    const auto begin = std::chrono::steady_clock::now();
    while (!stop.load() && std::chrono::steady_clock::now() - begin < std::chrono::seconds(10))
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    sawStop = stop.load();
  };
}
} // namespace

TEST(ParallelTest, AWaitWithTicksTicksWhileTheTaskRunsAndGivesItsResult)
{
  // A task of about 100 ms: the wait ticks every 10 ms or so meanwhile (with two cores), and
  // the task's writes are seen after it, as with wait().
  int ticks = 0;
  std::vector<int> values;
  strata::Background task(
    [&]
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      values.assign(1000, 7);
    });
  task.wait([&] { ++ticks; });
  ASSERT_EQ(values.size(), 1000u);
  EXPECT_EQ(values.back(), 7);
  if (std::thread::hardware_concurrency() >= 2)
  {
    EXPECT_GE(ticks, 3);
    EXPECT_LE(ticks, 11);
  }
  // What the task throws is rethrown.
  strata::Background failing([] { throw Stop(); });
  EXPECT_THROW(failing.wait([] {}), Stop);
}

TEST(ParallelTest, AnAbortWhileWaitingAsksTheTaskToStopAndReturnsSoon)
{
  // The task would run for 10 s unless asked to stop; the third tick throws (an abort): the
  // task sees the flag, the wait joins it and rethrows, long before the 10 s.
  std::atomic<bool> sawStop{ false };
  int ticks = 0;
  const auto start = std::chrono::steady_clock::now();
  const auto caller = [&]
  {
    strata::Background task(untilAskedToStop(sawStop));
    task.wait(
      [&]
      {
        if (++ticks == 3)
        {
          throw Stop();
        }
      });
  };
  if (std::thread::hardware_concurrency() < 2)
  {
    GTEST_SKIP() << "one core: the task runs in the constructor, before any wait";
  }
  EXPECT_THROW(caller(), Stop);
  EXPECT_TRUE(sawStop.load());
  EXPECT_EQ(ticks, 3);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(ParallelTest, AnExceptionOfTheCallerBeforeTheWaitAsksTheTaskToStop)
{
  // The caller throws before it waits: the destructor raises the flag, then joins.
  std::atomic<bool> sawStop{ false };
  const auto caller = [&]
  {
    strata::Background task(untilAskedToStop(sawStop));
    throw Stop();
  };
  if (std::thread::hardware_concurrency() < 2)
  {
    GTEST_SKIP() << "one core: the task runs in the constructor, before any wait";
  }
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THROW(caller(), Stop);
  EXPECT_TRUE(sawStop.load());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(ParallelTest, BothHalvesRunOnceAndTheSecondsWritesAreSeenAfterTheCall)
{
  // Many calls in a row (the second thread spinning between them) and calls further apart
  // than its spin (asleep between them): every call runs both halves once and returns after
  // both, the second half's writes visible to the caller.
  for (const int pauseMicroseconds : { 0, 1000 })
  {
    SCOPED_TRACE(pauseMicroseconds);
    const int calls = pauseMicroseconds == 0 ? 20000 : 50;
    std::vector<int> firsts(calls, 0), seconds(calls, 0);
    for (int c = 0; c < calls; ++c)
    {
      if (pauseMicroseconds > 0)
      {
        std::this_thread::sleep_for(std::chrono::microseconds(pauseMicroseconds));
      }
      strata::bothHalves([&] { ++firsts[c]; }, [&] { ++seconds[c]; });
      ASSERT_EQ(seconds[c], 1) << "call " << c;
      ASSERT_EQ(firsts[c], 1) << "call " << c;
    }
  }
}

TEST(ParallelTest, BothHalvesNestedOrFromTwoCallersAtOnceAllRun)
{
  // A second half that itself splits (the second thread is busy with it), and two threads
  // calling at once (one of them without the second thread): every half runs once.
  std::atomic<int> halves{ 0 };
  strata::bothHalves(
    [&] { ++halves; }, [&] { strata::bothHalves([&] { ++halves; }, [&] { ++halves; }); });
  EXPECT_EQ(halves.load(), 3);
  halves = 0;
  const auto caller = [&]
  {
    for (int c = 0; c < 2000; ++c)
    {
      strata::bothHalves([&] { ++halves; }, [&] { ++halves; });
    }
  };
  std::thread other(caller);
  caller();
  other.join();
  EXPECT_EQ(halves.load(), 2 * 2 * 2000);
}

TEST(ParallelTest, AFirstHalfThatThrowsWaitsForTheSecond)
{
  // (Neither half may throw; should the first after all, the call still waits for the second
  // half, which uses the caller's objects, before the exception leaves it.)
  std::atomic<int> done{ 0 };
  EXPECT_THROW(strata::bothHalves([] { throw Stop(); },
                 [&]
                 {
                   std::this_thread::sleep_for(std::chrono::milliseconds(20));
                   done = 1;
                 }),
    Stop);
  EXPECT_EQ(done.load(), 1);
  // The second thread is free again.
  int second = 0;
  strata::bothHalves([] {}, [&] { second = 1; });
  EXPECT_EQ(second, 1);
}
