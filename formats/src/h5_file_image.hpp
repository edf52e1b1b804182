#pragma once
// Fixing up an HDF5 file image taken from memory (H5Fget_file_image) before it is written to disk.
#include <cstdint>
#include <vector>

namespace dmgplace::formats::detail {

// Bob Jenkins' lookup3 hash (public domain): the checksum HDF5 puts on its metadata.
std::uint32_t lookup3(const std::uint8_t* data, std::size_t length);

// H5Fget_file_image (HDF5 before 1.14.7, HDFGroup/hdf5 #1915) clears the superblock's "open for
// writing" flags in the image but keeps the checksum of the flagged superblock, so the image would
// not reopen. Recomputes it (harmless where HDF5 already did).
void fix_superblock_checksum(std::vector<char>& image);

}  // namespace dmgplace::formats::detail
