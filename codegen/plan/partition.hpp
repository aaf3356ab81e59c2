// The parallel step's subsystems (docs/parallel.md): the constraint blocks
// split into parts that share no moving body, and an interface of the blocks
// that couple parts. Ordered parts first and the interface last, S = B M^-1 B^T
// is block arrowhead: each part's factor is formed on its own thread, the
// interface's (the Schur complement of the parts) after them.
#pragma once

#include <string>
#include <vector>


namespace mbrt::codegen {

struct ConstraintBlock;

struct Partition {
  int parts = 1;                // 1: the serial step
  int requested = 1;            // solver.parallel_parts
  std::vector<int> block_part;  // per constraint block: its part, or `parts` for the interface
  std::vector<int> body_part;   // per body: the part that updates it in the per-body phases
  // Per block: the part that runs it in phases without coupling (rows,
  // directions, Jacobian products): its own, or for interface blocks one
  // part each in turn.
  std::vector<int> phase_part;
  int interface_blocks = 0;
  int interface_rows = 0;
  std::vector<int> part_rows;   // constraint rows per part, the interface's not counted
  std::string serial_reason;    // why the serial step is used although parts were asked for
  // The interface's Schur complement: factorized, or solved by pcg_iterations
  // of preconditioned conjugate gradients (block or diagonal preconditioner).
  bool pcg = false;
  int pcg_iterations = 0;
  bool block_preconditioner = true;
  bool interface(int block) const { return block_part[static_cast<size_t>(block)] == parts; }
};

// Constraint rows per part below which the step stays serial: there the
// fixed cost of the phases' fork and join (about thirty a step, 0.1 to 2 us
// each) is a large share of a part's work. Above it, whether the parallel
// step pays depends on the machine (docs/parallel.md, "When it pays").
inline constexpr int kMinRowsPerPart = 96;

// Splits the blocks into `parts` parts of about equal rows along a
// depth-first order of the bodies (subtrees and chain segments stay
// together), then moves to the interface every block of a later part that
// shares a moving body with a block of an earlier one.
Partition partition_blocks(const std::vector<ConstraintBlock>& blocks, int bodies, int parts);

}  // namespace mbrt::codegen
