#include "pb4u/io/frame_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "pb4u/io/hdf5_file.h"
#include "pb4u/io/mesh_io.h"
#include "pb4u/io/point_cache.h"
#include "pb4u/io/usd_cache.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

TriMesh to_mesh(const std::vector<double>& xyz, const std::vector<int>& tris) {
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) m.V(i, k) = xyz[i * 3 + k];
  m.F.resize(static_cast<Eigen::Index>(tris.size() / 3), 3);
  for (Eigen::Index i = 0; i < m.F.rows(); ++i)
    for (int k = 0; k < 3; ++k) m.F(i, k) = tris[i * 3 + k];
  return m;
}

// Fans a polygon (0-based indices) into triangles.
void add_polygon(const std::vector<int>& poly, std::vector<int>* tris) {
  for (size_t k = 2; k < poly.size(); ++k) {
    tris->push_back(poly[0]);
    tris->push_back(poly[k - 1]);
    tris->push_back(poly[k]);
  }
}

TriMesh read_obj_in_order(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail_file(path, "cannot open");
  std::vector<double> xyz;
  std::vector<int> tris;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.size() < 2) continue;
    if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
      std::istringstream words(line.substr(2));
      double x, y, z;
      if (!(words >> x >> y >> z))
        fail_file(path, "line " + std::to_string(number) + ": expected 'v x y z'");
      xyz.insert(xyz.end(), {x, y, z});
    } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
      std::istringstream words(line.substr(2));
      std::vector<int> poly;
      for (std::string corner; words >> corner;) {
        const long index = std::strtol(corner.c_str(), nullptr, 10);
        const long count = static_cast<long>(xyz.size() / 3);
        const long zero_based = index < 0 ? count + index : index - 1;  // OBJ: 1-based, or negative = relative
        if (index == 0 || zero_based < 0)
          fail_file(path, "line " + std::to_string(number) + ": bad vertex index '" + corner + "'");
        poly.push_back(static_cast<int>(zero_based));
      }
      if (poly.size() < 3) fail_file(path, "line " + std::to_string(number) + ": a face needs 3 vertices");
      add_polygon(poly, &tris);
    }
  }
  const int n = static_cast<int>(xyz.size() / 3);
  if (n == 0) fail_file(path, "no vertices");
  for (int i : tris)
    if (i >= n) fail_file(path, "face index " + std::to_string(i + 1) + " beyond the " + std::to_string(n) + " vertices");
  return to_mesh(xyz, tris);
}

// ---- PLY ----

struct PlyProperty {
  std::string name, type;      // scalar type, or the item type of a list
  std::string count_type;      // non-empty for a list
};
struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

