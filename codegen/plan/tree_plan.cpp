#include "tree_plan.hpp"

#include <string>

#include "analysis.hpp"

namespace mbrt::codegen {

bool is_tree_joint(JointType type) {
  switch (type) {
    case JointType::spherical:
    case JointType::revolute:
    case JointType::universal:
    case JointType::cylindrical:
    case JointType::prismatic:
    case JointType::fixed:
    case JointType::screw:
    case JointType::planar: return true;
    case JointType::distance:
    case JointType::rolling_disk:
    case JointType::rolling_ball:
    case JointType::knife_edge:
    case JointType::velocity_toward: return false;
  }
  return false;
}

int tree_joint_dofs(JointType type) { return 6 - type_row(type).rows; }

bool has_coincidence_rows(JointType type) {
  return type == JointType::spherical || type == JointType::revolute || type == JointType::universal ||
         type == JointType::fixed;
}

TreePlan plan_tree(const Model& model, const std::vector<ConstraintBlock>& blocks) {
  const size_t bodies = model.bodies.size();
  std::vector<bool> used(blocks.size(), false);
  std::vector<int> position(bodies, -1);  // index in t.order; -1: not placed yet
  TreePlan t;
  auto in_tree = [&](int b) { return b == kGround || position[static_cast<size_t>(b)] >= 0; };
  auto rigid = [&](int b) { return b == kGround || !model.bodies[static_cast<size_t>(b)].particle; };
  auto place = [&](TreeBody tb) {
    position[static_cast<size_t>(tb.body)] = static_cast<int>(t.order.size());
    if (tb.parent != kGround) t.order[static_cast<size_t>(position[static_cast<size_t>(tb.parent)])].leaf = false;
    t.order.push_back(tb);
  };
  while (t.order.size() < bodies) {
    // Passes over the joints in file order: the first joint that reaches a
    // body from the tree carries it, so a model lists its loop-closing joints
    // last to make them the cut.
    for (bool grew = true; grew;) {
      grew = false;
      for (size_t j = 0; j < model.joints.size(); ++j) {
        const Joint& joint = model.joints[j];
        if (used[j] || !is_tree_joint(joint.type) || !rigid(joint.body1) || !rigid(joint.body2)) continue;
        if (in_tree(joint.body1) == in_tree(joint.body2)) continue;
        const bool child_is_body2 = in_tree(joint.body1);
        used[j] = true;
        place({child_is_body2 ? joint.body2 : joint.body1, child_is_body2 ? joint.body1 : joint.body2,
               static_cast<int>(j), child_is_body2, tree_joint_dofs(joint.type)});
        grew = true;
      }
    }
    // A body no tree joint reaches moves freely; its own subtree hangs from it.
    for (size_t b = 0; b < bodies; ++b) {
      if (position[b] >= 0) continue;
      place({static_cast<int>(b), kGround, -1, true, model.bodies[b].particle ? 3 : 6});
      break;
    }
  }
  for (size_t j = 0; j < blocks.size(); ++j) {
    if (used[j]) continue;
    t.cut_blocks.push_back(static_cast<int>(j));
    t.cut_rows += blocks[j].rows;
  }
  if (t.cut_rows > kMaxCutRows) {
    throw ModelError({model.file, 0, 0}, "solver.scheme",
                     "staggered-nps closes loops with a dense system of cut-joint rows, at most " +
                         std::to_string(kMaxCutRows) + "; this model has " + std::to_string(t.cut_rows) +
                         " (use staggered-pcst)");
  }
  return t;
}

}  // namespace mbrt::codegen
