// A contact and joint friction in one mechanism (docs/contact.md,
// docs/friction.md): carriage wheels with a frictional hub on a frictional
// plane (tests/models/contact_hub_friction.yaml) in staggered-pcst,
// rk4-projected, baumgarte and blajer, 2 s at h = 1 ms, against the closed
// forms of the model's header (Newton-Euler along the travel and about the
// axle): a wheel rolling against its hub's moment stops at L0 / T and stays;
// one launched sliding spins up against the hub, rolls, stops and stays; on
// 15 degrees one held by the hub's static moment and the tyre's static
// friction does not move, one whose hub cannot hold rolls down with
// a = (M g r^2 sin - T r) / (M r^2 + J). Every step returns ok with a finite
// state; no step adds energy; the step allocates nothing.
//
// What is read from the state, independently of the friction and contact
// code: travel from the rail body's position along the travel direction d,
// its speed along d, the wheel's rate about +y (its axle), heights and
// energies from the masses and inertias of the model file. The hub's
// friction is along its joint coordinate, the wheel (body 2) relative to
// sz about +y: -T while the wheel turns forward.
//
// Tolerances. The impulses act as forces constant over the step, which the
// step integrates exactly, so motion under constant forces (sliding,
// rolling, at rest) is exact to round-off: 1e-9 m, m/s and J allowed
// (kExact; the same carriages with a frictionless hub are exact to 4e-13 m
// after 2 s in all four schemes). Across a change of phase the velocities
// stay exact: in the step where the tyre starts to roll the hub's impulse
// is -T h whatever the tyre does, so the moment of momentum about the
// contact line, L = M r v + J w, changes by exactly -T h, and v = w r at the
// step's end fixes v and w; in the step where the hub sticks everything
// stops. Only the position within that step is off, by at most the jump in
// acceleration times h^2 / 8 (2.6e-7 m where the sliding wheel starts to
// roll): 1e-6 m allowed (kAcrossChange) on the flat carriages. A
// first-order error in the velocity at a change (a h = 1e-3 m/s) would move
// them by about 1e-3 m.
// Forces from stuck solves (a least-norm solve with a 1e-10 relative shift,
// refined once) to 1e-6 N or N m (kForce); a slipping hub's friction is its
// limit to 1e-12 relative. States (stuck or not) are checked except within
// 1.5 steps of a change of phase, which falls inside a step.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "arm7_floor_friction_pcst.hpp"
#include "arm7_floor_friction_rk4p.hpp"
#include "contact_hub_friction_baumgarte.hpp"
#include "contact_hub_friction_blajer.hpp"
#include "contact_hub_friction_pcst.hpp"
#include "contact_hub_friction_rk4p.hpp"
#include "step_allocations.hpp"

namespace {

constexpr double kG = 9.81;
constexpr double kH = 1e-3;
constexpr int kSteps = 2000;

// The carriages (tests/models/contact_hub_friction.yaml): sx and sz 1 kg
// each, the wheel a 2 kg disk of radius 0.1 m; all three move along d (M),
// sz and the wheel rest on the tyre.
constexpr double kRadius = 0.1, kWheelJ = 0.01;
constexpr double kMass = 4.0, kLoadMass = 3.0;
constexpr double kRolling = kMass * kRadius * kRadius + kWheelJ;  // M r^2 + J = 0.05 kg m^2
constexpr double kMuS = 0.5, kMuK = 0.4;
const double kTilt = 15.0 * std::acos(-1.0) / 180.0;
const mbrt::Vec3 kSliderInertia(0.01, 0.01, 0.01), kWheelInertia(0.005, 0.01, 0.005);

constexpr double kExact = 1e-9;        // m, m/s, J: motion under constant forces
constexpr double kAcrossChange = 1e-6;  // m: positions after a change of phase
constexpr double kMoment = 1e-10;      // kg m^2/s: L = M r v + J w while the hub slips
constexpr double kForce = 1e-6;        // N, N m: forces of stuck solves
constexpr double kEnergyRise = 1e-10;  // J in a step

// The plane a carriage runs on: travel direction d (downhill), normal n, a point.
struct Plane {
  mbrt::Vec3 d, n, point;
};

// A carriage's closed form at time t: its travel s along d, speed v, the
// wheel's rate w about +y, the tyre's friction F along d and the hub's
// moment tau on the wheel (its friction output), and which of them slip.
struct Phase {
  double s, v, w, F, tau;
  bool hub_slips, tyre_slides;
  bool at_rest() const { return !hub_slips && !tyre_slides && v == 0.0; }
};

// On the flat, launched at v0 with spin w0 (v0 >= w0 r), the hub's moment T
// (the model's header): sliding while v > w r, then rolling, then at rest.
struct FlatLaunch {
  double v0, w0, torque;

