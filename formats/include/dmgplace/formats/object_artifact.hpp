#pragma once
// OBJECT.h5: everything the runtime needs about one rigid object: mesh, mass properties, the
// faces it can rest on, its Dexterous Manipulation Graph (DMG) for in-hand regrasping and the grasp
// graph derived from the DMG.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "dmgplace/formats/artifact_header.hpp"
#include "dmgplace/formats/artifact_kind.hpp"
#include "dmgplace/formats/geometry_types.hpp"
#include "dmgplace/formats/grasp_graph_table.hpp"

namespace dmgplace::formats {

inline constexpr const char* kObjectSchema = "dmgplace.object";
inline constexpr int kObjectSchemaVersion = 3;  // 3: the grasp graph is stored

struct MassProperties {
  double volume = 0;                                  // m^3, from the closed mesh
  double mass = 0;                                    // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // object frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the COM, kg m^2
  bool com_overridden = false;                        // --com given by the user
};

// A stable resting face: merged convex-hull facets. Only stable faces are stored.
struct PlacementFace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // outward unit normal (points down when resting)
  std::vector<Eigen::Vector3d> polygon;               // convex support polygon on the face plane, CCW about normal
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // object -> resting frame: normal -> -z
  double margin = 0;  // distance of the COM's projection inside the polygon (m)
  double height = 0;  // object-frame origin above the support plane when resting (m)
};

struct PlacementFaces {
  double merge_angle = 0.2;       // rad: a face holds the hull facets within this of its seed facet's normal
  double required_margin = 0.01;  // m: a face is stable when margin >= this
  std::vector<PlacementFace> faces;
};

// Parallel-jaw gripper in its TCP frame: z approach (palm -> fingertips), y closing axis, TCP
// between the finger pads at the contact depth.
struct GripperModel {
  double max_opening = 0.08;                          // m between the pads
  double finger_length = 0.055;                       // along z
  double finger_width = 0.022;                        // along x
  double finger_thickness = 0.027;                    // along y, outward from the pad
  double tip_offset = 0.01;                           // fingertip beyond the TCP along z
  Eigen::Vector3d palm_size{0.07, 0.215, 0.095};      // box, full extents
  Eigen::Vector3d palm_center{0.0, -0.002, -0.0834};  // box center in the TCP frame
  // Pads are checked this far off the contact: the surface may rise this much under a pad (a
  // curved or scanned surface; compliant pads), as the original allowed 3-5 mm of protrusion.
  double contact_tolerance = 0.003;
};

// A DMG node: one surface patch with one contiguous interval of valid finger angles. Angle index k
// means angle k * angle_step about `normal`, measured from `zero_axis`; the interval is
// first_angle, first_angle + 1, ... (angle_count of them, modulo the number of angles).
struct DmgNode {
  int patch = 0;           // surface patch index (< patch_count)
  int facet = 0;           // facet of the patch
  int opposite_patch = 0;  // patch hit by the other finger
  int first_angle = 0;
  int angle_count = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();        // finger-1 contact on the surface
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();         // outward unit patch normal (grasp axis)
  Eigen::Vector3d zero_axis = Eigen::Vector3d::UnitX();      // unit, perpendicular to normal
  Eigen::Vector3d opposite_point = Eigen::Vector3d::Zero();  // finger-2 contact: ray along -normal
  Eigen::Vector3d opposite_normal = Eigen::Vector3d::UnitZ();
};

struct Dmg {
  double angle_step_deg = 10;  // divides 360
  double seed_resolution = 0.01;
  double normal_threshold = 0.07;
  int patch_count = 0;
  std::vector<Eigen::Vector3d> facet_normals, facet_zero_axes;
  std::vector<DmgNode> nodes;
  std::vector<std::array<int, 2>> edges;  // directed; every edge is stored in both directions
  GripperModel gripper;
  int angle_count() const;  // 360 / angle_step_deg
};

struct ObjectArtifact {
  ArtifactHeader header;  // schema fields are filled by save/load
  TriMesh mesh;           // object frame, metres
  MassProperties mass;
  PlacementFaces placement;
  Dmg dmg;
  GraspGraphTable grasp_graph;  // save_object derives it from the DMG when it has no states
};

void save_object(ObjectArtifact artifact, const std::filesystem::path& path);
// Reads the file and refuses it (dmgplace::Error naming the file and its first problems) unless
// check_object finds nothing: every consumer loads through this gate.
ObjectArtifact load_object(const std::filesystem::path& path);
// Reads without the semantic checks (header, schema, checksums and the index ranges the reader
// itself needs are still enforced): for `validate`, which reports every problem, and for tests.
ObjectArtifact read_object_unchecked(const std::filesystem::path& path);
// Every semantic problem, one line each ("element: reason"); empty when sound. O(size of the file).
std::vector<std::string> check_object(const ObjectArtifact& a);
Summary summarize_object(const ObjectArtifact& a);

}  // namespace dmgplace::formats