int ply_type_size(const std::string& t) {
  static const std::map<std::string, int> sizes{
      {"char", 1},  {"uchar", 1},  {"int8", 1},  {"uint8", 1},   {"short", 2},   {"ushort", 2},
      {"int16", 2}, {"uint16", 2}, {"int", 4},   {"uint", 4},    {"int32", 4},   {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

class PlyReader {
 public:
  PlyReader(std::string path, std::ifstream& in, std::string format)
      : path_(std::move(path)), in_(in), format_(std::move(format)) {}

  double scalar(const std::string& type) {
    if (format_ == "ascii") {
      double v;
      if (!(in_ >> v)) fail_file(path_, "PLY data ends early or holds a non-number");
      return v;
    }
    unsigned char b[8];
    const int size = ply_type_size(type);
    if (!in_.read(reinterpret_cast<char*>(b), size)) fail_file(path_, "PLY data ends early");
    if (format_ == "binary_big_endian") std::reverse(b, b + size);
    if (type == "char" || type == "int8") return static_cast<int8_t>(b[0]);
    if (type == "uchar" || type == "uint8") return b[0];
    if (type == "short" || type == "int16") return load<int16_t>(b);
    if (type == "ushort" || type == "uint16") return load<uint16_t>(b);
    if (type == "int" || type == "int32") return load<int32_t>(b);
    if (type == "uint" || type == "uint32") return load<uint32_t>(b);
    if (type == "float" || type == "float32") return load<float>(b);
    return load<double>(b);
  }

 private:
  template <class T>
  static T load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);  // little-endian host (x86, arm64)
    return v;
  }
  std::string path_;
  std::ifstream& in_;
  std::string format_;
};

TriMesh read_ply_in_order(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, "cannot open");
  std::string line, format;
  std::vector<PlyElement> elements;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) fail_file(path, "not a PLY file (no 'ply' magic)");
  bool ended = false;
  const auto left = fs::file_size(path);
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") {
      ended = true;
      break;
    }
    if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      PlyElement e;
      double count = -1;
      if (!(words >> e.name >> count) || count < 0 || count > double(left))
        fail_file(path, "PLY header: bad element line '" + line + "'");
      e.count = static_cast<size_t>(count);
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) fail_file(path, "PLY header: property before any element");
      PlyProperty p;
      std::string type;
      words >> type;
      if (type == "list") words >> p.count_type >> p.type >> p.name;
      else {
        p.type = type;
        words >> p.name;
      }
      if (!ply_type_size(p.type) || (!p.count_type.empty() && !ply_type_size(p.count_type)))
        fail_file(path, "PLY header: unknown property type in '" + line + "'");
      elements.back().properties.push_back(p);
    }
  }
  if (!ended) fail_file(path, "PLY header has no end_header");
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    fail_file(path, "PLY format '" + format + "' is not ascii or binary");
  PlyReader reader(path, in, format);
  std::vector<double> xyz;
  std::vector<int> tris;
  for (const PlyElement& e : elements) {
    int ix = -1, iy = -1, iz = -1;
    for (size_t k = 0; k < e.properties.size(); ++k) {
      if (e.properties[k].name == "x") ix = int(k);
      if (e.properties[k].name == "y") iy = int(k);
      if (e.properties[k].name == "z") iz = int(k);
    }
    if (e.name == "vertex" && (ix < 0 || iy < 0 || iz < 0)) fail_file(path, "PLY vertices have no x, y, z");
    std::vector<double> values(e.properties.size());
    for (size_t i = 0; i < e.count; ++i) {
      std::vector<int> poly;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& p = e.properties[k];
        if (p.count_type.empty()) {
          values[k] = reader.scalar(p.type);
          continue;
        }
        const double count = reader.scalar(p.count_type);
        if (count < 0 || count > 1e6) fail_file(path, "PLY list of " + std::to_string(count) + " items");
        const bool is_face_list = e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
        for (int c = 0; c < int(count); ++c) {
          const double v = reader.scalar(p.type);
          if (is_face_list) poly.push_back(static_cast<int>(v));
        }
      }
      if (e.name == "vertex") xyz.insert(xyz.end(), {values[ix], values[iy], values[iz]});
      if (e.name == "face") {
        if (poly.size() < 3) fail_file(path, "PLY face " + std::to_string(i) + " has fewer than 3 vertices");
        add_polygon(poly, &tris);
      }
    }
  }
  const int n = static_cast<int>(xyz.size() / 3);
  if (n == 0) fail_file(path, "no vertices");
  for (int i : tris)
    if (i < 0 || i >= n) fail_file(path, "face index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
  return to_mesh(xyz, tris);
}

// ---- sequences ----

// The numbered files a printf pattern ("%04d") or a one-'*' glob names, in numeric order.
std::vector<std::string> numbered_files(const std::string& pattern) {
  std::vector<std::string> files;
  if (pattern.find('%') != std::string::npos) {
    char name[4096];
    int first = -1;
    for (int i = 0; i <= 1; ++i) {  // the sequence starts at 0 or 1
      std::snprintf(name, sizeof name, pattern.c_str(), i);
      if (fs::exists(name)) {
        first = i;
        break;
      }
    }
    if (first < 0) fail_file(pattern, "no file matches (tried frames 0 and 1)");
    for (int i = first;; ++i) {
      std::snprintf(name, sizeof name, pattern.c_str(), i);
      if (!fs::exists(name)) break;
      files.push_back(name);
    }
    return files;
  }
  const auto star = pattern.find('*');
  if (star == std::string::npos || pattern.find('*', star + 1) != std::string::npos)
    fail_file(pattern, "a mesh sequence needs one '*' or a printf number (e.g. garment_%04d.obj)");
  const fs::path dir = fs::path(pattern.substr(0, star)).parent_path();
  const std::string head = pattern.substr(0, star), tail = pattern.substr(star + 1);
  std::vector<std::pair<long, std::string>> numbered;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
    std::string p = entry.path().string();
    if (dir.empty() && p.rfind("./", 0) == 0) p = p.substr(2);
    if (p.size() < head.size() + tail.size() || p.compare(0, head.size(), head) != 0 ||
        p.compare(p.size() - tail.size(), tail.size(), tail) != 0)
      continue;
    const std::string middle = p.substr(head.size(), p.size() - head.size() - tail.size());
    if (middle.empty() || !std::all_of(middle.begin(), middle.end(), ::isdigit)) continue;
    numbered.emplace_back(std::stol(middle), p);
  }
  if (ec) fail_file(dir.string(), "cannot list the folder: " + ec.message());
  if (numbered.empty()) fail_file(pattern, "no file matches");
  std::sort(numbered.begin(), numbered.end());
  for (auto& [n, p] : numbered) files.push_back(p);
  return files;
}

