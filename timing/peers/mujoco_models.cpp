#include "mujoco_models.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "andrews_mechanism.hpp"

namespace timing {
namespace {

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A uniform 1 kg, 1 m rod along x or y of its body frame, starting at the
// frame origin: m L^2/12 transverse, 1e-4 axial (as the mbrt models).
std::string rod(char axis) {
  const std::string t = num(1.0 / 12.0);
  return axis == 'x' ? "<inertial pos='0.5 0 0' mass='1' diaginertia='1e-4 " + t + " " + t + "'/>"
                     : "<inertial pos='0 0.5 0' mass='1' diaginertia='" + t + " 1e-4 " + t + "'/>";
}

const char* kHinge = "<joint type='hinge' axis='0 0 1'/>";

// Loop closures as stiff as MuJoCo allows (time constant clamped to 2 steps,
// impedance near 1).
const char* kStiff = " solref='1e-6 1' solimp='0.9999 0.9999 0.001 0.5 2'";

std::string vec(const mbrt::Vec3& v) { return num(v[0]) + " " + num(v[1]) + " " + num(v[2]); }

std::string a01() {
  // The bar is massless: the body is the bob, a point mass (MuJoCo needs a
  // positive inertia; 1e-12 kg m^2 changes nothing at the compared digits).
  return "<worldbody><body name='bob' pos='-1 0 0'><joint type='hinge' pos='1 0 0' axis='0 0 1'/>"
         "<inertial pos='0 0 0' mass='1' diaginertia='1e-12 1e-12 1e-12'/></body></worldbody>";
}

std::string heavy_top() {
  // Ball joint velocities are body-frame angular velocities.
  return "<worldbody><body name='top'><joint type='ball'/>"
         "<inertial pos='0 1 0' mass='15' diaginertia='0.234375 0.46875 0.234375'/></body></worldbody>"
         "<keyframe><key qvel='0 150 -4.61538'/></keyframe>";
}

// Cranks pinned to the ground, each carrying the coupler to its right; the
// coupler's far end is connected to the next crank's top.
std::string n_four_bar(int n) {
  std::string bodies, equality, qvel;
  for (int i = 0; i <= n; ++i) {
    bodies += "<body name='crank_" + std::to_string(i) + "' pos='" + std::to_string(i) + " 0 0'>" + kHinge + rod('y');
    qvel += i == 0 ? "-1" : " -1";
    if (i < n) {
      bodies += "<body name='coupler_" + std::to_string(i) + "' pos='0 1 0'>" + kHinge + rod('x') + "</body>";
      qvel += " 1";  // couplers translate: +1 relative to the crank
      equality += "<connect body1='coupler_" + std::to_string(i) + "' body2='crank_" + std::to_string(i + 1) +
                  "' anchor='1 0 0'" + kStiff + "/>";
    }
    bodies += "</body>";
  }
  return "<worldbody>" + bodies + "</worldbody><equality>" + equality + "</equality><keyframe><key qvel='" + qvel +
         "'/></keyframe>";
}

// MuJoCo's XML parser refuses elements nested about 100 deep, and MJCF nests
// a chain's bodies: longer chains go on in included files, kChainPart links each.
constexpr int kChainPart = 32;

std::string chain(int n, Mjcf& out) {
  std::string rest;  // the links after this part, as an include
  for (int a = (n - 1) / kChainPart * kChainPart;; a -= kChainPart) {
    std::string open, close;
    for (int i = a; i < std::min(a + kChainPart, n); ++i) {
      open += "<body name='link_" + std::to_string(i) + "' pos='" + (i == 0 ? "0" : "1") + " 0 0'>" + kHinge + rod('x');
      close += "</body>";
    }
    if (a == 0) return "<worldbody>" + open + rest + close + "</worldbody>";
    const std::string file = "chain_from_" + std::to_string(a) + ".xml";
    out.includes.push_back({file, "<mujoco>" + open + rest + close + "</mujoco>"});
    rest = "<include file='" + file + "'/>";
  }
}

// The bodies whose parent is `parent`, nested, each frame at its centre of
// mass (unrotated, so positions relative to the parent are differences).
std::string andrews_tree(const std::string& parent) {
  std::string out;
  for (const andrews::Body& b : andrews::kBodies) {
    if (parent != b.parent) continue;
    out += "<body name='" + std::string(b.name) + "' pos='" + vec(b.com - andrews::com(b.parent)) + "'>" +
           "<joint name='" + b.name + "' type='hinge' axis='0 0 1' pos='" + vec(b.pin - b.com) + "'/>" +
           "<inertial pos='0 0 0' mass='" + num(b.mass) + "' diaginertia='" + vec(b.inertia) + "'/>";
    if (std::string(b.name) == "triangle") out += "<site name='d' pos='" + vec(andrews::kD - b.com) + "'/>";
    out += andrews_tree(b.name) + "</body>";
  }
  return out;
}

// Andrews' squeezer: the tree of andrews_mechanism.hpp, its loops closed by
// `connect`, the spring a spatial tendon, the constant torque an actuator's
// affine bias (its force whatever the control).
std::string andrews_squeezer() {
  std::string equality;
  for (const andrews::Closure& c : andrews::kClosures) {
    equality += "<connect body1='" + std::string(c.body1) + "'" +
                (*c.body2 ? " body2='" + std::string(c.body2) + "'" : std::string()) + " anchor='" +
                vec(c.point - andrews::com(c.body1)) + "'" + kStiff + "/>";
  }
  return "<worldbody><site name='c' pos='" + vec(andrews::kC) + "'/>" + andrews_tree("") + "</worldbody>" +
         "<equality>" + equality + "</equality>" +
         "<tendon><spatial stiffness='" + num(andrews::kSpringStiffness) + "' springlength='" +
         num(andrews::kSpringRestLength) + "'><site site='d'/><site site='c'/></spatial></tendon>" +
         "<actuator><general joint='crank' biastype='affine' biasprm='" + num(andrews::kCrankTorque) +
         " 0 0'/></actuator>";
}

std::string mechanism(const Problem& p, Mjcf& out) {
  switch (p.mechanism) {
    case Mechanism::a01_pendulum: return a01();
    case Mechanism::heavy_top: return heavy_top();
    case Mechanism::n_four_bar: return n_four_bar(p.n);
    case Mechanism::chain: return chain(p.n, out);
    case Mechanism::andrews: return andrews_squeezer();
    case Mechanism::model_file: break;  // built from the file (tree_peer.hpp)
  }
  throw std::logic_error("unknown mechanism");
}

}  // namespace

Mjcf mujoco_mjcf(const Problem& p) {
  Mjcf out;
  out.main = "<mujoco model='" + p.name + "'><option gravity='" + vec(gravity(p.mechanism)) + "'/>" + mechanism(p, out) +
             "</mujoco>";
  return out;
}

}  // namespace timing
