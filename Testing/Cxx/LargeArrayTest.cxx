// LargeArrayAllocator: the core's working arrays keep their contents through growth across the
// mapped-block threshold, large blocks start on a 2 MiB boundary (so huge pages can back them),
// and a request that cannot be met throws instead of returning garbage.
#include "LargeArray.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <new>
#include <numeric>

using strata::LargeVector;

TEST(LargeArrayTest, ContentsSurviveGrowthPastTheMappedBlockSize)
{
  // 3 M ints (12 MB) pushed one by one: the buffer moves from operator new to mapped blocks.
  LargeVector<int> v;
  const int n = 3 << 20;
  for (int i = 0; i < n; ++i)
  {
    v.push_back(i);
  }
  ASSERT_EQ(v.size(), static_cast<std::size_t>(n));
  EXPECT_GE(v.capacity() * sizeof(int), strata::detail::kLargeBlockBytes);
  long long sum = std::accumulate(v.begin(), v.end(), 0LL);
  EXPECT_EQ(sum, static_cast<long long>(n) * (n - 1) / 2);
  // Copies, moves and shrinking keep the values.
  LargeVector<int> copy = v;
  LargeVector<int> moved = std::move(v);
  EXPECT_EQ(copy, moved);
  copy.resize(10);
  copy.shrink_to_fit();
  EXPECT_EQ(copy[9], 9);
}

TEST(LargeArrayTest, LargeBlocksStartOnAHugePageBoundary)
{
  LargeVector<std::array<int, 3>> big(std::size_t(1) << 20); // 12 MB, value-initialized
  EXPECT_EQ(big[12345][2], 0);
#if defined(__linux__)
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % (std::uintptr_t(2) << 20), 0u);
#endif
  // From the threshold on (a per-vertex array of a 1 M-triangle run is 2 to 4 MiB).
  LargeVector<char> threshold(strata::detail::kLargeBlockBytes, 'x');
  EXPECT_EQ(threshold.back(), 'x');
#if defined(__linux__)
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(threshold.data()) % (std::uintptr_t(2) << 20), 0u);
#endif
  LargeVector<double> small(100, 1.5); // from operator new: only the usual alignment
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(double), 0u);
  EXPECT_DOUBLE_EQ(small[99], 1.5);
}

TEST(LargeArrayTest, AnImpossibleRequestThrowsBadAlloc)
{
  strata::LargeArrayAllocator<double> a;
  EXPECT_THROW(a.allocate(std::numeric_limits<std::size_t>::max() / 4), std::bad_alloc);
  EXPECT_THROW(a.allocate(std::size_t(1) << 57), std::bad_alloc); // 1 EiB
  LargeVector<char> v;
  EXPECT_THROW(v.reserve(std::size_t(1) << 62), std::exception);
}

TEST(LargeArrayTest, WithRoomGrowsInPlaceUpToASixteenthMore)
{
  // A working array filled to n items, then grown by splits: no move within the room.
  const std::size_t n = std::size_t(1) << 20;
  LargeVector<double> v;
  strata::withRoom(v, n).assign(n, 2.5);
  EXPECT_EQ(v.size(), n);
  EXPECT_GE(v.capacity(), n + n / 16);
  const double* before = v.data();
  for (std::size_t i = 0; i < n / 16; ++i)
  {
    v.push_back(static_cast<double>(i));
  }
  EXPECT_EQ(v.data(), before);
  EXPECT_DOUBLE_EQ(v[n - 1], 2.5);
  EXPECT_DOUBLE_EQ(v.back(), static_cast<double>(n / 16 - 1));
  // Small arrays get at least 1024 items of room; a copy into the room keeps it (a move would
  // take the other array's buffer instead).
  const LargeVector<int> seven(10, 7);
  LargeVector<int> small;
  strata::withRoom(small, 10) = seven;
  EXPECT_GE(small.capacity(), 10u + 1024u);
  EXPECT_EQ(small[9], 7);
}
