// groupIntoRows: the compressed rows the stages build (a vertex's triangles, a cell's
// segments, a node's curves) hold every item once, in its row, in the order it was emitted;
// a row out of range is an exception, not a write outside the offsets.
#include "Rows.h"
#include "LargeArray.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

using strata::groupIntoRows;
using strata::LargeVector;

TEST(RowsTest, EachRowHoldsItsItemsInTheOrderTheyWereEmitted)
{
  // Items 0..n-1 with pseudo-random rows; the reference is a list per row.
  const std::size_t rows = 37, n = 5000;
  std::mt19937 random(7);
  std::vector<int> rowOf(n);
  for (int& r : rowOf)
  {
    r = static_cast<int>(random() % rows);
  }
  std::vector<std::vector<int>> expected(rows);
  for (std::size_t i = 0; i < n; ++i)
  {
    expected[rowOf[i]].push_back(static_cast<int>(i));
  }
  LargeVector<int> start, items;
  groupIntoRows(rows,
    start,
    items,
    [&](auto&& emit)
    {
      for (std::size_t i = 0; i < n; ++i)
      {
        emit(rowOf[i], static_cast<int>(i));
      }
    });
  ASSERT_EQ(start.size(), rows + 1);
  EXPECT_EQ(start.front(), 0);
  EXPECT_EQ(static_cast<std::size_t>(start.back()), n);
  ASSERT_EQ(items.size(), n);
  for (std::size_t r = 0; r < rows; ++r)
  {
    const std::vector<int> got(items.begin() + start[r], items.begin() + start[r + 1]);
    EXPECT_EQ(got, expected[r]) << "row " << r;
  }
}

TEST(RowsTest, RowsWithoutItemsAreEmptyAndTheEarlierContentsAreReplaced)
{
  // A vertex's triangles (a star) where vertices 0, 2 and 5 are in no triangle; the vectors
  // held an earlier, larger grouping.
  const std::vector<std::array<int, 3>> triangles = { { 1, 3, 4 }, { 4, 3, 6 }, { 1, 4, 6 } };
  std::vector<int> start(100, 9), items(200, 9);
  groupIntoRows(7,
    start,
    items,
    [&](auto&& emit)
    {
      for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        for (int v : triangles[t])
        {
          emit(v, static_cast<int>(t));
        }
      }
    });
  EXPECT_EQ(start, (std::vector<int>{ 0, 0, 2, 2, 4, 7, 7, 9 }));
  EXPECT_EQ(items, (std::vector<int>{ 0, 2, 0, 1, 0, 1, 2, 1, 2 }));
}

TEST(RowsTest, NoItemsGiveZeroOffsetsAndNoRowsGiveOneOffset)
{
  LargeVector<int> start, items;
  groupIntoRows(4, start, items, [](auto&&) {});
  EXPECT_EQ(start, (LargeVector<int>{ 0, 0, 0, 0, 0 }));
  EXPECT_TRUE(items.empty());
  groupIntoRows(0, start, items, [](auto&&) {});
  EXPECT_EQ(start, (LargeVector<int>{ 0 }));
  EXPECT_TRUE(items.empty());
}

TEST(RowsTest, OffsetsAndItemsMayBeOfOtherTypes)
{
  // Offsets of std::size_t and std::uint32_t; pairs as items (an edge's end and its face).
  std::vector<std::size_t> start;
  LargeVector<std::pair<int, int>> out;
  groupIntoRows(3,
    start,
    out,
    [&](auto&& emit)
    {
      emit(2, std::make_pair(10, 0));
      emit(0, std::make_pair(11, 1));
      emit(2, std::make_pair(12, 2));
    });
  EXPECT_EQ(start, (std::vector<std::size_t>{ 0, 1, 1, 3 }));
  EXPECT_EQ(out, (LargeVector<std::pair<int, int>>{ { 11, 1 }, { 10, 0 }, { 12, 2 } }));
  LargeVector<std::uint32_t> cells;
  LargeVector<int> segments;
  groupIntoRows(2,
    cells,
    segments,
    [&](auto&& emit)
    {
      emit(1, 5);
      emit(1, 6);
    });
  EXPECT_EQ(cells, (LargeVector<std::uint32_t>{ 0, 0, 2 }));
  EXPECT_EQ(segments, (LargeVector<int>{ 5, 6 }));
}

TEST(RowsTest, ARowOutsideTheRowsThrowsBeforeAnythingIsPlaced)
{
  LargeVector<int> start, items = { 7, 8 };
  const auto emitAll = [](int bad)
  {
    return [bad](auto&& emit)
    {
      emit(0, 1);
      emit(bad, 2);
    };
  };
  EXPECT_THROW(groupIntoRows(3, start, items, emitAll(3)), std::out_of_range);
  EXPECT_THROW(groupIntoRows(3, start, items, emitAll(-1)), std::out_of_range);
  EXPECT_EQ(items, (LargeVector<int>{ 7, 8 })); // (nothing placed)
  groupIntoRows(3, start, items, emitAll(2));
  EXPECT_EQ(start, (LargeVector<int>{ 0, 1, 1, 2 }));
  EXPECT_EQ(items, (LargeVector<int>{ 1, 2 }));
}
