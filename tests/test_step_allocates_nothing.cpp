// step() makes no heap allocation, counted by a malloc interposer.
#include <doctest/doctest.h>

#include <vector>

#include "a01_pendulum.hpp"
#include "allocation_counter.hpp"
#include "four_bar.hpp"
#include "heavy_top.hpp"

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
