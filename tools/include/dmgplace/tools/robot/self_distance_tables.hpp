#pragma once
// Tabulates the exact distance between link pairs whose spheres cannot settle self-collision by
// themselves (they overlap somewhere in the joints' ranges) and whose relative pose depends on
// one or two revolute chain joints: the fast layer then reads a proven lower bound instead of
// calling FCL (see formats::SelfDistanceTable).
#include <vector>

#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::tools {

struct SelfTableOptions {
  double step = 0.02;        // radians between nodes (the bound loses slope * step / 2 per joint)
  int overlap_samples = 2000;  // random joint values tried to see whether the spheres overlap
  int threads = 0;           // <= 0: all cores
  bool enabled = true;
};

// For the pairs the chain of `kin` moves; `spheres` cover every link.
std::vector<formats::SelfDistanceTable> build_self_distance_tables(const runtime::Kinematics& kin,
                                                                   const std::vector<formats::LinkSphere>& spheres,
                                                                   const SelfTableOptions& options = {});

}  // namespace dmgplace::tools
