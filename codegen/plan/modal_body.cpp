#include "modal_body.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mbrt::codegen {

// Round-off where symmetry makes an entry zero (a bending mode's axial
// field, the other plane's coupling): zero, as generated code then says,
// against the largest entry of its kind.
template <class Matrix>
void zero_round_off(Matrix& m, double scale) {
  m = m.unaryExpr([&](double x) { return std::abs(x) <= 1e-12 * scale ? 0.0 : x; });
}

namespace {

// Where the first mode left out has the frequency of the last one kept (a
// symmetric structure's group, such as a round beam's two bending planes),
// which of the group is kept would be left to round-off: a message naming
// the group and the counts that keep it whole, else empty. `omega`: the
// frequencies available, ascending, rad/s.
std::string split_group(int modes, const std::vector<double>& omega) {
  const int n = static_cast<int>(omega.size());
  const auto same = [&](int i) { return std::abs(omega[i + 1] - omega[i]) <= 1e-6 * omega[i + 1]; };
  if (modes >= n || !same(modes - 1)) return "";
  int first = modes - 1, last = modes;  // the group, from 0
  while (first > 0 && same(first - 1)) --first;
  while (last + 1 < n && same(last)) ++last;
  std::vector<std::string> counts;
  if (first >= 1) counts.push_back(std::to_string(first));
  if (last + 1 <= kMaxModes) counts.push_back(std::to_string(last + 1));
  const std::string keep = counts.empty()
      ? "no count from 1 to " + std::to_string(kMaxModes) + " keeps it whole; make the structure a little less symmetric (a round beam: EI differing slightly between its planes)"
      : "keep " + counts.front() + (counts.size() > 1 ? " or " + counts.back() : "") + " modes, so that the group stays whole";
  return std::to_string(modes) + " modes kept, but modes " + std::to_string(first + 1) + (last == first + 1 ? " and " : " to ") +
         std::to_string(last + 1) +
         " have the same frequency (" + std::to_string(omega[modes - 1] / (2 * std::acos(-1.0))) + " Hz, a symmetric group): " + keep;
}

// A point of the body's mass: `mass` at `place` (body axes, from the frame's
// origin), moving by `displacement` q (3 x modes).
struct MassPoint {
  double mass;
  Eigen::Vector3d place;
  Eigen::Matrix<double, 3, Eigen::Dynamic> displacement;
};

// The modes' coupling with the frame and the inertia invariants (Shabana
// 2005, Dynamics of Multibody Systems, ch. 5) over the body's mass points.
// Then the reduced inverse mass and round-off zeroed; p.m, p.J and the
// geometric stiffness are set before.
void sum_invariants(ModalPlan& p, const std::vector<MassPoint>& points) {
  const int modes = p.modes;
  Eigen::Matrix<double, 3, Eigen::Dynamic> St = Eigen::MatrixXd::Zero(3, modes), Sr = St;
  for (auto& e : p.E) e = Eigen::MatrixXd::Zero(modes, modes);
  for (auto& g : p.G) g = Eigen::RowVectorXd::Zero(modes);
  for (const MassPoint& point : points) {
    const double dm = point.mass;
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& u = point.displacement;
    St += dm * u;
    for (int m = 0; m < modes; ++m) Sr.col(m) += dm * point.place.cross(u.col(m));
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        p.E[static_cast<size_t>(3 * a + b)] += dm * u.row(a).transpose() * u.row(b);
        p.G[static_cast<size_t>(3 * a + b)] += dm * point.place[a] * u.row(b);
      }
    }
  }
  p.St_T = St.transpose();
  p.Sr_T = Sr.transpose();
  // A unit modal mass couples at most sqrt(m) and sqrt(trace J): free modes'
  // round-off is small against that, not against itself.
  const double coupling = std::max({p.St_T.cwiseAbs().maxCoeff(), p.Sr_T.cwiseAbs().maxCoeff(), std::sqrt(p.m), std::sqrt(p.J.trace())});
  zero_round_off(p.St_T, coupling), zero_round_off(p.Sr_T, coupling);
  Eigen::Matrix<double, 6, Eigen::Dynamic> S(6, modes);
  S << p.St_T.transpose(), p.Sr_T.transpose();
  Eigen::Matrix<double, 6, 6> rigid = Eigen::Matrix<double, 6, 6>::Zero();
  rigid.topLeftCorner<3, 3>() = p.m * Eigen::Matrix3d::Identity();
  rigid.bottomRightCorner<3, 3>() = p.J;
  p.reduced_inverse = (rigid - S * S.transpose()).inverse();
  const auto largest = [](const auto& list) {
    double x = 0;
    for (const auto& m : list) x = std::max(x, m.cwiseAbs().maxCoeff());
    return x;
  };
  for (auto& k : p.kg) zero_round_off(k, k.cwiseAbs().maxCoeff());
  zero_round_off(p.reduced_inverse, p.reduced_inverse.cwiseAbs().maxCoeff());
  const double e = largest(p.E), g = largest(p.G);
  for (auto& m : p.E) zero_round_off(m, e);
  for (auto& m : p.G) zero_round_off(m, g);
}

