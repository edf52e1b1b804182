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

// A hidden temporary name beside `target` (".NAME.tmp.<pid>.<n>"): never mistaken for an output by
// a glob on its extension, unique per process and call.
std::filesystem::path temporary_name_for(const std::filesystem::path& target);
// Removes temporary files of earlier writers of `target` whose process is gone (killed mid-write),
// so they never pile up; a live writer's file is left alone.
void remove_stale_temporaries(const std::filesystem::path& target);

// fsync of a folder: makes renames and creations inside it durable (also used by H5Writer).
void sync_directory(const std::filesystem::path& dir);

}  // namespace dmgplace::formats
