#include "pb4u/body/marching_tetrahedra.h"

#include <algorithm>
#include <array>
#include <unordered_map>
#include <vector>

namespace pb4u {

TriMesh marching_tetrahedra(const Grid& grid, const Eigen::VectorXd& values) {
  const int nx = grid.nx, ny = grid.ny, nz = grid.nz;
  auto id = [&](int i, int j, int k) { return (int64_t(i) * ny + j) * nz + k; };
  // A node value of exactly zero would put a vertex on a grid node shared by many edges and
  // break manifoldness; nudging it outside keeps every crossing strictly inside an edge.
  auto value = [&](int64_t n) {
    const double v = values[n];
    return v == 0.0 ? 1e-12 : v;
  };
  std::unordered_map<int64_t, int> edge_vertex;
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> faces;
  auto position = [&](int64_t n) {
    const int k = static_cast<int>(n % nz), j = static_cast<int>((n / nz) % ny),
              i = static_cast<int>(n / (int64_t(nz) * ny));
    return grid.node(i, j, k);
  };
  auto crossing = [&](int64_t a, int64_t b) {
    if (a > b) std::swap(a, b);
    // Grid nodes fit in 2^31; pack the pair into one key.
    const int64_t key = a * (int64_t(1) << 31) ^ b;
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const double va = value(a), vb = value(b);
    // Clamped so that no vertex coincides with a node (no zero-length edges).
    const double t = std::clamp(va / (va - vb), 1e-3, 1.0 - 1e-3);
    verts.push_back((1 - t) * position(a) + t * position(b));
    const int idx = static_cast<int>(verts.size()) - 1;
    edge_vertex.emplace(key, idx);
    return idx;
  };
  auto emit = [&](int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d n = (verts[b] - verts[a]).cross(verts[c] - verts[a]);
    if (n.dot(outward) < 0) std::swap(b, c);
    faces.emplace_back(a, b, c);
  };
  // Kuhn subdivision: the six paths from corner 000 to 111 along the axis permutations.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int i = 0; i + 1 < nx; ++i)
    for (int j = 0; j + 1 < ny; ++j)
      for (int k = 0; k + 1 < nz; ++k) {
        // Quick reject: all eight corners on one side.
        int neg = 0;
        for (int c = 0; c < 8; ++c)
          neg += value(id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))) < 0;
        if (neg == 0 || neg == 8) continue;
        for (const auto& p : perms) {
          std::array<int, 3> d = {0, 0, 0};
          std::array<int64_t, 4> tet;
          tet[0] = id(i, j, k);
          for (int s = 0; s < 3; ++s) {
            d[p[s]] = 1;
            tet[s + 1] = id(i + d[0], j + d[1], k + d[2]);
          }
          std::array<int64_t, 4> in, out;
          int ni = 0, no = 0;
          for (int64_t n : tet) (value(n) < 0 ? in[ni++] : out[no++]) = n;
          if (ni == 0 || no == 0) continue;
          Eigen::Vector3d cin = Eigen::Vector3d::Zero(), cout = Eigen::Vector3d::Zero();
          for (int s = 0; s < ni; ++s) cin += position(in[s]) / ni;
          for (int s = 0; s < no; ++s) cout += position(out[s]) / no;
          const Eigen::Vector3d outward = cout - cin;
          if (ni == 1 || no == 1) {
            const int64_t lone = ni == 1 ? in[0] : out[0];
            const auto& others = ni == 1 ? out : in;
            emit(crossing(lone, others[0]), crossing(lone, others[1]), crossing(lone, others[2]),
                 outward);
          } else {
            const int a = crossing(in[0], out[0]), b = crossing(in[0], out[1]);
            const int c = crossing(in[1], out[1]), e = crossing(in[1], out[0]);
            emit(a, b, c, outward);
            emit(a, c, e, outward);
          }
        }
      }
  TriMesh mesh;
  mesh.V.resize(verts.size(), 3);
  for (size_t v = 0; v < verts.size(); ++v) mesh.V.row(v) = verts[v].transpose();
  mesh.F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) mesh.F.row(f) = faces[f].transpose();
  return mesh;
}

}  // namespace pb4u
