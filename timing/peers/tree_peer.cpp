#include "tree_peer.hpp"

#include <stdexcept>

#include "tree_engine.hpp"

namespace timing {
namespace {

class TreePeer final : public PeerEngine {
 public:
  TreePeer(const Problem& p, const std::string& engine, double h) : model_(mbrt::codegen::load_model(p.model_file)) {
    body_ = model_.bodies.size();
    for (std::size_t i = 0; i < model_.bodies.size(); ++i)
      if (model_.bodies[i].name == p.body) body_ = i;
    if (body_ == model_.bodies.size()) throw std::invalid_argument(p.model_file + " has no body " + p.body);
    engine_ = tree::make_engine(engine, model_, h);
    const std::string mismatch = tree::initial_mismatch(model_, engine_->states());
    if (!mismatch.empty()) throw std::runtime_error(engine + " does not start where " + p.model_file + " does: " + mismatch);
  }
  bool step() override { return engine_->step(); }
  double time() const override { return engine_->time(); }
  mbrt::Vec3 observed() override { return engine_->states()[body_].r; }

 private:
  tree::Model model_;
  std::size_t body_ = 0;
  std::unique_ptr<tree::Engine> engine_;
};

}  // namespace

std::unique_ptr<PeerEngine> tree_peer(const Problem& p, const std::string& engine, double h) {
  return std::make_unique<TreePeer>(p, engine, h);
}

}  // namespace timing
