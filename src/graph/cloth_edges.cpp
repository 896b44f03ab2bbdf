#include "pb4u/graph/cloth_edges.h"

#include <vector>

#include "pb4u/graph/graph_options.h"
#include "pb4u/spatial/points_over_faces.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {

GraphEdges build_cloth_edges(const torch::Tensor& x, const torch::Tensor& x_coast, const torch::Tensor& faces,
                             double radius, int64_t rows) {
  const Eigen::MatrixXd V = tensor_to_matrix(x);
  const Eigen::MatrixXi F = index_tensor_to_matrix(faces);
  std::vector<int64_t> senders, receivers, face_of;
  for (const PointOverFace& pair : points_over_faces(V, V, F, radius, true)) {
    int nearest = F(pair.face, 0);
    for (int k = 1; k < 3; ++k)
      if ((V.row(F(pair.face, k)) - V.row(pair.point)).squaredNorm() < (V.row(nearest) - V.row(pair.point)).squaredNorm())
        nearest = F(pair.face, k);
    senders.push_back(pair.point);
    receivers.push_back(nearest);
    face_of.push_back(pair.face);
  }
  const auto dev = x.device();
  GraphEdges out;
  out.senders = torch::tensor(senders, torch::kInt64).to(dev);
  out.receivers = torch::tensor(receivers, torch::kInt64).to(dev);
  auto face = torch::tensor(face_of, torch::kInt64).to(dev);
  auto corners = faces.to(dev).index_select(0, face);
  auto x0 = x.index_select(0, corners.select(1, 0));
  auto n = torch::cross(x.index_select(0, corners.select(1, 1)) - x0, x.index_select(0, corners.select(1, 2)) - x0, 1);
  n = n / n.norm(2, 1, true).clamp_min(1e-12);
  auto d = ((x.index_select(0, out.senders) - x0) * n).sum(1, true).abs();
  auto dp = x.index_select(0, out.receivers) - x.index_select(0, out.senders);
  auto dq = x_coast.index_select(0, out.receivers) - x_coast.index_select(0, out.senders);
  out.features = torch::cat({dp, dp.norm(2, 1, true), dq, dq.norm(2, 1, true), d * n, d}, 1);
  TORCH_CHECK(out.features.size(1) == kClothEdgeFeatureDim, "cloth edges: feature width");
  out.sender_rows = group_rows(out.senders, rows);
  out.receiver_rows = group_rows(out.receivers, rows);
  return out;
}

}  // namespace pb4u
