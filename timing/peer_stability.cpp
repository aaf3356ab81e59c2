// An mbrt model file run in a peer engine at a fixed step, for the long-run
// stability comparison (timing/stability_stress): MuJoCo's or Simbody's
// fixed-step integrators on the same bodies, joints, gravity and initial
// state, with the energy computed here from the engine's body states by the
// definition mbrt uses, so the drifts of all engines and of mbrt compare.
//
//   peer_stability MODEL.yaml --engine ENGINE --h H --t-end T [--series F.csv] [--samples N=1000]
//   peer_stability --list          the engines built in, one a line
//
// ENGINE: mujoco-euler (semi-implicit Euler), mujoco-rk4, simbody-rk3,
// simbody-rk-merson, simbody-semiexplicit-euler, simbody-semiexplicit-euler2
// (two half steps per step), all at the fixed step H.
//
// Models: rigid bodies on revolute and spherical joints forming a tree from
// ground, gravity; nothing else (no springs, forces, drivers, particles).
// Before stepping, the engine's initial state is checked against the model's
// (COM positions, orientations, COM and angular velocities, energy); a
// mismatch is an error (exit 1), so the two runs really start alike.
//
// Prints one JSON line: engine, model, h, steps, finite, t_nonfinite,
// energy_initial, energy_final, max_abs_energy_drift, relative_drift
// (max |E - E0| / |E0|; these three null when the run did not stay finite),
// energy_samples, wall_s, ns_per_step. The energy is sampled every
// max(1, steps / N) steps, at t = 0 and at the last step too; wall_s times the
// steps only, not the sampling. --series writes t,energy per sample.
// Exit status: 0 for a run (finite or not), 1 for a model this cannot run or
// an initial-state mismatch, 2 for a bad command line.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "model.hpp"

#ifdef MBRT_WITH_MUJOCO
#include <mujoco/mujoco.h>
#endif
#ifdef MBRT_WITH_SIMBODY
#include <Simbody.h>
#endif

namespace {

using mbrt::codegen::Body;
using mbrt::codegen::Joint;
using mbrt::codegen::JointType;
using mbrt::codegen::kGround;
using mbrt::codegen::Model;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// ---- The model's side --------------------------------------------------------

// One rigid body's state, all in world axes: COM position and velocity,
// body-to-world rotation, angular velocity.
struct BodyState {
  Vec3 r, v, w;
  Mat3 R;
};

Mat3 rotation(const Eigen::Vector4d& e) { return Eigen::Quaterniond(e[0], e[1], e[2], e[3]).toRotationMatrix(); }

Vec3 gravity(const Model& m) { return m.gravity.value_or(Vec3::Zero()); }

// The model's initial states (its angular velocities are in body axes).
std::vector<BodyState> model_states(const Model& m) {
  std::vector<BodyState> out;
  for (const Body& b : m.bodies) {
    const Mat3 R = rotation(b.orientation);
    out.push_back({b.position, b.velocity, R * b.angular_velocity, R});
  }
  return out;
}

struct Energy {
  double kinetic = 0, potential = 0;
  double total() const { return kinetic + potential; }
};

// mbrt's energy: translational and rotational kinetic energy, and gravity's
// potential -m g.r (zero at the origin).
Energy energy(const Model& m, const std::vector<BodyState>& s) {
  Energy e;
  const Vec3 g = gravity(m);
  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    const Vec3 w_body = s[i].R.transpose() * s[i].w;
    e.kinetic += 0.5 * b.mass * s[i].v.squaredNorm() + 0.5 * w_body.dot(b.inertia * w_body);
    e.potential -= b.mass * g.dot(s[i].r);
  }
  return e;
}

// A body with the joint that connects it to its parent (kGround or a body
// index). tree() lists parents before their children.
struct Link {
  int body;
  int parent;
  const Joint* joint;
};

