// StrataMesh core: an allocator for the large working arrays (grid nodes, springs, stars), so
// that filling them costs one page fault per 2 MiB rather than one per 4 KiB. No VTK.
#ifndef StrataMeshCore_LargeArray_h
#define StrataMeshCore_LargeArray_h

#include <algorithm>
#include <cstddef>
#include <limits>
#include <new>
#include <vector>

namespace strata
{
namespace detail
{
/// Blocks of at least this many bytes are mapped on their own (on Linux). From 1 MiB a 2 MiB
/// page (one fault, at most 1 MiB of it unused) costs less than the 256 faults of 4 KiB pages
/// (10 us each on the machines of issue 4, also when the process had the memory before);
/// below, operator new's pool. (It was 4 MiB until 2026-12-04: the per-vertex and
/// per-triangle arrays of a 1 M-triangle run, 2 to 4 MiB, took 4 KiB pages.)
constexpr std::size_t kLargeBlockBytes = std::size_t(1) << 20;
/// Returns `bytes` bytes aligned for any fundamental type. A block of kLargeBlockBytes or more
/// is, on Linux, an anonymous mapping of whole 2 MiB pages aligned to 2 MiB and advised as
/// transparent huge pages (madvise MADV_HUGEPAGE); smaller blocks, and every block elsewhere,
/// come from operator new. Throws std::bad_alloc when the memory cannot be had.
void* allocateLarge(std::size_t bytes);
/// Releases a block of allocateLarge(bytes) (the same `bytes`).
void deallocateLarge(void* block, std::size_t bytes) noexcept;
} // namespace detail

/// A stateless std::allocator replacement for arrays that grow to megabytes: with 4 KiB pages a
/// first write costs a page fault per page, which some virtual machines make very expensive
/// (about 11 us each on the machines of issue 4: 2 s of a 1 M-triangle run). Huge pages, where
/// the kernel has them, cut that by 512. The contents are those of any vector.
template<class T>
struct LargeArrayAllocator
{
  using value_type = T;
  static_assert(alignof(T) <= alignof(std::max_align_t), "over-aligned types are not supported");

  LargeArrayAllocator() noexcept = default;
  template<class U>
  LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept
  {
  }

  T* allocate(std::size_t n)
  {
    if (n > std::numeric_limits<std::size_t>::max() / sizeof(T))
    {
      throw std::bad_array_new_length();
    }
    return static_cast<T*>(detail::allocateLarge(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { detail::deallocateLarge(p, n * sizeof(T)); }

  template<class U>
  bool operator==(const LargeArrayAllocator<U>&) const noexcept
  {
    return true;
  }
  template<class U>
  bool operator!=(const LargeArrayAllocator<U>&) const noexcept
  {
    return false;
  }
};

/// A std::vector of a working array that may grow to megabytes (see LargeArrayAllocator).
template<class T>
using LargeVector = std::vector<T, LargeArrayAllocator<T>>;

/// Room for `more` items beyond v's size: when the capacity must grow, fourfold rather than
/// the vector's twofold. An array that grows item by item to n items then writes about 1.3 n
/// items to new memory rather than 2 n, and copies n / 3 rather than n: on the machines of
/// issue 4 a first write costs about 2.5 s per GiB. (The capacity beyond the size is address
/// space: pages never written take no memory.)
template<class T>
void reserveGrowth(LargeVector<T>& v, std::size_t more = 1)
{
  if (v.size() + more > v.capacity())
  {
    const std::size_t fourfold = v.capacity() <= v.max_size() / 4 ? 4 * v.capacity() : v.max_size();
    v.reserve(v.size() + more > fourfold ? v.size() + more : fourfold);
  }
}

/// v with capacity for n items and a sixteenth more (at least 1024): call it before filling a
/// working array to n items that may then grow by a few (the compression's edge splits add
/// vertices and triangles to some 40 arrays). Growth within that room moves nothing; beyond
/// it, a vector copies itself whole to new memory (at 1 M triangles, 35 ms for those arrays'
/// first split). The room is address space: pages never written take no memory. A copy
/// assigned to v keeps the room; a vector moved into v brings its own buffer instead.
template<class T>
LargeVector<T>& withRoom(LargeVector<T>& v, std::size_t n)
{
  v.reserve(n + std::max<std::size_t>(n / 16, 1024));
  return v;
}

/// The list sorted, without repeats (the working lists of ids: marks gathered in any order).
template<class List>
void sortUnique(List& list)
{
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
}

} // namespace strata

#endif
