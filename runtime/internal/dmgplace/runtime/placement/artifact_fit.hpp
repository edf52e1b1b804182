#pragma once
// Do a robot, an object and an environment artifact belong together? Each is sound on its own
// (the loaders check that); this checks what only the three together can tell:
//   - the object's DMG was built for a gripper that opens no wider than the robot's fingers do;
//   - some placement region of the environment lies within the arm's reach (a sphere about the
//     base, the sum of the chain's link offsets: an upper bound, so "out of reach" is certain);
//   - units agree: an object 2 m across is a millimetre mesh baked without `--scale 0.001`
//     (a warning: large objects exist).
// Errors name both files involved. PlacementWorld refuses a set with errors; `dmgplace validate
// --set ROBOT.h5 OBJECT.h5 ENV.h5` prints errors and warnings.
#include <string>
#include <vector>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/runtime/robot/kinematics.hpp"

namespace dmgplace::runtime {

struct ArtifactFit {
  std::vector<std::string> errors, warnings;
  bool ok() const { return errors.empty(); }
};

struct FitNames {
  std::string robot = "<robot artifact>", object = "<object artifact>", environment = "<environment artifact>";
};

// `finger_gap(opening)`: distance between the robot's finger frames along the closing axis with
// the finger joints driven for `opening` (PlacementWorld::hand_at); `fingers`: how many finger
// links the hand has.
ArtifactFit check_fit(const formats::ObjectArtifact& object, const std::vector<formats::PlacementRegion>& regions,
                      const Kinematics& kin, double robot_max_opening, int fingers, const FitNames& names);

// Upper bound of how far the tip gets from the base link's origin: the chain's joint offsets
// summed (prismatic joints at their largest travel).
double reach_bound(const Kinematics& kin);

}  // namespace dmgplace::runtime
