// Run time at equal error: a method's work-precision curve (its runs at
// successive step sizes) interpolated in log-log at a given error.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "measure.hpp"

namespace timing {

// Run time of the curve (one problem, engine and method, any order) at the
// given error; nullopt where the error lies outside every segment between
// neighbouring step sizes. Where several segments span it, the fastest.
std::optional<double> seconds_at_error(std::vector<Measurement> curve, double error);

// m's run time over the run time, at m's error, of the fastest curve among
// the runs of m's problem that is_reference accepts (a curve: one engine and
// method).
std::optional<double> ratio_at_equal_error(const Measurement& m, const std::vector<Measurement>& all,
                                           const std::function<bool(const Measurement&)>& is_reference);

// ... against the fastest MuJoCo integrator.
std::optional<double> ratio_to_mujoco(const Measurement& m, const std::vector<Measurement>& all);

// ... of an mbrt run against staggered-pcst with the same euler_updates.
std::optional<double> ratio_to_staggered_pcst(const Measurement& m, const std::vector<Measurement>& all);

}  // namespace timing
