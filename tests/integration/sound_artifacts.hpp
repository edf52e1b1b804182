#pragma once
// A sound robot, object and environment baked in-process from the built-in data (small grids,
// coarse DMG: seconds), for tests that craft broken copies of them.
#include <filesystem>
#include <memory>

#include "test_support.hpp"

namespace dmgplace::test {

struct SoundArtifacts {
  TempDir dir;
  std::filesystem::path robot = dir / "arm.h5", object = dir / "eraser.h5", env = dir / "table.h5";
  std::filesystem::path urdf;  // the robot's input, named in its header
};

std::unique_ptr<SoundArtifacts> bake_sound_artifacts();

}  // namespace dmgplace::test
