// Counts every heap allocation of the test binary that includes it, at
// malloc (Eigen allocates with malloc, operator new calls it): malloc,
// calloc, realloc and the aligned allocators are interposed and forwarded
// to glibc's own. Include it in exactly one source file of a binary.
// Under AddressSanitizer, which owns malloc (interposing it again breaks
// ASan's start-up), the count comes from ASan's allocation hook instead.
#pragma once

#include <atomic>
#include <cstddef>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GROUNDSIM_TEST_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define GROUNDSIM_TEST_ASAN 1
#endif

#ifndef GROUNDSIM_TEST_ASAN
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
}
#endif

namespace groundsim::test {
inline std::atomic<long> g_allocations{0};
inline void countAllocation() { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace groundsim::test

#ifdef GROUNDSIM_TEST_ASAN
// sanitizer/allocator_interface.h's declaration (gcc ships no such header)
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*)(const volatile void*, std::size_t),
                                                         void (*)(const volatile void*));

namespace groundsim::test {
inline void onAsanMalloc(const volatile void*, std::size_t) { countAllocation(); }
inline void onAsanFree(const volatile void*) {}
// installed before main, like the interposed functions below are in force
inline const int g_asan_hooks = __sanitizer_install_malloc_and_free_hooks(onAsanMalloc, onAsanFree);
}  // namespace groundsim::test
#else
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
#endif
