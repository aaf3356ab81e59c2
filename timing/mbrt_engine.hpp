// A generated mbrt model as a work-precision engine (measure.hpp). Model is a
// BENCH_MODEL adapter (tests/model_adapter.hpp).
#pragma once

#include <stdexcept>

#include <mbrt/model_api.hpp>
#include <mbrt/rotation.hpp>

#include "measure.hpp"

namespace timing {

template <class Model>
class MbrtEngine {
 public:
  explicit MbrtEngine(const Problem& p) : state_(Model::initial_state()) {
    const mbrt::BodyInfo* b = Model::body(p.body);
    if (!b) throw std::invalid_argument("mbrt model has no body " + p.body);
    rigid_ = b->rigid;
    slot_ = b->slot;
    offset_ = p.point - position();  // bodies start unrotated
  }
  bool step() { return Model::step(state_) == mbrt::StepStatus::ok; }
  double time() const { return state_.t; }
  mbrt::Vec3 observed() const {
    if (!rigid_) return position();
    return position() + mbrt::rotation_matrix(state_.rigid[slot_].p) * offset_;
  }

 private:
  mbrt::Vec3 position() const { return rigid_ ? state_.rigid[slot_].r : state_.particle[slot_].r; }

  typename Model::State state_;
  bool rigid_ = false;
  int slot_ = 0;
  mbrt::Vec3 offset_;
};

// method: the scheme, and its euler_updates where they are varied.
template <class Model>
Measurement run_mbrt(const Problem& p, const std::string& method) {
  MbrtEngine<Model> engine(p);
  return measure(p, engine, {p.name, "mbrt", method, Model::kStep});
}

}  // namespace timing
