// Unilateral frictional contact in mbrt (staggered-pcst, docs/contact.md) and
// in MuJoCo 2.2.2, against closed forms only:
//   stick  a box on its four corners on a 25 deg slope, mu_s = 0.5 > tan 25:
//          it must not move (distance crept in the plane after 10 s; 0);
//   slide  the same box on 30 deg, mu_k = 0.4: s = a t^2 / 2 after 1 s,
//          a = g (sin 30 - mu_k cos 30);
//   roll   a solid ball launched at v0 = 2 m/s without spin, mu_k = 0.3:
//          rolls from t = 2 v0 / (7 mu_k g) on at 5/7 v0 (speed at 1.5 s,
//          and the first step end with slip |v + w x (-r n)| < 1e-3 m/s);
//   wheel  the same ball as a wheel (2 kg, J = 0.008 kg m^2) on a revolute
//          joint about y to an axle body (3 kg, its centre of mass on the
//          wheel's centre), both launched at v0 = 2 m/s, mu_k = 0.3: friction
//          mu_k (m + m_a) g slows both and spins up the wheel alone, which
//          rolls from t = v0 / (mu_k g (1 + (m + m_a) r^2 / J)) on at
//          v0 (1 - 1 / (1 + (m + m_a) r^2 / J)) (the same two measures).
// Every case and engine at h = 4, 2, 1 and 0.5 ms, all of them interleaved
// in each of REPETITIONS rounds (the machine is shared: load hits all
// alike); ns per step is the median over the rounds of a whole run's steps.
// Built and run by timing/contact_peers, which generates the mbrt models
// (stick_hK, slide_hK, roll_hK, wheel_hK; K = 4, 2, 1, 05) and defines
// MBRT_WITH_MUJOCO when MuJoCo's header is there.
//   contact_peers OUT.csv [REPETITIONS]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <mbrt/rotation.hpp>

#include "roll_h05.hpp"
#include "roll_h1.hpp"
#include "roll_h2.hpp"
#include "roll_h4.hpp"
#include "slide_h05.hpp"
#include "slide_h1.hpp"
#include "slide_h2.hpp"
#include "slide_h4.hpp"
#include "stick_h05.hpp"
#include "stick_h1.hpp"
#include "stick_h2.hpp"
#include "stick_h4.hpp"
#include "wheel_h05.hpp"
#include "wheel_h1.hpp"
#include "wheel_h2.hpp"
#include "wheel_h4.hpp"

#ifdef MBRT_WITH_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace {

using mbrt::Vec3;

// The models' values (tests/models/contact_incline.yaml, contact_balls.yaml,
// contact_jointed.yaml).
constexpr double kG = 9.81;
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kStickAngle = 25 * kDeg, kStickMu = 0.5, kStickTime = 10.0;  // mu_s
constexpr double kSlideAngle = 30 * kDeg, kSlideMu = 0.4, kSlideTime = 1.0;   // mu_k
constexpr double kBallRadius = 0.1, kV0 = 2.0, kRollMu = 0.3, kRollTime = 1.5;  // mu_k
constexpr double kRollingSlip = 1e-3;  // m/s: below it the ball counts as rolling
const char* const kBoxInertia = "0.00166666666666667 0.00416666666666667 0.00416666666666667";  // 1 kg, 0.2 x 0.1 x 0.1 m

// Closed forms. Sliding down a slope, friction mu_k m g cos th opposes the
// pull m g sin th: constant a = g (sin th - mu_k cos th), s = a t^2 / 2.
double slide_distance(double t) { return 0.5 * kG * (std::sin(kSlideAngle) - kSlideMu * std::cos(kSlideAngle)) * t * t; }
// The ball (I = 2/5 m r^2) slows as v = v0 - mu g t while friction spins it
// up, r w = 5/2 mu g t, until v = r w: t = 2 v0 / (7 mu g), v = 5/7 v0 after.
const double kRollStart = 2 * kV0 / (7 * kRollMu * kG);  // 0.194 s
const double kRollSpeed = 5.0 / 7.0 * kV0;
// The wheel on its axle (contact_jointed.yaml: hub and tyre). The hub passes
// no torque about y and the axle's centre of mass is on it, so the axle only
// translates: friction mu (m + m_a) g slows both, v = v0 - mu g t, and spins
// the wheel alone, J w' = mu (m + m_a) g r, until v = r w:
// t = v0 / (mu g (1 + k)), v = v0 (1 - 1 / (1 + k)), k = (m + m_a) r^2 / J.
constexpr double kWheelMass = 2.0, kWheelInertia = 0.008, kAxleMass = 3.0;  // kBallRadius, kV0, kRollMu as the ball
const char* const kAxleInertia = "0.01 0.02 0.01";
constexpr double kWheelK = (kWheelMass + kAxleMass) * kBallRadius * kBallRadius / kWheelInertia;  // 6.25
const double kWheelStart = kV0 / (kRollMu * kG * (1 + kWheelK));  // 0.0937 s
const double kWheelSpeed = kV0 * (1 - 1 / (1 + kWheelK));          // 1.7241 m/s

