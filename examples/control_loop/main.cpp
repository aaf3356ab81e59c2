// Runs the generated step for one simulated second, as a control loop would,
// and prints where the lower rod ended up.
#include <cmath>
#include <cstdio>

#include "double_pendulum.hpp"

namespace model = mbrt::models::double_pendulum;

int main() {
  model::State s = model::initial_state();  // caller-owned state: no globals
  for (int i = 0; i < 1000; ++i) {
    if (model::step(s) != mbrt::StepStatus::ok) {
      std::fprintf(stderr, "step %d failed\n", i);
      return 1;
    }
  }
  const mbrt::Energy e = model::energy(s);
  std::printf("t = %.3f s, lower rod at (%.4f, %.4f), energy %.6f J\n", s.t, s.rigid[1].r.x(), s.rigid[1].r.y(),
              e.total());
  // Released from rest at y = 0 with ideal joints: the energy stays 0.
  return std::abs(e.total()) < 1e-3 ? 0 : 1;
}
