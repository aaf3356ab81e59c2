// Main program of `mbrt sim`: runs one generated model and writes its
// trajectory. Compiled by `mbrt sim` together with the model, with
//   -DMBRT_MODEL_HEADER="<name>.hpp" -DMBRT_MODEL_NAMESPACE=mbrt::models::<name>
// and, for a model with tunable keys, -DMBRT_MODEL_PARAMETERS (--set KEY=VALUE).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <mbrt/parameter_settings.hpp>
#include <nlohmann/json.hpp>

#include MBRT_MODEL_HEADER

namespace model = MBRT_MODEL_NAMESPACE;

namespace {

struct Options {
  double t_end = 1.0;
  const char* out = nullptr;
  long every = 1;
  bool velocities = false;
  bool reactions = false;
  bool outputs = false;
  bool serial = false;  // the parallel step's parts on the caller's thread only
  std::vector<std::string> set;  // --set KEY=VALUE, in order
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr, "sim driver: %s\nusage: sim [--t-end T] [--out F.csv] [--every N] [--velocities] [--reactions] [--outputs] [--serial] [--set KEY=VALUE]...\n", why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--t-end") o.t_end = std::atof(value());
    else if (a == "--out") o.out = value();
    else if (a == "--every") o.every = std::atol(value());
    else if (a == "--velocities") o.velocities = true;
    else if (a == "--reactions") o.reactions = true;
    else if (a == "--outputs") o.outputs = true;
    else if (a == "--serial") o.serial = true;
    else if (a == "--set" || a.rfind("--set=", 0) == 0) o.set.push_back(a == "--set" ? value() : argv[i] + 6);
    else usage(("unknown option " + a).c_str());
  }
  if (!(o.t_end >= 0.0)) usage("--t-end must be >= 0");
  if (o.every < 1) usage("--every must be >= 1");
#ifndef MBRT_MODEL_OUTPUTS
  if (o.outputs) usage("--outputs: the model has no outputs");
#endif
  return o;
}

// With --reactions, each friction joint's torque or force and whether it
// stuck (docs/friction.md), where the model has joint friction.
template <class State>
void write_friction_header(std::FILE* f) {
  if constexpr (requires { State::friction_joints; }) {
    for (const char* j : State::friction_joints) std::fprintf(f, ",%s.friction,%s.stuck", j, j);
  }
}
template <class State>
void write_friction(std::FILE* f, const State& s) {
  if constexpr (requires { State::friction_joints; }) {
    for (std::size_t i = 0; i < s.friction.size(); ++i) std::fprintf(f, ",%.17g,%.17g", s.friction[i], s.stuck[i]);
  }
}

// With --reactions, each contact's normal force, friction force (world) and
// whether it stuck (docs/contact.md), where the model has contacts.
template <class State>
void write_contacts_header(std::FILE* f) {
  if constexpr (requires { State::contacts; }) {
    for (const char* c : State::contacts) std::fprintf(f, ",%s.normal,%s.fx,%s.fy,%s.fz,%s.stuck", c, c, c, c, c);
  }
}
template <class State>
void write_contacts(std::FILE* f, const State& s) {
  if constexpr (requires { State::contacts; }) {
    for (std::size_t i = 0; i < s.contact_normal.size(); ++i) {
      const auto& t = s.contact_tangential[i];
      std::fprintf(f, ",%.17g,%.17g,%.17g,%.17g,%.17g", s.contact_normal[i], t[0], t[1], t[2], s.contact_stuck[i]);
    }
  }
}

void write_header(std::FILE* f, const Options& o) {
  const bool velocities = o.velocities;
  std::fprintf(f, "t");
  for (const mbrt::BodyInfo& b : model::kBodyInfo) {
    std::fprintf(f, ",%s.x,%s.y,%s.z", b.name, b.name, b.name);
    if (b.rigid) std::fprintf(f, ",%s.e0,%s.e1,%s.e2,%s.e3", b.name, b.name, b.name, b.name);
    if (velocities) {
      std::fprintf(f, ",%s.vx,%s.vy,%s.vz", b.name, b.name, b.name);
      if (b.rigid) std::fprintf(f, ",%s.wx,%s.wy,%s.wz", b.name, b.name, b.name);
    }
  }
  if (o.reactions) {
    for (const mbrt::ConstraintInfo& c : model::kConstraintInfo) {
      for (const char* q : {"fx", "fy", "fz", "tx", "ty", "tz"}) std::fprintf(f, ",%s.%s", c.name, q);
    }
    write_friction_header<model::State>(f);
    write_contacts_header<model::State>(f);
  }
#ifdef MBRT_MODEL_OUTPUTS
  if (o.outputs) {
    for (const mbrt::OutputInfo& y : model::kOutputInfo) {
      for (int k = 0; k < y.count; ++k) std::fprintf(f, ",%s.%d", y.name, k);
    }
  }
#endif
  std::fprintf(f, "\n");
}

void write_vec(std::FILE* f, const double* x, int n) {
  for (int i = 0; i < n; ++i) std::fprintf(f, ",%.17g", x[i]);
}

