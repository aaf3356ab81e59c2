// Whether a scene qualifies for planar coordinates (docs/specializations.md,
// "planar"), in which plane of world coordinates, and its constraint blocks
// in planar form.
#pragma once

#include "analysis.hpp"

namespace mbrt::codegen {

// A plane of world coordinates, named by its normal, world axis k; its
// coordinates are i = k + 1 and j = k + 2 (mod 3), right-handed with k.
struct Plane {
  int normal;

  int i() const { return (normal + 1) % 3; }
  int j() const { return (normal + 2) % 3; }
  std::string name() const;       // "x-y", "x-z" or "y-z"
  std::string axis_name() const;  // "x", "y" or "z"
  bool contains(const Eigen::Vector3d& v) const { return v[normal] == 0.0; }
  bool along_normal(const Eigen::Vector3d& v) const { return v[i()] == 0.0 && v[j()] == 0.0; }
  // Components in plane coordinates (i, j, k), which the planar step's
  // formulas name (x, y, z).
  Eigen::Vector3d coordinates(const Eigen::Vector3d& v) const { return {v[i()], v[j()], v[normal]}; }
};

// The plan for a model whose analysis is otherwise complete; refusal says
// why a scene does not qualify.
PlanarPlan plan_planar(const Model& model, const Analysis& a);

}  // namespace mbrt::codegen
