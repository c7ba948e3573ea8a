// Benchmarks' entry point, with a global allocation counter so every benchmark can report how
// many heap allocations its timed loop made (the engine's step must make none).
#include <atomic>
#include <cstdlib>
#include <new>

#include <benchmark/benchmark.h>

#include "bench/alloc_counter.h"

namespace physik::bench {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  physik::bench::g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// the nothrow form too, so every allocation and its release go through one malloc/free pair
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  physik::bench::g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

BENCHMARK_MAIN();
