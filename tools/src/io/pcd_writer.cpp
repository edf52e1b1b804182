#include "dmgplace/tools/io/pcd_writer.hpp"

#include <cstdio>
#include <string>

#include "dmgplace/formats/atomic_file.hpp"
#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

void write_pcd(const std::filesystem::path& path, const RowMatrixX3d& points, const Eigen::Vector3d& viewpoint,
               const Eigen::Quaterniond& orientation) {
  if (!points.allFinite()) throw Error(path.string(), "points", "not finite");
  const Eigen::Index n = points.rows();
  std::string text =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
  char line[160];
  std::snprintf(line, sizeof line,
                "WIDTH %ld\nHEIGHT 1\nVIEWPOINT %.9g %.9g %.9g %.9g %.9g %.9g %.9g\nPOINTS %ld\nDATA ascii\n", long(n),
                viewpoint.x(), viewpoint.y(), viewpoint.z(), orientation.w(), orientation.x(), orientation.y(),
                orientation.z(), long(n));
  text += line;
  for (Eigen::Index i = 0; i < n; ++i) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", points(i, 0), points(i, 1), points(i, 2));
    text += line;
  }
  formats::write_file_atomically(path, text);
}

}  // namespace dmgplace::tools
