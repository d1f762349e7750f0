#include "simd_path.hpp"

namespace groundsim {
namespace {

bool cpuHasWide() {
#if defined(__x86_64__)
  static const bool has = __builtin_cpu_supports("x86-64-v3") != 0;
  return has;
#else
  return false;
#endif
}

}  // namespace

bool useWideSimd(const Model& m) { return !m.opt.deterministic && cpuHasWide(); }

const char* simdPathName(const Model& m) { return useWideSimd(m) ? "x86-64-v3" : "generic"; }

}  // namespace groundsim
