#include "equal_error.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace timing {

std::optional<double> seconds_at_error(std::vector<Measurement> curve, double error) {
  std::sort(curve.begin(), curve.end(), [](const Measurement& a, const Measurement& b) { return a.h > b.h; });
  std::optional<double> best;
  for (size_t i = 1; i < curve.size(); ++i) {
    const Measurement &a = curve[i - 1], &b = curve[i];
    if (a.failed || b.failed || a.error <= 0 || b.error <= 0) continue;
    const double lo = std::min(a.error, b.error), hi = std::max(a.error, b.error);
    if (error < lo || error > hi) continue;
    const double s = a.error == b.error ? 0.0 : std::log(error / a.error) / std::log(b.error / a.error);
    const double seconds = std::exp(std::log(a.seconds) + s * std::log(b.seconds / a.seconds));
    best = best ? std::min(*best, seconds) : seconds;
  }
  return best;
}

std::optional<double> ratio_at_equal_error(const Measurement& m, const std::vector<Measurement>& all,
                                           const std::function<bool(const Measurement&)>& is_reference) {
  if (m.failed) return std::nullopt;
  std::set<std::pair<std::string, std::string>> curves;
  for (const Measurement& r : all)
    if (r.problem == m.problem && is_reference(r)) curves.insert({r.engine, r.method});
  std::optional<double> fastest;
  for (const auto& [engine, method] : curves) {
    std::vector<Measurement> curve;
    for (const Measurement& r : all)
      if (r.problem == m.problem && r.engine == engine && r.method == method) curve.push_back(r);
    if (const auto s = seconds_at_error(curve, m.error)) fastest = fastest ? std::min(*fastest, *s) : *s;
  }
  if (!fastest) return std::nullopt;
  return m.seconds / *fastest;
}

std::optional<double> ratio_to_mujoco(const Measurement& m, const std::vector<Measurement>& all) {
  return ratio_at_equal_error(m, all, [](const Measurement& r) { return r.engine == "mujoco"; });
}

std::optional<double> ratio_to_staggered_pcst(const Measurement& m, const std::vector<Measurement>& all) {
  if (m.engine != "mbrt") return std::nullopt;
  // The method names the scheme first, then the euler_updates where varied.
  const size_t space = m.method.find(' ');
  const std::string reference = "staggered-pcst" + (space == std::string::npos ? "" : m.method.substr(space));
  return ratio_at_equal_error(m, all, [&](const Measurement& r) { return r.engine == "mbrt" && r.method == reference; });
}

}  // namespace timing
