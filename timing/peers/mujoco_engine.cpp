#include "mujoco_engine.hpp"

#include <cstring>
#include <memory>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "mujoco_models.hpp"
#include "tree_peer.hpp"

namespace timing {
namespace {

void add_file(mjVFS* vfs, const std::string& name, const std::string& text) {
  if (mj_makeEmptyFileVFS(vfs, name.c_str(), static_cast<int>(text.size())) != 0)
    throw std::runtime_error("MuJoCo: cannot make a virtual file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs, name.c_str())], text.data(), text.size());
}

mjModel* load(const Mjcf& mjcf) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* file = "model.xml";
  add_file(vfs.get(), file, mjcf.main);
  for (const auto& [name, text] : mjcf.includes) add_file(vfs.get(), name, text);
  char error[1000] = "";
  mjModel* m = mj_loadXML(file, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("MuJoCo: ") + error);
  return m;
}

class MujocoEngine final : public PeerEngine {
 public:
  MujocoEngine(const Problem& p, mjtIntegrator integrator, double h) : model_(load(mujoco_mjcf(p))) {
    model_->opt.timestep = h;
    model_->opt.integrator = integrator;
    data_ = mj_makeData(model_);
    if (model_->nkey > 0) mj_resetDataKeyframe(model_, data_, 0);
    body_ = mj_name2id(model_, mjOBJ_BODY, p.body.c_str());
    if (body_ < 0) throw std::invalid_argument("MuJoCo model has no body " + p.body);
    mj_kinematics(model_, data_);
    for (int i = 0; i < 3; ++i) offset_[i] = p.point[i] - data_->xpos[3 * body_ + i];  // bodies start unrotated
  }
  ~MujocoEngine() override {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }
  MujocoEngine(const MujocoEngine&) = delete;
  MujocoEngine& operator=(const MujocoEngine&) = delete;

  // MuJoCo resets the state when accelerations go bad: that is a failure.
  bool step() override {
    mj_step(model_, data_);
    return data_->warning[mjWARN_BADQACC].number == 0;
  }
  double time() const override { return data_->time; }
  mbrt::Vec3 observed() override {
    mj_kinematics(model_, data_);
    const mjtNum* x = data_->xpos + 3 * body_;
    const mjtNum* r = data_->xmat + 9 * body_;  // row-major body-to-world
    mbrt::Vec3 out;
    for (int i = 0; i < 3; ++i) out[i] = x[i] + r[3 * i] * offset_[0] + r[3 * i + 1] * offset_[1] + r[3 * i + 2] * offset_[2];
    return out;
  }

 private:
  mjModel* model_;
  mjData* data_ = nullptr;
  int body_ = -1;
  mbrt::Vec3 offset_;
};

mjtIntegrator integrator(const std::string& method) { return method == "rk4" ? mjINT_RK4 : mjINT_EULER; }

}  // namespace

const std::vector<std::string>& mujoco_methods() {
  static const std::vector<std::string> names{"euler", "rk4"};
  return names;
}

std::unique_ptr<PeerEngine> mujoco_engine(const Problem& p, const std::string& method, double h) {
  if (p.mechanism == Mechanism::model_file) return tree_peer(p, "mujoco-" + method, h);
  return std::make_unique<MujocoEngine>(p, integrator(method), h);
}

Measurement run_mujoco(const Problem& p, const std::string& method, double h) {
  const std::unique_ptr<PeerEngine> engine = mujoco_engine(p, method, h);
  return measure(p, *engine, {p.name, "mujoco", method, h});
}

}  // namespace timing
