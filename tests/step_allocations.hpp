// Heap allocations in a generated model's steps (allocation_counter.hpp: the
// executable must compile allocation_counter.cpp in).
#pragma once

#include <doctest/doctest.h>

#include <mbrt/step_status.hpp>

#include "allocation_counter.hpp"

// Heap allocations in `steps` steps from M's initial state, in one workspace.
template <class M>
long allocations_in(int steps) {
  typename M::State s = M::initial_state();
  static typename M::Workspace w;
  AllocationCounter counter;
  for (int i = 0; i < steps; ++i) REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
  return counter.count();
}
