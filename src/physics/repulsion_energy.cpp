#include "pb4u/physics/repulsion_energy.h"

#include <vector>

#include "pb4u/spatial/points_over_faces.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {


RepulsionPairs repulsion_pairs(const torch::Tensor& x, const torch::Tensor& faces, const torch::Tensor& pinned,
                               double radius, double pinned_factor) {
  const Eigen::MatrixXd V = tensor_to_matrix(x);
  const Eigen::MatrixXi F = index_tensor_to_matrix(faces);
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
  RepulsionPairs out;
  out.vertex = torch::tensor(vertex, torch::kInt64).to(x.device());
  out.face = torch::tensor(face, torch::kInt64).to(x.device());
  out.side = torch::tensor(side, torch::kFloat64).to(x.device(), x.scalar_type());
  out.factor = torch::tensor(factor, torch::kFloat64).to(x.device(), x.scalar_type());
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
  // The pairs depend on the state alone: a solver evaluating many x_next for one state finds
  // them once.
  const torch::Tensor& pinned = state.effects.pins ? state.pinned : torch::Tensor();
  if (!(cache_.x.defined() && cache_.x.is_same(state.x) && cache_.x_version == state.x._version() &&
        cache_.pinned.is_same(pinned))) {
    cache_.pairs = repulsion_pairs(state.x, cloth.faces, pinned, config_.radius, config_.pinned_factor);
    cache_.x = state.x;
    cache_.x_version = state.x._version();
    cache_.pinned = pinned;
  }
  return repulsion_energy(x_next, cloth.faces, cache_.pairs, config_.eps, config_.weight);
}

}  // namespace pb4u