// A mode's sign is the solver's choice, which rounding can flip between
// builds; its largest entry positive makes the generated constants the same.
void fix_signs(Eigen::MatrixXd& shapes) {
  for (Eigen::Index k = 0; k < shapes.cols(); ++k) {
    Eigen::Index largest = 0;
    shapes.col(k).cwiseAbs().maxCoeff(&largest);
    if (shapes(largest, k) < 0) shapes.col(k) *= -1.0;
  }
}

Eigen::MatrixXd restrict(const Eigen::MatrixXd& A, const std::vector<int>& rows, const std::vector<int>& cols) {
  Eigen::MatrixXd R(rows.size(), cols.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    for (size_t j = 0; j < cols.size(); ++j) R(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = A(rows[i], cols[j]);
  }
  return R;
}

}  // namespace

// The modes kept and the static shapes of unit loads at coordinates `loads`
// of stiffness K and mass M, those in `held` (clamped) kept still
// (MacNeal 1971; Rubin 1975), turned into one mass-orthonormal basis with a
// diagonal stiffness: the eigenvectors of K and M on their span, ascending.
// Each shape then carries its load's static response exactly, which the
// modes alone, free at the nodes, approach slowly (a moment at the tip).
// `where` names a load's coordinate for the error of one that adds nothing.
static void add_static_shapes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, const std::vector<int>& held,
                              const std::vector<int>& loads, const std::function<std::string(int)>& where,
                              Eigen::MatrixXd& shapes, Eigen::VectorXd& omega) {
  const Eigen::Index n = shapes.rows(), kept = shapes.cols(), added = static_cast<Eigen::Index>(loads.size());
  std::vector<int> free;
  for (int i = 0; i < n; ++i) {
    if (std::find(held.begin(), held.end(), i) == held.end()) free.push_back(i);
  }
  const Eigen::LDLT<Eigen::MatrixXd> stiffness(restrict(K, free, free));
  Eigen::MatrixXd basis(n, kept + added);
  basis.leftCols(kept) = shapes;
  for (Eigen::Index k = 0; k < added; ++k) {
    const auto at = std::find(free.begin(), free.end(), loads[static_cast<size_t>(k)]);
    if (at == free.end()) {
      throw std::invalid_argument("static_loads: the load at " + where(loads[static_cast<size_t>(k)]) + " is held still; name a free node");
    }
    Eigen::VectorXd load = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(free.size()));
    load[at - free.begin()] = 1.0;
    const Eigen::VectorXd u_free = stiffness.solve(load);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
    for (size_t i = 0; i < free.size(); ++i) u[free[i]] = u_free[static_cast<Eigen::Index>(i)];
    // What the modes kept and the shapes before it leave out, in the mass's
    // norm: a shape they already hold would make the basis singular.
    const double size = std::sqrt(u.dot(M * u));
    const Eigen::MatrixXd before = basis.leftCols(kept + k);
    u -= before * (before.transpose() * M * before).ldlt().solve(before.transpose() * M * u);
    if (!(std::sqrt(u.dot(M * u)) > 1e-6 * size)) {
      throw std::invalid_argument("static_loads: the load at " + where(loads[static_cast<size_t>(k)]) +
                                  " moves the body as the modes kept and the loads before it already do; drop it");
    }
    basis.col(kept + k) = u;
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(basis.transpose() * K * basis, basis.transpose() * M * basis);
  shapes = basis * eig.eigenvectors();
  omega = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  fix_signs(shapes);
}

