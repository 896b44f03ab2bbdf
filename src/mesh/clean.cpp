#include "pb4u/mesh/clean.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <unordered_map>

#include "pb4u/mesh/geometry.h"

namespace pb4u {
namespace {

struct CellHash {
  size_t operator()(const std::array<int64_t, 3>& c) const {
    return static_cast<size_t>(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
  }
};

}  // namespace

int weld_vertices(TriMesh& mesh, double relative_tolerance) {
  const int n = mesh.num_vertices();
  if (n == 0) return 0;
  auto box = bounding_box(mesh.V);
  double tol = relative_tolerance * (box.row(1) - box.row(0)).norm();
  if (!(tol > 0)) tol = 1e-12;
  // Hash grid with cell = tol: a partner lies in one of the 27 neighbouring cells.
  std::unordered_map<std::array<int64_t, 3>, std::vector<int>, CellHash> grid;
  std::vector<int> remap(n);
  std::vector<int> kept;
  auto cell_of = [&](int v) {
    return std::array<int64_t, 3>{static_cast<int64_t>(std::floor(mesh.V(v, 0) / tol)),
                                  static_cast<int64_t>(std::floor(mesh.V(v, 1) / tol)),
                                  static_cast<int64_t>(std::floor(mesh.V(v, 2) / tol))};
  };
  for (int v = 0; v < n; ++v) {
    auto c = cell_of(v);
    int match = -1;
    for (int dx = -1; dx <= 1 && match < 0; ++dx)
      for (int dy = -1; dy <= 1 && match < 0; ++dy)
        for (int dz = -1; dz <= 1 && match < 0; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (int w : it->second)
            if ((mesh.V.row(kept[w]) - mesh.V.row(v)).norm() <= tol) {
              match = w;
              break;
            }
        }
    if (match >= 0) {
      remap[v] = match;
    } else {
      remap[v] = static_cast<int>(kept.size());
      grid[c].push_back(static_cast<int>(kept.size()));
      kept.push_back(v);
    }
  }
  Eigen::MatrixXd V(kept.size(), 3);
  for (size_t i = 0; i < kept.size(); ++i) V.row(i) = mesh.V.row(kept[i]);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = remap[mesh.F(f, k)];
  mesh.V = std::move(V);
  return n - static_cast<int>(kept.size());
}

int remove_degenerate_faces(TriMesh& mesh, double min_area) {
  Eigen::VectorXd A = face_areas(mesh.V, mesh.F);
  std::set<std::array<int, 3>> seen;
  std::vector<int> keep;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    std::array<int, 3> s{mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    std::sort(s.begin(), s.end());
    if (s[0] == s[1] || s[1] == s[2]) continue;
    if (!(A(f) > min_area)) continue;
    if (!seen.insert(s).second) continue;
    keep.push_back(f);
  }
  int removed = mesh.num_faces() - static_cast<int>(keep.size());
  Eigen::MatrixXi F(keep.size(), 3);
  for (size_t i = 0; i < keep.size(); ++i) F.row(i) = mesh.F.row(keep[i]);
  mesh.F = std::move(F);
  return removed;
}

int remove_unreferenced_vertices(TriMesh& mesh) {
  std::vector<int> remap(mesh.num_vertices(), -1);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) remap[mesh.F(f, k)] = 0;
  int next = 0;
  for (int& r : remap)
    if (r == 0) r = next++;
  int removed = mesh.num_vertices() - next;
  if (removed == 0) return 0;
  Eigen::MatrixXd V(next, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (remap[v] >= 0) V.row(remap[v]) = mesh.V.row(v);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = remap[mesh.F(f, k)];
  mesh.V = std::move(V);
  return removed;
}

Eigen::MatrixXi triangulate_polygons(const std::vector<std::vector<int>>& polygons) {
  std::vector<std::array<int, 3>> tris;
  for (const auto& p : polygons)
    for (size_t k = 1; k + 1 < p.size(); ++k) tris.push_back({p[0], p[k], p[k + 1]});
  Eigen::MatrixXi F(tris.size(), 3);
  for (size_t i = 0; i < tris.size(); ++i) F.row(i) << tris[i][0], tris[i][1], tris[i][2];
  return F;
}

CleanReport clean_mesh(TriMesh& mesh, double relative_weld_tolerance) {
  CleanReport r;
  r.welded_vertices = weld_vertices(mesh, relative_weld_tolerance);
  r.removed_faces = remove_degenerate_faces(mesh);
  r.removed_vertices = remove_unreferenced_vertices(mesh);
  return r;
}

}  // namespace pb4u
