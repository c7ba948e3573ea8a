#include "physik/engine/subnormals.h"

#if defined(__x86_64__) || defined(_M_X64)
#include <xmmintrin.h>
#define PHYSIK_FLUSH_X86 1
#elif defined(__aarch64__)
#define PHYSIK_FLUSH_AARCH64 1
#endif

namespace physik {

namespace {

#if defined(PHYSIK_FLUSH_X86)
constexpr std::uint64_t kFlushBits = 0x8040;  // MXCSR FTZ (bit 15) | DAZ (bit 6)
std::uint64_t read_control() {
  return _mm_getcsr();
}
void write_control(std::uint64_t v) {
  _mm_setcsr(static_cast<unsigned int>(v));
}
#elif defined(PHYSIK_FLUSH_AARCH64)
constexpr std::uint64_t kFlushBits = std::uint64_t{1} << 24;  // FPCR FZ
std::uint64_t read_control() {
  std::uint64_t v;
  asm volatile("mrs %0, fpcr" : "=r"(v));
  return v;
}
void write_control(std::uint64_t v) {
  asm volatile("msr fpcr, %0" : : "r"(v));
}
#else
constexpr std::uint64_t kFlushBits = 0;
std::uint64_t read_control() {
  return 0;
}
void write_control(std::uint64_t) {}
#endif

}  // namespace

bool flush_subnormals_supported() {
  return kFlushBits != 0;
}

FlushSubnormals::FlushSubnormals(bool on) {
  if (!on || kFlushBits == 0) return;
  saved_ = read_control();
  // already set by the caller (a whole program built with -ffast-math): nothing to undo
  if ((saved_ & kFlushBits) == kFlushBits) return;
  write_control(saved_ | kFlushBits);
  set_ = true;
}

FlushSubnormals::~FlushSubnormals() {
  if (set_) write_control(saved_);
}

bool subnormals_flushed() {
  return kFlushBits != 0 && (read_control() & kFlushBits) == kFlushBits;
}

}  // namespace physik
