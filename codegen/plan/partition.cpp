#include "partition.hpp"

#include <algorithm>
#include <numeric>

#include "analysis.hpp"

namespace mbrt::codegen {

namespace {

// Bodies in depth-first order over the joint graph: from the bodies joined to
// ground, in block order, then from the most-joined body of each remaining
// mechanism (a vehicle's chassis), so that a subtree or a stretch of chain
// takes consecutive places.
std::vector<int> depth_first_bodies(const std::vector<ConstraintBlock>& blocks, int bodies) {
  std::vector<std::vector<int>> next(static_cast<size_t>(bodies));
  std::vector<int> roots;
  for (const ConstraintBlock& b : blocks) {
    if (b.body1 != kGround && b.body2 != kGround) {
      next[static_cast<size_t>(b.body1)].push_back(b.body2);
      next[static_cast<size_t>(b.body2)].push_back(b.body1);
    } else {
      roots.push_back(b.body1 == kGround ? b.body2 : b.body1);
    }
  }
  std::vector<int> by_degree(static_cast<size_t>(bodies));
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(),
                   [&](int x, int y) { return next[static_cast<size_t>(x)].size() > next[static_cast<size_t>(y)].size(); });
  roots.insert(roots.end(), by_degree.begin(), by_degree.end());
  std::vector<int> place(static_cast<size_t>(bodies), -1);
  int count = 0;
  std::vector<int> stack;
  for (int root : roots) {
    if (root == kGround || place[static_cast<size_t>(root)] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      if (place[static_cast<size_t>(b)] >= 0) continue;
      place[static_cast<size_t>(b)] = count++;
      const auto& n = next[static_cast<size_t>(b)];
      for (auto it = n.rbegin(); it != n.rend(); ++it) {
        if (place[static_cast<size_t>(*it)] < 0) stack.push_back(*it);
      }
    }
  }
  return place;
}

bool share_moving_body(const ConstraintBlock& a, const ConstraintBlock& b) {
  const auto in = [](int x, const ConstraintBlock& j) { return x != kGround && (x == j.body1 || x == j.body2); };
  return in(a.body1, b) || in(a.body2, b);
}

}  // namespace

Partition partition_blocks(const std::vector<ConstraintBlock>& blocks, int bodies, int parts) {
  Partition p;
  const int n = static_cast<int>(blocks.size());
  p.parts = std::max(1, std::min(parts, n));
  p.requested = parts;
  const std::vector<int> place = depth_first_bodies(blocks, bodies);
  const auto key = [&](int j) {
    const ConstraintBlock& b = blocks[static_cast<size_t>(j)];
    return std::max(b.body1 == kGround ? -1 : place[static_cast<size_t>(b.body1)],
                    b.body2 == kGround ? -1 : place[static_cast<size_t>(b.body2)]);
  };
  std::vector<int> sorted(static_cast<size_t>(n));
  std::iota(sorted.begin(), sorted.end(), 0);
  std::stable_sort(sorted.begin(), sorted.end(), [&](int x, int y) { return key(x) < key(y); });
  int total = 0;
  for (const ConstraintBlock& b : blocks) total += b.rows;
  p.block_part.assign(static_cast<size_t>(n), 0);
  int done = 0;
  for (int j : sorted) {
    // The part whose share of the rows this block's middle falls in.
    const int middle = 2 * done + blocks[static_cast<size_t>(j)].rows;
    p.block_part[static_cast<size_t>(j)] = std::min(p.parts - 1, middle * p.parts / std::max(1, 2 * total));
    done += blocks[static_cast<size_t>(j)].rows;
  }
  // The separator: of two coupled blocks in different parts, the later part's
  // goes to the interface. In the depth-first order that is the block that
  // joins a subtree or a chain's stretch to the rest.
  for (int i : sorted) {
    for (int k : sorted) {
      const int pi = p.block_part[static_cast<size_t>(i)], pk = p.block_part[static_cast<size_t>(k)];
      if (pi < pk && pk < p.parts && share_moving_body(blocks[static_cast<size_t>(i)], blocks[static_cast<size_t>(k)])) {
        p.block_part[static_cast<size_t>(k)] = p.parts;
      }
    }
  }
  p.phase_part = p.block_part;
  int shared_out = 0;
  for (int& part : p.phase_part) {
    if (part == p.parts) part = shared_out++ % p.parts;
  }
  p.part_rows.assign(static_cast<size_t>(p.parts), 0);
  for (int j = 0; j < n; ++j) {
    const int part = p.block_part[static_cast<size_t>(j)];
    if (part == p.parts) {
      ++p.interface_blocks;
      p.interface_rows += blocks[static_cast<size_t>(j)].rows;
    } else {
      p.part_rows[static_cast<size_t>(part)] += blocks[static_cast<size_t>(j)].rows;
    }
  }
  // A body goes with the first block of a part that moves it; bodies only the
  // interface moves, and free bodies, by their place in the order.
  p.body_part.assign(static_cast<size_t>(bodies), -1);
  for (int j : sorted) {
    const int part = p.block_part[static_cast<size_t>(j)];
    if (part == p.parts) continue;
    for (int b : {blocks[static_cast<size_t>(j)].body1, blocks[static_cast<size_t>(j)].body2}) {
      if (b != kGround && p.body_part[static_cast<size_t>(b)] < 0) p.body_part[static_cast<size_t>(b)] = part;
    }
  }
  for (int b = 0; b < bodies; ++b) {
    if (p.body_part[static_cast<size_t>(b)] < 0) {
      p.body_part[static_cast<size_t>(b)] = std::min(p.parts - 1, place[static_cast<size_t>(b)] * p.parts / std::max(1, bodies));
    }
  }
  return p;
}

}  // namespace mbrt::codegen