// The plane tilted by th about y (the mbrt models' normal) and its downhill direction.
Vec3 normal(double th) { return {std::sin(th), 0.0, std::cos(th)}; }
Vec3 downhill(double th) { return {std::cos(th), 0.0, -std::sin(th)}; }

struct Run {
  std::vector<double> errors;  // the case's measures, in the order of kMeasures
  double ns_per_step;
};

long steps(double t_end, double h) { return std::lround(t_end / h); }

// Runs n steps of `step` (which returns false on failure) and returns ns per step.
template <class Step>
double timed(long n, Step&& step) {
  bool ok = true;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < n; ++i) ok &= step();
  const auto t1 = std::chrono::steady_clock::now();
  if (!ok) throw std::runtime_error("a step failed");
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n);
}

// The roll measures from the first step end that rolls (NaN: never) and the
// final speed, against the closed forms' start and speed.
std::vector<double> roll_errors(double t_rolling, double speed, double start = kRollStart, double rolling = kRollSpeed) {
  return {std::abs(speed - rolling), std::abs(t_rolling - start)};
}

// ---- mbrt: each generated model holds one case's bodies, its body of
// interest at index 0 (the script cuts them out of the test model so that a
// case's cost is its own bodies'; the wheel's model is the wheel, the axle,
// the hub and the tyre).

#define MBRT_MODEL(NS)                                                                            \
  struct NS {                                                                                     \
    using State = mbrt::models::NS::State;                                                        \
    using Workspace = mbrt::models::NS::Workspace;                                                \
    static constexpr double h = mbrt::models::NS::kStep;                                          \
    static State initial_state() { return mbrt::models::NS::initial_state(); }                    \
    static bool step(State& s, Workspace& w) { return mbrt::models::NS::step(s, w) == mbrt::StepStatus::ok; } \
  };
namespace gen {
MBRT_MODEL(stick_h4) MBRT_MODEL(stick_h2) MBRT_MODEL(stick_h1) MBRT_MODEL(stick_h05)
MBRT_MODEL(slide_h4) MBRT_MODEL(slide_h2) MBRT_MODEL(slide_h1) MBRT_MODEL(slide_h05)
MBRT_MODEL(roll_h4) MBRT_MODEL(roll_h2) MBRT_MODEL(roll_h1) MBRT_MODEL(roll_h05)
MBRT_MODEL(wheel_h4) MBRT_MODEL(wheel_h2) MBRT_MODEL(wheel_h1) MBRT_MODEL(wheel_h05)
}  // namespace gen

// Stick: the box on its 4 corners (box_stick), the centre's displacement within the plane.
template <class M>
Run mbrt_stick() {
  auto s = M::initial_state();
  const auto w = std::make_unique<typename M::Workspace>();
  const Vec3 r0 = s.rigid[0].r;
  const double ns = timed(steps(kStickTime, M::h), [&] { return M::step(s, *w); });
  const Vec3 d = s.rigid[0].r - r0, n = normal(kStickAngle);
  return {{(d - d.dot(n) * n).norm()}, ns};
}

// Slide: the box on its 4 corners (box_slide), the distance down the slope.
template <class M>
Run mbrt_slide() {
  auto s = M::initial_state();
  const auto w = std::make_unique<typename M::Workspace>();
  const Vec3 r0 = s.rigid[0].r;
  const long n = steps(kSlideTime, M::h);
  const double ns = timed(n, [&] { return M::step(s, *w); });
  return {{std::abs((s.rigid[0].r - r0).dot(downhill(kSlideAngle)) - slide_distance(n * M::h))}, ns};
}