// The model as a tree from ground, or why it is not one the engines here can run.
std::vector<Link> tree(const Model& m) {
  if (!m.forces.empty() || !m.drivers.empty())
    throw std::runtime_error("only bodies, joints and gravity are supported (the model has forces or drivers)");
  for (const Body& b : m.bodies)
    if (b.particle) throw std::runtime_error("body " + b.name + " is a particle; only rigid bodies are supported");
  for (const Joint& j : m.joints)
    if (j.type != JointType::revolute && j.type != JointType::spherical)
      throw std::runtime_error("joint " + j.name + ": only revolute and spherical joints are supported");
  if (m.joints.size() != m.bodies.size())
    throw std::runtime_error("the joints do not form a tree from ground (one joint per body needed)");
  // Breadth first from ground; a joint may name the parent as body1 or body2.
  std::vector<Link> out;
  std::vector<bool> placed(m.bodies.size(), false);
  std::vector<int> frontier{kGround};
  for (std::size_t k = 0; k < frontier.size(); ++k) {
    for (const Joint& j : m.joints) {
      const int child = j.body1 == frontier[k] ? j.body2 : j.body2 == frontier[k] ? j.body1 : kGround - 1;
      if (child < 0 || placed[child]) continue;
      placed[child] = true;
      out.push_back({child, frontier[k], &j});
      frontier.push_back(child);
    }
  }
  if (out.size() != m.bodies.size())
    throw std::runtime_error("the joints do not form a tree from ground (a loop, or a body not connected to ground)");
  return out;
}

// Angular velocity of a link relative to its parent, world axes, at t = 0.
Vec3 relative_angular_velocity(const std::vector<BodyState>& s, const Link& l) {
  return s[l.body].w - (l.parent == kGround ? Vec3::Zero() : s[l.parent].w);
}

// ---- Engines -----------------------------------------------------------------

class Engine {
 public:
  virtual ~Engine() = default;
  // One fixed step; false when the state is no longer finite (or the engine
  // failed or reset itself).
  virtual bool step() = 0;
  virtual std::vector<BodyState> states() = 0;  // in the model's body order
};

template <class T>
bool all_finite(const T* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

#ifdef MBRT_WITH_MUJOCO

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
Mjcf mjcf(const Model& m, const std::vector<Link>& links, const std::string& integrator, double h) {
  MjcfTree t{m, std::vector<std::vector<const Link*>>(m.bodies.size() + 1), {}};
  for (const Link& l : links) t.children[l.parent + 1].push_back(&l);
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
      : links_(tree(m)), model_(load_mjcf(mjcf(m, links_, integrator, h))), data_(mj_makeData(model_)) {
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

#endif  // MBRT_WITH_MUJOCO

#ifdef MBRT_WITH_SIMBODY

SimTK::Vec3 simtk(const Vec3& v) { return {v[0], v[1], v[2]}; }
SimTK::Rotation simtk(const Mat3& R) {
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = R(i, j);
  return SimTK::Rotation(m);
}
Vec3 eigen(const SimTK::Vec3& v) { return {v[0], v[1], v[2]}; }

// A rotation whose z axis is the unit vector a: the joint frame of a revolute
// joint, since Simbody's Pin turns about its frames' z.
Mat3 frame_with_z(const Vec3& a) { return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), a).toRotationMatrix(); }

std::unique_ptr<SimTK::Integrator> simbody_integrator(const std::string& method, const SimTK::System& system,
                                                      double h) {
  std::unique_ptr<SimTK::Integrator> out;
  if (method == "rk3") out = std::make_unique<SimTK::RungeKutta3Integrator>(system);
  if (method == "rk-merson") out = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
  if (method == "semiexplicit-euler") out = std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system, h);
  if (method == "semiexplicit-euler2") out = std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system);
  if (!out) throw std::invalid_argument("no Simbody integrator " + method);
  // Equal minimum and maximum step: the error estimates of the
  // error-controlled methods never change it. Without interpolation stepTo
  // ends exactly on the requested time.
  out->setFixedStepSize(h);
  out->setAllowInterpolation(false);
  return out;
}

