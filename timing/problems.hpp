// The work-precision problems: each mechanism, how long it runs, which point
// is observed and its independent reference (reference_solutions.hpp), and
// the step sizes tried. Every engine builds the same mechanism; body names
// are shared (tests/models, timing/models) so each engine finds the observed
// body by name.
#pragma once

#include <string>
#include <vector>

#include <mbrt/types.hpp>

namespace timing {

// model_file: a tree of an mbrt model file, which the peers build from the
// file itself (peers/tree_peer.hpp); the others each peer builds by hand.
enum class Mechanism { a01_pendulum, heavy_top, n_four_bar, chain, andrews, model_file };

// The observed point at time t, compared on the axes where mask is 1.
struct Observation {
  double t;
  mbrt::Vec3 value;
  mbrt::Vec3 mask;
};

struct Problem {
  std::string name;
  Mechanism mechanism;
  int n;                 // windows of the N four-bar, links of the chain
  std::string body;      // the observed body
  mbrt::Vec3 point;      // the observed point on it, world coordinates at t = 0 (all bodies start unrotated)
  double base_step;      // mbrt's largest step; peers also try up to 16 times larger
  std::vector<Observation> reference;
  std::string model_file;  // model_file: the model, and the observed point is the body's centre of mass
};

// Error of an observed point against the reference sample.
inline double observation_error(const Observation& o, const mbrt::Vec3& observed) {
  return (observed - o.value).cwiseProduct(o.mask).norm();
}

const std::vector<Problem>& problems();
const Problem& problem(const std::string& name);

// Gravity of the mechanism, m/s^2: -z for the heavy top, none for Andrews'
// squeezer, -y for the planar mechanisms (model files carry their own).
mbrt::Vec3 gravity(Mechanism m);

// Peers' step sizes: base_step times 16, 8, 4, 2, 1, 1/2, 1/4 (their methods'
// orders range from 1 to 4, so their errors span more than mbrt's).
std::vector<double> peer_steps(const Problem& p);

}  // namespace timing
