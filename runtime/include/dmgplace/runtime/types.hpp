#pragma once
// Plain value types of the runtime's public API that need no planning library.
#include <vector>

namespace dmgplace::runtime {

// A joint-space path: waypoints in the arm chain's joint order (radians; metres for prismatic
// joints). Consecutive waypoints are joined by straight lines in joint space, each checked free at
// the query's motion resolution.
using JointPath = std::vector<std::vector<double>>;

}  // namespace dmgplace::runtime
