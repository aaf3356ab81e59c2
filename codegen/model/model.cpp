#include "model.hpp"

#include <filesystem>

#include <mbrt/rotation.hpp>

namespace mbrt::codegen {

namespace {
std::string format_error(const SourceLocation& where, const std::string& key, const std::string& message) {
  std::string s = where.file;
  if (where.line > 0) s += ":" + std::to_string(where.line) + ":" + std::to_string(where.column);
  s += ": ";
  if (!key.empty()) s += key + ": ";
  return s + message;
}
}  // namespace

ModelError::ModelError(const SourceLocation& where, const std::string& key, const std::string& message)
    : std::runtime_error(format_error(where, key, message)), where_(where), key_(key) {}

const std::string& Model::body_name(int index) const {
  static const std::string ground = "ground";
  return index == kGround ? ground : bodies.at(static_cast<size_t>(index)).name;
}

std::string Model::file_name() const { return std::filesystem::path(file).filename().string(); }

double joint_rate_at_start(const Model& model, const Joint& joint) {
  Eigen::Vector3d w[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, v[2] = {w[0], w[0]}, r[2] = {w[0], w[0]};
  const int ends[2] = {joint.body1, joint.body2};
  for (int i = 0; i < 2; ++i) {
    if (ends[i] == kGround) continue;
    const Body& b = model.bodies[static_cast<size_t>(ends[i])];
    w[i] = mbrt::rotation_matrix(b.orientation) * b.angular_velocity;
    v[i] = b.velocity;
    r[i] = b.position;
  }
  const Eigen::Vector3d axis = joint.axis.normalized();
  if (joint.type == JointType::revolute) return axis.dot(w[1] - w[0]);
  return axis.dot(v[1] - v[0] - w[0].cross(r[1] - r[0]));
}

mbrt::TimeValue evaluate(const FunctionPiece& piece, double t) {
  return mbrt::polynomial_and_harmonics(piece.polynomial.data(), piece.polynomial.size(), piece.harmonics.data(),
                                        piece.harmonics.size(), t);
}

mbrt::TimeValue evaluate(const TimeFunction& f, double t) {
  if (f.piecewise()) {
    for (const FunctionPiece& piece : f.pieces) {
      if (t < piece.until) return evaluate(piece, t);
    }
    return evaluate(f.pieces.back(), t);
  }
  if (f.is_sine) return mbrt::sine({f.amplitude, f.omega, f.phase, f.offset}, t);
  return mbrt::polynomial(f.polynomial.data(), f.polynomial.size(), t);
}

}  // namespace mbrt::codegen
