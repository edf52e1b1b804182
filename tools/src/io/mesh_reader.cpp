#include "dmgplace/tools/io/mesh_reader.hpp"

#include "dmgplace/tools/io/input_log.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <system_error>
#include <vector>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::tools {
namespace {

// Appends every triangle below `node`, vertices moved by the accumulated node transform.
void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, std::vector<Eigen::Vector3d>& verts,
             std::vector<Eigen::Vector3i>& tris, const std::string& file) {
  const aiMatrix4x4 world = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    if (node.mMeshes[m] >= scene.mNumMeshes) throw Error(file, "", "cannot read mesh: a node names a missing mesh");
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int base = int(verts.size());
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D p = world * mesh.mVertices[i];
      verts.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines are not surfaces
      tris.emplace_back(base + int(face.mIndices[0]), base + int(face.mIndices[1]), base + int(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], world, verts, tris, file);
}

// assimp 5.2's PLY importer loops forever when its header parser misses the end of the header (found
// by fuzzing: `dmgplace bake-env` hung on a truncated PLY, and on `end_header` glued to a control
// character). It takes every file that starts with "ply" whatever the extension (STL and OBJ go by
// extension), so those must show a plain-text header (no control characters but tab, CR, LF) ending
// in an `end_header` line within their first megabyte before assimp sees them.
void check_ply_header(const std::filesystem::path& path, const std::string& file) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".stl" || ext == ".obj") return;
  std::ifstream in(path, std::ios::binary);
  std::string head(std::size_t(1) << 20, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  if (head.size() < 3 || std::tolower(static_cast<unsigned char>(head[0])) != 'p' ||
      std::tolower(static_cast<unsigned char>(head[1])) != 'l' ||
      std::tolower(static_cast<unsigned char>(head[2])) != 'y')
    return;
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  for (std::size_t pos = 0; pos < head.size();) {
    const std::size_t end = std::min(head.find('\n', pos), head.size());
    const std::size_t first = head.find_first_not_of(" \t\r", pos);
    if (first < end && head.compare(first, 10, "end_header") == 0 &&
        (first + 10 == head.size() || space(head[first + 10])))
      return;
    for (std::size_t i = pos; i < end; ++i)
      if (static_cast<unsigned char>(head[i]) < 0x20 && !space(head[i]))
        throw Error(file, "", "cannot read mesh: control character in the PLY header (corrupt)");
    pos = end + 1;
  }
  throw Error(file, "", "cannot read mesh: PLY header has no end_header line (truncated or corrupt)");
}

}  // namespace

TriMesh read_mesh(const std::filesystem::path& path, const MeshReadOptions& options, MeshReport* report) {
  const std::string file = path.string();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw Error(file, "", "file not found");
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(file, "", "not a regular file");
  const Eigen::Vector3d scale = options.scale * options.axis_scale;
  if (!scale.allFinite() || (scale.array() == 0).any()) throw Error(file, "scale", "scale must be finite and non-zero");

  note_input(path);
  check_ply_header(path, file);

  Assimp::Importer importer;
  // Keep the file's own axes: robot meshes are z-up; assimp would turn Collada z-up into y-up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Fuzzing found broken PLY files that crashed assimp's own post-processing (a SEGV in
  // JoinIdenticalVertices on face indices beyond the vertices; an ai_assert abort in Triangulate,
  // which Debian's build keeps, on faces without corners). So: read without post-processing, reject
  // empty faces and out-of-range indices, recompute each mesh's primitive flags from its faces, and
  // only then post-process.
  const aiScene* scene = importer.ReadFile(file, 0);
  if (!scene) throw Error(file, "", std::string("cannot read mesh: ") + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) throw Error(file, "", "cannot read mesh: the file is incomplete");
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh& mesh = *scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      const unsigned n = face.mNumIndices;
      // A face without corners still reaches here and is what trips Triangulate's assertion.
      if (n == 0 || !face.mIndices) throw Error(file, "", "cannot read mesh: a face without vertices (corrupt)");
      for (unsigned i = 0; i < n; ++i)
        if (face.mIndices[i] >= mesh.mNumVertices)
          throw Error(file, "", "cannot read mesh: a face refers to a vertex that does not exist (corrupt)");
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
  scene = importer.ApplyPostProcessing(aiProcess_JoinIdenticalVertices | aiProcess_Triangulate);
  if (!scene) throw Error(file, "", std::string("cannot read mesh: ") + importer.GetErrorString());
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    throw Error(file, "", "cannot read mesh: the file is incomplete");

  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), verts, tris, file);
  if (tris.empty()) throw Error(file, "", "no triangles in the file (not a surface mesh?)");

  TriMesh mesh;
  mesh.vertices.resize(Eigen::Index(verts.size()), 3);
  for (std::size_t i = 0; i < verts.size(); ++i) mesh.vertices.row(Eigen::Index(i)) = verts[i].cwiseProduct(scale);
  const bool mirrored = scale.prod() < 0;  // a mirror turns faces inside out: swap the winding back
  mesh.triangles.resize(Eigen::Index(tris.size()), 3);
  for (std::size_t f = 0; f < tris.size(); ++f)
    mesh.triangles.row(Eigen::Index(f)) =
        mirrored ? Eigen::RowVector3i(tris[f][0], tris[f][2], tris[f][1]) : Eigen::RowVector3i(tris[f].transpose());

  MeshReport local;
  return clean_mesh(mesh, file, report ? *report : local, options.repair);
}

}  // namespace dmgplace::tools
