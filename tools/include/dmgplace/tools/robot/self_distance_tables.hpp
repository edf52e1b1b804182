#pragma once
// Tabulates the exact distance between link pairs whose spheres cannot settle self-collision by
// themselves (they overlap somewhere in the joints' ranges) and whose relative pose depends on
// one or two revolute chain joints: the fast layer then reads a proven lower bound instead of
// calling FCL (see formats::SelfDistanceTable).
//
// Bound first, refine near contact: the exact distance is computed on every `coarse_stride`-th
// node; any other node whose Lipschitz bound from the corners of its coarse cell (distance minus
// slope x joint offset) is at least `exact_below` stores that bound, which is a lower bound as
// every stored value must be; the rest, near contact, are computed within `tolerance` of exact:
// the links' convex hulls' gap where the two triangles closest at the cell's nearest lattice node
// prove it that close (ExactChecker::link_distance_within), FCL's exact distance otherwise.
#include <cstddef>
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"
#include "dmgplace/tools/system/progress.hpp"

namespace dmgplace::tools {

struct SelfTableOptions {
  double step = 0.02;          // radians between nodes (the bound loses slope * step / 2 per joint)
  int overlap_samples = 2000;  // random joint values tried to see whether the spheres overlap
  int threads = 0;             // <= 0: all cores
  bool enabled = true;
  int coarse_stride = 4;      // 1: every node exact
  double exact_below = 0.05;  // m: nodes bounded below this are computed exactly
  double tolerance = 2e-4;    // m: how far below exact such a node may be (0: FCL at each)
  // Nodes settled of all nodes so far known (the tables are found one by one).
  ProgressFn progress;
};

// For the pairs the chain of `kin` moves; `spheres` cover every link.
std::vector<formats::SelfDistanceTable> build_self_distance_tables(const runtime::Kinematics& kin,
                                                                   const std::vector<formats::LinkSphere>& spheres,
                                                                   const SelfTableOptions& options = {});

}  // namespace dmgplace::tools
