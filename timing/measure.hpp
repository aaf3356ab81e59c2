// One work-precision run of any engine: steps to each reference time it
// lands on, timing and counting heap allocations of the stepping only, and
// keeps the largest error of the observed point. An engine is a type with
//   bool step()            one fixed step; false if the engine failed
//   double time() const
//   mbrt::Vec3 observed()  the problem's observed point, world coordinates
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "allocation_counter.hpp"
#include "problems.hpp"

namespace timing {

struct Measurement {
  std::string problem, engine, method;
  double h = 0;
  long steps = 0;
  double error = 0;    // max over the reference samples
  double seconds = 0;  // stepping only
  long allocations = 0;
  bool failed = false;
  long samples = 0;  // reference samples compared (none: the step lands on none of them)
};

// Whether a run at step h lands on time t (a whole number of steps).
inline bool on_step(double t, double h) { return std::abs(t / h - std::round(t / h)) < 1e-6; }

// Compared: the reference samples the run's steps land on, so every engine
// is compared at the times it reached, never one a part of a step away.
// Every run steps to the last sample's time, compared or not, so every run
// is timed over the same span.
template <class Engine>
Measurement measure(const Problem& p, Engine& engine, Measurement m) {
  using Clock = std::chrono::steady_clock;
  for (std::size_t k = 0; k < p.reference.size() && !m.failed; ++k) {
    const Observation& o = p.reference[k];
    const bool compared = on_step(o.t, m.h);
    if (!compared && k + 1 < p.reference.size()) continue;
    long allocations = 0;
    const auto start = Clock::now();
    {
      AllocationCounter counter;
      while (!m.failed && engine.time() < o.t - 0.5 * m.h) {
        m.failed = !engine.step();
        ++m.steps;
      }
      allocations = counter.count();
    }
    m.seconds += std::chrono::duration<double>(Clock::now() - start).count();
    m.allocations += allocations;
    if (m.failed) {  // the engine's state is not to be read
      m.error = std::numeric_limits<double>::infinity();
    } else if (compared) {
      ++m.samples;
      const double e = observation_error(o, engine.observed());
      m.error = std::max(m.error, std::isfinite(e) ? e : std::numeric_limits<double>::infinity());
    }
  }
  return m;
}

}  // namespace timing
