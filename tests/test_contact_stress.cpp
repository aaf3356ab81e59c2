// Contacts on mechanisms under stress, 10 s at 1 kHz in every scheme that
// takes contacts on bodies in joints (tests/models/contact_stress.yaml): a
// spatial arm with a light spinning wrist falling onto the floor, a table
// of welded legs dropped sliding and turning onto four feet, a rope of
// eight links on spherical joints with a bead at each link, a light wheel
// at 1000 rad/s on its axle dropped onto the floor. Every step finite; no
// energy created (impacts and friction only take it; the smooth step's own
// error is bounded below); the table and the rope come to rest; the wheel
// rolls off at r w0 J / (J + (m + m_a) r^2), its angular momentum about the
// contact point kept through the landing and the slip.
#include <doctest/doctest.h>

#include <cmath>

#include "contact_stress.hpp"
#include "contact_stress_baumgarte.hpp"
#include "contact_stress_blajer.hpp"
#include "contact_stress_rk4.hpp"

namespace {

template <class State, class Step, class Energy>
void check_stress(State& s, Step step, Energy energy) {
  const double e0 = energy(s);
  double highest = e0;
  for (int n = 0; n < 10000; ++n) {
    REQUIRE(step(s) == mbrt::StepStatus::ok);
    highest = std::max(highest, energy(s));
  }
  MESSAGE("energy: " << e0 << " J at the start, at most " << highest << ", " << energy(s) << " at 10 s");
  CHECK(highest <= e0 * (1.0 + 1e-6));
  CHECK(energy(s) < e0);
}

}  // namespace

TEST_CASE("contacts on an arm, a table, a rope and a fast light wheel stay finite and take energy only, at 1 kHz") {
  // The wheel: r = 0.02 m, J = 1.6e-6, m = 0.01 kg, axle 0.2 kg, w0 = 1000 rad/s.
  const double rolling = 0.02 * 1000.0 * 1.6e-6 / (1.6e-6 + 0.21 * 0.02 * 0.02);
#define STRESS_SCHEME(ns)                                                                                 \
  {                                                                                                       \
    namespace m = mbrt::models::ns;                                                                       \
    m::State s = m::initial_state();                                                                      \
    check_stress(s, [](m::State& x) { return m::step(x); }, [](const m::State& x) { return m::energy(x).total(); }); \
    CHECK(s.rigid[m::rigid::light_wheel].v.x() == doctest::Approx(rolling).epsilon(1e-6));               \
    CHECK(s.rigid[m::rigid::top].v.norm() < 1e-9);                                                        \
    for (const int c : {m::contact::foot0, m::contact::foot1, m::contact::foot2, m::contact::foot3}) {    \
      CHECK(s.contact_stuck[c] == 1.0);                                                                   \
    }                                                                                                     \
    CHECK(s.rigid[m::rigid::link4].v.norm() < 1e-6);                                                      \
  }
  SUBCASE("staggered-pcst") STRESS_SCHEME(contact_stress)
  SUBCASE("baumgarte") STRESS_SCHEME(contact_stress_baumgarte)
  SUBCASE("blajer") STRESS_SCHEME(contact_stress_blajer)
  SUBCASE("rk4-projected") STRESS_SCHEME(contact_stress_rk4)
#undef STRESS_SCHEME
}
