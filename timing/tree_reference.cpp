// The reference trajectory of a model-file work-precision problem
// (problems.cpp, Mechanism::model_file): the centre of mass of one body of an
// mbrt model file, from Simbody's error-controlled Runge-Kutta-Merson, an
// engine independent of mbrt, written as timing/references/NAME.csv.
//
//   tree_reference MODEL.yaml --body NAME --t-end T --every DT [--accuracy A=1e-12] > NAME.csv
//
// The same run at 100 A and, where MuJoCo is built in, MuJoCo's RK4 at a
// step of DT / 1000 bound the reference's own error; both differences go
// into the CSV's header and to stderr.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "tree_engine.hpp"

namespace {

using namespace timing::tree;

struct Options {
  std::string model, body;
  double t_end = 0, every = 0, accuracy = 1e-12;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "tree_reference: %s\nusage: tree_reference MODEL.yaml --body NAME --t-end T --every DT "
               "[--accuracy A=1e-12]\n",
               why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--body") o.body = value();
    else if (a == "--t-end") o.t_end = std::atof(value().c_str());
    else if (a == "--every") o.every = std::atof(value().c_str());
    else if (a == "--accuracy") o.accuracy = std::atof(value().c_str());
    else if (a.rfind("--", 0) == 0 || !o.model.empty()) usage("unexpected " + a);
    else o.model = a;
  }
  if (o.model.empty() || o.body.empty()) usage("a model file and --body are needed");
  if (!(o.t_end > 0) || !(o.every > 0) || !(o.accuracy > 0)) usage("--t-end, --every and --accuracy must be positive");
  return o;
}

double largest_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double d = 0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) d = std::max(d, (a[k] - b[k]).norm());
  return a.size() == b.size() ? d : INFINITY;
}

#ifdef MBRT_WITH_MUJOCO
std::vector<Vec3> mujoco_rk4(const Model& m, int body, const Options& o) {
  const long per_sample = 1000, samples = std::lround(o.t_end / o.every);
  const std::unique_ptr<Engine> e = make_engine("mujoco-rk4", m, o.every / per_sample);
  std::vector<Vec3> out{e->states()[static_cast<std::size_t>(body)].r};
  for (long k = 1; k <= samples; ++k) {
    for (long i = 0; i < per_sample; ++i)
      if (!e->step()) return out;
    out.push_back(e->states()[static_cast<std::size_t>(body)].r);
  }
  return out;
}
#endif

int main_checked(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const Model m = mbrt::codegen::load_model(o.model);
  links(m);  // refuse what the engines cannot build
  int body = -1;
  for (std::size_t i = 0; i < m.bodies.size(); ++i)
    if (m.bodies[i].name == o.body) body = static_cast<int>(i);
  if (body < 0) usage(o.model + " has no body " + o.body);
  const std::vector<Vec3> ref = simbody_reference(m, body, o.t_end, o.every, o.accuracy);
  const double coarser = largest_difference(ref, simbody_reference(m, body, o.t_end, o.every, 100 * o.accuracy));
  char text[200];
  std::snprintf(text, sizeof text, "# largest difference from the same at accuracy %.3g: %.3g m", 100 * o.accuracy,
                coarser);
  std::string check = text;
#ifdef MBRT_WITH_MUJOCO
  std::snprintf(text, sizeof text, "\n# largest difference from MuJoCo 2.2.2 RK4 at h = %.3g s: %.3g m",
                o.every / 1000, largest_difference(ref, mujoco_rk4(m, body, o)));
  check += text;
#endif
  std::fprintf(stderr, "%s\n", check.c_str());
  std::printf("# %s, centre of mass of %s: Simbody 3.7 Runge-Kutta-Merson, error-controlled, accuracy %.3g\n",
              o.model.substr(o.model.rfind('/') + 1).c_str(), o.body.c_str(), o.accuracy);
  std::printf("# timing/tree_reference %s --body %s --t-end %g --every %g --accuracy %g\n%s\nt,x,y,z\n",
              o.model.substr(o.model.find("tests/") == std::string::npos ? 0 : o.model.find("tests/")).c_str(),
              o.body.c_str(), o.t_end, o.every, o.accuracy, check.c_str());
  for (std::size_t k = 0; k < ref.size(); ++k)
    std::printf("%.6g,%.17g,%.17g,%.17g\n", o.every * static_cast<double>(k), ref[k][0], ref[k][1], ref[k][2]);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return main_checked(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tree_reference: %s\n", e.what());
    return 1;
  }
}