  static double normal() { return kLoadMass * kG; }
  static double slide_deceleration() { return kMuK * normal() / kMass; }
  double spin_up() const { return (kMuK * normal() * kRadius - torque) / kWheelJ; }
  double rolls_at() const { return (v0 - w0 * kRadius) / (slide_deceleration() + kRadius * spin_up()); }
  double braking() const { return torque * kRadius / kRolling; }
  double rolling_speed() const { return v0 - slide_deceleration() * rolls_at(); }
  double stops_at() const { return rolls_at() + rolling_speed() / braking(); }

  Phase at(double t) const {
    const double t1 = rolls_at(), a = braking(), v1 = rolling_speed();
    const double s1 = v0 * t1 - 0.5 * slide_deceleration() * t1 * t1;
    if (t < t1) {
      return {v0 * t - 0.5 * slide_deceleration() * t * t, v0 - slide_deceleration() * t, w0 + spin_up() * t,
              -kMuK * normal(), -torque, true, true};
    }
    if (t <= stops_at()) {
      const double u = t - t1, v = v1 - a * u;
      return {s1 + v1 * u - 0.5 * a * u * u, v, v / kRadius, -kMass * a, -torque, true, false};
    }
    return {s1 + 0.5 * v1 * v1 / a, 0.0, 0.0, 0.0, 0.0, false, false};
  }
};

// On the plane tilted by kTilt, released at rest, the hub's static and
// kinetic moments: held where the static one holds the wheel,
// M g r sin(theta), else rolling down from the first step.
struct InclineRelease {
  double static_torque, kinetic_torque;

  static double holding_moment() { return kMass * kG * kRadius * std::sin(kTilt); }
  bool held() const { return static_torque >= holding_moment(); }
  double acceleration() const { return (holding_moment() - kinetic_torque) * kRadius / kRolling; }

  Phase at(double t) const {
    if (held()) return {0.0, 0.0, 0.0, -kMass * kG * std::sin(kTilt), -holding_moment(), false, false};
    const double a = acceleration();
    const double tyre = -kMass * (kG * kWheelJ * std::sin(kTilt) + kinetic_torque * kRadius) / kRolling;
    return {0.5 * a * t * t, a * t, a * t / kRadius, tyre, -kinetic_torque, true, false};
  }
};

// A carriage's parts: indices into State (rigid::, friction::, contact::).
struct Carriage {
  int sx, sz, wheel, hub, tyre;
};

template <class State>
const mbrt::RigidState& body(const State& s, int b) {
  return s.rigid[static_cast<std::size_t>(b)];
}

// A rigid body's kinetic and gravitational energy, w and the inertia's
// diagonal in body axes.
double energy_of(const mbrt::RigidState& b, double m, const mbrt::Vec3& inertia) {
  return 0.5 * m * b.v.squaredNorm() + 0.5 * b.w.dot(inertia.cwiseProduct(b.w)) + m * kG * b.r.z();
}

template <class State>
double carriage_energy(const State& s, const Carriage& c) {
  return energy_of(body(s, c.sx), 1.0, kSliderInertia) + energy_of(body(s, c.sz), 1.0, kSliderInertia) +
         energy_of(body(s, c.wheel), 2.0, kWheelInertia);
}

// The wheel's rate about world y, its axle.
double wheel_rate(const mbrt::RigidState& wheel) { return (mbrt::rotation_matrix(wheel.p) * wheel.w).y(); }

// Every body's state, contact output and friction output is finite.
template <class State>
bool all_finite(const State& s) {
  for (const mbrt::RigidState& b : s.rigid) {
    if (!b.r.allFinite() || !b.p.allFinite() || !b.v.allFinite() || !b.w.allFinite()) return false;
  }
  for (std::size_t k = 0; k < s.friction.size(); ++k) {
    if (!std::isfinite(s.friction[k]) || !(s.stuck[k] == 0.0 || s.stuck[k] == 1.0)) return false;
  }
  for (std::size_t c = 0; c < s.contact_normal.size(); ++c) {
    if (!std::isfinite(s.contact_normal[c]) || !s.contact_tangential[c].allFinite() ||
        !(s.contact_stuck[c] == 0.0 || s.contact_stuck[c] == 1.0)) {
      return false;
    }
  }
  return std::isfinite(s.t);
}

// One carriage followed through a run: the largest errors against its
// closed form, and the steps in which it did what the closed form rules out.
struct Track {
  std::string name;
  Carriage c;
  Plane plane;
  std::function<Phase(double)> form;
  std::vector<double> changes;  // times its phase changes
  double position_tolerance;
  bool rolls_throughout;  // the tyre never slides: the energy lost is the hub's T s / r
  double kinetic_torque;

