// The schemes' steps (include/mbrt/schemes/) on their own, without the
// generator: a spherical pendulum written by hand as the Model they are
// templates over (one particle of mass m on a massless rod of length L to the
// origin, gravity -g z), checked against closed forms and conservation laws.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <mbrt/body_state.hpp>
#include <mbrt/schemes/staggered.hpp>

namespace {

constexpr double kMass = 2.0, kLength = 0.8, kG = 9.81;

struct State {
  double t = 0.0;
  std::array<mbrt::RigidState, 0> rigid;
  std::array<mbrt::ParticleState, 1> particle;
  std::array<mbrt::RigidAcceleration, 0> rigid_acceleration;
  std::array<mbrt::Vec3, 1> particle_acceleration;
  Eigen::Matrix<double, 1, 1> lambda;
};

using Rows = Eigen::Matrix<double, 1, 1>;
using BodyVectors = std::array<mbrt::Vec6, 1>;

struct Kinematics {
  mbrt::Vec3 r, vel;
};

struct Loads {
  mbrt::Vec3 f;
};

// phi = (|r|^2 - L^2) / 2, B = [r^T 0], quad = |v|^2 (B' u); mbt = M^-1 B^T.
struct ConstraintSystem {
  double phi = 0.0, quad = 0.0;
  mbrt::Vec6 b, mbt;
  double s = 0.0;  // S = B M^-1 B^T
};

struct NewtonMatrix {
  double g = 0.0;
};

struct Workspace {
  State last_good;
  Kinematics k;
  ConstraintSystem c, c0;
  NewtonMatrix g;
  Loads l;
};

template <mbrt::Scheme S, bool PositionStage>
struct Pendulum {
  using State = ::State;
  using Workspace = ::Workspace;
  using Rows = ::Rows;
  using BodyVectors = ::BodyVectors;
  using Kinematics = ::Kinematics;
  using Loads = ::Loads;
  using ConstraintSystem = ::ConstraintSystem;
  using NewtonMatrix = ::NewtonMatrix;
  static constexpr mbrt::Scheme kScheme = S;
  static constexpr double kStep = 1e-3;
  static constexpr int kStages = 1;
  static constexpr bool kPositionStage = PositionStage;
  static constexpr int kPositionIterations = 2;
  static constexpr int kCorrections = 1;
  static constexpr double kAlpha = 1000.0;  // staggered-pcst's decay rate of phi, 1/s

  static void kinematics(const State& s, Kinematics& k) noexcept { k = {s.particle[0].r, s.particle[0].v}; }
  static mbrt::Vec3 velocities_of(const State& s) noexcept { return s.particle[0].v; }
  static BodyVectors generalized_velocities(const State& s) noexcept {
    BodyVectors u;
    u[0] << s.particle[0].v, mbrt::Vec3::Zero();
    return u;
  }
  static void set_velocities(const BodyVectors& u, State& s) noexcept { s.particle[0].v = u[0].head<3>(); }
  static BodyVectors accelerations_of(const State& s) noexcept {
    BodyVectors a;
    a[0] << s.particle_acceleration[0], mbrt::Vec3::Zero();
    return a;
  }
  static void applied_loads(const Kinematics&, const State&, Loads& l) noexcept { l.f = {0.0, 0.0, -kMass * kG}; }
  static BodyVectors free_accelerations(const Loads& l) noexcept {
    BodyVectors a;
    a[0] << l.f / kMass, mbrt::Vec3::Zero();
    return a;
  }
  static void kick(State& s) noexcept { s.particle[0].v += (0.5 * kStep) * s.particle_acceleration[0]; }
  static void drift(State& s) noexcept {
    s.particle[0].r += kStep * s.particle[0].v;
    s.t += kStep;
  }
  static void constraint_rows(const Kinematics& k, const State&, ConstraintSystem& c) noexcept {
    c.phi = 0.5 * (k.r.squaredNorm() - kLength * kLength);
    c.quad = k.vel.squaredNorm();
    c.b << k.r, mbrt::Vec3::Zero();
  }
  static void constraint_directions(ConstraintSystem& c) noexcept { c.mbt = c.b / kMass; }
  static bool factorize(ConstraintSystem& c) noexcept {
    constraint_directions(c);
    c.s = c.b.dot(c.mbt);
    return c.s > 0.0;
  }
  static void solve(const ConstraintSystem& c, Rows& x) noexcept { x[0] /= c.s; }
  static void factorize_newton(const ConstraintSystem& c0, const ConstraintSystem& c, NewtonMatrix& g) noexcept {
    g.g = c.b.dot(c0.mbt);
  }
  static void solve_newton(const NewtonMatrix& g, Rows& x) noexcept { x[0] /= g.g; }
  static Rows stacked_phi(const ConstraintSystem& c) noexcept { return Rows(c.phi); }
  static Rows velocity_residual(const ConstraintSystem& c, const BodyVectors& u) noexcept { return Rows(c.b.dot(u[0])); }
  static void subtract_constraint_forces(const ConstraintSystem& c, const Rows& x, double scale, BodyVectors& u) noexcept {
    u[0] -= scale * x[0] * c.mbt;
  }
  // S lambda = B M^-1 F + quad + stabilization (staggered-pcst: (2/h)(B u + alpha phi)).
  static void constraint_forces(const ConstraintSystem& c, const Loads& l, const Rows& phi, State& s) noexcept {
    BodyVectors a = free_accelerations(l);
    Rows lambda(c.b.dot(a[0]) + c.quad);
    if constexpr (S == mbrt::Scheme::staggered_pcst) {
      lambda += (2.0 / kStep) * (velocity_residual(c, generalized_velocities(s)) + kAlpha * phi);
    }
    solve(c, lambda);
    subtract_constraint_forces(c, lambda, 1.0, a);
    s.lambda = lambda;
    s.particle_acceleration[0] = a[0].head<3>();
  }
  // Blajer's position correction along M^-1 B^T.
  static void correct_positions(const ConstraintSystem& c, State& s) noexcept {
    Rows x = stacked_phi(c);
    solve(c, x);
    s.particle[0].r -= x[0] * c.mbt.head<3>();
  }
};

// The pendulum at angle theta0 from the downward vertical, at rest, with the
// accelerations and multiplier of that state.
template <class M>
State released(double theta0) {
  State s;
  s.particle[0].r = {kLength * std::sin(theta0), 0.0, -kLength * std::cos(theta0)};
  s.particle[0].v.setZero();
  Workspace w;
  M::kinematics(s, w.k);
  M::constraint_rows(w.k, s, w.c);
  M::factorize(w.c);
  M::applied_loads(w.k, s, w.l);
  M::constraint_forces(w.c, w.l, M::stacked_phi(w.c), s);
  return s;
}

double energy(const State& s) {
  return 0.5 * kMass * s.particle[0].v.squaredNorm() + kMass * kG * s.particle[0].r.z();
}

// Time of the first return to x > 0 after crossing to x < 0: one period.
template <class M>
double period(double theta0) {
  State s = released<M>(theta0);
  Workspace w;
  bool crossed = false;
  double x_old = s.particle[0].r.x();
  for (int i = 0; i < 100000; ++i) {
    REQUIRE(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::ok);
    const double x = s.particle[0].r.x();
    if (x < 0.0) crossed = true;
    // The velocity's sign change at the turning point, interpolated.
    if (crossed && s.particle[0].v.x() <= 0.0 && x > 0.0 && x_old > 0.0) return s.t;
    x_old = x;
  }
  return 0.0;
}

}  // namespace

