// The C interface steps exactly as the C++ one: the same models stepped
// through <name>_c.h and <name>.hpp give bit-identical states, energies,
// reactions and outputs, and the C step allocates nothing. One model per kind
// of state member: a particle (staggered-pcst), joint coordinates (rk4-tree),
// ali3p's multipliers and generalized-alpha's forces, inputs and outputs, and
// a scene without constraints.
#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>

#include "a01_ali3p.hpp"
#include "a01_ali3p_c.h"
#include "a01_pendulum.hpp"
#include "a01_pendulum_c.h"
#include "a01_revolute_rk4_256.hpp"
#include "a01_revolute_rk4_256_c.h"
#include "actuated.hpp"
#include "actuated_c.h"
#include "allocation_counter.hpp"
#include "heavy_top_generalized_alpha_1.hpp"
#include "heavy_top_generalized_alpha_1_c.h"
#include "spring_pair.hpp"
#include "spring_pair_c.h"

namespace {

// One model's two interfaces, by name.
#define MBRT_BOTH_INTERFACES(NAME)                                                                      \
  struct NAME##_interfaces {                                                                            \
    using CState = NAME##_state;                                                                        \
    using CWork = NAME##_work;                                                                          \
    using State = mbrt::models::NAME::State;                                                            \
    using Workspace = mbrt::models::NAME::Workspace;                                                    \
    static constexpr auto c_work_size = NAME##_work_size, c_work_align = NAME##_work_align;             \
    static constexpr auto c_init = NAME##_init;                                                         \
    static constexpr auto c_step = NAME##_step;                                                         \
    static constexpr auto c_energy = NAME##_energy;                                                     \
    static State initial_state() { return mbrt::models::NAME::initial_state(); }                       \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::NAME::step(s, w); }     \
    static mbrt::Energy energy(const State& s) { return mbrt::models::NAME::energy(s); }                \
  }
MBRT_BOTH_INTERFACES(a01_pendulum);
MBRT_BOTH_INTERFACES(a01_revolute_rk4_256);
MBRT_BOTH_INTERFACES(a01_ali3p);
MBRT_BOTH_INTERFACES(heavy_top_generalized_alpha_1);
MBRT_BOTH_INTERFACES(actuated);
MBRT_BOTH_INTERFACES(spring_pair);

struct Free {
  void operator()(void* p) const { std::free(p); }
};

// A C state with its caller-owned workspace beside a C++ one, from the initial state.
template <class M>
struct Both {
  typename M::CState c;
  std::unique_ptr<typename M::CWork, Free> w{
      static_cast<typename M::CWork*>(std::aligned_alloc(M::c_work_align(), M::c_work_size()))};
  typename M::State s = M::initial_state();
  typename M::Workspace ws;
  Both() { M::c_init(&c, w.get()); }

  // n steps of each; returns the C steps' heap allocations.
  long step(int n) {
    long allocations = 0;
    for (int i = 0; i < n; ++i) {
      mbrt_step_status status;
      {
        AllocationCounter counter;
        status = M::c_step(&c, w.get());
        allocations += counter.count();
      }
      REQUIRE(status == MBRT_STEP_OK);
      REQUIRE(M::step(s, ws) == mbrt::StepStatus::ok);
    }
    return allocations;
  }
};

template <int N>
bool same(const double (&c)[N], const Eigen::Matrix<double, N, 1>& x) {
  for (int i = 0; i < N; ++i)
    if (c[i] != x[i]) return false;
  return true;
}
template <std::size_t N>
bool same(const double (&c)[N], const std::array<double, N>& x) {
  for (std::size_t i = 0; i < N; ++i)
    if (c[i] != x[i]) return false;
  return true;
}

