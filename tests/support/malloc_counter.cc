#include "tests/support/malloc_counter.h"

#include <atomic>
#include <cstdlib>
#include <new>

extern "C" void* __libc_malloc(size_t);
extern "C" void* __libc_calloc(size_t, size_t);
extern "C" void* __libc_realloc(void*, size_t);

namespace {
std::atomic<size_t> g_count{0};
}

namespace igms::test {
size_t allocationCount() { return g_count.load(); }
}  // namespace igms::test

// Every allocation path of glibc and libstdc++ ends in one of these.
extern "C" void* malloc(size_t n) {
  g_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
extern "C" void* calloc(size_t n, size_t s) {
  g_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, s);
}
extern "C" void* realloc(void* p, size_t n) {
  g_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
extern "C" void* __libc_memalign(size_t, size_t);
extern "C" int posix_memalign(void** p, size_t alignment, size_t n) {
  g_count.fetch_add(1, std::memory_order_relaxed);
  *p = __libc_memalign(alignment, n);
  return *p ? 0 : 12;  // ENOMEM
}
extern "C" void* aligned_alloc(size_t alignment, size_t n) {
  g_count.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, n);
}
