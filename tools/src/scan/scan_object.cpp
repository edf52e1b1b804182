#include "dmgplace/tools/scan/scan_object.hpp"

#include <cmath>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {

ScanObject object_from_scans(const std::vector<std::filesystem::path>& files, const ScanObjectOptions& o) {
  if (files.empty()) throw Error("bake-object", "", "no scan given");
  const std::string name = files.front().string();
  if (!(o.scale > 0) || !std::isfinite(o.scale)) throw Error(name, "--scale", "must be positive");
  std::vector<ScanCloud> scans;
  for (const auto& f : files) {
    ScanCloud s = read_scan(f);
    s.points *= o.scale;
    s.viewpoint *= o.scale;
    scans.push_back(std::move(s));
  }
  ScanObject out;
  out.segmented = segment_object(scans, o.segment, name);
  const TriMesh scan_mesh =
      reconstruct_surface(out.segmented.points, out.segmented.normals, o.reconstruct, name, out.reconstruction);
  Eigen::AlignedBox3d box;
  for (Eigen::Index i = 0; i < scan_mesh.vertices.rows(); ++i) box.extend(scan_mesh.vertices.row(i).transpose());
  out.origin_in_scan = box.center();
  out.mesh = scan_mesh;
  out.mesh.vertices.rowwise() -= out.origin_in_scan.transpose();
  for (std::size_t i = 0; i < out.segmented.points.size(); ++i) {
    out.points.push_back(out.segmented.points[i] - out.origin_in_scan);
    out.normals.push_back(out.segmented.normals[i]);
  }
  return out;
}

}  // namespace dmgplace::tools
