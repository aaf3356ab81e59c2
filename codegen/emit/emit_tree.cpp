// staggered-tree (docs/staggered-tree.md): the articulated-body recursion
// (Featherstone 2008, "Rigid Body Dynamics Algorithms", table 7.1) in joint
// coordinates, run here on symbolic values so that the generated code keeps
// only the operations this model's numbers need.
#include <algorithm>
#include <string>
#include <vector>

#include "emitter.hpp"
#include "spatial_expr.hpp"
#include "straight_line.hpp"

namespace mbrt::codegen {

using namespace spatial;

namespace {

// The motion subspace of a one-dof joint along the frame's z axis: index 2
// (turn) or 5 (slide) of [w; v].
int axis_index(const TreeFrame& f) { return f.revolute ? 2 : 5; }

Motion along_axis(const TreeFrame& f, const Expr& x) {
  Motion m{V3{0.0, 0.0, 0.0}, V3{0.0, 0.0, 0.0}};
  (f.revolute ? m.w : m.v)[2] = x;
  return m;
}

// The parent-to-child transform of a frame: shift the origin by r (parent
// axes), rotate by Ex, shift by d along z, rotate by Rz(phi)^T.
struct Transform {
  M3 rz_t;  // Rz(phi)^T
  M3 ex;
  V3 r;
  V3 d;  // (0, 0, d), or the slide (prismatic)
};

Transform transform_of(const TreeFrame& f, const std::string& joint_trig, const Expr& q) {
  Transform x;
  x.ex = constant(f.Ex);
  x.r = constant(f.r);
  x.d = V3{0.0, 0.0, f.d};
  if (f.revolute) {
    StraightLine& line = StraightLine::current();
    const Expr ch = line.input(joint_trig + ".c"), sh = line.input(joint_trig + ".s");
    const Expr c = ch * ch - sh * sh, s = 2.0 * (sh * ch);  // cos(phi), sin(phi) from the half angle
    x.rz_t = {V3{c, s, 0.0}, V3{-s, c, 0.0}, V3{0.0, 0.0, 1.0}};
  } else {
    x.rz_t = constant(Eigen::Matrix3d(Eigen::Matrix3d::Identity()));
    x.d = V3{0.0, 0.0, f.d + q};  // the slide along the child's z
  }
  return x;
}

Motion to_child(const Transform& x, const Motion& m) {
  const V3 w = times(x.ex, m.w);
  const V3 v = times(x.ex, m.v - cross(x.r, m.w)) - cross(x.d, w);
  return {times(x.rz_t, w), times(x.rz_t, v)};
}

Wrench to_parent(const Transform& x, const Wrench& f) {
  const V3 n1 = transpose_times(x.rz_t, f.n), f1 = transpose_times(x.rz_t, f.f);
  const V3 n2 = n1 + cross(x.d, f1);
  const V3 g = transpose_times(x.ex, f1);
  return {transpose_times(x.ex, n2) + cross(x.r, g), g};
}

// A turn whose cos or sin is a constant 0 (none, or a quarter turn) costs the
// plain congruence nothing; any other goes by the double angle.
bool general_angle(const Expr& c, const Expr& s) {
  return !(c.is_constant() && s.is_constant()) || (!c.is(0.0) && !s.is(0.0));
}

Inertia to_parent(const Transform& x, const Inertia& I) {
  const Expr c = x.rz_t[0][0], s = x.rz_t[0][1];
  const Inertia turned = general_angle(c, s) ? to_old_axes(0, 1, c, s, I) : to_old_axes(x.rz_t, I);
  const Inertia shifted = to_origin(x.d, turned);
  // Craig's turn about x: rows and columns 1 and 2.
  const M3& e = x.ex;
  const bool about_x = e[0][0].is(1.0) && e[0][1].is(0.0) && e[0][2].is(0.0) && e[1][0].is(0.0) && e[2][0].is(0.0) &&
                       e[1][1].is_constant() && e[1][2].is_constant() && e[2][2].is(e[1][1].constant()) &&
                       e[2][1].is(-e[1][2].constant());
  const bool plane = about_x && general_angle(e[1][1], e[1][2]);
  return to_origin(x.r, plane ? to_old_axes(1, 2, e[1][1], e[1][2], shifted) : to_old_axes(x.ex, shifted));
}

}  // namespace

// The articulated-body recursion (Featherstone 2008, table 7.1) recorded
// into the current StraightLine: each frame's joint acceleration, gravity
// entering as the ground's acceleration -g. terms leaves out the rates,
// gravity or the applied loads, and adds a unit force in one joint: with
// none of the first three, the result is that joint's column of M^-1.
std::vector<Expr> Emitter::tree_recursion(const TreeRecursionTerms& terms) const {
  const std::vector<TreeFrame>& frames = a_.tree_frames.frames;
  const size_t n = frames.size();
  const auto dof = [&](size_t k) { return "body::" + body(frames[k].body).name; };
  StraightLine& line = StraightLine::current();
  // A model value, or the runtime parameter that replaces it.
  const auto value = [&](ParameterTarget target, int index, int component, double folded) {
    return tunable(target, index, component) ? line.input(value_of(target, index, component, folded, "s.params"))
                                             : Expr(folded);
  };
  std::vector<Transform> x(n);
  std::vector<Motion> v(n), c(n), a(n);
  std::vector<Inertia> ia(n);
  std::vector<Wrench> pa(n);
  std::vector<Expr> d(n), u(n), inv_d(n), qdds(n);
  std::vector<std::array<Expr, 6>> w(n);
  for (size_t k = 0; k < n; ++k) {
    const TreeFrame& f = frames[k];
    const Expr q = line.input("s.q[" + dof(k) + "]");
    x[k] = transform_of(f, "ha[" + dof(k) + "]", q);
    const Motion s_qd = along_axis(f, terms.rates ? line.input("qd[" + dof(k) + "]") : Expr(0.0));
    if (f.parent == kGround) {
      v[k] = s_qd;
      c[k] = {V3{0.0, 0.0, 0.0}, V3{0.0, 0.0, 0.0}};
    } else {
      v[k] = to_child(x[k], v[static_cast<size_t>(f.parent)]) + s_qd;
      c[k] = cross(v[k], s_qd);
    }
    if (plan(f.body).tunable_mass) {
      // The inertia in frame axes from the principal moments: E diag(J) E^T.
      const Eigen::Vector3d j = body(f.body).inertia.diagonal();
      M3 ic;
      for (size_t r = 0; r < 3; ++r) {
        for (size_t c = 0; c < 3; ++c) {
          for (int m = 0; m < 3; ++m) {
            const double e = f.body_axes(static_cast<Eigen::Index>(r), m) * f.body_axes(static_cast<Eigen::Index>(c), m);
            if (e != 0.0) ic[r][c] = ic[r][c] + e * value(ParameterTarget::inertia, f.body, m, j[m]);
          }
        }
      }
      const Expr mass = value(ParameterTarget::mass, f.body, 0, f.mass);
      ia[k] = rigid_inertia(mass, f.com, ic);
      pa[k] = rigid_bias(mass, f.com, ic, v[k]);
    } else {
      ia[k] = rigid_inertia(f.mass, f.com, f.inertia);
      pa[k] = rigid_bias(f.mass, f.com, constant(f.inertia), v[k]);
    }
    if (terms.loads && tree_external_loads()) {
      // The applied wrench at the COM: force in world axes, torque in body axes.
      const std::string b = "body::" + body(f.body).name;
      const M3 axes = constant(f.body_axes);
      V3 force_world, torque_body;
      M3 rot;
      for (int i = 0; i < 3; ++i) {
        force_world[static_cast<size_t>(i)] = line.input("l.w[" + b + "].f[" + std::to_string(i) + "]");
        torque_body[static_cast<size_t>(i)] = line.input("l.w[" + b + "].tau[" + std::to_string(i) + "]");
        for (int j = 0; j < 3; ++j) rot[static_cast<size_t>(i)][static_cast<size_t>(j)] = line.input("k.pose[" + b + "].R(" + std::to_string(i) + ", " + std::to_string(j) + ")");
      }
      const V3 force = times(axes, transpose_times(rot, force_world));
      const V3 torque = times(axes, torque_body);
      pa[k] = pa[k] - Wrench{torque + cross(constant(f.com), force), force};
    }
  }
  for (size_t k = n; k-- > 0;) {
    const TreeFrame& f = frames[k];
    const int i = axis_index(f);
    std::array<Expr, 6> col;
    for (int r = 0; r < 6; ++r) col[static_cast<size_t>(r)] = ia[k].at(r, i);
    // The armature adds to the joint's own inertia only (Featherstone
    // section 7.3: D = S^T IA S plus the rotor's); without one, W's own
    // entry and the reduced inertia's row and column of the joint are
    // exactly 1 and 0, and are set so.
    const bool plain = f.armature == 0.0;
    d[k] = col[static_cast<size_t>(i)] + f.armature;
    inv_d[k] = 1.0 / d[k];
    for (int r = 0; r < 6; ++r) w[k][static_cast<size_t>(r)] = r == i && plain ? Expr(1.0) : col[static_cast<size_t>(r)] * inv_d[k];
    u[k] = -component(pa[k], i);
    const double force = static_cast<int>(k) == terms.unit_force ? 1.0 : 0.0;  // the joint's own
    u[k] = u[k] + force;
    if (f.parent == kGround) continue;
    // Articulated inertia and bias force the parent sees through the joint.
    Inertia reduced = ia[k];
    for (int r = 0; r < 6; ++r)
      for (int s = r; s < 6; ++s)
        reduced.set(r, s, plain && (r == i || s == i) ? Expr(0.0) : ia[k].at(r, s) - w[k][static_cast<size_t>(r)] * col[static_cast<size_t>(s)]);
    Wrench bias = pa[k] + times(reduced, c[k]);
    bias.n = bias.n + u[k] * V3{w[k][0], w[k][1], w[k][2]};
    bias.f = bias.f + u[k] * V3{w[k][3], w[k][4], w[k][5]};
    // Without armature, the joint's own component of the bias is pa's plus
    // u: the joint's force.
    if (plain && f.revolute) bias.n[2] = force;
    if (plain && !f.revolute) bias.f[2] = force;
    const size_t p = static_cast<size_t>(f.parent);
    ia[p] = ia[p] + to_parent(x[k], reduced);
    pa[p] = pa[p] + to_parent(x[k], bias);
  }
  const Eigen::Vector3d g = m_.gravity.value_or(Eigen::Vector3d::Zero());
  Motion ground{V3{0.0, 0.0, 0.0}, V3{0.0, 0.0, 0.0}};
  for (int i = 0; i < 3; ++i) {
    if (terms.gravity) ground.v[static_cast<size_t>(i)] = -value(ParameterTarget::gravity, -1, i, g[i]);
  }
  for (size_t k = 0; k < n; ++k) {
    const TreeFrame& f = frames[k];
    const Motion from = f.parent == kGround ? ground : a[static_cast<size_t>(f.parent)];
    const Motion ap = to_child(x[k], from) + c[k];
    // The joint's own component of a = ap + S qdd is u / D - W' ap, W'
    // being W without its unit entry (no armature); qdd follows from it.
    const int i = axis_index(f);
    const bool plain = f.armature == 0.0;
    Expr wa = 0.0;
    for (int r = 0; r < 6; ++r) {
      if (r != i || !plain) wa = wa + w[k][static_cast<size_t>(r)] * component(ap, r);
    }
    const Expr along = u[k] * inv_d[k] - wa;
    const Expr qdd = plain ? along - component(ap, i) : along;
    a[k] = ap;
    Expr& own = (f.revolute ? a[k].w : a[k].v)[2];
    own = plain ? along : own + qdd;
    qdds[k] = qdd;
  }
  return qdds;
}

bool Emitter::tree_scheme() const { return mbrt::joint_space(scheme_kind()); }

bool Emitter::runge_kutta_tree() const {
  return scheme_kind() == Scheme::rk4_tree || scheme_kind() == Scheme::rk8_tree;
}

std::string Emitter::tree_step_name() const {
  if (scheme_kind() == Scheme::midpoint_tree) return "tree_midpoint_step";
  if (scheme_kind() == Scheme::rk4_tree) return "tree_rk4_step";
  if (scheme_kind() == Scheme::rk8_tree) return "tree_rk8_step";
  return "tree_step";
}

bool Emitter::tree_external_loads() const { return !m_.forces.empty() || !m_.inputs.empty(); }

std::string Emitter::refresh_bodies_comment() const {
  if (!tree_scheme()) return "// Nothing to do here: the step advances s.rigid itself.\n";
  return body_states_on_demand()
             ? "// (s.q, s.qd) => (s.rigid): where every body is and how it moves. step()\n"
               "// does not form s.rigid (solver.body_states: on_demand); call this\n"
               "// before reading it. The functions below form it themselves.\n"
             : "// (s.q, s.qd) => (s.rigid): where every body is and how it moves; step()\n"
               "// does this itself, so only a caller who sets s.q or s.qd needs it.\n";
}

std::string Emitter::refresh_bodies_function() const {
  if (!tree_scheme()) return "void refresh_bodies(State&) noexcept {}\n\n";
  return "void refresh_bodies(State& s) noexcept {\n  HalfAngles ha;\n  Model::half_angles(s.q, ha);\n"
         "  Model::body_states(s.q, ha, s.qd, s);\n}\n\n";
}

void Emitter::tree_types(std::ostringstream& o) const {
  o << "inline constexpr int kDofs = " << tree_dofs() << ";  // joint coordinates, in kBodyInfo order\n"
    << "using Dofs = std::array<double, kDofs>;\n"
    << "// cos and sin of half of each revolute joint's angle from its frame's x axis.\n"
    << "using HalfAngles = std::array<mbrt::SinCos, kDofs>;\n\n";
  if (friction_joints().empty()) return;
  friction_declarations(o);
  o << "// Column c: M^-1 times a unit force in friction joint c.\n"
    << "using FrictionColumns = std::array<Dofs, kFrictionJoints>;\n\n";
}

std::vector<size_t> Emitter::friction_frames() const {
  const std::vector<TreeFrame>& frames = a_.tree_frames.frames;
  std::vector<size_t> out;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (frames[k].friction.any()) out.push_back(k);
  }
  std::sort(out.begin(), out.end(), [&](size_t a, size_t b) { return frames[a].joint < frames[b].joint; });
  return out;
}

