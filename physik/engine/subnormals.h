// Subnormal numbers flushed to zero for the duration of a step (engine.cpp step(), the parameter
// `flush_subnormals`; docs/engine.md "Subnormal numbers").
//
// A double below 2.2e-308 in magnitude is subnormal: IEEE 754 keeps it with fewer significant
// bits, and x86 processors compute an operation that takes or gives one in microcode, some
// 10-100x slower than the same operation on normal numbers. A long chain pulled at one end from
// rest fills with them: the pull's effect on the accelerations decays by a constant factor per
// joint along the chain, so past some hundred bones from the pulled end the recursion's
// accelerations, velocities and their products pass through 1e-308 on their way to exact zeros
// (the scaling experiment's 10,000-bone chain took 2.3x the time per bone of its 100-bone chain,
// flat in instructions). Physically these numbers are nothing: 1e-308 rig units/s moves no bone.
//
// FlushSubnormals sets the processor's flush modes on construction and restores the caller's
// control register on destruction, whatever the step did (an exception included):
//   x86-64   MXCSR bit 15 FTZ (a subnormal result becomes a signed 0) and bit 6 DAZ (a subnormal
//            operand is read as 0), for the SSE arithmetic every double here uses (Intel SDM
//            vol. 1, 10.2.3.3 and 10.2.3.4);
//   AArch64  FPCR bit 24 FZ (subnormal operands and results of single and double precision are
//            0; Arm ARM, "FPCR, Floating-point Control Register");
//   elsewhere nothing (flush_subnormals_supported() says false): the step runs as without.
// The modes are per thread: another thread, and the caller after the step, see their own.
#pragma once

#include <cstdint>

namespace physik {

// Whether this processor's flush modes are known to FlushSubnormals.
bool flush_subnormals_supported();

// The flush modes set for the lifetime of the object when `on` (nothing otherwise); the previous
// control register restored when it ends. Out of line, so that the step's arithmetic, in other
// functions, cannot be moved across the register writes.
class FlushSubnormals {
 public:
  explicit FlushSubnormals(bool on);
  ~FlushSubnormals();
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;

 private:
  bool set_ = false;         // whether the constructor changed the register
  std::uint64_t saved_ = 0;  // the caller's MXCSR or FPCR
};

// Whether the calling thread computes with subnormals flushed now (for the tests).
bool subnormals_flushed();

}  // namespace physik
