// mbrt generated model 'four_bar' from four_bar.yaml: the C interface of four_bar_c.h over the C++
// one of four_bar.hpp. Generated code: regenerate, do not edit.
#include "four_bar_c.h"

#include <new>

#include <mbrt/c_interface.hpp>

#include "four_bar.hpp"

const char* const four_bar_body_names[FOUR_BAR_BODIES] = {"crank", "coupler", "rocker"};
const char* const four_bar_constraint_names[FOUR_BAR_CONSTRAINT_BLOCKS] = {"pin_o", "pin_a", "pin_b", "pin_c"};

namespace {

namespace model = mbrt::models::four_bar;
using mbrt::c_interface::from_c;
using mbrt::c_interface::to_c;

// What four_bar_work holds: the C++ workspace and the state it steps.
struct Work {
  model::State s;
  model::Workspace w;
};

Work& work_of(four_bar_work* w) noexcept { return *std::launder(reinterpret_cast<Work*>(w)); }

void copy(const model::State& s, four_bar_state& c) noexcept {
  to_c(s.t, c.t);
  to_c(s.rigid, c.rigid);
  to_c(s.rigid_acceleration, c.rigid_acceleration);
  to_c(s.lambda, c.lambda);
}

void copy(const four_bar_state& c, model::State& s) noexcept {
  from_c(c.t, s.t);
  from_c(c.rigid, s.rigid);
  from_c(c.rigid_acceleration, s.rigid_acceleration);
  from_c(c.lambda, s.lambda);
}

model::State state_of(const four_bar_state& c) noexcept {
  model::State s;
  copy(c, s);
  return s;
}

}  // namespace

size_t four_bar_work_size(void) noexcept { return sizeof(Work); }
size_t four_bar_work_align(void) noexcept { return alignof(Work); }

void four_bar_init(four_bar_state* s, four_bar_work* w) noexcept {
  Work* k = new (w) Work;
  k->s = model::initial_state();
  copy(k->s, *s);
}

mbrt_step_status four_bar_step(four_bar_state* s, four_bar_work* w) noexcept {
  Work& k = work_of(w);
  copy(*s, k.s);
  const mbrt::StepStatus status = model::step(k.s, k.w);
  copy(k.s, *s);
  return to_c(status);
}

void four_bar_refresh_bodies(four_bar_state* s) noexcept {
  model::State cpp = state_of(*s);
  model::refresh_bodies(cpp);
  copy(cpp, *s);
}

mbrt_energy four_bar_energy(const four_bar_state* s) noexcept { return to_c(model::energy(state_of(*s))); }

mbrt_constraint_violation four_bar_constraint_violation(const four_bar_state* s) noexcept {
  return to_c(model::constraint_violation(state_of(*s)));
}

void four_bar_reactions(const four_bar_state* s, mbrt_joint_reaction r[FOUR_BAR_CONSTRAINT_BLOCKS]) noexcept {
  model::Reactions cpp;
  model::reactions(state_of(*s), cpp);
  for (int j = 0; j < FOUR_BAR_CONSTRAINT_BLOCKS; ++j) to_c(cpp[static_cast<size_t>(j)], r[j]);
}
