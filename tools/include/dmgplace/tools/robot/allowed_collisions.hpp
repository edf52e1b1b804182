#pragma once
// Which link pairs may touch, for a robot without an SRDF: what MoveIt's setup assistant decides.
// A pair is disabled when its links are adjacent (joined by a joint, links without geometry
// skipped), when it collides in the default pose (every chain joint at 0, clamped to its limits),
// when it collides in every one of N random configurations ("always") or in none of them
// ("never"). Only the planning chain's joints are sampled; the rest stay where the model has them.
#include <cstdint>
#include <string>
#include <vector>

#include "dmgplace/formats/robot_model.hpp"

namespace dmgplace::tools {

struct AllowedCollisionOptions {
  int samples = 2000;  // random configurations (MoveIt's default is 10000; 2000 settles the Panda)
  std::uint64_t seed = 1;
  int threads = 0;  // <= 0: every CPU the process may use (the result does not depend on it)
};

enum class DisableReason { Adjacent, Default, Always, Never };
const char* to_string(DisableReason r);  // the SRDF reason attribute: Adjacent, Default, Always, Never

struct DisabledPair {
  int a = -1, b = -1;  // link indices, a < b
  DisableReason reason = DisableReason::Never;
};

// A pair left to be checked, with the number of sampled configurations in which it collided.
struct CheckedPair {
  int a = -1, b = -1;
  int collisions = 0;
};

struct AllowedCollisions {
  std::vector<DisabledPair> disabled;
  std::vector<CheckedPair> checked;  // the rest: they collide sometimes
  int samples = 0;
  int checked_pairs = 0;  // pairs with geometry on both links (disabled + checked)
  int count(DisableReason r) const;
};

// The model's arm chain (model.arm_base, model.arm_tip) must be set.
AllowedCollisions compute_allowed_collisions(const RobotModel& model, const AllowedCollisionOptions& options = {});

// An SRDF holding one <disable_collisions> per pair, for the user to review and pass back.
std::string srdf_text(const RobotModel& model, const std::vector<DisabledPair>& pairs);

}  // namespace dmgplace::tools
