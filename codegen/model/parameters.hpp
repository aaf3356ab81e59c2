// Runtime parameters (docs/parameters.md): the model keys a file marks
// `tunable`, as the scalar values the generated Parameters struct holds.
#pragma once

#include <string>
#include <vector>

#include "model.hpp"

namespace mbrt::codegen {

enum class ParameterTarget {
  gravity,                 // component: x, y, z
  mass,                    // index: body
  inertia,                 // index: body; component: the diagonal xx, yy, zz
  position,                // index: body; initial state, world
  velocity,                // index: body; initial state, world
  angular_velocity,        // index: body; initial state, body axes
  spring_stiffness,        // index: force (spring_damper or joint_spring)
  spring_damping,          // index: force
  spring_rest,             // index: force (rest_length or rest)
  joint_coordinate,        // index: joint (revolute, prismatic); initial state of the tree schemes
  joint_rate,              // index: joint; initial state of the tree schemes
  driver_coefficient,      // index: driver; component: polynomial c0, c1, ... or sine amplitude, omega, phase, offset
};

struct Parameter {
  std::string name;  // "upper_arm.mass", "gravity.z", "pin.spring.stiffness", "forces.0.rest_length", "pin.coordinate",
                     // "motor.function.c1"
  ParameterTarget target = ParameterTarget::gravity;
  int index = -1;      // Model::bodies, Model::forces, Model::joints or Model::drivers
  int component = 0;   // of a vector, of an inertia's diagonal or of a driver's function
  double value = 0.0;  // the model file's value: the default
  SourceLocation where;  // the `tunable:` entry that marked it
  std::string entry;     // that entry as written
};

// Every scalar parameter of the keys the model marks tunable, in the order of
// its `tunable:` list. Throws ModelError at an entry that names nothing
// tunable (listing what is), a diagonal of a body whose inertia has products,
// or a parameter marked twice.
std::vector<Parameter> parameters(const Model& model);

// Their names, for a command line to check `--set KEY=VALUE` before compiling.
std::vector<std::string> tunable_names(const Model& model);

// The C++ identifier of a parameter's index constant: "upper_arm.mass" -> upper_arm_mass.
std::string parameter_identifier(const std::string& name);

}  // namespace mbrt::codegen