// Every member the C state has against the C++ state's, and the energies.
template <class M>
void check_same(const Both<M>& b) {
  const auto& c = b.c;
  const auto& s = b.s;
  CHECK(c.t == s.t);
  if constexpr (requires { c.rigid; }) {
    for (std::size_t i = 0; i < s.rigid.size(); ++i) {
      CHECK(same(c.rigid[i].r, s.rigid[i].r));
      CHECK(same(c.rigid[i].p, s.rigid[i].p));
      CHECK(same(c.rigid[i].v, s.rigid[i].v));
      CHECK(same(c.rigid[i].w, s.rigid[i].w));
      CHECK(same(c.rigid_acceleration[i].a, s.rigid_acceleration[i].a));
      CHECK(same(c.rigid_acceleration[i].alpha, s.rigid_acceleration[i].alpha));
    }
  }
  if constexpr (requires { c.particle; }) {
    for (std::size_t i = 0; i < s.particle.size(); ++i) {
      CHECK(same(c.particle[i].r, s.particle[i].r));
      CHECK(same(c.particle[i].v, s.particle[i].v));
      CHECK(same(c.particle_acceleration[i], s.particle_acceleration[i]));
    }
  }
  if constexpr (requires { c.lambda; }) CHECK(same(c.lambda, s.lambda));
  if constexpr (requires { c.q; }) {
    CHECK(same(c.q, s.q));
    CHECK(same(c.qd, s.qd));
    CHECK(same(c.qdd, s.qdd));
  }
  if constexpr (requires { c.inputs; }) CHECK(same(c.inputs, s.inputs));
  if constexpr (requires { c.ali3p_lambda_star; }) CHECK(same(c.ali3p_lambda_star, s.ali3p_lambda_star));
  if constexpr (requires { c.ali3p_force; }) {
    for (std::size_t i = 0; i < s.ali3p_force.size(); ++i) CHECK(same(c.ali3p_force[i], s.ali3p_force[i]));
  }
  const mbrt_energy e = M::c_energy(&c);
  CHECK(e.kinetic == M::energy(s).kinetic);
  CHECK(e.potential == M::energy(s).potential);
}

template <class M>
void check_steps(int n) {
  Both<M> b;
  check_same(b);
  CHECK(b.step(n) == 0);
  check_same(b);
}

}  // namespace

TEST_CASE("a particle on a distance joint, staggered-pcst, and its reactions") {
  check_steps<a01_pendulum_interfaces>(400);
  Both<a01_pendulum_interfaces> b;
  b.step(1000);
  mbrt_joint_reaction r[A01_PENDULUM_CONSTRAINT_BLOCKS];
  a01_pendulum_reactions(&b.c, r);
  mbrt::models::a01_pendulum::Reactions cpp;
  mbrt::models::a01_pendulum::reactions(b.s, cpp);
  CHECK(same(r[A01_PENDULUM_CONSTRAINT_BAR].force, cpp[mbrt::models::a01_pendulum::constraint::bar].force));
  CHECK(same(r[A01_PENDULUM_CONSTRAINT_BAR].torque_joint,
             cpp[mbrt::models::a01_pendulum::constraint::bar].torque_joint));
}

TEST_CASE("joint coordinates, rk4-tree") { check_steps<a01_revolute_rk4_256_interfaces>(300); }

TEST_CASE("ali3p's multipliers and generalized-alpha's forces") {
  check_steps<a01_ali3p_interfaces>(200);
  check_steps<heavy_top_generalized_alpha_1_interfaces>(200);
}

TEST_CASE("inputs and outputs") {
  Both<actuated_interfaces> b;
  b.c.inputs[ACTUATED_INPUT_TAU_PIVOT] = 0.3;
  b.s.inputs[mbrt::models::actuated::input::tau_pivot] = 0.3;
  CHECK(b.step(300) == 0);
  check_same(b);
  double y[ACTUATED_OUTPUTS];
  actuated_outputs(&b.c, y);
  mbrt::models::actuated::Outputs cpp;
  mbrt::models::actuated::outputs(b.s, cpp);
  for (int i = 0; i < ACTUATED_OUTPUTS; ++i) CHECK(y[i] == cpp[static_cast<std::size_t>(i)]);
}

TEST_CASE("a scene without constraints") { check_steps<spring_pair_interfaces>(300); }