ModalPlan plan_modal_body(const BeamProperties& beam, int modes, double damping, const std::vector<int>& static_loads) {
  const int available = kNodeCoordinates * beam.elements;
  // Enough candidates that the lowest `modes` bending and axial ones are among
  // them whatever the torsion modes in between.
  const int candidates = std::min(available, 2 * modes + beam.elements + 6);
  const BeamModes all = beam_modes(beam, BeamSupport::clamped_root, candidates);
  const BeamField all_field = beam_field(beam, all.shapes);
  std::vector<int> chosen;  // the modes kept and those up to one beyond the most a body keeps, for split_group
  for (int k = 0; k < candidates && static_cast<int>(chosen.size()) <= std::max(modes, kMaxModes); ++k) {
    double translational = 0.0;  // of the mode's unit modal mass
    for (size_t p = 0; p < all_field.displacement.size(); ++p) {
      translational += all_field.mass[static_cast<Eigen::Index>(p)] * all_field.displacement[p].col(k).squaredNorm();
    }
    if (translational > 0.5) chosen.push_back(k);
  }
  if (static_cast<int>(chosen.size()) < modes) {
    throw std::invalid_argument(std::to_string(modes) + " modes: " + std::to_string(beam.elements) +
                                " elements give " + std::to_string(chosen.size()) +
                                " bending and axial modes; use more elements");
  }
  std::vector<double> frequencies;
  for (const int k : chosen) frequencies.push_back(all.omega[k]);
  if (const std::string split = split_group(modes, frequencies); !split.empty()) throw std::invalid_argument(split);
  ModalPlan p;
  p.modes = modes;
  const int n = static_cast<int>(all.shapes.rows());
  Eigen::MatrixXd shapes(n, modes);
  p.omega.resize(modes);
  for (int k = 0; k < modes; ++k) {
    shapes.col(k) = all.shapes.col(chosen[static_cast<size_t>(k)]);
    p.omega[k] = all.omega[chosen[static_cast<size_t>(k)]];
  }
  if (!static_loads.empty()) {
    const BeamMatrices m = assemble_beam(beam);
    const auto where = [&](int c) {
      const int node = c / kNodeCoordinates;
      return "node " + (node == beam.elements ? std::string("tip") : std::to_string(node)) + " along " +
             kNodeCoordinateNames[static_cast<size_t>(c % kNodeCoordinates)];
    };
    add_static_shapes(m.K, m.M, {0, 1, 2, 3, 4, 5}, static_loads, where, shapes, p.omega);  // the root held
    p.modes = static_cast<int>(shapes.cols());
  }
  p.damping = damping * p.omega.cwiseAbs2();
  p.shapes = shapes;
  const double L = beam.length, centre = L / 2;
  p.m = beam.rho_A * L;
  p.J = Eigen::Vector3d(beam.rho_J * L, p.m * L * L / 12, p.m * L * L / 12).asDiagonal();
  for (int k = 0; k <= beam.elements; ++k) {
    p.node_names.push_back(k == 0 ? "root" : k == beam.elements ? "tip" : std::to_string(k));
    p.node_points.push_back(beam_node_place(L, beam.elements, k));
  }
  p.clamped = {0};

  // Geometric stiffness: the axial force rho_A ((L^2 - x^2) / 2 - centre (L - x))
  // per unit w_y^2 and w_z^2 about the centre, and -rho_A (L - x) per unit
  // acceleration along x, away from the root (beam_modes' hub radius
  // -centre, and 0 less 1).
  const auto projected = [&](double hub_radius) {
    const BeamMatrices m = assemble_beam(beam, hub_radius);
    return Eigen::MatrixXd(shapes.transpose() * m.KG * shapes);
  };
  for (auto& k : p.kg) k = Eigen::MatrixXd::Zero(p.modes, p.modes);
  p.kg[kSpinYY] = p.kg[kSpinZZ] = projected(-centre);
  p.kg[kAccelerationX] = projected(0.0) - projected(1.0);

  // The invariants over the beam's mass, positions rho0 = (x - L/2, 0, 0).
  const BeamField f = beam_field(beam, shapes);
  std::vector<MassPoint> points;
  for (Eigen::Index k = 0; k < f.x.size(); ++k) points.push_back({f.mass[k], {f.x[k] - centre, 0, 0}, f.displacement[static_cast<size_t>(k)]});
  sum_invariants(p, points);
  // The spin's cases as a stretch beta(q) x along the beam (the mass's
  // second moment of the shortening, as the acceleration's is its first):
  // the spin then stiffens through the kinetic energy, which it keeps.
  for (const MassPoint& point : points) p.axial_moment += point.mass * point.place.x() * point.place.x();
  p.stretch = -p.kg[kSpinYY] / p.axial_moment;
  return p;
}

