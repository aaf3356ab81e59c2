#include "tree_engine.hpp"

#include <stdexcept>

namespace timing::tree {

std::vector<std::string> engines() {
  std::vector<std::string> out;
#ifdef MBRT_WITH_MUJOCO
  for (const char* m : {"euler", "rk4"}) out.push_back(std::string("mujoco-") + m);
#endif
#ifdef MBRT_WITH_SIMBODY
  for (const char* m : {"rk3", "rk-merson", "semiexplicit-euler", "semiexplicit-euler2"})
    out.push_back(std::string("simbody-") + m);
#endif
#ifdef MBRT_WITH_DART
  out.push_back("dart-euler");
#endif
  return out;
}

std::unique_ptr<Engine> make_engine(const std::string& name, const Model& m, double h) {
#ifdef MBRT_WITH_MUJOCO
  if (name == "mujoco-euler") return mujoco_engine(m, "Euler", h);
  if (name == "mujoco-rk4") return mujoco_engine(m, "RK4", h);
#endif
#ifdef MBRT_WITH_SIMBODY
  const std::string prefix = "simbody-";
  if (name.rfind(prefix, 0) == 0) return simbody_engine(m, name.substr(prefix.size()), h);
#endif
#ifdef MBRT_WITH_DART
  if (name == "dart-euler") return dart_engine(m, h);
#endif
  (void)m, (void)h;
  throw std::invalid_argument("no engine " + name + " built in");
}

}  // namespace timing::tree