// The tree's friction constants: the shared limits and each joint's
// coordinate (docs/friction.md).
void Emitter::friction_constants(std::ostringstream& o) const {
  const std::vector<size_t> friction = friction_frames();
  if (friction.empty()) return;
  std::string dofs;
  for (size_t c = 0; c < friction.size(); ++c) {
    dofs += (c ? ", " : "") + std::string("body::") + body(a_.tree_frames.frames[friction[c]].body).name;
  }
  friction_limits(o);
  o << "using FrictionColumns = mbrt::models::" << m_.name << "::FrictionColumns;\n"
    << "static constexpr std::array<std::size_t, kFrictionJoints> kFrictionDof{{" << dofs << "}};  // their coordinates\n";
}

// M^-1's columns of the friction joints at s.q: the recursion without rates,
// gravity and loads, once per joint with a unit force in it; the articulated
// inertias are common to all and recorded once.
void Emitter::friction_response_kernel(std::ostringstream& o) const {
  const std::vector<size_t> friction = friction_frames();
  if (friction.empty()) return;
  const std::vector<TreeFrame>& frames = a_.tree_frames.frames;
  StraightLine line;
  for (size_t c = 0; c < friction.size(); ++c) {
    const std::vector<Expr> column = tree_recursion({false, false, false, static_cast<int>(friction[c])});
    for (size_t k = 0; k < frames.size(); ++k) {
      line.output("g[" + std::to_string(c) + "][body::" + body(frames[k].body).name + "]", column[k]);
    }
  }
  o << "// (s.q" << (a_.tunable ? ", s.params" : "") << ") => (g): M^-1 times a unit force in each friction joint,\n"
    << "// the articulated-body recursion without rates, gravity or loads.\n"
    << line.count().comment() << "\n"
    << "static void friction_response([[maybe_unused]] const State& s, [[maybe_unused]] const HalfAngles& ha, "
    << "FrictionColumns& g) noexcept {\n"
    << line.code("  ") << "}\n\n";
}

