// Run time at equal error: a method's work-precision curve (its runs at
// successive step sizes) interpolated in log-log at a given error.
#pragma once

#include <optional>
#include <vector>

#include "measure.hpp"

namespace timing {

// Run time of the curve (one problem, engine and method, any order) at the
// given error; nullopt where the error lies outside every segment between
// neighbouring step sizes. Where several segments span it, the fastest.
std::optional<double> seconds_at_error(std::vector<Measurement> curve, double error);

// m's run time over the fastest MuJoCo integrator's run time at m's error.
std::optional<double> ratio_to_mujoco(const Measurement& m, const std::vector<Measurement>& all);

}  // namespace timing
