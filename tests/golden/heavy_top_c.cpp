// mbrt generated model 'heavy_top' from heavy_top.yaml: the C interface of heavy_top_c.h over the C++
// one of heavy_top.hpp. Generated code: regenerate, do not edit.
#include "heavy_top_c.h"

#include <new>

#include <mbrt/c_interface.hpp>

#include "heavy_top.hpp"

const char* const heavy_top_body_names[HEAVY_TOP_BODIES] = {"top"};
const char* const heavy_top_constraint_names[HEAVY_TOP_CONSTRAINT_BLOCKS] = {"tip"};

namespace {

namespace model = mbrt::models::heavy_top;
using mbrt::c_interface::from_c;
using mbrt::c_interface::to_c;

// What heavy_top_work holds: the C++ workspace and the state it steps.
struct Work {
  model::State s;
  model::Workspace w;
};

Work& work_of(heavy_top_work* w) noexcept { return *std::launder(reinterpret_cast<Work*>(w)); }

void copy(const model::State& s, heavy_top_state& c) noexcept {
  to_c(s.t, c.t);
  to_c(s.rigid, c.rigid);
  to_c(s.rigid_acceleration, c.rigid_acceleration);
  to_c(s.lambda, c.lambda);
}

void copy(const heavy_top_state& c, model::State& s) noexcept {
  from_c(c.t, s.t);
  from_c(c.rigid, s.rigid);
  from_c(c.rigid_acceleration, s.rigid_acceleration);
  from_c(c.lambda, s.lambda);
}

model::State state_of(const heavy_top_state& c) noexcept {
  model::State s;
  copy(c, s);
  return s;
}

}  // namespace

size_t heavy_top_work_size(void) noexcept { return sizeof(Work); }
size_t heavy_top_work_align(void) noexcept { return alignof(Work); }

void heavy_top_init(heavy_top_state* s, heavy_top_work* w) noexcept {
  Work* k = new (w) Work;
  k->s = model::initial_state();
  copy(k->s, *s);
}

mbrt_step_status heavy_top_step(heavy_top_state* s, heavy_top_work* w) noexcept {
  Work& k = work_of(w);
  copy(*s, k.s);
  const mbrt::StepStatus status = model::step(k.s, k.w);
  copy(k.s, *s);
  return to_c(status);
}

void heavy_top_refresh_bodies(heavy_top_state* s) noexcept {
  model::State cpp = state_of(*s);
  model::refresh_bodies(cpp);
  copy(cpp, *s);
}

mbrt_energy heavy_top_energy(const heavy_top_state* s) noexcept { return to_c(model::energy(state_of(*s))); }

mbrt_constraint_violation heavy_top_constraint_violation(const heavy_top_state* s) noexcept {
  return to_c(model::constraint_violation(state_of(*s)));
}

void heavy_top_reactions(const heavy_top_state* s, mbrt_joint_reaction r[HEAVY_TOP_CONSTRAINT_BLOCKS]) noexcept {
  model::Reactions cpp;
  model::reactions(state_of(*s), cpp);
  for (int j = 0; j < HEAVY_TOP_CONSTRAINT_BLOCKS; ++j) to_c(cpp[static_cast<size_t>(j)], r[j]);
}
