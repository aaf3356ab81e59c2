// Errors of a generated model's step against the independent references of
// reference_solutions.hpp, shared by the tests of the fourth-order schemes.
// Each takes the model's namespace name (mbrt::models::NAME).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "reference_solutions.hpp"

// Largest error of the top's centre-of-mass height against the closed form
// at the tabulated times up to 1 s.
#define HEAVY_TOP_HEIGHT_ERROR(model)                                                       \
  [] {                                                                                      \
    namespace m = mbrt::models::model;                                                      \
    m::State s = m::initial_state();                                                        \
    double worst = 0.0;                                                                     \
    for (const reference::TimedValue& c : reference::kHeavyTopHeight) {                     \
      if (c.t > 1.0) break;                                                                 \
      while (s.t < c.t - 0.5 * m::kStep) REQUIRE(m::step(s) == mbrt::StepStatus::ok);       \
      worst = std::max(worst, std::abs(s.rigid[m::rigid::top].r.z() - c.value));            \
    }                                                                                       \
    return worst;                                                                           \
  }()

// Largest distance of the bob from the reference every 0.5 s up to 2000 s.
#define A01_ERROR(model, ref)                                                               \
  [&] {                                                                                     \
    namespace m = mbrt::models::model;                                                      \
    m::State s = m::initial_state();                                                        \
    const long per_sample = std::lround(0.5 / m::kStep);                                    \
    double worst = 0.0;                                                                     \
    for (std::size_t k = 1; k < (ref).size(); ++k) {                                        \
      for (long i = 0; i < per_sample; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);    \
      const mbrt::Vec3& r = s.particle[m::particle::bob].r;                                 \
      worst = std::max(worst, std::hypot(r.x() - (ref)[k].x(), r.y() - (ref)[k].y()));      \
    }                                                                                       \
    return worst;                                                                           \
  }()

#define ARM_TIP_ERROR(model)                                                                \
  [] {                                                                                      \
    namespace m = mbrt::models::model;                                                      \
    m::State s = m::initial_state();                                                        \
    const long steps = std::lround(0.5 / m::kStep);                                         \
    for (long k = 0; k < steps; ++k) REQUIRE(m::step(s) == mbrt::StepStatus::ok);          \
    return (s.rigid[m::rigid::link_6].r - reference::kArmTipAtHalfSecond).norm();           \
  }()
