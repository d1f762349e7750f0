// Counts every heap allocation of the test binary that includes it, at
// malloc (Eigen allocates with malloc, operator new calls it): malloc,
// calloc, realloc and the aligned allocators are interposed and forwarded
// to glibc's own. Include it in exactly one source file of a binary.
#pragma once

#include <atomic>
#include <cstddef>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
}

namespace groundsim::test {
inline std::atomic<long> g_allocations{0};
inline void countAllocation() { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace groundsim::test

extern "C" {
void* malloc(std::size_t n) {
  groundsim::test::countAllocation();
  return __libc_malloc(n);
}
void* calloc(std::size_t k, std::size_t n) {
  groundsim::test::countAllocation();
  return __libc_calloc(k, n);
}
void* realloc(void* p, std::size_t n) {
  groundsim::test::countAllocation();
  return __libc_realloc(p, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  groundsim::test::countAllocation();
  return __libc_memalign(a, n);
}
void* memalign(std::size_t a, std::size_t n) {
  groundsim::test::countAllocation();
  return __libc_memalign(a, n);
}
int posix_memalign(void** p, std::size_t a, std::size_t n) {
  groundsim::test::countAllocation();
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;  // ENOMEM
}
}
