#include "physics/simd/vector_math.hpp"

#include <cmath>

#include "physics/simd/simd_path.hpp"

#if defined(GROUNDSIM_HAVE_LIBMVEC) && defined(__x86_64__)
#include <immintrin.h>
// libmvec's AVX2 variants (the x86-64 vector function ABI's 'd' ISA: four
// doubles in a ymm register), declared by their ABI names since glibc's
// <math.h> declares them only under -ffast-math. Declared with AVX2
// enabled: clang refuses a call passing __m256d to a function declared
// without it (the fuzz build's clang 14)
extern "C" {
__attribute__((target("avx2,fma"))) __m256d _ZGVdN4v_atan(__m256d);
__attribute__((target("avx2,fma"))) __m256d _ZGVdN4v_sin(__m256d);
__attribute__((target("avx2,fma"))) __m256d _ZGVdN4v_tanh(__m256d);
}
#define GROUNDSIM_VECTOR_MATH 1
#endif

namespace groundsim {
namespace {

#ifdef GROUNDSIM_VECTOR_MATH
GROUNDSIM_WIDE void atanWide(const double* in, double* out) {
  _mm256_storeu_pd(out, _ZGVdN4v_atan(_mm256_loadu_pd(in)));
}
GROUNDSIM_WIDE void sinWide(const double* in, double* out) {
  _mm256_storeu_pd(out, _ZGVdN4v_sin(_mm256_loadu_pd(in)));
}
GROUNDSIM_WIDE void tanhWide(const double* in, double* out) {
  _mm256_storeu_pd(out, _ZGVdN4v_tanh(_mm256_loadu_pd(in)));
}
#endif

}  // namespace

void atan4(const double* in, double* out, bool wide) {
#ifdef GROUNDSIM_VECTOR_MATH
  if (wide) return atanWide(in, out);
#endif
  (void)wide;
  for (int i = 0; i < 4; ++i) out[i] = std::atan(in[i]);
}

void sin4(const double* in, double* out, bool wide) {
#ifdef GROUNDSIM_VECTOR_MATH
  if (wide) return sinWide(in, out);
#endif
  (void)wide;
  for (int i = 0; i < 4; ++i) out[i] = std::sin(in[i]);
}

void tanh4(const double* in, double* out, bool wide) {
#ifdef GROUNDSIM_VECTOR_MATH
  if (wide) return tanhWide(in, out);
#endif
  (void)wide;
  for (int i = 0; i < 4; ++i) out[i] = std::tanh(in[i]);
}

bool vectorMathAvailable() {
#ifdef GROUNDSIM_VECTOR_MATH
  return true;
#else
  return false;
#endif
}

}  // namespace groundsim
