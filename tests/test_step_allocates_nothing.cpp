// step() makes no heap allocation: malloc itself is interposed (Eigen's
// temporaries call malloc, not operator new) and counted while armed.
#include <doctest/doctest.h>

#include <cstddef>
#include <cstdlib>
#include <vector>

#include "a01_pendulum.hpp"
#include "four_bar.hpp"
#include "heavy_top.hpp"

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

TEST_CASE("the allocation counter sees heap allocations") {
  long seen = 0;
  {
    AllocationCounter counter;
    std::vector<double> v(1000, 1.0);
    seen = counter.count();
    CHECK(v.back() == 1.0);
  }
  CHECK(seen >= 1);
}

#define CHECK_NO_ALLOCATION(model, steps)                                   \
  do {                                                                      \
    namespace m = mbrt::models::model;                                      \
    m::State s = m::initial_state();                                        \
    m::step(s); /* warm up outside the counted region */                   \
    long bad = 0;                                                           \
    long seen = 0;                                                          \
    {                                                                       \
      AllocationCounter counter;                                            \
      for (long i = 0; i < (steps); ++i) bad += m::step(s) != mbrt::StepStatus::ok; \
      seen = counter.count();                                               \
    }                                                                       \
    CHECK(bad == 0);                                                        \
    CHECK(seen == 0);                                                       \
  } while (false)

TEST_CASE("step() allocates nothing over 1e5 steps") {
  CHECK_NO_ALLOCATION(a01_pendulum, 100000);
  CHECK_NO_ALLOCATION(heavy_top, 100000);
  CHECK_NO_ALLOCATION(four_bar, 100000);
}
