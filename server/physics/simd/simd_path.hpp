// Which build of the hot loops runs: the wide one (AVX2 and FMA,
// x86-64-v3) where the CPU has it, or the generic x86-64 one (SSE2).
//
// The two give different bits: FMA rounds a*b+c once where SSE2 rounds
// twice, and a vectorised sum adds in 4 lanes instead of 2. Options.
// deterministic pins the generic build on every machine, so a run gives
// the same bits on every x86-64 CPU (see docs/performance.md for what is
// promised and what it costs). Each hot function is written once, as an
// always-inline body instantiated in a GROUNDSIM_WIDE wrapper and a plain
// one; the choice is made per call from the model.
#pragma once

namespace groundsim {

// True when the CPU has x86-64-v3 (checked once) and the model does not ask
// for determinism (Options::deterministic, passed in: this floor knows no
// Model).
bool useWideSimd(bool deterministic);
// "x86-64-v3" or "generic": the build useWideSimd chooses.
const char* simdPathName(bool deterministic);

}  // namespace groundsim

#if defined(__x86_64__)
#define GROUNDSIM_WIDE __attribute__((target("arch=x86-64-v3")))
#else
#define GROUNDSIM_WIDE
#endif
#define GROUNDSIM_INLINE_BODY __attribute__((always_inline)) inline
