#pragma once
// Writes a whole file so that readers (and a run resumed after kill -9 or a power cut) see either
// the old file or the complete new one, never a part: the bytes go to a unique hidden temporary
// file in the same folder, are fsynced, renamed over the target, and the folder is fsynced so the
// rename itself is durable. On failure the temporary file is removed and dmgplace::Error names
// the target.
#include <filesystem>
#include <string_view>

namespace dmgplace::formats {

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// fsync of a folder: makes renames and creations inside it durable (also used by H5Writer).
void sync_directory(const std::filesystem::path& dir);

}  // namespace dmgplace::formats
