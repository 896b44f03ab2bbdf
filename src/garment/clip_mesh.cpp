#include "pb4u/garment/clip_mesh.h"

#include <algorithm>
#include <map>
#include <vector>

#include "pb4u/mesh/clean.h"

namespace pb4u {

TriMesh clip_mesh(const TriMesh& mesh, const Eigen::VectorXd& g_in) {
  // Exact zeros would create vertices on existing ones; treat them as kept.
  Eigen::VectorXd g = g_in;
  for (Eigen::Index i = 0; i < g.size(); ++i)
    if (g[i] == 0.0) g[i] = 1e-12;
  std::vector<Eigen::RowVector3d> verts;
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) verts.push_back(mesh.V.row(i));
  std::map<std::pair<int, int>, int> cut;
  auto crossing = [&](int a, int b) {
    auto key = std::minmax(a, b);
    auto it = cut.find(key);
    if (it != cut.end()) return it->second;
    const double t = std::clamp(g[a] / (g[a] - g[b]), 1e-3, 1.0 - 1e-3);
    verts.push_back((1 - t) * mesh.V.row(a) + t * mesh.V.row(b));
    const int idx = static_cast<int>(verts.size()) - 1;
    cut.emplace(key, idx);
    return idx;
  };
  std::vector<Eigen::RowVector3i> faces;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    int v[3] = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    bool in[3] = {g[v[0]] > 0, g[v[1]] > 0, g[v[2]] > 0};
    const int count = in[0] + in[1] + in[2];
    if (count == 3) {
      faces.emplace_back(v[0], v[1], v[2]);
      continue;
    }
    if (count == 0) continue;
    // Rotate so that v[0] is the vertex on its own side; orientation is preserved.
    int r = 0;
    for (int k = 0; k < 3; ++k)
      if (in[k] == (count == 1)) r = k;
    const int a = v[r], b = v[(r + 1) % 3], c = v[(r + 2) % 3];
    const int ab = crossing(a, b), ac = crossing(a, c);
    if (count == 1) {
      faces.emplace_back(a, ab, ac);
    } else {
      faces.emplace_back(ab, b, c);
      faces.emplace_back(ab, c, ac);
    }
  }
  TriMesh out;
  out.V.resize(verts.size(), 3);
  for (size_t i = 0; i < verts.size(); ++i) out.V.row(i) = verts[i];
  out.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) out.F.row(f) = faces[f];
  remove_unreferenced_vertices(out);
  return out;
}

}  // namespace pb4u
