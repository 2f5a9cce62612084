#pragma once
// Replaces the global operator new of the test binary that includes this (once, in one file) to
// count every allocation: a loop that must not allocate is run between two reads of the count.
#include <atomic>
#include <cstdlib>
#include <new>

namespace dynweigh::testing {
inline std::atomic<long> g_allocations{0};
}

// The replacements pair malloc with free on purpose; GCC cannot see that and warns.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++dynweigh::testing::g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++dynweigh::testing::g_allocations;
  return std::malloc(size ? size : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop
