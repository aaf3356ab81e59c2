// A program with a known number of floating-point operations per "step", run
// the way `mbrt sim` runs a model (--t-end T --every N; h = 1e-3): each step
// does 2 multiplications, 2 additions, 1 subtraction, 1 division and 1
// square root on volatile doubles, 7 operations the compiler cannot merge.
#include <cmath>
#include <cstdlib>
#include <cstring>

int main(int argc, char** argv) {
  double t_end = 0.0;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--t-end") == 0) t_end = std::atof(argv[i + 1]);
  }
  const long steps = std::lround(t_end / 1e-3);
  volatile double x = 1.5, y = 2.5, z = 0.0;
  for (long i = 0; i < steps; ++i) {
    const double a = x * y + x;   // 2
    const double b = a * y - x;   // 2
    const double c = b / y + y;   // 2
    z = std::sqrt(c);             // 1
  }
  return z > 0.0 ? 0 : 1;
}
