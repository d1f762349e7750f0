// Actions for batched-environment tests and benchmarks: every control moved
// through its range, different per environment and step, deterministic
// (the same sequence in process and remote).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "experiments/batch_env.hpp"

namespace groundsim::test {

inline std::vector<float> sweepActions(const experiments::Layout& l, int n, int step) {
  std::vector<float> a(static_cast<std::size_t>(n) * l.actionSize());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < l.actionSize(); ++j) {
      const float lo = std::isfinite(l.action_low[j]) ? l.action_low[j] : -1.0f;
      const float hi = std::isfinite(l.action_high[j]) ? l.action_high[j] : 1.0f;
      const float u = 0.5f + 0.45f * std::sin(0.3f * step + 1.7f * i + 2.9f * j);
      a[static_cast<std::size_t>(i) * l.actionSize() + j] = lo + (hi - lo) * u;
    }
  return a;
}

}  // namespace groundsim::test
