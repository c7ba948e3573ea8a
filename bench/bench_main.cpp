// Benchmarks' entry point, with a global allocation counter so every benchmark can report how
// many heap allocations its timed loop made (the engine's step must make none).
// --flush_subnormals (a measurement, never the default): the whole process runs with the SSE
// control bits flush-to-zero and denormals-are-zero, so an arithmetic result or operand below
// 2.2e-308 is 0. It shows how much of a time is the processor's slow path for subnormal numbers
// (a long pulled chain's far end, docs/DESIGN.md "Benchmarks"); it changes results there. The
// engine's own step sets the same bits for its duration (flush_subnormals, on by default); this
// flag covers the rest of the process too (mj_step, DART).
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

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

int main(int argc, char** argv) {
  // take --flush_subnormals out before Google Benchmark reads the flags
  int kept = 1;
  bool flush = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--flush_subnormals") == 0) {
      flush = true;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  if (flush) {
#if defined(__SSE2__)
    _mm_setcsr(_mm_getcsr() | 0x8040);  // FTZ (bit 15) and DAZ (bit 6)
#else
    std::cerr << "physik_bench: --flush_subnormals: not available on this processor\n";
    return 2;
#endif
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
