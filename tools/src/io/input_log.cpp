#include "dmgplace/tools/io/input_log.hpp"

#include <algorithm>

namespace dmgplace::tools {
namespace {
thread_local InputLog* current = nullptr;
}

InputLog::InputLog() : outer_(current) { current = this; }
InputLog::~InputLog() { current = outer_; }

void note_input(const std::filesystem::path& path) {
  for (InputLog* log = current; log; log = log->outer_)
    if (std::find(log->files_.begin(), log->files_.end(), path) == log->files_.end()) log->files_.push_back(path);
}

}  // namespace dmgplace::tools
