#pragma once
// The viewer page's data: every mesh as base64 Float32/Uint32 arrays, the sampled arm motion, the
// in-hand steps and the result summary, as JSON text safe to put inside a <script> element.
#include <string>

#include "dmgplace/formats/environment_artifact.hpp"
#include "dmgplace/formats/object_artifact.hpp"
#include "dmgplace/formats/robot_artifact.hpp"
#include "dmgplace/tools/viewer/arm_motion.hpp"
#include "dmgplace/tools/viewer/view_result.hpp"

namespace dmgplace::tools::viewer {

std::string scene_data_json(const ViewResult& r, const ArmMotion& motion, const formats::RobotArtifact& robot,
                            const formats::ObjectArtifact& object, const formats::EnvironmentArtifact& env);

}  // namespace dmgplace::tools::viewer
