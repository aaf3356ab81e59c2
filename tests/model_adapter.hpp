// Adapts a generated model's namespace to a type, so the benchmark tests can
// run every scheme's variant of a model through one template:
//   BENCH_MODEL(Pcst, a02_n40_pcst);  then  Pcst::step(s), Pcst::slot("crank0"), Pcst::body("bob") ...
#pragma once

#include <string_view>

#include <mbrt/model_api.hpp>

// A model's step(State&) as a value (step is overloaded with the one that
// takes the caller's Workspace): STEP_OF(mbrt::models::four_bar).
#define STEP_OF(model) [](auto& s) { return model::step(s); }

#define BENCH_MODEL(Tag, ns)                                                                                         \
  struct Tag {                                                                                                       \
    using State = mbrt::models::ns::State;                                                                           \
    static constexpr double kStep = mbrt::models::ns::kStep;                                                         \
    static constexpr const char* kScheme = mbrt::models::ns::kScheme;                                                \
    static State initial_state() { return mbrt::models::ns::initial_state(); }                                       \
    static mbrt::StepStatus step(State& s) { return mbrt::models::ns::step(s); }                                     \
    static mbrt::Energy energy(const State& s) { return mbrt::models::ns::energy(s); }                               \
    static mbrt::ConstraintViolation violation(const State& s) { return mbrt::models::ns::constraint_violation(s); } \
    static double quaternion_norm_error(const State& s) { return mbrt::models::ns::quaternion_norm_error(s); }        \
    static const mbrt::BodyInfo* body(std::string_view name) {                                                       \
      for (const auto& b : mbrt::models::ns::kBodyInfo)                                                              \
        if (name == b.name) return &b;                                                                               \
      return nullptr;                                                                                                \
    }                                                                                                                \
    static int slot(std::string_view name) {                                                                         \
      const mbrt::BodyInfo* b = body(name);                                                                          \
      return b ? b->slot : -1;                                                                                       \
    }                                                                                                                \
  }