  mbrt::Vec3 start = mbrt::Vec3::Zero();
  double e0 = 0.0, energy = 0.0;
  std::optional<std::array<mbrt::RigidState, 3>> rest{};  // where it came to rest
  double largest_rise = -std::numeric_limits<double>::infinity();
  double position_error = 0.0, velocity_error = 0.0, moment_error = 0.0, balance_error = 0.0;
  double normal_error = 0.0, tyre_force_error = 0.0, hub_error = 0.0, creep = 0.0;
  double lowest_gap = std::numeric_limits<double>::infinity(), highest_gap = -lowest_gap;
  int wrong_hub_state = 0, wrong_tyre_state = 0, off_limit = 0, checked = 0;

  template <class State>
  std::array<mbrt::RigidState, 3> parts(const State& s) const {
    return {body(s, c.sx), body(s, c.sz), body(s, c.wheel)};
  }

  bool near_change(double t) const {
    return std::any_of(changes.begin(), changes.end(), [t](double change) { return std::abs(t - change) < 1.5 * kH; });
  }

  template <class State>
  void begin(const State& s) {
    start = body(s, c.sx).r;
    e0 = energy = carriage_energy(s, c);
    if (form(0.0).at_rest()) rest = parts(s);
  }

  template <class State>
  void observe(const State& s) {
    const double t = s.t;
    const Phase x = form(t);
    const mbrt::RigidState& sx = body(s, c.sx);
    const mbrt::RigidState& wheel = body(s, c.wheel);
    const double travel = (sx.r - start).dot(plane.d), v = sx.v.dot(plane.d), w = wheel_rate(wheel);
    position_error = std::max(position_error, std::abs(travel - x.s));
    // Friction only takes energy out; rolling, only the hub's.
    const double e = carriage_energy(s, c);
    largest_rise = std::max(largest_rise, e - energy);
    energy = e;
    if (rolls_throughout) {
      balance_error = std::max(balance_error, std::abs(e0 - e - kinetic_torque * travel / kRadius));
    }
    // L' = M g r sin(theta) - T while the hub slips, the tyre's state aside
    // (the model's header): exact through a change of the tyre's phase.
    if (x.hub_slips) {
      const double moment = kMass * kRadius * v + kWheelJ * w, expected = kMass * kRadius * x.v + kWheelJ * x.w;
      moment_error = std::max(moment_error, std::abs(moment - expected));
    }
    // On its plane: pushing, never sinking; the tyre carries (m_sz + m_wheel) g cos(theta).
    const double gap = (wheel.r - plane.point).dot(plane.n) - kRadius;
    lowest_gap = std::min(lowest_gap, gap);
    highest_gap = std::max(highest_gap, gap);
    normal_error = std::max(normal_error, std::abs(s.contact_normal[static_cast<std::size_t>(c.tyre)] -
                                                   kLoadMass * kG * plane.n.z()));
    if (near_change(t)) return;
    ++checked;
    velocity_error = std::max({velocity_error, std::abs(v - x.v), kRadius * std::abs(w - x.w)});
    if (s.stuck[static_cast<std::size_t>(c.hub)] != (x.hub_slips ? 0.0 : 1.0)) ++wrong_hub_state;
    if (s.contact_stuck[static_cast<std::size_t>(c.tyre)] != (x.tyre_slides ? 0.0 : 1.0)) ++wrong_tyre_state;
    const double hub = s.friction[static_cast<std::size_t>(c.hub)];
    if (x.hub_slips) {
      if (std::abs(hub - x.tau) > 1e-12 * std::abs(x.tau)) ++off_limit;
    } else {
      hub_error = std::max(hub_error, std::abs(hub - x.tau));
    }
    const mbrt::Vec3& tyre = s.contact_tangential[static_cast<std::size_t>(c.tyre)];
    tyre_force_error = std::max(tyre_force_error, (tyre - x.F * plane.d).norm());
    if (x.at_rest()) {
      if (!rest) rest = parts(s);
      const std::array<mbrt::RigidState, 3> now = parts(s);
      for (std::size_t b = 0; b < now.size(); ++b) {
        creep = std::max({creep, (now[b].r - (*rest)[b].r).norm(), (now[b].p - (*rest)[b].p).norm()});
      }
    }
  }