// Roll: the ball (slider), the slip of its contact point (r below the centre)
// each step. Wheel: the same on the wheel, body 0 (the axle is body 1).
template <class M, bool kWheel = false>
Run mbrt_roll() {
  auto s = M::initial_state();
  const auto w = std::make_unique<typename M::Workspace>();
  double t_rolling = std::numeric_limits<double>::quiet_NaN();
  const double ns = timed(steps(kRollTime, M::h), [&] {
    const bool ok = M::step(s, *w);
    const auto& b = s.rigid[0];
    const Vec3 slip = b.v + (mbrt::rotation_matrix(b.p) * b.w).cross(Vec3(0, 0, -kBallRadius));
    if (std::isnan(t_rolling) && std::hypot(slip.x(), slip.y()) < kRollingSlip) t_rolling = s.t;
    return ok;
  });
  const double speed = std::hypot(s.rigid[0].v.x(), s.rigid[0].v.y());
  return {kWheel ? roll_errors(t_rolling, speed, kWheelStart, kWheelSpeed) : roll_errors(t_rolling, speed), ns};
}

#ifdef MBRT_WITH_MUJOCO
// ---- MuJoCo: the same bodies in MJCF, default solver settings (soft
// contacts, solref 0.02 1, Newton solver). One friction coefficient per
// contact (the geoms' largest): mu_s where the box must stick, mu_k where
// things slide. condim 3 (the default) gives sliding friction and no
// rolling or torsional friction, as in mbrt.

struct Variant {
  const char* name;
  mjtIntegrator integrator;
  mjtCone cone;
};
const Variant kVariants[] = {{"mujoco euler", mjINT_EULER, mjCONE_PYRAMIDAL},
                             {"mujoco rk4", mjINT_RK4, mjCONE_PYRAMIDAL},
                             {"mujoco euler elliptic", mjINT_EULER, mjCONE_ELLIPTIC},
                             {"mujoco rk4 elliptic", mjINT_RK4, mjCONE_ELLIPTIC}};

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A plane z = 0 under gravity tilted by th about y (downhill is +x): the same
// contact problem as the mbrt models' tilted plane, with simpler geometry.
std::string mjcf(double th, double mu, const std::string& body) {
  return "<mujoco><option gravity='" + num(kG * std::sin(th)) + " 0 " + num(-kG * std::cos(th)) + "'/>"
         "<default><geom friction='" + num(mu) + " 0 0'/></default>"
         "<worldbody><geom type='plane' size='10 10 0.1'/>" + body + "</worldbody></mujoco>";
}
// The box resting on its bottom face (corners 5 cm below the centre).
const std::string kBox = std::string("<body pos='0 0 0.05'><freejoint/><inertial pos='0 0 0' mass='1' diaginertia='") +
                         kBoxInertia + "'/><geom type='box' size='0.1 0.05 0.05'/></body>";
// The ball touching the plane (contact_balls.yaml's slider: 2 kg, I = 2/5 m r^2).
const std::string kBall = "<body pos='0 0 0.1'><freejoint/><inertial pos='0 0 0' mass='2' diaginertia='0.008 0.008 0.008'/>"
                          "<geom type='sphere' size='0.1'/></body>";

// The wheel hinged about y to the axle, which floats (a free joint): a hinge
// about the axle's y axis through the wheel's centre, both centres of mass
// there (contact_jointed.yaml's wheel, axle and hub). The axle has no geom.
const std::string kWheel = std::string("<body pos='0 0 0.1'><freejoint/><inertial pos='0 0 0' mass='") + num(kAxleMass) +
                           "' diaginertia='" + kAxleInertia + "'/><body pos='0 0 0'><joint type='hinge' axis='0 1 0'/>"
                           "<inertial pos='0 0 0' mass='" + num(kWheelMass) + "' diaginertia='" + num(kWheelInertia) + " " +
                           num(kWheelInertia) + " " + num(kWheelInertia) + "'/><geom type='sphere' size='" +
                           num(kBallRadius) + "'/></body></body>";

