// The spanning tree staggered-nps eliminates (docs/staggered-nps.md): each
// body's parent joint, chosen by joint type, and the rows left over (loop
// closures, drivers, distances, contacts), which it treats as cut rows.
#pragma once

#include <vector>

#include "model.hpp"

namespace mbrt::codegen {

struct ConstraintBlock;

struct TreeBody {
  int body;           // Model::bodies index
  int parent;         // body index or kGround
  int joint = -1;     // constraint block joining it to the parent; -1: a free body
  bool child_is_body2 = true;  // which side of the joint the body is on
  int dofs = 6;       // columns of its null-space block H (free particles: 3)
  bool leaf = true;   // no body hangs from it
};

struct TreePlan {
  std::vector<TreeBody> order;  // parents before children
  std::vector<int> cut_blocks;  // constraint blocks handled by cut-row multipliers
  int cut_rows = 0;
};

// Cut rows make a dense system solved through the tree; beyond this many the
// generator refuses staggered-nps and names staggered-pcst instead.
constexpr int kMaxCutRows = 30;

// Joints a tree may use: their null space has a closed form.
bool is_tree_joint(JointType type);
int tree_joint_dofs(JointType type);
// Tree joints whose first rows make the joint points coincide: the transfer
// from the parent is anchored at the joint point.
bool has_coincidence_rows(JointType type);

// Grows the tree from ground over tree joints between rigid bodies, taking
// joints in file order; bodies not reached become free bodies. A particle
// thus never has children. Throws ModelError beyond kMaxCutRows.
TreePlan plan_tree(const Model& model, const std::vector<ConstraintBlock>& blocks);

}  // namespace mbrt::codegen
