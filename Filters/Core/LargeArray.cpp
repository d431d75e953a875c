// StrataMesh core: the large-array allocator (see LargeArray.h). No VTK.
#include "LargeArray.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace strata
{
namespace detail
{
namespace
{
#if defined(__linux__)
constexpr std::size_t kHugePage = std::size_t(2) << 20;

std::size_t mappedBytes(std::size_t bytes)
{
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}
#endif
} // namespace

void* allocateLarge(std::size_t bytes)
{
#if defined(__linux__)
  if (bytes >= kLargeBlockBytes)
  {
    if (bytes > std::numeric_limits<std::size_t>::max() - 2 * kHugePage)
    {
      throw std::bad_alloc();
    }
    const std::size_t size = mappedBytes(bytes);
    // Map one huge page more than needed, then unmap the unaligned head and the tail.
    void* raw =
      mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED)
    {
      throw std::bad_alloc();
    }
    const auto begin = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (begin + kHugePage - 1) / kHugePage * kHugePage;
    if (aligned > begin)
    {
      munmap(raw, aligned - begin);
    }
    const std::uintptr_t end = begin + size + kHugePage;
    if (end > aligned + size)
    {
      munmap(reinterpret_cast<void*>(aligned + size), end - (aligned + size));
    }
    void* block = reinterpret_cast<void*>(aligned);
    madvise(block, size, MADV_HUGEPAGE); // advice only: without huge pages it stays 4 KiB pages
    return block;
  }
#endif
  return ::operator new(bytes);
}

void deallocateLarge(void* block, std::size_t bytes) noexcept
{
  if (!block)
  {
    return;
  }
#if defined(__linux__)
  if (bytes >= kLargeBlockBytes)
  {
    munmap(block, mappedBytes(bytes));
    return;
  }
#endif
  ::operator delete(block);
}

} // namespace detail
} // namespace strata
