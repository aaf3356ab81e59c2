// Fixed-size vector and matrix types shared by the runtime and generated code.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace mbrt {

using Vec3 = Eigen::Matrix<double, 3, 1>;
using Vec4 = Eigen::Matrix<double, 4, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

// Euler parameters (e0, e1, e2, e3), scalar first, body-to-world, unit norm.
using EulerParameters = Vec4;

// Cross-product matrix: skew(a) * b == a.cross(b).
inline Mat3 skew(const Vec3& a) noexcept {
  Mat3 s;
  s << 0.0, -a.z(), a.y(),
       a.z(), 0.0, -a.x(),
       -a.y(), a.x(), 0.0;
  return s;
}

}  // namespace mbrt
