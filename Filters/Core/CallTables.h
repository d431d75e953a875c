// StrataMesh core: small tables that one call of a step fills and reads, reused from call to
// call without clearing (the Delaunay refinement's wedges). No VTK.
#ifndef StrataMeshCore_CallTables_h
#define StrataMeshCore_CallTables_h

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace strata
{

/// The places of a call's keys (say, triangles) in its list: open addressing, twice as many
/// slots as keys at least, each slot stamped with the call that filled it, so that nothing is
/// cleared between calls. (The Delaunay refinement's wedges looked each neighbour up by a
/// binary search of their list: half of that step on long zigzag curves. A table over every
/// triangle of the mesh instead cost a 1 M mesh 26 ms of first writes for its hundred corners.)
class PlaceTable
{
public:
  /// Starts a call of at most n keys. (The call uses the first Size slots only: a table grown
  /// for a call of many keys does not spread the next calls' few over all of it, out of the
  /// cache.)
  void begin(std::size_t n)
  {
    this->Size = 64;
    this->Shift = 26;
    while (this->Size < 2 * n)
    {
      this->Size *= 2;
      --this->Shift;
    }
    if (this->Size > this->Slots.size())
    {
      this->Slots.assign(this->Size, Slot{});
      this->Stamp = 0;
    }
    if (++this->Stamp == 0)
    {
      std::fill(this->Slots.begin(), this->Slots.end(), Slot{});
      this->Stamp = 1;
    }
  }
  /// Adds a key not added since begin().
  void insert(int key, int place)
  {
    std::size_t h = this->slotOf(key);
    while (this->Slots[h].stamp == this->Stamp)
    {
      h = (h + 1) & (this->Size - 1);
    }
    this->Slots[h] = { key, this->Stamp, place };
  }
  /// The key's place, or -1 when it was not added since begin().
  int find(int key) const
  {
    for (std::size_t h = this->slotOf(key); this->Slots[h].stamp == this->Stamp;
         h = (h + 1) & (this->Size - 1))
    {
      if (this->Slots[h].key == key)
      {
        return this->Slots[h].place;
      }
    }
    return -1;
  }

private:
  struct Slot
  {
    int key = 0;
    std::uint32_t stamp = 0;
    int place = 0;
  };
  std::size_t slotOf(int key) const // (Fibonacci hashing: the product's high bits)
  {
    return static_cast<std::size_t>((static_cast<std::uint32_t>(key) * 2654435769u) >> this->Shift);
  }
  std::vector<Slot> Slots;
  std::size_t Size = 64; // slots used by the call: a power of two
  std::uint32_t Stamp = 0;
  int Shift = 26; // 32 - log2(Size)
};

/// Two values per vertex that one call works out (a kept corner's arcs along its sides), kept in
/// a fixed table of kMemoSlots slots by the vertex's index: a vertex whose slot another vertex
/// of the call took is worked out again (the memo only spares work: what it gives is the
/// value).
class VertexMemo
{
public:
  static constexpr std::size_t kMemoSlots = std::size_t(1) << 14;
  /// Starts a call.
  void begin()
  {
    if (this->Slots.empty())
    {
      this->Slots.resize(kMemoSlots);
    }
    if (++this->Stamp == 0)
    {
      std::fill(this->Slots.begin(), this->Slots.end(), Slot{});
      this->Stamp = 1;
    }
  }
  /// v's values: f(values) fills them unless this call kept them.
  template<class F>
  const std::array<double, 2>& get(int v, F&& f)
  {
    Slot& s = this->Slots[static_cast<std::size_t>(v) & (kMemoSlots - 1)];
    if (s.stamp != this->Stamp || s.v != v)
    {
      s.stamp = this->Stamp;
      s.v = v;
      f(s.values);
    }
    return s.values;
  }

private:
  struct Slot
  {
    int v = -1;
    std::uint32_t stamp = 0;
    std::array<double, 2> values{};
  };
  std::vector<Slot> Slots;
  std::uint32_t Stamp = 0;
};

} // namespace strata

#endif
