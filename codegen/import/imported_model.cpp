#include "imported_model.hpp"

#include <array>
#include <charconv>
#include <stdexcept>

namespace mbrt::codegen {

std::string number_text(double x) {
  std::array<char, 32> buf;
  const auto end = std::to_chars(buf.data(), buf.data() + buf.size(), x == 0.0 ? 0.0 : x).ptr;  // no -0
  return std::string(buf.data(), end);
}

void merge_part(MassPart& into, const MassPart& part) {
  const double mass = into.mass + part.mass;
  if (mass == 0.0) return;
  const Eigen::Vector3d com = (into.mass * into.com + part.mass * part.com) / mass;
  // Inertia about com of a point mass m at offset d: m (|d|^2 1 - d d^T).
  const auto shifted = [&com](const MassPart& p) -> Eigen::Matrix3d {
    const Eigen::Vector3d d = p.com - com;
    return p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  };
  into.inertia = shifted(into) + shifted(part);
  into.com = com;
  into.mass = mass;
}

void require_masses(const ImportedModel& model, const std::string& what_has_mass) {
  for (const ImportedBody& b : model.bodies) {
    if (!(b.mass.mass > 0.0)) {
      throw std::runtime_error(model.source + ": '" + b.name + "' has no mass (" + what_has_mass +
                               "); mbrt's moving bodies need one, so give it mass or fix it to its parent");
    }
  }
}

}  // namespace mbrt::codegen