void Emitter::tree_kernels(std::ostringstream& o) const {
  const std::vector<TreeFrame>& frames = a_.tree_frames.frames;
  const size_t n = frames.size();
  const auto dof = [&](size_t k) { return "body::" + body(frames[k].body).name; };

  o << "// (q) => (ha): the half angles every kernel below turns frames by.\n"
    << "static void half_angles([[maybe_unused]] const Dofs& q, [[maybe_unused]] HalfAngles& ha) noexcept {\n";
  for (size_t k = 0; k < n; ++k) {
    if (!frames[k].revolute) continue;
    const std::string angle = frames[k].theta0 == 0.0 ? "q[" + dof(k) + "]" : "(q[" + dof(k) + "] + " + num(frames[k].theta0) + ")";
    o << "  ha[" << dof(k) << "] = mbrt::sin_cos(0.5 * " << angle << ");  // "
      << m_.bodies[static_cast<size_t>(frames[k].body)].name << "\n";
  }
  o << "}\n\n";

  {
    StraightLine line;
    const std::vector<Expr> qdd = tree_recursion({});
    for (size_t k = 0; k < n; ++k) line.output("qdd[" + dof(k) + "]", qdd[k]);
    o << "// (s.q, qd" << (tree_external_loads() ? ", k, l" : "") << (a_.tunable ? ", s.params" : "")
      << ") => (qdd): the articulated-body recursion, this model's nonzero terms only.\n"
      << line.count().comment() << "\n"
      << "static void joint_accelerations([[maybe_unused]] const State& s, [[maybe_unused]] const HalfAngles& ha, "
      << "[[maybe_unused]] const Dofs& qd, "
      << "[[maybe_unused]] const Kinematics& k, [[maybe_unused]] const Loads& l, Dofs& qdd) noexcept {\n"
      << line.code("  ") << "}\n\n";
  }
  friction_response_kernel(o);
  friction_loads_function(o);

  // Body states from the joint coordinates, chained from body to body in the
  // bodies' own axes: a body's Euler parameters are its parent's times a
  // quaternion linear in the joint's half-angle cos and sin, its rotation
  // matrix follows from them, and every offset between a parent's centre of
  // mass, the joint and the child's centre of mass is a constant in one
  // body's axes.
  {
    StraightLine line;
    std::vector<Quaternion> turn(n);  // Euler parameters, body to world
    std::vector<M3> rot(n);           // body to world
    std::vector<V3> com(n), vel(n), omega(n);  // world
    for (size_t k = 0; k < n; ++k) {
      const TreeFrame& f = frames[k];
      const bool root = f.parent == kGround;
      const size_t p = root ? 0 : static_cast<size_t>(f.parent);
      const V3 to_joint = constant(f.joint_from_parent), axis_p = constant(f.axis_in_parent);
      const V3 to_com = constant(f.com_in_body);
      Quaternion relative = constant(f.relative_c);
      const Expr q = line.input("q[" + dof(k) + "]"), qd = line.input("qd[" + dof(k) + "]");
      if (f.revolute) {
        const Expr ch = line.input("ha[" + dof(k) + "].c"), sh = line.input("ha[" + dof(k) + "].s");
        for (size_t i = 0; i < 4; ++i) relative[i] = ch * relative[i] + sh * f.relative_s[static_cast<Eigen::Index>(i)];
      }
      turn[k] = root ? relative : quaternion_product(turn[p], relative);
      rot[k] = rotation_matrix(turn[k]);
      const M3 parent_rot = root ? constant(Eigen::Matrix3d(Eigen::Matrix3d::Identity())) : rot[p];
      const V3 zero{0.0, 0.0, 0.0};
      const V3 parent_omega = root ? zero : omega[p];
      const V3 joint = times(parent_rot, f.revolute ? to_joint : to_joint + q * axis_p);  // world
      const V3 arm = times(rot[k], to_com);                                                 // world
      const V3 axis_w = times(parent_rot, axis_p);
      omega[k] = f.revolute ? parent_omega + qd * axis_w : parent_omega;
      com[k] = (root ? zero : com[p]) + joint + arm;
      vel[k] = (root ? zero : vel[p]) + cross(parent_omega, joint) + cross(omega[k], arm);
      if (!f.revolute) vel[k] = vel[k] + qd * axis_w;
      const V3 w_body = transpose_times(rot[k], omega[k]);
      const std::string st = "s.rigid" + slot_of(f.body);
      for (int i = 0; i < 3; ++i) {
        const std::string idx = "[" + std::to_string(i) + "]";
        line.output(st + ".r" + idx, com[k][static_cast<size_t>(i)]);
        line.output(st + ".v" + idx, vel[k][static_cast<size_t>(i)]);
        line.output(st + ".w" + idx, w_body[static_cast<size_t>(i)]);
      }
      for (int i = 0; i < 4; ++i) line.output(st + ".p[" + std::to_string(i) + "]", turn[k][static_cast<size_t>(i)]);
    }
    o << "// (q, qd) => (s.rigid): where every body is and how it moves.\n"
      << line.count().comment() << "\n"
      << "static void body_states([[maybe_unused]] const Dofs& q, [[maybe_unused]] const HalfAngles& ha, [[maybe_unused]] const Dofs& qd, State& s) noexcept {\n"
      << line.code("  ") << "}\n\n";
  }
}

}  // namespace mbrt::codegen
