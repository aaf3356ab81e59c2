// Counts heap allocations: malloc itself is interposed (Eigen's temporaries
// call malloc, not operator new) and counted while an AllocationCounter is
// alive. Defines malloc and friends: include it in exactly one source file
// of a test executable, and link nothing else that replaces malloc.
#pragma once

#include <cstddef>

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void __libc_free(void*);
}

namespace {
bool armed = false;
long allocations = 0;

void count() {
  if (armed) ++allocations;
}

// Counts allocations inside its scope.
class AllocationCounter {
 public:
  AllocationCounter() {
    allocations = 0;
    armed = true;
  }
  ~AllocationCounter() { armed = false; }
  long count() const { return allocations; }
};
}  // namespace

extern "C" {
void* malloc(size_t n) {
  count();
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t m) {
  count();
  return __libc_calloc(n, m);
}
void* realloc(void* p, size_t n) {
  count();
  return __libc_realloc(p, n);
}
void* aligned_alloc(size_t a, size_t n) {
  count();
  return __libc_memalign(a, n);
}
int posix_memalign(void** p, size_t a, size_t n) {
  count();
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;
}
void free(void* p) { __libc_free(p); }
}