// A model and its data, loaded from MJCF text through a virtual file.
class Mujoco {
 public:
  Mujoco(const std::string& xml, double h, const Variant& v) {
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    if (mj_makeEmptyFileVFS(vfs.get(), "model.xml", static_cast<int>(xml.size())) != 0)
      throw std::runtime_error("MuJoCo: cannot make a virtual file");
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), "model.xml")], xml.data(), xml.size());
    char error[1000] = "";
    m = mj_loadXML("model.xml", vfs.get(), error, sizeof error);
    mj_deleteVFS(vfs.get());
    if (!m) throw std::runtime_error(std::string("MuJoCo: ") + error);
    m->opt.timestep = h;
    m->opt.integrator = v.integrator;
    m->opt.cone = v.cone;
    d = mj_makeData(m);
  }
  ~Mujoco() {
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  Mujoco(const Mujoco&) = delete;
  Mujoco& operator=(const Mujoco&) = delete;
  // MuJoCo resets the state when accelerations go bad: that is a failure.
  bool step() {
    mj_step(m, d);
    return d->warning[mjWARN_BADQACC].number == 0;
  }
  mjModel* m;
  mjData* d;
};

// Stick: the box's displacement in the plane (qpos: x, y, z, then the quaternion).
Run mujoco_stick(const Variant& v, double h) {
  Mujoco mj(mjcf(kStickAngle, kStickMu, kBox), h, v);
  const double x0 = mj.d->qpos[0], y0 = mj.d->qpos[1];
  const double ns = timed(steps(kStickTime, h), [&] { return mj.step(); });
  return {{std::hypot(mj.d->qpos[0] - x0, mj.d->qpos[1] - y0)}, ns};
}

// Slide: the distance down the slope (+x).
Run mujoco_slide(const Variant& v, double h) {
  Mujoco mj(mjcf(kSlideAngle, kSlideMu, kBox), h, v);
  const double x0 = mj.d->qpos[0];
  const long n = steps(kSlideTime, h);
  const double ns = timed(n, [&] { return mj.step(); });
  return {{std::abs(mj.d->qpos[0] - x0 - slide_distance(n * h))}, ns};
}

// Roll: the free joint's qvel is the world velocity, then the angular velocity in body axes.
Run mujoco_roll(const Variant& v, double h) {
  Mujoco mj(mjcf(0.0, kRollMu, kBall), h, v);
  mj.d->qvel[0] = kV0;
  double t_rolling = std::numeric_limits<double>::quiet_NaN();
  const double ns = timed(steps(kRollTime, h), [&] {
    const bool ok = mj.step();
    double w[3];
    mju_rotVecQuat(w, mj.d->qvel + 3, mj.d->qpos + 3);  // to world axes
    // v + w x (0, 0, -r), in the plane
    const double slip = std::hypot(mj.d->qvel[0] - kBallRadius * w[1], mj.d->qvel[1] + kBallRadius * w[0]);
    if (std::isnan(t_rolling) && slip < kRollingSlip) t_rolling = mj.d->time;
    return ok;
  });
  return {roll_errors(t_rolling, std::hypot(mj.d->qvel[0], mj.d->qvel[1])), ns};
}

// Wheel: qpos is the axle's free joint (x, y, z, quaternion), then the hinge
// angle; qvel the axle's world velocity, its angular velocity in its own axes,
// then the hinge rate about the axle's y. The wheel's centre is the axle's.
Run mujoco_wheel(const Variant& v, double h) {
  Mujoco mj(mjcf(0.0, kRollMu, kWheel), h, v);
  if (mj.m->nq != 8 || mj.m->nv != 7) throw std::runtime_error("MuJoCo: the wheel is not a free joint and a hinge");
  mj.d->qvel[0] = kV0;
  double t_rolling = std::numeric_limits<double>::quiet_NaN();
  const double ns = timed(steps(kRollTime, h), [&] {
    const bool ok = mj.step();
    const double w_axle[3] = {mj.d->qvel[3], mj.d->qvel[4] + mj.d->qvel[6], mj.d->qvel[5]};  // the wheel's, in the axle's axes
    double w[3];
    mju_rotVecQuat(w, w_axle, mj.d->qpos + 3);  // to world axes
    const double slip = std::hypot(mj.d->qvel[0] - kBallRadius * w[1], mj.d->qvel[1] + kBallRadius * w[0]);
    if (std::isnan(t_rolling) && slip < kRollingSlip) t_rolling = mj.d->time;
    return ok;
  });
  return {roll_errors(t_rolling, std::hypot(mj.d->qvel[0], mj.d->qvel[1]), kWheelStart, kWheelSpeed), ns};
}
#endif

