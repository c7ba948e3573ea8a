// Heap allocations made by the whole process so far (counted in bench_main.cpp).
#pragma once

#include <atomic>

namespace physik::bench {
extern std::atomic<long> g_allocations;
inline long allocations() {
  return g_allocations.load(std::memory_order_relaxed);
}
}  // namespace physik::bench
