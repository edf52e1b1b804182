#include "dmgplace/tools/io/pcd_reader.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <system_error>

#include "dmgplace/formats/error.hpp"
#include "dmgplace/tools/io/input_log.hpp"
#include "pcd_layout.hpp"

namespace dmgplace::tools {

RowMatrixX3d read_pcd(const std::filesystem::path& pcd) { return read_scan(pcd).points; }

ScanCloud read_scan(const std::filesystem::path& pcd) {
  const std::string file = pcd.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(pcd, ec)) throw Error(file, "", "file not found");

  note_input(pcd);
  detail::check_pcd_layout(file);  // PCL would crash or read garbage on some broken files
  pcl::PCLPointCloud2 blob;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  try {
    pcl::PCDReader reader;
    int version = 0;
    if (reader.read(file, blob, origin, orientation, version) < 0)
      throw Error(file, "", "PCL cannot read it (bad header, or data shorter than the header says)");
    const auto has = [&](const char* name) {
      return std::any_of(blob.fields.begin(), blob.fields.end(), [&](const auto& f) { return f.name == name; });
    };
    for (const char* axis : {"x", "y", "z"})
      if (!has(axis)) throw Error(file, "FIELDS", std::string("no '") + axis + "' field");
    // PCL trusts WIDTH x HEIGHT; a body that does not hold that many points is a lie we reject.
    const std::size_t points = std::size_t(blob.width) * blob.height;
    if (points == 0) throw Error(file, "POINTS", "the cloud is empty");
    if (blob.data.size() < points * blob.point_step)
      throw Error(file, "DATA",
                  "holds " + std::to_string(blob.data.size()) + " bytes, the header promises " +
                      std::to_string(points * blob.point_step));
    pcl::fromPCLPointCloud2(blob, cloud);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // pcl::PCLException and friends on corrupt data
    throw Error(file, "", std::string("PCL cannot read it: ") + e.what());
  }

  ScanCloud scan;
  RowMatrixX3d& out = scan.points;
  out.resize(Eigen::Index(cloud.size()), 3);
  Eigen::Index n = 0;
  for (const auto& p : cloud.points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) out.row(n++) << p.x, p.y, p.z;
  if (n == 0) throw Error(file, "", "no finite point among " + std::to_string(cloud.size()));
  out.conservativeResize(n, 3);
  scan.viewpoint = origin.head<3>().cast<double>();
  scan.orientation = orientation.cast<double>();
  if (!scan.viewpoint.allFinite() || !scan.orientation.coeffs().allFinite() || scan.orientation.norm() < 1e-6)
    throw Error(file, "VIEWPOINT", "not a finite position and a non-zero quaternion");
  scan.orientation.normalize();
  return scan;
}

Scene read_scan_scene(const std::filesystem::path& pcd, const Eigen::Isometry3d& frame) {
  Scene scene;
  const RowMatrixX3d local = read_pcd(pcd);
  // Row vectors: p_world^T = p^T R^T + t^T.
  scene.points = (local * frame.linear().transpose()).rowwise() + frame.translation().transpose();
  return scene;
}

}  // namespace dmgplace::tools