  void report(const std::string& scheme) const {
    INFO(scheme, ": carriage ", name);
    MESSAGE(scheme << " " << name << ": position off by " << position_error << " m, velocity " << velocity_error
                   << " m/s, L " << moment_error << " kg m^2/s; tyre force " << tyre_force_error << " N, normal "
                   << normal_error << " N; stuck hub " << hub_error << " N m; gap " << lowest_gap << " to "
                   << highest_gap << " m; largest energy rise " << largest_rise << " J; crept " << creep << " m");
    CHECK(checked > kSteps / 2);
    CHECK(position_error < position_tolerance);
    CHECK(velocity_error < kExact);
    CHECK(moment_error < kMoment);
    CHECK(wrong_hub_state == 0);
    CHECK(wrong_tyre_state == 0);
    CHECK(off_limit == 0);
    CHECK(hub_error < kForce);
    CHECK(tyre_force_error < kForce);
    CHECK(normal_error < kForce);
    CHECK(lowest_gap > -kExact);
    CHECK(highest_gap <= 0.5 * kG * kH * kH);  // the resting gap (docs/contact.md)
    CHECK(largest_rise < kEnergyRise);
    if (rolls_throughout) {
      CHECK(balance_error < kExact);
    }
    if (rest) {
      CHECK(creep < kExact);
    }
  }
};

#define CARRIAGE(ns, c)                                                                                        \
  Carriage {                                                                                                   \
    mbrt::models::ns::rigid::sx_##c, mbrt::models::ns::rigid::sz_##c, mbrt::models::ns::rigid::wheel_##c,      \
        mbrt::models::ns::friction::hub_##c, mbrt::models::ns::contact::tyre_##c                               \
  }

// One generated model: its state, step and workspace, and its carriages.
#define HUB_FRICTION_MODEL(Name, ns)                                                                   \
  struct Name {                                                                                        \
    using State = mbrt::models::ns::State;                                                             \
    using Workspace = mbrt::models::ns::Workspace;                                                     \
    static constexpr const char* kScheme = mbrt::models::ns::kScheme;                                  \
    static_assert(mbrt::models::ns::kStep == kH);                                                      \
    static_assert(mbrt::models::ns::kFrictionJoints == 4 && mbrt::models::ns::kContacts == 4);         \
    static_assert(std::is_same_v<decltype(Workspace::k), mbrt::models::ns::detail::Kinematics>,        \
                  "contacts and friction take the spatial step");                                      \
    static State initial_state() { return mbrt::models::ns::initial_state(); }                         \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::ns::step(s, w); }      \
    static constexpr Carriage roll = CARRIAGE(ns, roll), slide = CARRIAGE(ns, slide);                  \
    static constexpr Carriage held = CARRIAGE(ns, held), down = CARRIAGE(ns, down);                    \
  }

HUB_FRICTION_MODEL(HubPcst, contact_hub_friction_pcst);
HUB_FRICTION_MODEL(HubRk4, contact_hub_friction_rk4p);
HUB_FRICTION_MODEL(HubBaumgarte, contact_hub_friction_baumgarte);
HUB_FRICTION_MODEL(HubBlajer, contact_hub_friction_blajer);

