// Counting replacements of the global allocation functions, for the tests that show an
// operation allocates nothing (or a fixed number of buffers). Include it in exactly one
// translation unit of a test binary: the replacements are program-wide.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace se3_interpolation
{
namespace test
{
/// Heap allocations made through operator new since the program started.
inline std::atomic<long>& allocationCount()
{
  static std::atomic<long> count{ 0 };
  return count;
}
}  // namespace test
}  // namespace se3_interpolation

// The replacements pair operator new's malloc with operator delete's free themselves; GCC, seeing
// free called on memory from operator new after inlining, warns without cause.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size)
{
  ++se3_interpolation::test::allocationCount();
  if (void* p = std::malloc(size == 0 ? 1 : size))
    return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept
{
  std::free(p);
}
void operator delete(void* p, std::size_t /*size*/) noexcept
{
  std::free(p);
}
