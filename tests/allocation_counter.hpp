// Counts heap allocations: malloc itself is interposed (Eigen's temporaries
// call malloc, not operator new) by allocation_counter.cpp, which an
// executable compiles in once; it must link nothing else that replaces
// malloc. AllocationCounter counts the allocations made inside its scope.
#pragma once

namespace allocation_counting {
inline bool armed = false;
inline long allocations = 0;

inline void count() {
  if (armed) ++allocations;
}
}  // namespace allocation_counting

class AllocationCounter {
 public:
  AllocationCounter() {
    allocation_counting::allocations = 0;
    allocation_counting::armed = true;
  }
  ~AllocationCounter() { allocation_counting::armed = false; }
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  long count() const { return allocation_counting::allocations; }
};
