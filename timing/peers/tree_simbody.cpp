#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Simbody.h>

#include "tree_engine.hpp"

namespace timing::tree {
namespace {


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

// accuracy 0: the method at the fixed step h. Otherwise error-controlled at
// that accuracy, h only where the caller asks for states.
std::unique_ptr<SimTK::Integrator> simbody_integrator(const std::string& method, const SimTK::System& system,
                                                      double h, double accuracy) {
  std::unique_ptr<SimTK::Integrator> out;
  if (method == "rk3") out = std::make_unique<SimTK::RungeKutta3Integrator>(system);
  if (method == "rk-merson") out = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
  if (method == "semiexplicit-euler") out = std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system, h);
  if (method == "semiexplicit-euler2") out = std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system);
  if (!out) throw std::invalid_argument("no Simbody integrator " + method);
  if (accuracy > 0) {
    out->setAccuracy(accuracy);
  } else {
    // Equal minimum and maximum step: the error estimates of the
    // error-controlled methods never change it.
    out->setFixedStepSize(h);
  }
  // Without interpolation stepTo ends exactly on the requested time.
  out->setAllowInterpolation(false);
  return out;
}

// The model in mobilizer coordinates: each body's frame is the mbrt body frame
// (origin at the COM), each mobilizer's F and M frames the joint frame at t = 0
// (z along a revolute axis), so q = 0 (identity quaternion) is the t = 0 pose.
class SimbodyEngine final : public Engine {
 public:
  SimbodyEngine(const Model& m, const std::string& method, double h, double accuracy = 0)
      : matter_(system_), forces_(system_), h_(h) {
    SimTK::Force::UniformGravity(forces_, matter_, simtk(gravity(m)));
    const std::vector<BodyState> s = model_states(m);
    const std::vector<Link> tree = links(m);
    index_.resize(m.bodies.size());
    for (const Link& l : tree) add_mobilizer(m, s, l);
    state_ = system_.realizeTopology();
    system_.realize(state_, SimTK::Stage::Position);
    // Simbody's mobilizer velocity is the angular velocity of M relative to
    // F in F's axes; at t = 0 F has the joint frame's world axes.
    for (const Link& l : tree) {
      const Vec3 w_FM = joint_frame(l).transpose() * relative_angular_velocity(s, l);
      matter_.getMobilizedBody(index_[l.body]).setUToFitAngularVelocity(state_, simtk(w_FM));
    }
    system_.realize(state_, SimTK::Stage::Velocity);
    integrator_ = simbody_integrator(method, system_, h, accuracy);
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

  double time() const override { return integrator_->getTime(); }

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


}  // namespace

std::unique_ptr<Engine> simbody_engine(const Model& m, const std::string& method, double h) {
  return std::make_unique<SimbodyEngine>(m, method, h);
}

std::vector<Vec3> simbody_reference(const Model& m, int body, double t_end, double dt, double accuracy) {
  SimbodyEngine engine(m, "rk-merson", dt, accuracy);
  const std::string mismatch = initial_mismatch(m, engine.states());
  if (!mismatch.empty()) throw std::runtime_error("Simbody does not start where the model does: " + mismatch);
  std::vector<Vec3> out{engine.states()[static_cast<std::size_t>(body)].r};
  const long samples = std::lround(t_end / dt);
  for (long k = 1; k <= samples; ++k) {
    if (!engine.step()) throw std::runtime_error("Simbody failed before t = " + std::to_string(k * dt));
    out.push_back(engine.states()[static_cast<std::size_t>(body)].r);
  }
  return out;
}

}  // namespace timing::tree