// The model in mobilizer coordinates: each body's frame is the mbrt body frame
// (origin at the COM), each mobilizer's F and M frames the joint frame at t = 0
// (z along a revolute axis), so q = 0 (identity quaternion) is the t = 0 pose.
class SimbodyEngine final : public Engine {
 public:
  SimbodyEngine(const Model& m, const std::string& method, double h)
      : matter_(system_), forces_(system_), h_(h) {
    SimTK::Force::UniformGravity(forces_, matter_, simtk(gravity(m)));
    const std::vector<BodyState> s = model_states(m);
    const std::vector<Link> links = tree(m);
    index_.resize(m.bodies.size());
    for (const Link& l : links) add_mobilizer(m, s, l);
    state_ = system_.realizeTopology();
    system_.realize(state_, SimTK::Stage::Position);
    // Simbody's mobilizer velocity is the angular velocity of M relative to
    // F in F's axes; at t = 0 F has the joint frame's world axes.
    for (const Link& l : links) {
      const Vec3 w_FM = joint_frame(l).transpose() * relative_angular_velocity(s, l);
      matter_.getMobilizedBody(index_[l.body]).setUToFitAngularVelocity(state_, simtk(w_FM));
    }
    system_.realize(state_, SimTK::Stage::Velocity);
    integrator_ = simbody_integrator(method, system_, h);
    integrator_->initialize(state_);
  }

  // Simbody throws when a step fails; a NaN may also pass silently.
  bool step() override {
    const double target = integrator_->getTime() + h_;
    try {
      // The first stepTo after initialize() returns at once (the start of the
      // continuous interval): call until time has advanced.
      while (integrator_->getTime() < target - 0.5 * h_) integrator_->stepTo(target);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "Simbody: %s\n", e.what());
      return false;
    }
    const SimTK::Vector& y = integrator_->getState().getY();
    return all_finite(&y[0], y.size());
  }

  std::vector<BodyState> states() override {
    const SimTK::State& s = integrator_->getState();
    system_.realize(s, SimTK::Stage::Velocity);
    std::vector<BodyState> out;
    for (const SimTK::MobilizedBodyIndex i : index_) {
      const SimTK::MobilizedBody& b = matter_.getMobilizedBody(i);
      const SimTK::Transform& X = b.getBodyTransform(s);
      const SimTK::SpatialVec& V = b.getBodyVelocity(s);  // angular, then the origin's (COM's) linear
      Mat3 R;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) R(r, c) = X.R().asMat33()(r, c);
      out.push_back({eigen(X.p()), eigen(V[1]), eigen(V[0]), R});
    }
    return out;
  }

 private:
  static Mat3 joint_frame(const Link& l) {
    return l.joint->type == JointType::revolute ? frame_with_z(l.joint->axis) : Mat3::Identity();
  }

  // The joint frame seen from a body (or ground) at its t = 0 pose.
  static SimTK::Transform joint_in(const BodyState* body, const Link& l) {
    const Mat3 R = body ? body->R : Mat3::Identity();
    const Vec3 r = body ? body->r : Vec3::Zero();
    return SimTK::Transform(simtk(Mat3(R.transpose() * joint_frame(l))),
                            simtk(Vec3(R.transpose() * (l.joint->point - r))));
  }

  void add_mobilizer(const Model& m, const std::vector<BodyState>& s, const Link& l) {
    const Body& b = m.bodies[l.body];
    const Mat3& J = b.inertia;  // about the COM, body axes: the body frame's origin
    const SimTK::Inertia inertia(SimTK::Vec3(J(0, 0), J(1, 1), J(2, 2)), SimTK::Vec3(J(0, 1), J(0, 2), J(1, 2)));
    const SimTK::Body::Rigid body(SimTK::MassProperties(b.mass, SimTK::Vec3(0), inertia));
    SimTK::MobilizedBody& parent =
        l.parent == kGround ? matter_.updGround() : matter_.updMobilizedBody(index_[l.parent]);
    const SimTK::Transform X_PF = joint_in(l.parent == kGround ? nullptr : &s[l.parent], l);
    const SimTK::Transform X_BM = joint_in(&s[l.body], l);
    if (l.joint->type == JointType::revolute) {
      index_[l.body] = SimTK::MobilizedBody::Pin(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
    } else {
      index_[l.body] = SimTK::MobilizedBody::Ball(parent, X_PF, body, X_BM).getMobilizedBodyIndex();
    }
  }

  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::State state_;
  std::unique_ptr<SimTK::Integrator> integrator_;
  std::vector<SimTK::MobilizedBodyIndex> index_;  // of each mbrt body
  double h_;
};

