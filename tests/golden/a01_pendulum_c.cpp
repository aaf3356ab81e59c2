// mbrt generated model 'a01_pendulum' from a01_pendulum.yaml: the C interface of a01_pendulum_c.h over the C++
// one of a01_pendulum.hpp. Generated code: regenerate, do not edit.
#include "a01_pendulum_c.h"

#include <new>

#include <mbrt/c_interface.hpp>

#include "a01_pendulum.hpp"

const char* const a01_pendulum_body_names[A01_PENDULUM_BODIES] = {"bob"};
const char* const a01_pendulum_constraint_names[A01_PENDULUM_CONSTRAINT_BLOCKS] = {"bar"};

namespace {

namespace model = mbrt::models::a01_pendulum;
using mbrt::c_interface::from_c;
using mbrt::c_interface::to_c;

// What a01_pendulum_work holds: the C++ workspace and the state it steps.
struct Work {
  model::State s;
  model::Workspace w;
};

Work& work_of(a01_pendulum_work* w) noexcept { return *std::launder(reinterpret_cast<Work*>(w)); }

void copy(const model::State& s, a01_pendulum_state& c) noexcept {
  to_c(s.t, c.t);
  to_c(s.particle, c.particle);
  to_c(s.particle_acceleration, c.particle_acceleration);
  to_c(s.lambda, c.lambda);
}

void copy(const a01_pendulum_state& c, model::State& s) noexcept {
  from_c(c.t, s.t);
  from_c(c.particle, s.particle);
  from_c(c.particle_acceleration, s.particle_acceleration);
  from_c(c.lambda, s.lambda);
}

model::State state_of(const a01_pendulum_state& c) noexcept {
  model::State s;
  copy(c, s);
  return s;
}

}  // namespace

size_t a01_pendulum_work_size(void) noexcept { return sizeof(Work); }
size_t a01_pendulum_work_align(void) noexcept { return alignof(Work); }

void a01_pendulum_init(a01_pendulum_state* s, a01_pendulum_work* w) noexcept {
  Work* k = new (w) Work;
  k->s = model::initial_state();
  copy(k->s, *s);
}

mbrt_step_status a01_pendulum_step(a01_pendulum_state* s, a01_pendulum_work* w) noexcept {
  Work& k = work_of(w);
  copy(*s, k.s);
  const mbrt::StepStatus status = model::step(k.s, k.w);
  copy(k.s, *s);
  return to_c(status);
}

void a01_pendulum_refresh_bodies(a01_pendulum_state* s) noexcept {
  model::State cpp = state_of(*s);
  model::refresh_bodies(cpp);
  copy(cpp, *s);
}

mbrt_energy a01_pendulum_energy(const a01_pendulum_state* s) noexcept { return to_c(model::energy(state_of(*s))); }

mbrt_constraint_violation a01_pendulum_constraint_violation(const a01_pendulum_state* s) noexcept {
  return to_c(model::constraint_violation(state_of(*s)));
}

void a01_pendulum_reactions(const a01_pendulum_state* s, mbrt_joint_reaction r[A01_PENDULUM_CONSTRAINT_BLOCKS]) noexcept {
  model::Reactions cpp;
  model::reactions(state_of(*s), cpp);
  for (int j = 0; j < A01_PENDULUM_CONSTRAINT_BLOCKS; ++j) to_c(cpp[static_cast<size_t>(j)], r[j]);
}
