// Each environment's random stream: SplitMix64 (Steele, Lea and Flood,
// "Fast splittable pseudorandom number generators", OOPSLA 2014), with our
// own uniform mapping. Both are a few lines of integer arithmetic fixed
// here, not a standard library's choice, so a seed gives the same draws on
// every platform and library version, and the whole state is one 64-bit
// word (what a snapshot stores).
#pragma once

#include <cstdint>

namespace groundsim::experiments {

class Rng {
 public:
  static constexpr std::uint64_t kGamma = 0x9E3779B97F4A7C15ull;

  // The seed is mixed first, so seeds s and s + 1 (environments i and i + 1
  // of one reset) start far apart in the sequence.
  void seed(std::uint64_t s) { state_ = mix(s); }
  std::uint64_t next() {
    state_ += kGamma;
    return mix(state_);
  }
  // Uniform in [0, 1): the top 53 bits as a double's mantissa.
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }
  // Uniform in [lo, hi); exactly lo when lo == hi.
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }

  std::uint64_t state() const { return state_; }
  void setState(std::uint64_t s) { state_ = s; }

  static std::uint64_t mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_ = 0;
};

}  // namespace groundsim::experiments
