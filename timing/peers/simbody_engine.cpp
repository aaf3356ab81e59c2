#include "simbody_engine.hpp"

#include <map>
#include <memory>
#include <stdexcept>

#include <Simbody.h>

#include "andrews_mechanism.hpp"
#include "tree_peer.hpp"

namespace timing {
namespace {

// Constraint tolerance: far below every compared error, so the projection is
// never what limits Simbody's accuracy.
constexpr double kConstraintTolerance = 1e-10;

SimTK::Vec3 vec(const mbrt::Vec3& v) { return {v[0], v[1], v[2]}; }

// A body of the given mass, centre of mass and central inertia diag(i).
SimTK::Body::Rigid rigid_body(double mass, const SimTK::Vec3& com, const SimTK::Vec3& i) {
  return SimTK::Body::Rigid(SimTK::MassProperties(mass, com, SimTK::Inertia(i).shiftFromMassCenter(com, mass)));
}

// A uniform 1 kg, 1 m rod starting at its body origin along x or y: m L^2/12
// transverse, 1e-4 axial (as the mbrt models).
SimTK::Body::Rigid rod(char axis) {
  const double t = 1.0 / 12.0;
  return axis == 'x' ? rigid_body(1, {0.5, 0, 0}, {1e-4, t, t}) : rigid_body(1, {0, 0.5, 0}, {t, 1e-4, t});
}

class Mechanism {
 public:
  explicit Mechanism(const Problem& p) : matter_(system_), forces_(system_) {
    SimTK::Force::UniformGravity(forces_, matter_, vec(gravity(p.mechanism)));
    switch (p.mechanism) {
      case timing::Mechanism::a01_pendulum: build_a01(); break;
      case timing::Mechanism::heavy_top: build_heavy_top(); break;
      case timing::Mechanism::n_four_bar: build_n_four_bar(p.n); break;
      case timing::Mechanism::chain: build_chain(p.n); break;
      case timing::Mechanism::andrews: build_andrews(); break;
      case timing::Mechanism::model_file: throw std::logic_error("a model file is built by tree_peer");
    }
    state_ = system_.realizeTopology();
    system_.realize(state_, SimTK::Stage::Position);
    for (const auto& [index, rate] : initial_rates_) matter_.getMobilizedBody(index).setUToFitAngularVelocity(state_, rate);
    system_.realize(state_, SimTK::Stage::Velocity);
  }
  SimTK::MultibodySystem& system() { return system_; }
  const SimTK::State& initial_state() const { return state_; }
  const SimTK::MobilizedBody& body(const std::string& name) const {
    const auto it = bodies_.find(name);
    if (it == bodies_.end()) throw std::invalid_argument("Simbody mechanism has no body " + name);
    return matter_.getMobilizedBody(it->second);
  }

 private:
  SimTK::MobilizedBody::Pin pin(SimTK::MobilizedBody& parent, const SimTK::Vec3& at, const SimTK::Body& b,
                                const std::string& name) {
    SimTK::MobilizedBody::Pin m(parent, SimTK::Transform(at), b, SimTK::Transform());
    bodies_[name] = m.getMobilizedBodyIndex();
    return m;
  }

  void build_a01() {
    // The bob is a point mass at the body origin, on a massless bar to the
    // pivot (a zero inertia fails Simbody's checks by round-off; 1e-12 kg m^2
    // changes nothing at the compared digits, as in MuJoCo).
    SimTK::MobilizedBody::Pin bob(matter_.Ground(), SimTK::Transform(), rigid_body(1, {0, 0, 0}, {1e-12, 1e-12, 1e-12}),
                                  SimTK::Transform(SimTK::Vec3(1, 0, 0)));
    bodies_["bob"] = bob.getMobilizedBodyIndex();
  }

  void build_heavy_top() {
    SimTK::MobilizedBody::Ball top(matter_.Ground(), SimTK::Transform(),
                                   rigid_body(15, {0, 1, 0}, {0.234375, 0.46875, 0.234375}), SimTK::Transform());
    bodies_["top"] = top.getMobilizedBodyIndex();
    initial_rates_.push_back({top.getMobilizedBodyIndex(), SimTK::Vec3(0, 150, -4.61538)});
  }

  void build_n_four_bar(int n) {
    std::vector<SimTK::MobilizedBody> cranks, couplers;
    for (int i = 0; i <= n; ++i) {
      cranks.push_back(pin(matter_.Ground(), {double(i), 0, 0}, rod('y'), "crank_" + std::to_string(i)));
      initial_rates_.push_back({cranks.back().getMobilizedBodyIndex(), SimTK::Vec3(0, 0, -1)});
    }
    for (int i = 0; i < n; ++i) {
      couplers.push_back(pin(cranks[i], {0, 1, 0}, rod('x'), "coupler_" + std::to_string(i)));
      // Couplers translate: +1 rad/s relative to their crank.
      initial_rates_.push_back({couplers.back().getMobilizedBodyIndex(), SimTK::Vec3(0, 0, 1)});
      SimTK::Constraint::Ball(couplers[i], SimTK::Vec3(1, 0, 0), cranks[i + 1], SimTK::Vec3(0, 1, 0));
    }
  }

