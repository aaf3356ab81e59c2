// The malloc interposer behind AllocationCounter: counts, then forwards to glibc.
#include "allocation_counter.hpp"

#include <cstddef>

extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void __libc_free(void*);

void* malloc(size_t n) {
  allocation_counting::count();
  return __libc_malloc(n);
}
void* calloc(size_t n, size_t m) {
  allocation_counting::count();
  return __libc_calloc(n, m);
}
void* realloc(void* p, size_t n) {
  allocation_counting::count();
  return __libc_realloc(p, n);
}
void* aligned_alloc(size_t a, size_t n) {
  allocation_counting::count();
  return __libc_memalign(a, n);
}
int posix_memalign(void** p, size_t a, size_t n) {
  allocation_counting::count();
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;
}
void free(void* p) { __libc_free(p); }
}
