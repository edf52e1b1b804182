#pragma once
// Provenance of everything a bake reads: while an InputLog lives on a thread, every file the
// readers open on that thread (meshes named by a URDF or a scene, package resources) is noted in
// it, so the artifact's header can carry each one with its hash, not just the file on the
// command line. Logs nest: an inner one also reports to the outer.
#include <filesystem>
#include <vector>

namespace dmgplace::tools {

class InputLog {
 public:
  InputLog();
  ~InputLog();
  InputLog(const InputLog&) = delete;
  InputLog& operator=(const InputLog&) = delete;
  // Files noted so far, in the order first read, each once.
  const std::vector<std::filesystem::path>& files() const { return files_; }

 private:
  friend void note_input(const std::filesystem::path& path);
  InputLog* outer_;
  std::vector<std::filesystem::path> files_;
};

// Called by the readers for each file they open.
void note_input(const std::filesystem::path& path);

}  // namespace dmgplace::tools
