#include "dmgplace/tools/viewer/write_viewer.hpp"

#include <fstream>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/viewer/arm_motion.hpp"
#include "dmgplace/tools/viewer/scene_data.hpp"
#include "dmgplace/tools/viewer/view_result.hpp"
#include "dmgplace/tools/viewer/viewer_page.hpp"

namespace dmgplace::tools::viewer {

ViewerSummary write_viewer(const std::filesystem::path& result_dir, const std::filesystem::path& html,
                           const std::filesystem::path& artifacts) {
  const ViewResult r = read_view_result(result_dir, artifacts);
  const auto robot = formats::load_robot(r.robot);
  const auto object = formats::load_object(r.object);
  const auto env = formats::load_environment(r.environment);
  const ArmMotion motion = sample_arm_motion(r, robot, object.dmg.gripper.max_opening);
  const std::string page = viewer_page("dmgplace: " + std::filesystem::path(r.query_file).stem().string(),
                                       scene_data_json(r, motion, robot, object, env));
  formats::write_file_atomically(html, page);
  return {r.solved, int(r.path.size() + r.retreat.size()), motion.frames, page.size()};
}

}  // namespace dmgplace::tools::viewer