// The closed forms agree with themselves and with the model's numbers.
void check_closed_forms(const FlatLaunch& roll, const FlatLaunch& slide, const InclineRelease& held,
                        const InclineRelease& down) {
  const double flat_normal = kLoadMass * kG, tilted_normal = kLoadMass * kG * std::cos(kTilt);
  // Rolling from the start, stopping at L0 / T = 1 s after 0.5 m.
  REQUIRE(roll.rolls_at() == 0.0);
  REQUIRE(roll.stops_at() == doctest::Approx(1.0).epsilon(1e-12));
  REQUIRE(roll.at(2.0).s == doctest::Approx(0.5).epsilon(1e-12));
  // The sliding wheel: its hub cannot hold it (mu_k N r > T); it rolls at
  // 0.195791 s and stops at L0 / T = M r v0 / T = 1.777778 s, at 1.461380 m.
  REQUIRE(kMuK * flat_normal * kRadius > slide.torque);
  REQUIRE(slide.rolls_at() == doctest::Approx(0.195791).epsilon(1e-5).scale(0));
  REQUIRE(slide.stops_at() == doctest::Approx(kMass * kRadius * slide.v0 / slide.torque).epsilon(1e-12));
  REQUIRE(slide.at(2.0).s == doctest::Approx(1.461380).epsilon(1e-6));
  // Rolling, the tyre's friction within mu_s N (it sticks); slide's within mu_k N too.
  REQUIRE(kMass * roll.braking() <= kMuS * flat_normal);
  REQUIRE(kMass * slide.braking() <= kMuK * flat_normal);
  // On 15 degrees: held by the hub (1.0156 N m of 1.2) and the tyre
  // (10.156 N of mu_s N = 14.214 N); the other hub cannot hold (0.4 N m),
  // rolling down at 1.431212 m/s^2 with 4.4312 N at the tyre.
  REQUIRE(held.held());
  REQUIRE(kMass * kG * std::sin(kTilt) <= kMuS * tilted_normal);
  REQUIRE_FALSE(down.held());
  REQUIRE(down.acceleration() == doctest::Approx(1.431212).epsilon(1e-6));
  REQUIRE(std::abs(down.at(0.0).F) <= kMuS * tilted_normal);
}

template <class M>
void check_carriages() {
  const FlatLaunch roll{1.0, 10.0, 0.5}, slide{2.0, 0.0, 0.45};
  const InclineRelease held{1.2, 1.0}, down{0.4, 0.3};
  check_closed_forms(roll, slide, held, down);
  const Plane flat0{mbrt::Vec3::UnitX(), mbrt::Vec3::UnitZ(), mbrt::Vec3(0, 0, 0)};
  const Plane flat1{mbrt::Vec3::UnitX(), mbrt::Vec3::UnitZ(), mbrt::Vec3(0, 1, 0)};
  const mbrt::Vec3 downhill(std::cos(kTilt), 0.0, -std::sin(kTilt)), normal(std::sin(kTilt), 0.0, std::cos(kTilt));
  const Plane tilted2{downhill, normal, mbrt::Vec3(0, 2, 0)}, tilted3{downhill, normal, mbrt::Vec3(0, 3, 0)};
  std::array<Track, 4> tracks{{
      {"roll", M::roll, flat0, [roll](double t) { return roll.at(t); }, {roll.stops_at()}, kAcrossChange, true,
       roll.torque},
      {"slide", M::slide, flat1, [slide](double t) { return slide.at(t); }, {slide.rolls_at(), slide.stops_at()},
       kAcrossChange, false, slide.torque},
      {"held", M::held, tilted2, [held](double t) { return held.at(t); }, {}, kExact, true, held.kinetic_torque},
      {"down", M::down, tilted3, [down](double t) { return down.at(t); }, {}, kExact, true, down.kinetic_torque},
  }};

  typename M::State s = M::initial_state();
  static typename M::Workspace w;
  for (Track& track : tracks) {
    INFO("carriage ", track.name);
    const Phase x = track.form(0.0);
    REQUIRE(body(s, track.c.sx).v.dot(track.plane.d) == doctest::Approx(x.v).epsilon(1e-12));
    REQUIRE(wheel_rate(body(s, track.c.wheel)) == doctest::Approx(x.w).epsilon(1e-12));
    track.begin(s);
  }
  bool finite = true;
  for (int n = 0; n < kSteps; ++n) {
    REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
    finite = finite && all_finite(s);
    for (Track& track : tracks) track.observe(s);
  }
  CHECK(finite);
  CHECK(s.t == doctest::Approx(kSteps * kH).epsilon(1e-12));
  for (const Track& track : tracks) track.report(std::string(M::kScheme));
  // Both flat carriages came to rest, and the rolling one lost T x / r = 2.5 J.
  CHECK(tracks[0].rest.has_value());
  CHECK(tracks[1].rest.has_value());
  CHECK(tracks[0].e0 - tracks[0].energy == doctest::Approx(2.5).epsilon(1e-9));
}

