#pragma once
// ENV.h5: an environment's exact collision geometry, its target volume, its distance fields and
// its placement regions.
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/geometry_types.hpp"

namespace dmgplace::formats {

inline constexpr const char* kEnvironmentSchema = "dmgplace.environment";
inline constexpr int kEnvironmentSchemaVersion = 2;

// A regular grid of float samples: sample (i, j, k) sits at origin + resolution * (i, j, k) and is
// values[i + nx * (j + ny * k)] (x fastest), the layout runtime::Grid3 uses. Values are clamped
// to [-band, band]; a value of +-band means "at least band away".
struct FieldGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double resolution = 0;
  std::array<int, 3> dims{0, 0, 0};
  double band = 0;
  std::vector<float> values;

  bool empty() const { return values.empty(); }
  std::size_t size() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
  Eigen::AlignedBox3d bounds() const {
    return {origin, origin + resolution * Eigen::Vector3d(dims[0] - 1, dims[1] - 1, dims[2] - 1)};
  }
};

// One contiguous horizontal support surface, rasterised on square cells of `resolution`:
// cell (i, j) spans x0 + i*res .. x0 + (i+1)*res (same for y); x fastest in mask and free_height.
struct PlacementRegion {
  double height = 0;                                 // z of the supporting surface (world)
  double resolution = 0;                             // cell edge (m)
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // x0, y0: lower corner of cell (0, 0)
  int width = 0, depth = 0;                          // cells along x and y
  std::vector<std::uint8_t> mask;                    // 1 = supported and free above
  std::vector<float> free_height;  // free height above each mask cell (m, capped at the top of V); 0 outside
  double area = 0;                 // mask cells x resolution^2
  int surface = -1;                // connected surface the region was split from (equal for siblings)

  std::size_t cell_count() const;
  Eigen::Vector2d cell_center(int i, int j) const { return origin + resolution * Eigen::Vector2d(i + 0.5, j + 0.5); }
};

struct EnvironmentArtifact {
  ArtifactHeader header;
  Scene scene;                 // obstacles in the world frame (z up), scan points if any
  Eigen::AlignedBox3d volume;  // the target volume V
  // Distance to the obstacles over V plus a margin; negative inside closed obstacles when
  // `sdf_signed`, unsigned (>= 0) for scans and open meshes. Empty when not baked.
  FieldGrid sdf;
  bool sdf_signed = true;
  // Clearance over V: distance to obstacle geometry strictly above each sample's height (the
  // support below is ignored), 0 inside obstacles, clamped to its band. Empty when not baked.
  FieldGrid clearance;
  std::vector<PlacementRegion> regions;
};

void save_environment(EnvironmentArtifact artifact, const std::filesystem::path& path);
// Reads the file and refuses it unless check_environment finds nothing (see load_object).
EnvironmentArtifact load_environment(const std::filesystem::path& path);
// Reads without the semantic checks: for `validate` and tests (see read_object_unchecked).
EnvironmentArtifact read_environment_unchecked(const std::filesystem::path& path);
std::vector<std::string> check_environment(const EnvironmentArtifact& a);
Summary summarize_environment(const EnvironmentArtifact& a);

// The grid sample nearest to p (clamped into the grid); the grid must not be empty.
float nearest_sample(const FieldGrid& g, const Eigen::Vector3d& p);
// Trilinear interpolation at p (clamped into the grid); the grid must have >= 2 samples an axis.
float interpolated_sample(const FieldGrid& g, const Eigen::Vector3d& p);

}  // namespace dmgplace::formats
