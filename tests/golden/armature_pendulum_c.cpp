// mbrt generated model 'armature_pendulum' from armature_pendulum.yaml: the C interface of armature_pendulum_c.h over the C++
// one of armature_pendulum.hpp. Generated code: regenerate, do not edit.
#include "armature_pendulum_c.h"

#include <new>

#include <mbrt/c_interface.hpp>

#include "armature_pendulum.hpp"

const char* const armature_pendulum_body_names[ARMATURE_PENDULUM_BODIES] = {"rod"};
const char* const armature_pendulum_constraint_names[ARMATURE_PENDULUM_CONSTRAINT_BLOCKS] = {"pin"};

namespace {

namespace model = mbrt::models::armature_pendulum;
using mbrt::c_interface::from_c;
using mbrt::c_interface::to_c;

// What armature_pendulum_work holds: the C++ workspace and the state it steps.
struct Work {
  model::State s;
  model::Workspace w;
};

Work& work_of(armature_pendulum_work* w) noexcept { return *std::launder(reinterpret_cast<Work*>(w)); }

void copy(const model::State& s, armature_pendulum_state& c) noexcept {
  to_c(s.t, c.t);
  to_c(s.rigid, c.rigid);
  to_c(s.q, c.q);
  to_c(s.qd, c.qd);
  to_c(s.qdd, c.qdd);
  to_c(s.rigid_acceleration, c.rigid_acceleration);
  to_c(s.lambda, c.lambda);
}

void copy(const armature_pendulum_state& c, model::State& s) noexcept {
  from_c(c.t, s.t);
  from_c(c.rigid, s.rigid);
  from_c(c.q, s.q);
  from_c(c.qd, s.qd);
  from_c(c.qdd, s.qdd);
  from_c(c.rigid_acceleration, s.rigid_acceleration);
  from_c(c.lambda, s.lambda);
}

model::State state_of(const armature_pendulum_state& c) noexcept {
  model::State s;
  copy(c, s);
  return s;
}

}  // namespace

size_t armature_pendulum_work_size(void) noexcept { return sizeof(Work); }
size_t armature_pendulum_work_align(void) noexcept { return alignof(Work); }

void armature_pendulum_init(armature_pendulum_state* s, armature_pendulum_work* w) noexcept {
  Work* k = new (w) Work;
  k->s = model::initial_state();
  copy(k->s, *s);
}

mbrt_step_status armature_pendulum_step(armature_pendulum_state* s, armature_pendulum_work* w) noexcept {
  Work& k = work_of(w);
  copy(*s, k.s);
  const mbrt::StepStatus status = model::step(k.s, k.w);
  copy(k.s, *s);
  return to_c(status);
}

void armature_pendulum_refresh_bodies(armature_pendulum_state* s) noexcept {
  model::State cpp = state_of(*s);
  model::refresh_bodies(cpp);
  copy(cpp, *s);
}

void armature_pendulum_set_multipliers(armature_pendulum_state* s) noexcept {
  model::State cpp = state_of(*s);
  model::set_multipliers(cpp);
  copy(cpp, *s);
}

mbrt_energy armature_pendulum_energy(const armature_pendulum_state* s) noexcept { return to_c(model::energy(state_of(*s))); }

mbrt_constraint_violation armature_pendulum_constraint_violation(const armature_pendulum_state* s) noexcept {
  return to_c(model::constraint_violation(state_of(*s)));
}

void armature_pendulum_reactions(const armature_pendulum_state* s, mbrt_joint_reaction r[ARMATURE_PENDULUM_CONSTRAINT_BLOCKS]) noexcept {
  model::Reactions cpp;
  model::reactions(state_of(*s), cpp);
  for (int j = 0; j < ARMATURE_PENDULUM_CONSTRAINT_BLOCKS; ++j) to_c(cpp[static_cast<size_t>(j)], r[j]);
}

void armature_pendulum_outputs(const armature_pendulum_state* s, double y[ARMATURE_PENDULUM_OUTPUTS]) noexcept {
  model::Outputs cpp;
  model::outputs(state_of(*s), cpp);
  for (int i = 0; i < ARMATURE_PENDULUM_OUTPUTS; ++i) y[i] = cpp[static_cast<size_t>(i)];
}
