#include "physics/simd/simd_path.hpp"

namespace groundsim {
namespace {

bool cpuHasWide() {
#if defined(__x86_64__)
#if defined(__clang__) && __clang_major__ < 16
  // clang before 16 (the fuzz build's clang 14) knows no level names here:
  // the x86-64-v3 features it can ask for (every CPU with these has the
  // rest of the level: F16C, LZCNT, MOVBE)
  static const bool has = __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") &&
                          __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                          __builtin_cpu_supports("bmi2");
#else
  static const bool has = __builtin_cpu_supports("x86-64-v3") != 0;
#endif
  return has;
#else
  return false;
#endif
}

}  // namespace

bool useWideSimd(bool deterministic) { return !deterministic && cpuHasWide(); }

const char* simdPathName(bool deterministic) {
  return useWideSimd(deterministic) ? "x86-64-v3" : "generic";
}

}  // namespace groundsim
