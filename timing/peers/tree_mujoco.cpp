#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <mujoco/mujoco.h>

#include "tree_engine.hpp"

namespace timing::tree {
namespace {


std::string numbers(std::initializer_list<double> xs) {
  std::ostringstream o;
  o.precision(17);
  for (double x : xs) o << (o.tellp() > 0 ? " " : "") << x;
  return o.str();
}
std::string numbers(const Vec3& v) { return numbers({v[0], v[1], v[2]}); }
std::string numbers(const Eigen::Quaterniond& q) { return numbers({q.w(), q.x(), q.y(), q.z()}); }

// The inertial frame of a body in world axes and its principal moments:
// MuJoCo takes a diagonal inertia in a frame of its own, mbrt's is a full
// matrix in body axes.
std::pair<Eigen::Quaterniond, Vec3> principal_frame(const Body& b) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(b.inertia);
  Mat3 axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) *= -1;  // a rotation, not a reflection
  return {Eigen::Quaterniond(rotation(b.orientation) * axes).normalized(), eig.eigenvalues()};
}

// MJCF as MuJoCo reads it: the main file and the files it includes
// (part0.xml, part1.xml, ...).
struct Mjcf {
  std::string main;
  std::vector<std::string> parts;
};

// Bodies nested deeper than this go to an included file: MuJoCo's XML parser
// refuses elements nested more than 100 deep (a 128-link chain), and it parses
// each included file on its own.
constexpr int kMaxNesting = 50;

struct MjcfTree {
  const Model& model;
  std::vector<std::vector<const Link*>> children;  // of each body, index + 1 (0: ground)
  std::vector<std::string> parts;
};

// A body in global coordinates: its frame the mbrt body frame (origin at the
// COM) at its t = 0 pose, then its subtree.
void write_body(MjcfTree& t, const Link& l, int depth, std::ostream& o) {
  const std::string indent(2 * depth, ' ');
  if (depth > kMaxNesting) {
    std::ostringstream part;
    part << "<mujocoinclude>\n";
    write_body(t, l, 1, part);
    part << "</mujocoinclude>\n";
    t.parts.push_back(part.str());
    o << indent << "<include file='part" << t.parts.size() - 1 << ".xml'/>\n";
    return;
  }
  const Body& b = t.model.bodies[l.body];
  const auto [inertial_frame, moments] = principal_frame(b);
  const Eigen::Vector4d& e = b.orientation;
  o << indent << "<body name='b" << l.body << "' pos='" << numbers(b.position) << "' quat='"
    << numbers({e[0], e[1], e[2], e[3]}) << "'>\n"
    << indent << "  <inertial pos='" << numbers(b.position) << "' quat='" << numbers(inertial_frame) << "' mass='"
    << numbers({b.mass}) << "' diaginertia='" << numbers(moments) << "'/>\n"
    << indent << "  <joint type='" << (l.joint->type == JointType::revolute ? "hinge" : "ball") << "' pos='"
    << numbers(l.joint->point) << "'";
  if (l.joint->type == JointType::revolute) o << " axis='" << numbers(l.joint->axis) << "'";
  o << " damping='0' armature='0' frictionloss='0' limited='false'/>\n";
  for (const Link* c : t.children[l.body + 1]) write_body(t, *c, depth + 1, o);
  o << indent << "</body>\n";
}

// The model in MuJoCo: each body nested under its parent, no contacts, no
// damping, armature or friction in the joints.
Mjcf mjcf(const Model& m, const std::vector<Link>& tree, const std::string& integrator, double h) {
  MjcfTree t{m, std::vector<std::vector<const Link*>>(m.bodies.size() + 1), {}};
  for (const Link& l : tree) t.children[l.parent + 1].push_back(&l);
  std::ostringstream o;
  o << "<mujoco model='peer_stability'>\n"
    << "  <compiler coordinate='global' angle='radian' inertiafromgeom='false'/>\n"
    << "  <option timestep='" << numbers({h}) << "' integrator='" << integrator << "' gravity='"
    << numbers(gravity(m)) << "'>\n"
    << "    <flag contact='disable' constraint='disable'/>\n  </option>\n  <worldbody>\n";
  for (const Link* top : t.children[0]) write_body(t, *top, 2, o);
  o << "  </worldbody>\n</mujoco>\n";
  return {o.str(), t.parts};
}