TEST_CASE("staggered-pcst's template: a hand-written pendulum keeps its length and energy") {
  using M = Pendulum<mbrt::Scheme::staggered_pcst, true>;
  State s = released<M>(1.2);
  const double e0 = energy(s);
  Workspace w;
  double worst_length = 0.0, worst_energy = 0.0;
  for (int i = 0; i < 20000; ++i) {  // 20 s, about 11 periods
    REQUIRE(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::ok);
    worst_length = std::max(worst_length, std::abs(s.particle[0].r.norm() - kLength));
    worst_energy = std::max(worst_energy, std::abs(energy(s) - e0) / std::abs(e0));
  }
  CHECK(worst_length < 1e-12);  // the position stage lands on phi = 0
  CHECK(worst_energy < 1e-3);   // bounded, second order: no drift
  CHECK(s.t == doctest::Approx(20.0).epsilon(1e-12));
}

TEST_CASE("staggered-pcst's template: the multiplier is the rod's tension over L") {
  using M = Pendulum<mbrt::Scheme::staggered_pcst, true>;
  // Released from rest at theta0 the tension is m g cos(theta0); after one
  // step of 1 ms it has changed by O(h^2) (the speed is still g sin(theta0) h).
  const double theta0 = 0.7;
  State s = released<M>(theta0);
  Workspace w;
  REQUIRE(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::ok);
  CHECK(s.lambda[0] * kLength == doctest::Approx(kMass * kG * std::cos(theta0)).epsilon(1e-4));
}

TEST_CASE("the staggered template's small-amplitude period is 2 pi sqrt(L / g)") {
  const double exact = 2.0 * M_PI * std::sqrt(kLength / kG);
  // Amplitude 0.01 rad: the finite-amplitude correction theta0^2 / 16 is 6e-6.
  const double pcst = period<Pendulum<mbrt::Scheme::staggered_pcst, true>>(0.01);
  CHECK(pcst == doctest::Approx(exact).epsilon(2e-3));  // the period is read to one step, 1e-3 s
  const double blajer = period<Pendulum<mbrt::Scheme::blajer, false>>(0.01);
  CHECK(blajer == doctest::Approx(exact).epsilon(2e-3));
}

TEST_CASE("the staggered template restores the state and says why when a step turns non-finite") {
  using M = Pendulum<mbrt::Scheme::staggered_pcst, true>;
  State s = released<M>(0.5);
  Workspace w;
  REQUIRE(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::ok);
  s.particle_acceleration[0].x() = std::numeric_limits<double>::quiet_NaN();
  const State before = s;
  CHECK(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::non_finite);
  CHECK(s.t == before.t);
  CHECK(s.particle[0].r == before.particle[0].r);
  CHECK(std::isnan(s.particle_acceleration[0].x()));
}

TEST_CASE("blajer's template corrects the drift of the index-1 multipliers") {
  using M = Pendulum<mbrt::Scheme::blajer, false>;
  State s = released<M>(1.2);
  Workspace w;
  double worst_length = 0.0;
  for (int i = 0; i < 5000; ++i) {
    REQUIRE(mbrt::schemes::staggered_step<M>(s, w) == mbrt::StepStatus::ok);
    worst_length = std::max(worst_length, std::abs(s.particle[0].r.norm() - kLength));
  }
  CHECK(worst_length < 1e-7);
}
