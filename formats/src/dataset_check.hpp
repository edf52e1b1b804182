#pragma once
// The semantic check of `batch-collect`'s dataset files (private to dmgplace_formats).
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::formats::detail {

// One line per problem: a table's columns of unequal length or shape, a missing column, offsets
// and `run` columns that do not link the tables; empty when sound.
std::vector<std::string> check_dataset(const std::filesystem::path& path);

}  // namespace dmgplace::formats::detail
