#include "pb4u/graph/world_edges.h"

#include <Eigen/Core>

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {

namespace {
Eigen::MatrixXd to_eigen(const torch::Tensor& t) {
  auto c = t.detach().to(torch::kCPU, torch::kFloat64).contiguous();
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(c.data_ptr<double>(), c.size(0), 3);
}
}  // namespace

torch::Tensor garment_body_pairs(const torch::Tensor& x, const torch::Tensor& body_vertices,
                                 double radius, bool nearest_only) {
  PointKdTree tree(to_eigen(body_vertices));
  const Eigen::MatrixXd queries = to_eigen(x);
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
