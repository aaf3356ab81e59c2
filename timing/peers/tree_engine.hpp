// An mbrt model file (a tree, tree_model.hpp) in a peer engine at a fixed
// step: MuJoCo, Simbody or DART, each built from the model's bodies, joints,
// gravity and initial state. timing/peer_stability runs them for energy,
// timing/work_precision (through tree_peer.hpp) for accuracy.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tree_model.hpp"

namespace timing::tree {

class Engine {
 public:
  virtual ~Engine() = default;
  // One fixed step; false when the state is no longer finite (or the engine
  // failed or reset itself).
  virtual bool step() = 0;
  virtual double time() const = 0;
  virtual std::vector<BodyState> states() = 0;  // in the model's body order
};

// ENGINE-METHOD names of the engines built in: mujoco-euler (semi-implicit),
// mujoco-rk4, simbody-rk3, simbody-rk-merson, simbody-semiexplicit-euler,
// simbody-semiexplicit-euler2 (two half steps a step), dart-euler (World::step,
// semi-implicit Euler).
std::vector<std::string> engines();

// The model (which must outlive the engine) in the named engine at step h.
std::unique_ptr<Engine> make_engine(const std::string& name, const Model& m, double h);

// The engines, each where its library is built in.
std::unique_ptr<Engine> mujoco_engine(const Model& m, const std::string& integrator, double h);
std::unique_ptr<Engine> simbody_engine(const Model& m, const std::string& method, double h);
std::unique_ptr<Engine> dart_engine(const Model& m, double h);

// A reference trajectory from Simbody's error-controlled Runge-Kutta-Merson
// at the given accuracy (relative, per step): the COM of `body` at t = 0,
// dt, 2 dt, ... up to t_end.
std::vector<Vec3> simbody_reference(const Model& m, int body, double t_end, double dt, double accuracy);

}  // namespace timing::tree