  void build_chain(int n) {
    SimTK::MobilizedBody parent = matter_.Ground();
    for (int i = 0; i < n; ++i) parent = pin(parent, {i == 0 ? 0.0 : 1.0, 0, 0}, rod('x'), "link_" + std::to_string(i));
  }

  // The tree of andrews_mechanism.hpp, body frames at the centres of mass
  // (unrotated); the loops closed by ball constraints.
  void build_andrews() {
    const auto mobilized = [this](const char* name) -> SimTK::MobilizedBody& {
      return *name ? matter_.updMobilizedBody(bodies_.at(name)) : matter_.updGround();
    };
    for (const andrews::Body& b : andrews::kBodies) {
      SimTK::MobilizedBody::Pin m(mobilized(b.parent), SimTK::Transform(vec(b.pin - andrews::com(b.parent))),
                                  rigid_body(b.mass, {0, 0, 0}, vec(b.inertia)), SimTK::Transform(vec(b.pin - b.com)));
      bodies_[b.name] = m.getMobilizedBodyIndex();
    }
    for (const andrews::Closure& c : andrews::kClosures)
      SimTK::Constraint::Ball(mobilized(c.body1), vec(c.point - andrews::com(c.body1)), mobilized(c.body2),
                              vec(c.point - andrews::com(c.body2)));
    SimTK::Force::TwoPointLinearSpring(forces_, mobilized("triangle"), vec(andrews::kD - andrews::com("triangle")),
                                       matter_.Ground(), vec(andrews::kC), andrews::kSpringStiffness,
                                       andrews::kSpringRestLength);
    SimTK::Force::MobilityConstantForce(forces_, mobilized("crank"), SimTK::MobilizerUIndex(0), andrews::kCrankTorque);
  }

  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::State state_;
  std::map<std::string, SimTK::MobilizedBodyIndex> bodies_;
  std::vector<std::pair<SimTK::MobilizedBodyIndex, SimTK::Vec3>> initial_rates_;  // angular velocities relative to the parent
};

std::unique_ptr<SimTK::Integrator> integrator(const std::string& method, SimTK::MultibodySystem& system, double h) {
  std::unique_ptr<SimTK::Integrator> out;
  if (method == "rk_merson") {
    out = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
  } else {
    out = std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system, h);
  }
  out->setFixedStepSize(h);
  out->setConstraintTolerance(kConstraintTolerance);
  return out;
}

class SimbodyEngine final : public PeerEngine {
 public:
  SimbodyEngine(const Problem& p, const std::string& method, double h)
      : mechanism_(p), integrator_(integrator(method, mechanism_.system(), h)), body_(mechanism_.body(p.body)), h_(h) {
    const SimTK::State& s = mechanism_.initial_state();
    station_ = body_.findStationAtGroundPoint(s, SimTK::Vec3(p.point[0], p.point[1], p.point[2]));
    integrator_->initialize(s);
  }
  // Simbody throws when a step fails (e.g. the projection does not converge).
  bool step() override {
    try {
      integrator_->stepTo(integrator_->getTime() + h_);
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }
  double time() const override { return integrator_->getTime(); }
  mbrt::Vec3 observed() override {
    const SimTK::Vec3 x = body_.findStationLocationInGround(integrator_->getState(), station_);
    return {x[0], x[1], x[2]};
  }

 private:
  Mechanism mechanism_;
  std::unique_ptr<SimTK::Integrator> integrator_;
  const SimTK::MobilizedBody& body_;
  SimTK::Vec3 station_;
  double h_;
};

}  // namespace

const std::vector<std::string>& simbody_methods() {
  static const std::vector<std::string> names{"rk_merson", "semi_explicit_euler"};
  return names;
}

// A model file's tree in the same method, by peer_stability's name for it.
std::unique_ptr<PeerEngine> simbody_engine(const Problem& p, const std::string& method, double h) {
  if (p.mechanism == timing::Mechanism::model_file)
    return tree_peer(p, method == "rk_merson" ? "simbody-rk-merson" : "simbody-semiexplicit-euler", h);
  return std::make_unique<SimbodyEngine>(p, method, h);
}

Measurement run_simbody(const Problem& p, const std::string& method, double h) {
  const std::unique_ptr<PeerEngine> engine = simbody_engine(p, method, h);
  return measure(p, *engine, {p.name, "simbody", method, h});
}

}  // namespace timing
