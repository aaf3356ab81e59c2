// Andrews' squeezer as the peers build it: the bodies, joint points, spring
// and torque of tests/models/benchmarks/a03_andrews_squeezer.yaml (the Test
// Set for IVP Solvers' "andrews" at its consistent q0, at rest; world
// coordinates at t = 0, every body unrotated, every joint a pin about z).
// The peers need a spanning tree: bodies hang from their parent by a pin,
// and the three joints left over close the loops.
#pragma once

#include <string_view>

#include <mbrt/types.hpp>

namespace timing::andrews {

inline const mbrt::Vec3 kO(0, 0, 0);
inline const mbrt::Vec3 kF(0.006986674115451445, -0.0004317230645688955, 0);
inline const mbrt::Vec3 kE(-0.020960022346354336, 0.0012951691937066864, 0);
inline const mbrt::Vec3 kB(-0.03635, 0.03273, 0);
inline const mbrt::Vec3 kG(-0.03399720388583998, 0.01646197167499768, 0);
inline const mbrt::Vec3 kA(-0.06934, -0.00227, 0);
inline const mbrt::Vec3 kH(-0.03163313450740889, -0.015618868668304536, 0);
inline const mbrt::Vec3 kD(-0.010472393888814624, 0.025357788530275253, 0);  // spring end on the triangle
inline const mbrt::Vec3 kC(0.014, 0.072, 0);                                  // spring end on the ground

struct Body {
  const char* name;
  const char* parent;  // "" for the ground
  double mass;
  mbrt::Vec3 inertia;  // central, about x, y, z
  mbrt::Vec3 com;
  mbrt::Vec3 pin;      // the joint to the parent
};

// Parents before children.
inline const Body kBodies[] = {
    {"crank", "", 0.04325, {1.097e-6, 1.097e-6, 2.194e-6}, {0.0009182485980307614, -5.674074562905483e-05, 0}, kO},
    {"rod_fe", "crank", 0.00365, {2.205e-7, 2.205e-7, 4.410e-7}, {-0.0044914333599330725, 0.0002775362557942899, 0}, kF},
    {"triangle", "rod_fe", 0.02373, {2.6275e-6, 2.6275e-6, 5.255e-6}, {-0.01874218667031546, 0.02048510678907393, 0}, kE},
    {"rod_ge", "rod_fe", 0.00706, {2.8335e-7, 2.8335e-7, 5.667e-7}, {-0.030222939830158887, 0.012071182356663938, 0}, kE},
    {"rod_he", "rod_fe", 0.00706, {2.8335e-7, 2.8335e-7, 5.667e-7}, {-0.028543268536783597, -0.010722254707252287, 0}, kE},
    {"link_ag", "", 0.07050, {5.845e-6, 5.845e-6, 1.169e-5}, {-0.05323682815570414, 0.016631847966616306, 0}, kA},
    {"link_ah", "", 0.05498, {9.56e-6, 9.56e-6, 1.912e-5}, {-0.059262402801791715, -0.010600698332712844, 0}, kA},
};

// The loop-closing joints: body1's and body2's points coincide ("" is the ground).
struct Closure {
  const char* body1;
  const char* body2;
  mbrt::Vec3 point;
};
inline const Closure kClosures[] = {{"triangle", "", kB}, {"rod_ge", "link_ag", kG}, {"rod_he", "link_ah", kH}};

inline constexpr double kSpringStiffness = 4530;  // N/m, from D to C
inline constexpr double kSpringRestLength = 0.07785;
inline constexpr double kCrankTorque = 0.033;  // N m about z, ground on the crank

// A body's centre of mass; the ground's is the origin.
inline mbrt::Vec3 com(const char* name) {
  for (const Body& b : kBodies)
    if (std::string_view(name) == b.name) return b.com;
  return mbrt::Vec3::Zero();
}

}  // namespace timing::andrews