// The 7-link arm with friction in every joint falling onto a tilted
// frictional floor (tests/models/stress/arm7_floor_friction.yaml), 10 s at
// 1 kHz: impacts while joints stick and slip. Every step ok and finite;
// friction and impacts take energy out: the energy never rises between
// steps by more than max_rise (the contacts' own: the same arm without joint
// friction rises by up to 7.9e-4 J, docs/friction.md; measured here 4.5e-6 J
// in staggered-pcst, 7.9e-4 J in rk4-projected), and the fall dissipates
// more than 60 J (74.6 J measured with `mbrt sim`).
template <class State, class Workspace, class Step, class EnergyOf>
void check_arm_on_floor(const State& start, Step step, EnergyOf energy_of, double max_rise) {
  State s = start;
  static Workspace w;
  const double e0 = energy_of(s);
  double energy = e0, largest_rise = -std::numeric_limits<double>::infinity();
  bool ok = true;
  for (int n = 0; n < 10000; ++n) {
    ok = ok && step(s, w) == mbrt::StepStatus::ok && all_finite(s);
    const double e = energy_of(s);
    largest_rise = std::max(largest_rise, e - energy);
    energy = e;
  }
  INFO("largest energy rise in a step ", largest_rise, " J; energy ", e0, " -> ", energy, " J");
  CHECK(ok);
  CHECK(largest_rise <= max_rise);
  CHECK(energy < e0 - 60.0);
}

}  // namespace

TEST_CASE("wheels with frictional hubs on frictional planes roll, slide, stop and hold as the closed forms say") {
  SUBCASE("staggered-pcst") { check_carriages<HubPcst>(); }
  SUBCASE("rk4-projected") { check_carriages<HubRk4>(); }
  SUBCASE("baumgarte") { check_carriages<HubBaumgarte>(); }
  SUBCASE("blajer") { check_carriages<HubBlajer>(); }
}

TEST_CASE("the step with contacts and joint friction in one mechanism allocates nothing") {
  // Through every phase: sliding, rolling, stopping, held.
  CHECK(allocations_in<HubPcst>(kSteps) == 0);
  CHECK(allocations_in<HubRk4>(100) == 0);
  CHECK(allocations_in<HubBaumgarte>(100) == 0);
  CHECK(allocations_in<HubBlajer>(100) == 0);
}

TEST_CASE("an arm whose joints stick and slip falls onto a frictional floor without gaining energy") {
  namespace pcst = mbrt::models::arm7_floor_friction_pcst;
  namespace rk4p = mbrt::models::arm7_floor_friction_rk4p;
  SUBCASE("staggered-pcst") {
    check_arm_on_floor<pcst::State, pcst::Workspace>(
        pcst::initial_state(), [](pcst::State& s, pcst::Workspace& w) { return pcst::step(s, w); },
        [](const pcst::State& s) { return pcst::energy(s).total(); }, 1e-4);
  }
  SUBCASE("rk4-projected") {
    check_arm_on_floor<rk4p::State, rk4p::Workspace>(
        rk4p::initial_state(), [](rk4p::State& s, rk4p::Workspace& w) { return rk4p::step(s, w); },
        [](const rk4p::State& s) { return rk4p::energy(s).total(); }, 2e-3);
  }
}
