#pragma once
// Parallel-jaw gripper geometry for grasp analysis: the built-in arm's hand or a YAML file
// (datasets/grippers/dmgarm_hand.yaml documents the keys).
#include <filesystem>

#include "dmgplace/formats/object_artifact.hpp"

namespace dmgplace::tools {

// The dmgarm hand (same numbers as datasets/grippers/dmgarm_hand.yaml).
formats::GripperModel default_gripper();

// Missing keys keep the default's value. Unreadable file, unknown key, non-positive size or a
// malformed vector: dmgplace::Error naming the file and the key.
formats::GripperModel load_gripper_yaml(const std::filesystem::path& path);

}  // namespace dmgplace::tools
