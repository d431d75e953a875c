// StrataMesh core: compressed rows, the grouping of items by a key (a vertex's triangles, a
// cell's segments, a node's curves) that the stages share. No VTK.
#ifndef StrataMeshCore_Rows_h
#define StrataMeshCore_Rows_h

#include "LargeArray.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace strata
{

/// Groups items by row (a stable counting sort, O(rows + items)): afterwards row r's items are
/// items[start[r]] to items[start[r + 1] - 1], in the order they were emitted, and
/// start[rows] is the number of items. `emitAll(emit)` calls `emit(row, item)` for each item,
/// with row in [0, rows), and must make the same calls each time: it is called twice, first
/// to count the rows' sizes, then to place the items (the count ignores the items, so an
/// optimizing build leaves out what only computes them). `Starts`, `Items`: vectors;
/// the type of start's values (int, std::size_t) must hold the number of items. A row outside
/// [0, rows) throws std::out_of_range from the count, before anything is placed (a negative
/// row converts to a large one).
template<class Starts, class Items, class EmitAll>
void groupIntoRows(std::size_t rows, Starts& start, Items& items, EmitAll&& emitAll)
{
  using Offset = typename Starts::value_type;
  start.assign(rows + 1, Offset(0));
  emitAll(
    [&](std::size_t row, const auto&)
    {
      if (row >= rows)
      {
        throw std::out_of_range("groupIntoRows: row " + std::to_string(row) + " is not in [0, " +
          std::to_string(rows) + ")");
      }
      ++start[row + 1];
    });
  for (std::size_t r = 0; r < rows; ++r)
  {
    start[r + 1] += start[r];
  }
  items.resize(static_cast<std::size_t>(start[rows]));
  LargeVector<Offset> next(start.begin(), start.end() - 1);
  emitAll([&](std::size_t row, const auto& item)
    { items[static_cast<std::size_t>(next[row]++)] = item; });
}

} // namespace strata

#endif
