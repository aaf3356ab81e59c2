// `--set KEY=VALUE` (docs/parameters.md): runtime parameters set by name
// before a run, for the programs built around a generated model (the sim
// program and the HIL loop). Start-up only; nothing here is on the loop path.
#pragma once

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mbrt/model_api.hpp"

namespace mbrt {

// "KEY=VALUE" into key and value; "" or why it is not one with a finite number.
inline std::string parse_setting(const std::string& text, std::string& key, double& value) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return "expected KEY=VALUE, got '" + text + "'";
  const std::string number = text.substr(eq + 1);
  char* end = nullptr;
  errno = 0;
  value = std::strtod(number.c_str(), &end);
  if (number.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
    return "expected KEY=VALUE with a finite number, got '" + text + "'";
  }
  key = text.substr(0, eq);
  return "";
}

// Sets each "KEY=VALUE" of settings in values by name, in order; "" or why
// one cannot be (naming the model's parameters).
template <std::size_t N>
std::string apply_settings(const std::array<ParameterInfo, N>& info, std::array<double, N>& values,
                           const std::vector<std::string>& settings) {
  for (const std::string& setting : settings) {
    std::string key;
    double value = 0.0;
    if (std::string why = parse_setting(setting, key, value); !why.empty()) return why;
    if (set_parameter(info, values, key, value)) continue;
    std::string names;
    for (const ParameterInfo& p : info) names += std::string(names.empty() ? "" : ", ") + p.name;
    return "'" + key + "' is not a tunable parameter of the model; its parameters are " + names;
  }
  return "";
}

// Why a state started from set parameters cannot run: its joints off by
// more than the generator's check of a model file's initial state allows.
inline std::string check_set_start(const ConstraintViolation& v) {
  constexpr double kTolerance = 1e-8;
  if (v.position <= kTolerance && v.velocity <= kTolerance) return "";
  char why[256];
  std::snprintf(why, sizeof why,
                "the initial state set violates the joints (position %.3g, velocity %.3g, tolerance %.0e): "
                "set positions and velocities that satisfy them",
                v.position, v.velocity, kTolerance);
  return why;
}

// A generated model's initial state with the settings applied to its
// default parameters p (initial_state and constraint_violation: the model's
// functions); "" or why it cannot start (an unknown key, or a start off the
// joints).
template <class State, class Parameters, std::size_t N>
std::string start_with_settings(const std::array<ParameterInfo, N>& info, Parameters p,
                                const std::vector<std::string>& settings,
                                State (*initial_state)(const Parameters&),
                                ConstraintViolation (*constraint_violation)(const State&), State& s) {
  if (std::string why = apply_settings(info, p.value, settings); !why.empty()) return why;
  s = initial_state(p);
  return settings.empty() ? "" : check_set_start(constraint_violation(s));
}

}  // namespace mbrt
