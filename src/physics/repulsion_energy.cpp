#include "pb4u/physics/repulsion_energy.h"

#include <vector>

#include "pb4u/spatial/points_over_faces.h"

namespace pb4u {

namespace {
Eigen::MatrixXd to_matrix(const torch::Tensor& x) {
  auto c = x.detach().to(torch::kCPU, torch::kFloat64).contiguous();
  Eigen::MatrixXd m(c.size(0), 3);
  auto a = c.accessor<double, 2>();
  for (int64_t i = 0; i < c.size(0); ++i)
    for (int k = 0; k < 3; ++k) m(i, k) = a[i][k];
  return m;
}

Eigen::MatrixXi to_faces(const torch::Tensor& faces) {
  auto c = faces.to(torch::kCPU, torch::kInt64).contiguous();
  Eigen::MatrixXi f(c.size(0), 3);
  auto a = c.accessor<int64_t, 2>();
  for (int64_t i = 0; i < c.size(0); ++i)
    for (int k = 0; k < 3; ++k) f(i, k) = static_cast<int>(a[i][k]);
  return f;
}
}  // namespace

RepulsionPairs repulsion_pairs(const torch::Tensor& x, const torch::Tensor& faces, const torch::Tensor& pinned,
                               double radius, double pinned_factor) {
  const Eigen::MatrixXd V = to_matrix(x);
  const Eigen::MatrixXi F = to_faces(faces);
  std::vector<char> is_pinned(static_cast<size_t>(V.rows()), 0);
  if (pinned.defined()) {
    auto p = pinned.to(torch::kCPU, torch::kBool).contiguous();
    for (int64_t i = 0; i < p.size(0); ++i) is_pinned[static_cast<size_t>(i)] = p.data_ptr<bool>()[i];
  }
  std::vector<int64_t> vertex, face;
  std::vector<double> side, factor;
  for (const PointOverFace& pair : points_over_faces(V, V, F, radius, true)) {
    const int v = pair.point, f = pair.face;
    vertex.push_back(v);
    face.push_back(f);
    side.push_back(pair.distance >= 0 ? 1.0 : -1.0);
    const bool pin = is_pinned[static_cast<size_t>(v)] || is_pinned[static_cast<size_t>(F(f, 0))] ||
                     is_pinned[static_cast<size_t>(F(f, 1))] || is_pinned[static_cast<size_t>(F(f, 2))];
    factor.push_back(pin ? pinned_factor : 1.0);
  }
  const auto index = torch::TensorOptions().dtype(torch::kInt64);
  const auto real = torch::TensorOptions().dtype(torch::kFloat64);
  const int64_t P = static_cast<int64_t>(vertex.size());
  RepulsionPairs out;
  out.vertex = torch::from_blob(vertex.data(), {P}, index).clone().to(x.device());
  out.face = torch::from_blob(face.data(), {P}, index).clone().to(x.device());
  out.side = torch::from_blob(side.data(), {P}, real).clone().to(x.device(), x.scalar_type());
  out.factor = torch::from_blob(factor.data(), {P}, real).clone().to(x.device(), x.scalar_type());
  return out;
}

torch::Tensor repulsion_energy(const torch::Tensor& x_next, const torch::Tensor& faces, const RepulsionPairs& pairs,
                               double eps, double weight) {
  if (pairs.size() == 0) return torch::zeros({}, x_next.options());
  auto corners = faces.index_select(0, pairs.face);  // (P, 3)
  auto x0 = x_next.index_select(0, corners.select(1, 0));
  auto x1 = x_next.index_select(0, corners.select(1, 1));
  auto x2 = x_next.index_select(0, corners.select(1, 2));
  auto n = torch::cross(x1 - x0, x2 - x0, 1);
  n = n / n.norm(2, 1, true).clamp_min(1e-12);
  auto d = ((x_next.index_select(0, pairs.vertex) - x0) * n).sum(1);
  auto overlap = (eps - pairs.side * d).clamp_min(0) * pairs.factor;
  return weight * overlap.pow(3).sum();
}

torch::Tensor RepulsionTerm::energy(const torch::Tensor& x_next, const FrameState& state, const ClothGeometry& cloth,
                                    const BodyContact* /*contact*/) const {
  check_positions(x_next, cloth);
  const RepulsionPairs pairs = repulsion_pairs(state.x, cloth.faces, state.effects.pins ? state.pinned : torch::Tensor(),
                                               config_.radius, config_.pinned_factor);
  return repulsion_energy(x_next, cloth.faces, pairs, config_.eps, config_.weight);
}

}  // namespace pb4u