void write_row(std::FILE* f, const model::State& s, const Options& o) {
  const bool velocities = o.velocities;
  std::fprintf(f, "%.17g", s.t);
  for (const mbrt::BodyInfo& b : model::kBodyInfo) {
    if (b.rigid) {
      const mbrt::RigidState& x = s.rigid[static_cast<size_t>(b.slot)];
      write_vec(f, x.r.data(), 3);
      write_vec(f, x.p.data(), 4);
      if (velocities) {
        write_vec(f, x.v.data(), 3);
        write_vec(f, x.w.data(), 3);
      }
    } else {
      const mbrt::ParticleState& x = s.particle[static_cast<size_t>(b.slot)];
      write_vec(f, x.r.data(), 3);
      if (velocities) write_vec(f, x.v.data(), 3);
    }
  }
  if (o.reactions) {
    model::Reactions r;
    model::reactions(s, r);
    for (const mbrt::JointReaction& j : r) {
      write_vec(f, j.force.data(), 3);
      write_vec(f, j.torque.data(), 3);
    }
    write_friction(f, s);
    write_contacts(f, s);
  }
#ifdef MBRT_MODEL_OUTPUTS
  if (o.outputs) {
    model::Outputs y;
    model::outputs(s, y);
    write_vec(f, y.data(), static_cast<int>(y.size()));
  }
#endif
  std::fprintf(f, "\n");
}

// The initial state with the --set parameters applied by name (docs/parameters.md);
// exit 2 for a key the model does not have or a state off the joints.
model::State initial_state(const Options& o) {
#ifdef MBRT_MODEL_PARAMETERS
  model::State s;
  const std::string why = mbrt::start_with_settings(model::kParameterInfo, model::kDefaultParameters, o.set,
                                                    model::initial_state, model::constraint_violation, s);
  if (!why.empty()) usage(("--set: " + why).c_str());
  return s;
#else
  if (!o.set.empty()) usage(("--set " + o.set.front() + ": the model has no tunable keys (docs/parameters.md)").c_str());
  return model::initial_state();
#endif
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  std::FILE* csv = nullptr;
  if (opt.out) {
    csv = std::fopen(opt.out, "w");
    if (!csv) {
      std::fprintf(stderr, "error: cannot write %s: %s\n", opt.out, std::strerror(errno));
      return 1;
    }
    write_header(csv, opt);
  }
  model::State s = initial_state(opt);
  if (!opt.serial) model::start_workers();  // the parallel step's threads (docs/parallel.md); none for a serial one
  const auto workspace = std::make_unique<model::Workspace>();  // large models: not on the stack
  const double e0 = model::energy(s).total();
  const long steps = std::lround(opt.t_end / model::kStep);
  double max_pos = 0.0, max_vel = 0.0, max_acc = 0.0, max_quat = 0.0;
  const auto sample = [&]() {
    model::refresh_bodies(s);  // where the step leaves them to be formed on demand
    const mbrt::ConstraintViolation v = model::constraint_violation(s);
    max_pos = std::max(max_pos, v.position);
    max_vel = std::max(max_vel, v.velocity);
    max_acc = std::max(max_acc, v.acceleration);
    max_quat = std::max(max_quat, model::quaternion_norm_error(s));
    if (csv) write_row(csv, s, opt);
  };
  sample();

  using clock = std::chrono::steady_clock;
  const auto started = clock::now();
  auto last_report = started;
  double stepping_s = 0.0;
  double slowest_s = 0.0;  // the slowest chunk's time per step: with --every 1, the slowest step
  long done = 0;
  mbrt::StepStatus status = mbrt::StepStatus::ok;
  while (done < steps && status == mbrt::StepStatus::ok) {
    const long chunk = std::min(opt.every - done % opt.every, steps - done);
    const auto t0 = clock::now();
    for (long i = 0; i < chunk && status == mbrt::StepStatus::ok; ++i, ++done) status = model::step(s, *workspace);
    const auto t1 = clock::now();
    stepping_s += std::chrono::duration<double>(t1 - t0).count();
    slowest_s = std::max(slowest_s, std::chrono::duration<double>(t1 - t0).count() / static_cast<double>(std::max(chunk, 1L)));
    if (done % opt.every == 0 || done == steps) sample();
    if (t1 - last_report > std::chrono::seconds(5)) {  // progress on long runs
      std::fprintf(stderr, "t = %.6g of %.6g s (%.0f%%)\n", s.t, opt.t_end, 100.0 * done / std::max(steps, 1L));
      last_report = t1;
    }
  }
  if (csv) std::fclose(csv);
  const double wall_s = std::chrono::duration<double>(clock::now() - started).count();
  // The summary: one JSON object on the last line (non-finite numbers become null).
  const nlohmann::ordered_json summary = {
      {"model", model::kName},
      {"scheme", model::kScheme},
      {"h", model::kStep},
      {"steps", done},
      {"wall_s", wall_s},
      {"ns_per_step", done ? 1e9 * stepping_s / static_cast<double>(done) : 0.0},
      {"max_ns_per_step", 1e9 * slowest_s},
      {"max_position_violation", max_pos},
      {"max_velocity_violation", max_vel},
      {"max_acceleration_violation", max_acc},
      {"max_quat_norm_error", max_quat},
      {"energy_initial", e0},
      {"energy_final", model::energy(s).total()},
      {"status", mbrt::to_string(status)}};
  std::printf("%s\n", summary.dump().c_str());
  return status == mbrt::StepStatus::ok ? 0 : 3;
}