namespace {

// A structure's geometric stiffness on its modes (shapes over the file's
// coordinates): each given case projected, the spin cases (where the file
// gives any) moved from the file's origin to the frame's, the nodes' centre
// c. Spinning about the origin loads the structure as spinning about c and
// accelerating by w x (w x c), whose products w_a w_b take c's part normal
// to a (negated) along the axes for a = b, and c_b along a plus c_a along b
// otherwise.
std::array<Eigen::MatrixXd, 9> structure_geometric_stiffness(const ModalStructure& s, const Eigen::MatrixXd& shapes) {
  std::array<Eigen::MatrixXd, 9> kg;
  for (size_t k = 0; k < kg.size(); ++k) {
    const Eigen::MatrixXd& g = s.geometric_stiffness[k];
    kg[k] = g.size() > 0 ? Eigen::MatrixXd(shapes.transpose() * g * shapes) : Eigen::MatrixXd::Zero(shapes.cols(), shapes.cols());
  }
  if (!s.spin_stiffens()) return kg;
  const Eigen::Vector3d& c = s.centre;
  const int pairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (size_t k = 0; k < 6; ++k) {
    const int a = pairs[k][0], b = pairs[k][1];
    Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // per unit w_a w_b
    if (a == b) {
      acceleration = -c;
      acceleration[a] = 0;
    } else {
      acceleration[a] = c[b], acceleration[b] = c[a];
    }
    for (int i = 0; i < 3; ++i) kg[k] -= acceleration[i] * kg[static_cast<size_t>(kAccelerationX + i)];
  }
  return kg;
}

}  // namespace