// What each case measures: its name in the CSV and the unit.
struct Measure {
  const char* name;
  const char* unit;
};
const std::vector<Measure> kStickMeasures{{"stick", "m"}};
const std::vector<Measure> kSlideMeasures{{"slide", "m"}};
const std::vector<Measure> kRollMeasures{{"roll_speed", "m/s"}, {"roll_time", "s"}};
const std::vector<Measure> kWheelMeasures{{"wheel_speed", "m/s"}, {"wheel_time", "s"}};

struct Entry {
  const std::vector<Measure>* measures;
  std::string engine;
  double h;
  std::function<Run()> run;
  std::vector<double> errors, ns;
};

template <class Stick, class Slide, class Roll, class Wheel>
void add_mbrt(std::vector<Entry>& e) {
  e.push_back({&kStickMeasures, "mbrt staggered-pcst", Stick::h, mbrt_stick<Stick>, {}, {}});
  e.push_back({&kSlideMeasures, "mbrt staggered-pcst", Slide::h, mbrt_slide<Slide>, {}, {}});
  e.push_back({&kRollMeasures, "mbrt staggered-pcst", Roll::h, mbrt_roll<Roll>, {}, {}});
  e.push_back({&kWheelMeasures, "mbrt staggered-pcst", Wheel::h, mbrt_roll<Wheel, true>, {}, {}});
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t k = x.size() / 2;
  return x.size() % 2 ? x[k] : 0.5 * (x[k - 1] + x[k]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: contact_peers OUT.csv [REPETITIONS]\n");
    return 2;
  }
  const int repetitions = argc > 2 ? std::atoi(argv[2]) : 5;
  std::vector<Entry> entries;
  add_mbrt<gen::stick_h4, gen::slide_h4, gen::roll_h4, gen::wheel_h4>(entries);
  add_mbrt<gen::stick_h2, gen::slide_h2, gen::roll_h2, gen::wheel_h2>(entries);
  add_mbrt<gen::stick_h1, gen::slide_h1, gen::roll_h1, gen::wheel_h1>(entries);
  add_mbrt<gen::stick_h05, gen::slide_h05, gen::roll_h05, gen::wheel_h05>(entries);
#ifdef MBRT_WITH_MUJOCO
  for (const double h : {4e-3, 2e-3, 1e-3, 5e-4})
    for (const Variant& v : kVariants) {
      entries.push_back({&kStickMeasures, v.name, h, [v, h] { return mujoco_stick(v, h); }, {}, {}});
      entries.push_back({&kSlideMeasures, v.name, h, [v, h] { return mujoco_slide(v, h); }, {}, {}});
      entries.push_back({&kRollMeasures, v.name, h, [v, h] { return mujoco_roll(v, h); }, {}, {}});
      entries.push_back({&kWheelMeasures, v.name, h, [v, h] { return mujoco_wheel(v, h); }, {}, {}});
    }
#endif
  try {
    for (int r = 0; r < repetitions; ++r)
      for (Entry& e : entries) {
        const Run run = e.run();
        e.errors = run.errors;  // deterministic: the same every round
        e.ns.push_back(run.ns_per_step);
      }
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "contact_peers: %s\n", ex.what());
    return 1;
  }
  std::ofstream out(argv[1]);
  out << "case,engine,h,error,unit,ns_per_step\n";
  char line[256];
  for (const Entry& e : entries)
    for (std::size_t i = 0; i < e.measures->size(); ++i) {
      const Measure& m = (*e.measures)[i];
      std::snprintf(line, sizeof line, "%s,%s,%g,%.6g,%s,%.1f\n", m.name, e.engine.c_str(), e.h, e.errors[i], m.unit,
                    median(e.ns));
      out << line;
    }
  return out ? 0 : 1;
}
