#include "pb4u/io/mesh_io.h"

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

std::string file_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace {

// A PLY header longer than this is not one (comments included).
constexpr int kMaxPlyHeaderLines = 10000;

void check_readable(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail_file(path, "no such file");
  if (fs::is_directory(path, ec)) fail_file(path, "is a directory, not a file");
  if (fs::file_size(path, ec) == 0) fail_file(path, "file is empty");
}

// assimp trusts a PLY header: counts of billions of vertices in a small file cost minutes and
// gigabytes, a header without end_header is searched to the end, and a vertex element without
// x, y, z aborts the process in its post-processing (all found by mesh_fuzz). The header is
// checked first: known keywords only, x/y/z on the vertices, and no count above the bytes left
// (every element takes at least one byte in any PLY encoding).
void check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line.size() < 3) return;
  std::string magic = line.substr(0, 3);
  std::transform(magic.begin(), magic.end(), magic.begin(), [](unsigned char c) { return std::tolower(c); });
  if (magic != "ply") return;  // not PLY (assimp's own check ignores case: "Ply", found by mesh_fuzz)
  const uintmax_t size = fs::file_size(path);
  std::vector<std::pair<std::string, uintmax_t>> elements;
  std::set<std::string> vertex_properties;
  for (int lines = 2; std::getline(in, line) && lines <= kMaxPlyHeaderLines; ++lines) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword, name;
    words >> keyword;
    if (keyword == "end_header") {
      const auto body = static_cast<uintmax_t>(std::max<std::streamoff>(0, in.tellg()));
      const uintmax_t left = size - std::min(body, size);
      for (const auto& [element, count] : elements)
        if (count > left)
          fail_file(path, "PLY header declares " + std::to_string(count) + " " + element + " elements but only " +
                              std::to_string(left) + " bytes follow");
      const bool has_vertices = std::any_of(elements.begin(), elements.end(),
                                            [](const auto& e) { return e.first == "vertex"; });
      for (const char* axis : {"x", "y", "z"})
        if (has_vertices && !vertex_properties.count(axis))
          fail_file(path, std::string("PLY vertices have no '") + axis + "' property");
      return;
    }
    if (keyword == "element") {
      double count = 0;
      if (!(words >> name >> count) || !(count >= 0))
        fail_file(path, "PLY header line " + std::to_string(lines) + ": expected 'element <name> <count>'");
      elements.emplace_back(name, count > 1e18 ? uintmax_t(1e18) : static_cast<uintmax_t>(count));
    } else if (keyword == "property") {
      std::string last;
      while (words >> name) last = name;
      if (elements.empty() || last.empty())
        fail_file(path, "PLY header line " + std::to_string(lines) + ": a property outside an element");
      if (elements.back().first == "vertex") vertex_properties.insert(last);
    } else if (!keyword.empty() && keyword != "format" && keyword != "comment" && keyword != "obj_info") {
      fail_file(path, "PLY header line " + std::to_string(lines) + ": unknown keyword '" + keyword.substr(0, 32) + "'");
    }
  }
  fail_file(path, "PLY header has no end_header line within " + std::to_string(kMaxPlyHeaderLines) + " lines");
}

void append_node(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent,
                 std::vector<Eigen::Vector3d>& verts, std::vector<std::vector<int>>& polys,
                 const std::string& path) {
  aiMatrix4x4 world = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* m = scene->mMeshes[node->mMeshes[i]];
    if (!(m->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
    const int base = static_cast<int>(verts.size());
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      aiVector3D p = world * m->mVertices[v];
      verts.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices < 3) continue;  // points and lines are not cloth
      std::vector<int> poly(face.mNumIndices);
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= m->mNumVertices)
          fail_file(path, "face " + std::to_string(f) + " references vertex " +
                              std::to_string(face.mIndices[k]) + " of " +
                              std::to_string(m->mNumVertices));
        poly[k] = base + static_cast<int>(face.mIndices[k]);
      }
      polys.push_back(std::move(poly));
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    append_node(scene, node->mChildren[c], world, verts, polys, path);
}

}  // namespace

TriMesh read_mesh(const std::string& path, const MeshReadOptions& options, CleanReport* report) {
  check_readable(path);
  check_ply_header(path);  // whatever the extension: assimp picks its PLY reader by content too
  Assimp::Importer importer;
  // Only triangulation and validation: welding is ours (tolerance relative to the bbox).
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_ValidateDataStructure | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "unknown format";
    fail_file(path, "cannot read mesh: " + why);
  }
  std::vector<Eigen::Vector3d> verts;
  std::vector<std::vector<int>> polys;
  append_node(scene, scene->mRootNode, aiMatrix4x4(), verts, polys, path);
  if (polys.empty()) fail_file(path, "contains no triangles");
  TriMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (size_t i = 0; i < verts.size(); ++i) {
    if (!verts[i].allFinite())
      fail_file(path, "vertex " + std::to_string(i) + " has a non-finite coordinate");
    mesh.V.row(i) = verts[i];
  }
  mesh.F = triangulate_polygons(polys);
  if (options.clean) {
    CleanReport r = clean_mesh(mesh, options.relative_weld_tolerance);
    if (report) *report = r;
    if (mesh.num_faces() == 0) fail_file(path, "every triangle is degenerate");
  }
  return mesh;
}

void write_obj(const std::string& path, const TriMesh& mesh) {
  AtomicFile file(path);
  auto& out = file.stream();
  char buf[96];
  out << "# pb4u\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
    out << buf;
  }
  for (int f = 0; f < mesh.num_faces(); ++f)
    out << "f " << mesh.F(f, 0) + 1 << ' ' << mesh.F(f, 1) + 1 << ' ' << mesh.F(f, 2) + 1 << '\n';
  file.commit();
}

void write_ply(const std::string& path, const TriMesh& mesh) {
  AtomicFile file(path, /*binary=*/true);
  auto& out = file.stream();
  out << "ply\nformat binary_little_endian 1.0\ncomment pb4u\n"
      << "element vertex " << mesh.num_vertices() << "\nproperty float x\nproperty float y\n"
      << "property float z\nelement face " << mesh.num_faces()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    float p[3] = {static_cast<float>(mesh.V(v, 0)), static_cast<float>(mesh.V(v, 1)),
                  static_cast<float>(mesh.V(v, 2))};
    out.write(reinterpret_cast<const char*>(p), sizeof p);
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    uint8_t n = 3;
    int32_t idx[3] = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    out.write(reinterpret_cast<const char*>(&n), 1);
    out.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  file.commit();
}

void write_mesh(const std::string& path, const TriMesh& mesh) {
  std::string ext = file_extension(path);
  if (ext == ".obj") return write_obj(path, mesh);
  if (ext == ".ply") return write_ply(path, mesh);
  fail_file(path, "cannot write '" + ext + "' meshes (use .obj or .ply)");
}

}  // namespace pb4u