// MuJoCo's messages go to stderr: stdout carries the JSON line.
void mujoco_warning(const char* message) { std::fprintf(stderr, "MuJoCo: %s\n", message); }

void add_file(mjVFS* vfs, const std::string& name, const std::string& text) {
  if (mj_makeEmptyFileVFS(vfs, name.c_str(), static_cast<int>(text.size())) != 0)
    throw std::runtime_error("MuJoCo: cannot make a virtual file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs, name.c_str())], text.data(), text.size());
}

mjModel* load_mjcf(const Mjcf& xml) {
  mju_user_warning = mujoco_warning;
  auto vfs = std::make_unique<mjVFS>();  // about 2 MB: not on the stack
  mj_defaultVFS(vfs.get());
  add_file(vfs.get(), "peer_stability.xml", xml.main);
  for (std::size_t i = 0; i < xml.parts.size(); ++i)
    add_file(vfs.get(), "part" + std::to_string(i) + ".xml", xml.parts[i]);
  char error[1000] = "";
  mjModel* model = mj_loadXML("peer_stability.xml", vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!model) throw std::runtime_error(std::string("MuJoCo cannot load the model: ") + error);
  return model;
}

class MujocoEngine final : public Engine {
 public:
  MujocoEngine(const Model& m, const std::string& integrator, double h)
      : links_(links(m)), model_(load_mjcf(mjcf(m, links_, integrator, h))), data_(mj_makeData(model_)) {
    for (std::size_t i = 0; i < m.bodies.size(); ++i)
      body_id_.push_back(mj_name2id(model_, mjOBJ_BODY, ("b" + std::to_string(i)).c_str()));
    set_initial_velocities(model_states(m));
    mj_forward(model_, data_);
  }
  ~MujocoEngine() override {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }
  MujocoEngine(const MujocoEngine&) = delete;
  MujocoEngine& operator=(const MujocoEngine&) = delete;

  // MuJoCo does not stop on a bad state: it resets to the initial pose and
  // counts a warning, which would hide a blow-up. Both count as the end here.
  bool step() override {
    mj_step(model_, data_);
    for (int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC})
      if (data_->warning[w].number > 0) return false;
    return all_finite(data_->qpos, model_->nq) && all_finite(data_->qvel, model_->nv);
  }

  double time() const override { return data_->time; }

  std::vector<BodyState> states() override {
    // mj_step leaves the positions and velocities derived from the state
    // before its last update: recompute them for the current one.
    mj_kinematics(model_, data_);
    mj_comPos(model_, data_);
    mj_comVel(model_, data_);
    std::vector<BodyState> out;
    for (int id : body_id_) {
      mjtNum vel[6];  // angular, then the COM's linear velocity, world axes
      mj_objectVelocity(model_, data_, mjOBJ_BODY, id, vel, 0);
      out.push_back({Vec3(data_->xipos + 3 * id), Vec3(vel + 3), Vec3(vel),
                     Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(data_->xmat + 9 * id)});
    }
    return out;
  }

 private:
  // Joint rates from the bodies' angular velocities: a hinge's rate is the
  // relative angular velocity along its axis; a ball's velocity is the
  // relative angular velocity in the child's frame (MuJoCo integrates ball
  // quaternions in the moving frame).
  void set_initial_velocities(const std::vector<BodyState>& s) {
    for (const Link& l : links_) {
      const int dof = model_->jnt_dofadr[model_->body_jntadr[body_id_[l.body]]];
      const Vec3 w = relative_angular_velocity(s, l);
      if (l.joint->type == JointType::revolute) {
        data_->qvel[dof] = l.joint->axis.dot(w);
      } else {
        Eigen::Map<Vec3>(data_->qvel + dof) = s[l.body].R.transpose() * w;
      }
    }
  }

  std::vector<Link> links_;
  mjModel* model_;
  mjData* data_;
  std::vector<int> body_id_;  // MuJoCo's body id of each mbrt body
};


}  // namespace

std::unique_ptr<Engine> mujoco_engine(const Model& m, const std::string& integrator, double h) {
  return std::make_unique<MujocoEngine>(m, integrator, h);
}

}  // namespace timing::tree
