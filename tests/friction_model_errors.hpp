// The joint-friction tests' model errors (test_joint_friction.cpp,
// test_joint_friction_absolute.cpp): a one-joint pendulum's model text and
// the error the generator's parser and analysis give for it. Links
// mbrt_codegen.
#pragma once

#include <string>

#include <doctest/doctest.h>

#include "analysis.hpp"
#include "model.hpp"

namespace friction_errors {

// A rod on a pin (or a joint of `type`) at the origin, axis y; the joint is
// on line 6, with `joint_extra` (", friction: {...}") in its braces.
inline std::string pendulum_with(const std::string& joint_extra, const std::string& type = "revolute") {
  return "name: p\ngravity: [0, 0, -9.81]\nbodies:\n"
         "  - {name: rod, mass: 1, inertia: [0.1, 0.1, 0.01], position: [0, 0, -0.5]}\n"
         "joints:\n"
         "  - {name: pin, type: " + type + ", body1: ground, body2: rod, point: [0, 0, 0]" +
         (type == "spherical" ? "" : ", axis: [0, 1, 0]") + joint_extra + "}\n";
}

// The error's text (file:line: key: message) for a model that must fail.
inline std::string error_of(const std::string& yaml) {
  try {
    const mbrt::codegen::Model model = mbrt::codegen::parse_model(yaml, "arm.yaml");
    mbrt::codegen::analyse(model);
  } catch (const mbrt::codegen::ModelError& e) {
    return e.what();
  }
  return "(no error)";
}

// That the pendulum model `yaml` fails with an error on the joint's line
// naming `key` and containing `phrase`.
inline void check(const std::string& yaml, const std::string& key, const std::string& phrase) {
  const std::string what = error_of(yaml);
  INFO(what);
  CHECK(what.find("arm.yaml:6") != std::string::npos);
  CHECK(what.find(key) != std::string::npos);
  CHECK(what.find(phrase) != std::string::npos);
}

}  // namespace friction_errors
