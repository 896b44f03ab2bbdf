#include "pb4u/graph/world_edges.h"

#include <Eigen/Core>

#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/util/eigen_tensor.h"

namespace pb4u {


torch::Tensor garment_body_pairs(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                 double radius, bool nearest_only) {
  PointKdTree tree(tensor_to_matrix(body_vertices));
  const Eigen::MatrixXd queries = tensor_to_matrix(x);
  std::vector<std::pair<int, int>> pairs;
  if (nearest_only) {
    Eigen::VectorXi index;
    Eigen::VectorXd d2;
    tree.nearest(queries, &index, &d2);
    for (int i = 0; i < index.size(); ++i)
      if (index(i) >= 0 && d2(i) < radius * radius) pairs.emplace_back(i, index(i));
  } else {
    pairs = tree.within_radius(queries, radius);
  }
  auto out = torch::empty({static_cast<int64_t>(pairs.size()), 2}, torch::kInt64);
  auto a = out.accessor<int64_t, 2>();
  for (size_t i = 0; i < pairs.size(); ++i) {
    a[i][0] = pairs[i].first;
    a[i][1] = pairs[i].second;
  }
  return out;
}

}  // namespace pb4u