#endif  // MBRT_WITH_SIMBODY

// ENGINE-METHOD names, as --engine takes them.
std::vector<std::string> engines() {
  std::vector<std::string> out;
#ifdef MBRT_WITH_MUJOCO
  for (const char* m : {"euler", "rk4"}) out.push_back(std::string("mujoco-") + m);
#endif
#ifdef MBRT_WITH_SIMBODY
  for (const char* m : {"rk3", "rk-merson", "semiexplicit-euler", "semiexplicit-euler2"})
    out.push_back(std::string("simbody-") + m);
#endif
  return out;
}

std::unique_ptr<Engine> make_engine(const std::string& name, const Model& m, double h) {
#ifdef MBRT_WITH_MUJOCO
  if (name == "mujoco-euler") return std::make_unique<MujocoEngine>(m, "Euler", h);
  if (name == "mujoco-rk4") return std::make_unique<MujocoEngine>(m, "RK4", h);
#endif
#ifdef MBRT_WITH_SIMBODY
  const std::string prefix = "simbody-";
  if (name.rfind(prefix, 0) == 0) return std::make_unique<SimbodyEngine>(m, name.substr(prefix.size()), h);
#endif
  (void)m, (void)h;
  throw std::invalid_argument("no engine " + name);
}

// ---- The initial-state check -------------------------------------------------

// Empty when the engine starts where the model does, to 1e-9 relative;
// otherwise what differs.
std::string initial_mismatch(const Model& m, const std::vector<BodyState>& engine) {
  const std::vector<BodyState> model = model_states(m);
  double length = 1, speed = 1, dr = 0, dR = 0, dv = 0;
  for (std::size_t i = 0; i < model.size(); ++i) {
    length = std::max(length, model[i].r.norm());
    speed = std::max({speed, model[i].v.norm(), model[i].w.norm()});
    dr = std::max(dr, (engine[i].r - model[i].r).norm());
    dR = std::max(dR, (engine[i].R - model[i].R).cwiseAbs().maxCoeff());
    dv = std::max({dv, (engine[i].v - model[i].v).norm(), (engine[i].w - model[i].w).norm()});
  }
  const Energy e_model = energy(m, model);
  const double dE = std::abs(energy(m, engine).total() - e_model.total());
  const double energy_scale = std::max(std::abs(e_model.total()), e_model.kinetic + std::abs(e_model.potential));
  char text[400];
  std::snprintf(text, sizeof text,
                "COM position %.3g m, orientation %.3g, velocity %.3g (m/s or rad/s), energy %.3g J (relative %.3g)",
                dr, dR, dv, dE, energy_scale > 0 ? dE / energy_scale : 0.0);
  const bool ok = dr <= 1e-9 * length && dR <= 1e-9 && dv <= 1e-9 * speed && dE <= 1e-9 * energy_scale;
  return ok ? "" : text;
}

// ---- The run -----------------------------------------------------------------

struct Options {
  std::string model, engine, series;
  double h = 0, t_end = 0;
  long samples = 1000;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "peer_stability: %s\nusage: peer_stability MODEL.yaml --engine ENGINE --h H --t-end T "
               "[--series F.csv] [--samples N=1000]\n       peer_stability --list\n",
               why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--engine") o.engine = value();
    else if (a == "--h") o.h = std::atof(value().c_str());
    else if (a == "--t-end") o.t_end = std::atof(value().c_str());
    else if (a == "--series") o.series = value();
    else if (a == "--samples") o.samples = std::atol(value().c_str());
    else if (a.rfind("--", 0) == 0 || !o.model.empty()) usage("unexpected " + a);
    else o.model = a;
  }
  if (o.model.empty() || o.engine.empty()) usage("a model file and --engine are needed");
  const std::vector<std::string> built = engines();
  if (std::find(built.begin(), built.end(), o.engine) == built.end())
    usage("no engine " + o.engine + " built in (peer_stability --list)");
  if (!(o.h > 0) || !(o.t_end > 0) || o.samples < 1) usage("--h and --t-end must be positive, --samples at least 1");
  return o;
}

