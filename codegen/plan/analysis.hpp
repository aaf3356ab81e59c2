// Analysis of a validated model: what the generated step contains. Body
// frames of joints and forces, the constraint rows, the fixed block sparsity
// of S = B M^-1 B^T with a fill-reducing elimination order, and which terms
// the scene needs at all.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <mbrt/beam_element.hpp>
#include <mbrt/forces.hpp>
#include <mbrt/joints.hpp>

#include "modal_body.hpp"
#include "model.hpp"
#include "partition.hpp"
#include "specializations.hpp"
#include "tree_frames.hpp"
#include "tree_plan.hpp"

namespace mbrt::codegen {

struct BodyPlan {
  int model_index;      // index in Model::bodies
  bool rigid;
  int slot;             // index in State::rigid or State::particle
  bool principal_axes;  // inertia diagonal in body axes: no product terms
  bool isotropic;       // equal principal moments: no gyroscopic torque
  bool loaded;          // some applied load acts on it (gravity, gyroscopic torque, force, input)
  bool tunable_mass = false;     // its mass or inertia is a runtime parameter (docs/parameters.md)
  bool tunable_inertia = false;  // its inertia's diagonal is: no isotropic specialization
  int modal = -1;                // a modal body's frame: its Analysis::modal index
};

enum class ConstraintSource { joint, driver };

// One block of constraint rows: a joint, or a driver (rheonomic).
struct ConstraintBlock {
  std::string name;
  SourceLocation where;
  ConstraintSource source;
  JointType joint_type = JointType::spherical;       // joints
  DriverType driver_type = DriverType::joint_angle;  // drivers
  std::string kernel;   // runtime function generated code calls: the type's, or a planar one (planar_scene.cpp)
  int body1;
  int body2;
  int rows;             // constraint rows of this block
  int first_row;        // offset in the stacked multiplier vector
  mbrt::JointFrame frame;
  const TimeFunction* function = nullptr;  // drivers only (points into the Model)
  int driver = -1;                         // drivers only: Model::drivers index
  int holonomic_rows = 0;  // the first rows; the rest act on velocities only (rolling_disk, knife_edge)
  std::vector<int> spatial_rows = {};  // planar blocks: the rows of the spatial block they are, in order
  int node1 = -1, node2 = -1;  // joints at a modal body's node and their drivers: the node, else -1
};

struct ForcePlan {
  int model_index;
  mbrt::SpringDamper spring;  // spring_damper
  mbrt::AxialTorque torque;   // torque
  mbrt::JointSpring joint_spring;  // joint_spring, on its joint's coordinate (frame: Analysis::constraints[joint])
  Eigen::Vector3d point;      // force: body-frame point
};

// A point_contact or sphere_contact (docs/contact.md) as the step sees it.
struct ContactPlan {
  int model_index;                    // Model::contacts
  int body;                           // Model::bodies
  Eigen::Vector3d offset;             // body axes: from the COM to the point, or to the sphere's centre
  Eigen::Vector3d tangent1, tangent2; // world: with the plane's normal a right-handed triad
  Eigen::Matrix3d inverse_inertia;    // body axes; zero for a particle
  int mechanism;                      // the first body of its mechanism (bodies joined by joints or drivers)
  bool jointed;                       // its body is in a joint or driver
};

// Where an input acts: a torque about axis1 (body-1 axes) on body2 with the
// reaction on body1, or a force along axis1 at point s2 of body2 with the
// reaction at point s1 of body1 (joint_force).
struct InputPlan {
  int body1;
  int body2;
  Eigen::Vector3d axis1;
  Eigen::Vector3d s1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d s2 = Eigen::Vector3d::Zero();
};

// Block pattern of the Cholesky factor of S, in elimination order. Blocks are
// indexed by constraint block (Analysis::constraints).
struct FactorPattern {
  std::vector<int> order;                   // joints in elimination order
  std::vector<std::vector<int>> lower;      // lower[k]: joints i eliminated after k with L(i,k) != 0
  bool kept(int k, int i) const {           // L(i, k) is formed: i in lower[k]
    const auto& v = lower[static_cast<size_t>(k)];
    return std::find(v.begin(), v.end(), i) != v.end();
  }
  std::vector<std::vector<int>> coupled;    // coupled[j]: joints sharing a moving body with j (S(i,j) != 0)
  int fill_blocks = 0;                      // blocks of L that are zero in S
};

// ali3p's integrator coefficients (Newmark beta, gamma; generalized-alpha
// weights delta_m, delta_f) and the penalty of every constraint block.
struct Ali3pPlan {
  double beta = 0.25, gamma = 0.5, delta_m = 0.0, delta_f = 0.0;
  std::vector<double> alpha;  // per constraint block
};

// The planar specialization (codegen/plan/planar_scene.cpp): whether the scene
// moves in a plane of world coordinates, the plane's normal (world axis 0, 1
// or 2), and each constraint block's in-plane rows, a subset of the spatial
// block's rows (ConstraintBlock::spatial_rows).
struct PlanarPlan {
  bool applies = false;
  int stages = 2;                            // implicit passes of the planar step (StepPlan::stages)
  std::string refusal;                       // why not, when it does not apply
  int normal = 2;
  std::vector<ConstraintBlock> constraints;  // same order as Analysis::constraints, planar kernels and rows
  int constraint_rows = 0;
};

// How the scheme's step runs for this model (include/mbrt/schemes/).
struct StepPlan {
  mbrt::Scheme scheme = mbrt::Scheme::staggered_pcst;
  // Implicit passes per step: two when the end-of-step accelerations depend
  // on the end-of-step velocities (gyroscopic or damping loads, Baumgarte's
  // velocity term) or without the single-stage specialization, else one.
  int stages = 2;
  // staggered-pcst with constraints: RATTLE's position stage after the drift.
  bool position_stage = false;
  // staggered-pcst: bodies turn by their torque-free rotation in the drift,
  // and the gyroscopic torque enters only the multipliers' right-hand side;
  // the other schemes apply it as a load (docs/stability.md).
  bool free_rotation = false;
};

struct Analysis {
  StepPlan step;
  std::vector<BodyPlan> bodies;  // same order as Model::bodies
  int rigid_count = 0;
  int particle_count = 0;
  std::vector<ConstraintBlock> constraints;  // joints, then drivers
  int constraint_rows = 0;
  bool rheonomic = false;                    // drivers present: explicit time terms
  bool nonholonomic = false;                 // rows on velocities only
  std::vector<ForcePlan> forces;
  std::vector<mbrt::BeamElement> beams;  // same order as Model::beam_elements
  std::vector<ModalPlan> modal;          // same order as Model::modal
  std::vector<InputPlan> inputs;  // same order as Model::inputs
  std::vector<ContactPlan> contacts;  // same order as Model::contacts
  std::vector<int> mechanism;  // per body: the first body of its mechanism (bodies joined by joints or drivers)
  Partition partition;  // the parallel step's subsystems (one part: serial)
  FactorPattern pattern;
  bool gravity = false;
  bool velocity_dependent_forces = false;  // gyroscopic or damping terms: two stages per step
  double regularization = 0.0;             // added to the diagonal of S
  int redundant_rows = 0;                  // constraint rows minus the rank of B at t = 0
  double newton_shift = 0.0;               // added to the diagonal of staggered-pcst's position-stage matrix
  double stabilization = 0.0;              // staggered-pcst alpha, 1/s
  double baumgarte_alpha = 0.0;            // baumgarte, 1/s
  double baumgarte_beta = 0.0;             // baumgarte, 1/s
  Ali3pPlan ali3p;                         // ali3p only
  TreePlan tree;                           // staggered-nps only
  TreeFrames tree_frames;                  // staggered-tree only
  PlanarPlan planar;
  // Runtime parameters (docs/parameters.md): the step reads them from State::params.
  bool tunable = false;         // the model marks some key tunable
  bool tunable_masses = false;  // some body's mass or inertia: M^-1 is formed from the parameters
  Specializations specialize;              // which ones the emitter may make
  std::vector<Skipped> skipped;            // the ones that applied, for the source's comment and reports
};

// Throws ModelError for models the generator cannot handle (e.g. a revolute
// joint on a particle).
Analysis analyse(const Model& model, const Specializations& specialize = {});

// The scheme for a model whose file names none: rk4-tree where the bodies
// hang from ground by revolute and prismatic joints alone (the cheapest at
// equal error of the tree schemes, and the one that kept the energy best at
// 1 kHz, docs/staggered-tree.md), else staggered-pcst.
mbrt::Scheme default_scheme(const Model& model);

}  // namespace mbrt::codegen
