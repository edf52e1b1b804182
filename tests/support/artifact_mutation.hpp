#pragma once
// Crafted artifacts for tests and the structure-aware fuzzer: a copy of a sound artifact with one
// element of one dataset overwritten and that dataset's SHA-256 recomputed, so every checksum is
// consistent and only the loaders' semantic gate stands between the file and the runtime (a buggy
// writer, another tool, a future version).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dmgplace::test {

// Number of elements of dataset `name` (all dimensions multiplied).
std::size_t dataset_size(const std::filesystem::path& file, const std::string& name);

// Element `index` of dataset `name`, converted to double.
double dataset_value(const std::filesystem::path& file, const std::string& name, std::size_t index);

// Copies `from` to `to` (replacing it), then sets element `index` of dataset `name` to `value`
// (converted to the dataset's type; NaN into an integer dataset is written as 0 by HDF5's
// conversion) and rewrites the dataset's sha256 attribute to match.
void mutate_dataset(const std::filesystem::path& from, const std::filesystem::path& to, const std::string& name,
                    std::size_t index, double value);

// Every dataset of the artifact (sorted).
std::vector<std::string> artifact_datasets(const std::filesystem::path& file);

}  // namespace dmgplace::test
