#include "physics_test_util.h"

#include <map>
#include <utility>

namespace pb4u::test {

torch::Tensor positions_tensor(const Eigen::MatrixXd& V, torch::Dtype dtype) {
  torch::Tensor t = torch::empty({V.rows(), 3}, torch::kFloat64);
  for (int i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) t[i][k] = V(i, k);
  return t.to(dtype);
}

torch::Tensor faces_tensor(const Eigen::MatrixXi& F) {
  torch::Tensor t = torch::empty({F.rows(), 3}, torch::kInt64);
  for (int i = 0; i < F.rows(); ++i)
    for (int k = 0; k < 3; ++k) t[i][k] = F(i, k);
  return t;
}

TriMesh icosphere(double radius, int subdivisions, const Eigen::RowVector3d& center) {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::RowVector3d> v = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0},
                                       {0, -1, p}, {0, 1, p},  {0, -1, -p}, {0, 1, -p},
                                       {p, 0, -1}, {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  std::vector<Eigen::RowVector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& x : v) x.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::RowVector3i> g;
    for (const auto& t : f) {
      int a = midpoint(t(0), t(1)), b = midpoint(t(1), t(2)), c = midpoint(t(2), t(0));
      g.push_back({t(0), a, c});
      g.push_back({t(1), b, a});
      g.push_back({t(2), c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
  TriMesh m;
  m.V.resize(v.size(), 3);
  for (size_t i = 0; i < v.size(); ++i) m.V.row(i) = v[i] * radius + center;
  m.F.resize(f.size(), 3);
  for (size_t i = 0; i < f.size(); ++i) m.F.row(i) = f[i];
  return m;
}

BodyFrame static_body(const TriMesh& body, torch::Dtype dtype) {
  BodyFrame b;
  b.vertices = positions_tensor(body.V, dtype);
  b.next_vertices = b.vertices.clone();
  b.faces = faces_tensor(body.F);
  return b;
}

FrameState resting_state(const torch::Tensor& x) {
  FrameState s;
  s.x = x.clone();
  s.x_prev = x.clone();
  s.effects.gravity = s.effects.collision = s.effects.friction = s.effects.pins = false;
  return s;
}

}  // namespace pb4u::test
