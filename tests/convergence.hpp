// Shared by the convergence tests: run a generated model (named by its
// namespace) to a time, and check an observed order of 2 from runs at h,
// h/2, h/4 against a much finer one.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <mbrt/rotation.hpp>

namespace convergence {

struct Final {
  mbrt::Vec3 r;
  mbrt::Mat3 R;
  mbrt::Vec3 w;
};

// COM position + rotation matrix + relative angular velocity differences.
inline double error(const Final& a, const Final& ref) {
  return (a.r - ref.r).norm() + (a.R - ref.R).norm() + (a.w - ref.w).norm() / std::max(1.0, ref.w.norm());
}

inline void check_second_order(const std::string& what, const Final& h1, const Final& h2, const Final& h4,
                               const Final& ref, double min_order = 1.8) {
  const double e1 = error(h1, ref), e2 = error(h2, ref), e4 = error(h4, ref);
  const double p12 = std::log2(e1 / e2), p24 = std::log2(e2 / e4);
  MESSAGE(what << ": errors " << e1 << ", " << e2 << ", " << e4 << "; observed orders " << p12 << ", " << p24);
  CHECK(p12 > min_order);
  CHECK(p12 < 2.3);
  CHECK(p24 > min_order);
  CHECK(p24 < 2.3);
}

}  // namespace convergence

// Final state of the first rigid body of mbrt::models::<model> at t_end.
#define MBRT_RUN_TO(model, t_end)                                                              \
  [&] {                                                                                        \
    namespace m = mbrt::models::model;                                                         \
    m::State s = m::initial_state();                                                           \
    const long n = std::lround((t_end) / m::kStep);                                            \
    for (long i = 0; i < n; ++i) REQUIRE(m::step(s) == mbrt::StepStatus::ok);                  \
    return convergence::Final{s.rigid[0].r, mbrt::rotation_matrix(s.rigid[0].p), s.rigid[0].w}; \
  }()