struct Result {
  long steps = 0;  // taken with a finite result
  bool finite = true;
  double t_nonfinite = NAN;
  double e0 = 0, e_final = 0, max_drift = 0;
  long samples = 0;
  double wall_s = 0;
};

// Steps to t_end, sampling the energy every `every` steps (not timed).
Result run(Engine& engine, const Model& m, const Options& o) {
  const long steps = std::max(1L, std::lround(o.t_end / o.h));
  const long every = std::max(1L, steps / o.samples);
  std::ofstream series;
  if (!o.series.empty()) {
    series.open(o.series);
    if (!series) throw std::runtime_error("cannot write " + o.series);
    series << "t,energy\n";
    series.precision(17);
  }
  Result r;
  const auto sample = [&](long k) {
    const double e = energy(m, engine.states()).total();
    if (k == 0) r.e0 = e;
    r.e_final = e;
    r.max_drift = std::max(r.max_drift, std::abs(e - r.e0));
    ++r.samples;
    if (series.is_open()) series << k * o.h << ',' << e << '\n';
    return std::isfinite(e);
  };
  sample(0);
  std::chrono::steady_clock::duration wall{};
  while (r.steps < steps) {
    const long chunk = std::min(every, steps - r.steps);
    const auto start = std::chrono::steady_clock::now();
    long done = 0;
    while (done < chunk && engine.step()) ++done;
    wall += std::chrono::steady_clock::now() - start;
    r.steps += done;
    if (done < chunk || !sample(r.steps)) {
      r.finite = false;
      r.t_nonfinite = (r.steps + (done < chunk ? 1 : 0)) * o.h;
      break;
    }
  }
  r.wall_s = std::chrono::duration<double>(wall).count();
  return r;
}

std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

void print_json(const Options& o, const Model& m, const Result& r) {
  // A run that blew up has no final energy, and its drift is unbounded
  // (MuJoCo has even reset the state): null, not the drift of the samples
  // before, which may be none.
  const double end = r.finite ? r.e_final : NAN, drift = r.finite ? r.max_drift : NAN;
  std::printf(
      "{\"engine\": %s, \"model\": %s, \"h\": %s, \"steps\": %ld, \"finite\": %s, \"t_nonfinite\": %s, "
      "\"energy_initial\": %s, \"energy_final\": %s, \"max_abs_energy_drift\": %s, \"relative_drift\": %s, "
      "\"energy_samples\": %ld, \"wall_s\": %s, \"ns_per_step\": %s}\n",
      json_string(o.engine).c_str(), json_string(m.name).c_str(), json_number(o.h).c_str(), r.steps,
      r.finite ? "true" : "false", json_number(r.t_nonfinite).c_str(), json_number(r.e0).c_str(),
      json_number(end).c_str(), json_number(drift).c_str(),
      json_number(r.e0 != 0 ? drift / std::abs(r.e0) : NAN).c_str(), r.samples, json_number(r.wall_s).c_str(),
      json_number(r.steps > 0 ? 1e9 * r.wall_s / r.steps : NAN).c_str());
}

int main_checked(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const std::string& e : engines()) std::printf("%s\n", e.c_str());
    return 0;
  }
  const Options o = parse(argc, argv);
  const Model m = mbrt::codegen::load_model(o.model);
  tree(m);  // an unsupported model is refused before any engine sees it
  const std::unique_ptr<Engine> engine = make_engine(o.engine, m, o.h);
  const std::string mismatch = initial_mismatch(m, engine->states());
  if (!mismatch.empty()) {
    std::fprintf(stderr, "peer_stability: %s in %s does not start where the model does: %s\n", o.model.c_str(),
                 o.engine.c_str(), mismatch.c_str());
    return 1;
  }
  print_json(o, m, run(*engine, m, o));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return main_checked(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_stability: %s\n", e.what());
    return 1;
  }
}