ModalPlan plan_modal_structure(const ModalStructure& s, int modes, double damping_ratio, const std::vector<int>& static_loads) {
  const int c = s.coordinates, nodes = static_cast<int>(s.nodes.size()), n = c * nodes;
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(s.file + ": " + what); };
  const auto coordinate = [&](int i) {
    return "node '" + s.nodes[static_cast<size_t>(i / c)].name + "' " + kNodeCoordinateNames[static_cast<size_t>(i % c)];
  };
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < nodes; ++k) {
    M.block(c * k, c * k, 3, 3).diagonal().setConstant(s.nodes[static_cast<size_t>(k)].mass);
    if (c == 6) M.block(c * k + 3, c * k + 3, 3, 3) = s.nodes[static_cast<size_t>(k)].inertia;
  }
  const auto clamped = [&](int node) { return std::find(s.clamped.begin(), s.clamped.end(), node) != s.clamped.end(); };
  // Motion d of the structure as a rigid body: along x, y, z, then turns about them through the centre.
  const auto rigid_motion = [&](int d) {
    Eigen::VectorXd motion = Eigen::VectorXd::Zero(n);
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(d % 3);
    for (int k = 0; k < nodes; ++k) {
      motion.segment<3>(c * k) = d < 3 ? axis : Eigen::Vector3d(axis.cross(s.nodes[static_cast<size_t>(k)].position - s.centre));
      if (c == 6 && d >= 3) motion.segment<3>(c * k + 3) = axis;
    }
    return motion;
  };
  const auto rigid_name = [](int d) { return std::string(d < 3 ? "move along " : "turn about ") + "xyz"[d % 3]; };
  Eigen::MatrixXd shapes = Eigen::MatrixXd::Zero(n, modes);
  Eigen::VectorXd omega(modes);
  if (s.stiffness.size() > 0) {
    std::vector<int> with_mass, without;  // the free coordinates
    for (int i = 0; i < n; ++i) {
      if (!clamped(i / c)) (M(i, i) > 0 ? with_mass : without).push_back(i);
    }
    // Coordinates without mass follow the others statically: u_b = T u_a.
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(without.size()), static_cast<Eigen::Index>(with_mass.size()));
    Eigen::MatrixXd K = restrict(s.stiffness, with_mass, with_mass);
    if (!without.empty()) {
      const Eigen::LDLT<Eigen::MatrixXd> own(restrict(s.stiffness, without, without));
      const double scale = s.stiffness.cwiseAbs().maxCoeff();
      if (own.info() != Eigen::Success || !(own.vectorD().minCoeff() > 1e-12 * scale)) {
        fail("the coordinates without mass (" + coordinate(without.front()) + (without.size() > 1 ? ", ..." : "") +
             ") need stiffness of their own; give their nodes mass or inertia, or check the stiffness");
      }
      const Eigen::MatrixXd K_ba = restrict(s.stiffness, without, with_mass);
      T = -own.solve(K_ba);
      K += K_ba.transpose() * T;
    }
    const int rigid = s.clamped.empty() ? 6 : 0;
    // A free structure must not strain when it moves as a rigid body.
    for (int d = 0; rigid > 0 && d < 6; ++d) {
      const Eigen::VectorXd motion = rigid_motion(d);
      if ((s.stiffness * motion).norm() > 1e-8 * s.stiffness.cwiseAbs().maxCoeff() * motion.norm()) {
        fail("without clamped nodes the structure must move freely as a rigid body, but a rigid " + rigid_name(d) +
             " strains it: check the stiffness, or clamp nodes (clamped: [...])");
      }
    }
    if (static_cast<int>(with_mass.size()) < rigid + modes) {
      fail(std::to_string(modes) + " modes kept, but its " + std::to_string(with_mass.size()) + " free coordinates with mass give " +
           std::to_string(static_cast<int>(with_mass.size()) - rigid));
    }
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, restrict(M, with_mass, with_mass));
    if (eig.info() != Eigen::Success) fail("the modes' eigenproblem failed; check the stiffness and the nodes' inertia");
    const Eigen::VectorXd& l = eig.eigenvalues();
    // The rigid motions checked above are exact null vectors: their
    // eigenvalues are round-off, far below any elastic one.
    const double scale = l.cwiseAbs().maxCoeff(), zero = 1e-11 * scale;
    const auto rate = [&](int k) { return std::to_string(std::sqrt(std::max(0.0, l[k]))) + " rad/s"; };
    if (l[0] < -zero) fail("the stiffness is not positive semi-definite (an eigenvalue " + std::to_string(l[0]) + ")");
    if (rigid > 0 && (l[5] > zero || l[6] <= zero)) {
      fail("without clamped nodes the structure should move freely in exactly 6 rigid-body modes (zero frequencies); its 6th and 7th "
           "lowest frequencies are " + rate(5) + " and " + rate(6) + ": check the stiffness, or clamp nodes (clamped: [...])");
    }
    if (rigid == 0 && l[0] <= zero) fail("the clamped structure still moves freely (a zero frequency); clamp more nodes or check the stiffness");
    std::vector<double> available;
    for (Eigen::Index k = rigid; k < l.size() && k <= rigid + kMaxModes; ++k) available.push_back(std::sqrt(std::max(0.0, l[k])));
    if (const std::string split = split_group(modes, available); !split.empty()) fail(split);
    for (int k = 0; k < modes; ++k) {
      omega[k] = std::sqrt(l[rigid + k]);
      const Eigen::VectorXd v = eig.eigenvectors().col(rigid + k), follow = T * v;
      for (size_t i = 0; i < with_mass.size(); ++i) shapes(with_mass[i], k) = v[static_cast<Eigen::Index>(i)];
      for (size_t i = 0; i < without.size(); ++i) shapes(without[i], k) = follow[static_cast<Eigen::Index>(i)];
    }
  } else {
    if (s.frequencies.size() < modes) {
      fail("it gives " + std::to_string(s.frequencies.size()) + " modes, the model keeps " + std::to_string(modes));
    }
    // The file orders a group of equal frequencies as its solver happened to.
    const std::vector<double> given(s.frequencies.data(), s.frequencies.data() + s.frequencies.size());
    if (const std::string split = split_group(modes, given); !split.empty()) fail(split);
    omega = s.frequencies.head(modes);
    shapes = s.shapes.leftCols(modes);
    const double largest = shapes.cwiseAbs().maxCoeff();
    for (int k = 0; k < modes; ++k) {
      for (const int node : s.clamped) {
        if (shapes.block(c * node, k, c, 1).cwiseAbs().maxCoeff() > 1e-9 * largest) {
          fail("mode " + std::to_string(k + 1) + " moves clamped node '" + s.nodes[static_cast<size_t>(node)].name + "'");
        }
      }
      const double modal_mass = shapes.col(k).dot(M * shapes.col(k));
      if (!(modal_mass > 0)) fail("mode " + std::to_string(k + 1) + " moves no mass");
      shapes.col(k) /= std::sqrt(modal_mass);
      for (int j = 0; j < k; ++j) {
        const double product = shapes.col(j).dot(M * shapes.col(k));
        if (std::abs(product) > 1e-3) {
          fail("modes " + std::to_string(j + 1) + " and " + std::to_string(k + 1) + " are not orthogonal in the nodes' mass (" +
               std::to_string(product) + " of a unit modal mass, at most 0.001): the shapes and the masses do not belong together");
        }
      }
      // A free structure's elastic modes carry no rigid-body motion (an
      // exported rigid mode at a near-zero frequency would leave the frame
      // almost no mass of its own).
      for (int d = 0; s.clamped.empty() && d < 6; ++d) {
        const Eigen::VectorXd motion = rigid_motion(d);
        const double share = motion.dot(M * shapes.col(k)) / std::sqrt(motion.dot(M * motion));
        if (std::abs(share) > 1e-3) {
          fail("mode " + std::to_string(k + 1) + " of the free structure carries a rigid-body " + rigid_name(d) + " (" +
               std::to_string(share) + " of a unit modal mass, at most 0.001): leave rigid-body modes out of the file, or clamp nodes");
        }
      }
    }
  }
  if (!static_loads.empty()) {
    if (s.stiffness.size() == 0 || s.clamped.empty()) fail("static_loads need the stiffness of a structure with clamped nodes");
    std::vector<int> held;
    for (const int node : s.clamped) {
      for (int i = 0; i < c; ++i) held.push_back(c * node + i);
    }
    add_static_shapes(s.stiffness, M, held, static_loads, coordinate, shapes, omega);
    modes = static_cast<int>(shapes.cols());
  }
  fix_signs(shapes);

  ModalPlan p;
  p.modes = modes;
  p.omega = omega;
  p.damping = 2 * damping_ratio * omega;
  p.shapes = Eigen::MatrixXd::Zero(kNodeCoordinates * nodes, modes);
  for (int k = 0; k < nodes; ++k) p.shapes.middleRows(kNodeCoordinates * k, c) = shapes.middleRows(c * k, c);
  p.clamped = s.clamped;
  p.m = 0;
  p.J.setZero();
  std::vector<MassPoint> points;
  for (int k = 0; k < nodes; ++k) {
    const ModalNodeData& d = s.nodes[static_cast<size_t>(k)];
    const Eigen::Vector3d x = s.node_place(k);
    p.node_names.push_back(d.name);
    p.node_points.push_back(x);
    p.m += d.mass;
    p.J += d.mass * (x.squaredNorm() * Eigen::Matrix3d::Identity() - x * x.transpose()) + d.inertia;
    const Eigen::MatrixXd u = p.shapes.middleRows(kNodeCoordinates * k, 3), turn = p.shapes.middleRows(kNodeCoordinates * k + 3, 3);
    points.push_back({d.mass, x, u});
    // The node's inertia as pairs of point masses mu_j at +-e_j along its
    // principal axes, less their sum at the node: the same inertia, no mass,
    // moving with the node's small turn (u + theta x r), so that every
    // invariant (first and second order) carries it alike. Any arm gives
    // the same sums; mu_j = (I_k + I_l - I_j) / 4 >= 0 for a real inertia.
    if (d.inertia.isZero()) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(d.inertia);
    const Eigen::Vector3d I = principal.eigenvalues();
    double total = 0;
    for (int j = 0; j < 3; ++j) {
      const double mu = (I.sum() - 2 * I[j]) / 4;
      const Eigen::Vector3d r = principal.eigenvectors().col(j);
      for (const double side : {1.0, -1.0}) {
        Eigen::MatrixXd moved = u;
        for (int m = 0; m < modes; ++m) moved.col(m) += Eigen::Vector3d(turn.col(m)).cross(side * r);
        points.push_back({mu, x + side * r, moved});
      }
      total += 2 * mu;
    }
    points.push_back({-total, x, u});
  }
  p.kg = structure_geometric_stiffness(s, shapes);
  sum_invariants(p, points);
  return p;
}

ModalPlan plan_modal(const ModalSource& source) {
  if (source.structure) return plan_modal_structure(*source.structure, source.modes, source.damping_ratio, source.static_loads);
  return plan_modal_body({source.length, source.EA, source.GJ, source.EIy, source.EIz, source.rho_A, source.rho_J, source.elements},
                         source.modes, source.damping, source.static_loads);
}

ModalNode modal_node(const ModalPlan& p, int k) {
  ModalNode node;
  node.point = p.node_points[static_cast<size_t>(k)];
  node.displacement = p.shapes.block(kNodeCoordinates * k, 0, 3, p.modes);
  node.rotation = p.shapes.block(kNodeCoordinates * k + 3, 0, 3, p.modes);
  const double largest = std::max(node.displacement.cwiseAbs().maxCoeff(), node.rotation.cwiseAbs().maxCoeff());
  zero_round_off(node.displacement, largest), zero_round_off(node.rotation, largest);
  return node;
}

}  // namespace mbrt::codegen