// A 2-D dataset of a rollout group as a matrix, its values converted to T.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> read_rollout_matrix(const Hdf5Group& g,
                                                                     const std::string& name) {
  const std::vector<size_t> dims = g.shape(name);
  if (dims.size() != 2) fail_file(g.file(), g.child_path(name) + ": expected a 2-D dataset");
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(dims[0], dims[1]);
  g.read(name, m.data());
  return m;
}

FrameSequence read_rollout_h5(const std::string& path, const std::string& group) {
  FrameSequence seq;
  const Hdf5Group file = open_hdf5(path);
  if (!file.has(group)) fail_file(path, "has no '" + group + "' group (not a pb4u rollout?)");
  const Hdf5Group g = file.group(group);
  const std::vector<size_t> dims = g.shape("positions");
  if (dims.size() != 3 || dims[2] != 3) fail_file(path, group + "/positions: expected T x n x 3");
  std::vector<double> buf(dims[0] * dims[1] * 3);
  g.read("positions", buf.data());
  for (size_t t = 0; t < dims[0]; ++t) {
    Eigen::MatrixXd x(dims[1], 3);
    for (size_t v = 0; v < dims[1]; ++v)
      for (int k = 0; k < 3; ++k) x(v, k) = buf[(t * dims[1] + v) * 3 + k];
    seq.frames.push_back(std::move(x));
  }
  if (g.has("faces")) seq.faces = read_rollout_matrix<int32_t>(g, "faces");
  if (g.has("rest")) seq.rest = read_rollout_matrix<double>(g, "rest");
  if (g.has("previous")) seq.previous = read_rollout_matrix<double>(g, "previous");
  return seq;
}

// The Mesh prim named like `group` (case ignored); for the garment, also the only Mesh of a file.
FrameSequence read_usd_mesh(const std::string& path, const std::string& group) {
  UsdCache cache = read_usd_cache(path);
  const auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  };
  UsdMeshSequence* found = cache.meshes.size() == 1 && lower(group) == "garment" ? &cache.meshes[0] : nullptr;
  std::string names;
  for (UsdMeshSequence& m : cache.meshes) {
    if (lower(m.name) == lower(group)) found = &m;
    names += (names.empty() ? "" : ", ") + m.name;
  }
  if (!found)
    fail_file(path, "no Mesh prim named '" + group + "' (its meshes: " + (names.empty() ? "none" : names) + ")");
  FrameSequence seq;
  seq.frames = std::move(found->frames);
  seq.faces = std::move(found->faces);
  return seq;
}

}  // namespace

TriMesh read_mesh_in_file_order(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail_file(path, "no such file");
  if (fs::is_directory(path, ec)) fail_file(path, "is a directory, not a file");
  const std::string ext = file_extension(path);
  if (ext == ".obj") return read_obj_in_order(path);
  if (ext == ".ply") return read_ply_in_order(path);
  fail_file(path, "vertex order is kept for OBJ and PLY only (convert other formats to one of them)");
}

FrameSequence read_frame_sequence(const std::string& source, const std::string& group) {
  FrameSequence seq;
  const std::string ext = file_extension(source);
  const bool pattern = source.find('%') != std::string::npos || source.find('*') != std::string::npos;
  if (!pattern && ext == ".pc2") {
    seq.frames = read_pc2(source);
  } else if (!pattern && (ext == ".h5" || ext == ".hdf5")) {
    if (!fs::exists(source)) fail_file(source, "no such file");
    seq = read_rollout_h5(source, group);
  } else if (!pattern && ext == ".usda") {
    seq = read_usd_mesh(source, group);
  } else if (pattern) {
    for (const std::string& file : numbered_files(source)) {
      TriMesh m = read_mesh_in_file_order(file);
      if (seq.frames.empty()) seq.faces = m.F;
      else if (m.V.rows() != seq.frames[0].rows())
        fail_file(file, "frame " + std::to_string(seq.frames.size()) + " has " + std::to_string(m.V.rows()) +
                            " vertices, the first frame " + std::to_string(seq.frames[0].rows()));
      seq.frames.push_back(std::move(m.V));
    }
  } else {
    fail_file(source, "not a frame sequence: give a .pc2, a rollout .h5, a .usda, or a numbered OBJ/PLY pattern "
                      "(garment_%04d.obj or garment_*.obj)");
  }
  if (seq.frames.empty()) fail_file(source, "holds no frames");
  for (size_t t = 0; t < seq.frames.size(); ++t)
    if (!seq.frames[t].allFinite()) fail_file(source, "frame " + std::to_string(t) + " has non-finite positions");
  return seq;
}

}  // namespace pb4u
