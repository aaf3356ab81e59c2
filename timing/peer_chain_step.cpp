// A peer engine on the planar N-link chain of tools/make_chain.py, stepped
// STEPS times at H from rest: the peers' side of timing/chain_growth. Prints
// ns per step (the whole run timed, as `mbrt sim` times its own) and the tip
// of the last link at the end, for the check against mbrt. Instructions per
// step come from callgrind over runs of STEPS and 2 STEPS steps, so that
// building the model cancels.
//   peer_chain_step N PEER STEPS [H=1e-4]   PEER: ENGINE-METHOD, e.g. mujoco-rk4
//   peer_chain_step --list                  the peers built in, one a line
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "peer_engine.hpp"
#include "problems.hpp"
#ifdef MBRT_WITH_MUJOCO
#include "mujoco_engine.hpp"
#endif
#ifdef MBRT_WITH_SIMBODY
#include "simbody_engine.hpp"
#endif
#ifdef MBRT_WITH_DART
#include "dart_engine.hpp"
#endif

namespace {

using Factory = std::function<std::unique_ptr<timing::PeerEngine>(const timing::Problem&, const std::string&, double)>;

struct Peer {
  std::string name;  // ENGINE-METHOD
  std::string method;
  Factory make;
};

std::vector<Peer> peers() {
  std::vector<Peer> out;
#ifdef MBRT_WITH_MUJOCO
  for (const std::string& m : timing::mujoco_methods()) out.push_back({"mujoco-" + m, m, timing::mujoco_engine});
#else
  std::fprintf(stderr, "MuJoCo not built in (apt-get install libmujoco-dev, then reconfigure)\n");
#endif
#ifdef MBRT_WITH_SIMBODY
  for (const std::string& m : timing::simbody_methods()) out.push_back({"simbody-" + m, m, timing::simbody_engine});
#else
  std::fprintf(stderr, "Simbody not built in (apt-get install libsimbody-dev, then reconfigure)\n");
#endif
#ifdef MBRT_WITH_DART
  for (const std::string& m : timing::dart_methods()) out.push_back({"dart-" + m, m, timing::dart_engine});
#else
  std::fprintf(stderr, "DART not built in (apt-get install libdart-dev, then reconfigure)\n");
#endif
  return out;
}

int usage() {
  std::fprintf(stderr, "usage: peer_chain_step N PEER STEPS [H=1e-4] | peer_chain_step --list\n");
  return 2;
}

int run(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list") {
    for (const Peer& p : peers()) std::printf("%s\n", p.name.c_str());
    return 0;
  }
  if (argc < 4 || argc > 5) return usage();
  const int n = std::atoi(argv[1]);
  const std::string name = argv[2];
  const long steps = std::atol(argv[3]);
  const double h = argc == 5 ? std::atof(argv[4]) : 1e-4;
  if (n < 1 || steps < 0 || !(h > 0)) return usage();
  const std::vector<Peer> all = peers();
  const Peer* peer = nullptr;
  for (const Peer& p : all)
    if (p.name == name) peer = &p;
  if (!peer) {
    std::fprintf(stderr, "no peer %s built in (peer_chain_step --list)\n", name.c_str());
    return 2;
  }
  // Observed: the tip of the last link, (N, 0, 0) at rest.
  const timing::Problem chain{"chain_" + std::to_string(n), timing::Mechanism::chain, n,
                              "link_" + std::to_string(n - 1), {double(n), 0, 0}, h, {}, {}};
  const std::unique_ptr<timing::PeerEngine> engine = peer->make(chain, peer->method, h);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  // To the time of STEPS steps, as measure.hpp steps to a time: Simbody's
  // first call after initializing advances nothing.
  const double t_end = h * static_cast<double>(steps);
  bool ok = true;
  while (ok && engine->time() < t_end - 0.5 * h) ok = engine->step();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const long done = std::lround(engine->time() / h);
  const mbrt::Vec3 tip = engine->observed();
  const nlohmann::ordered_json j = {{"links", n},
                                    {"peer", name},
                                    {"h", h},
                                    {"steps", done},
                                    {"t", engine->time()},
                                    {"ns_per_step", done ? 1e9 * seconds / static_cast<double>(done) : 0.0},
                                    {"tip", {tip[0], tip[1], tip[2]}},
                                    {"status", ok ? "ok" : "failed"}};
  std::printf("%s\n", j.dump().c_str());
  return ok ? 0 : 3;
}

}  // namespace

// An engine that cannot load the chain throws.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_chain_step: %s\n", e.what());
    return 1;
  }
}
