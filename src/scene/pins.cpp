#include "pb4u/scene/pins.h"

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {

std::vector<int> top_band_vertices(const Eigen::MatrixXd& x, double top_band) {
  std::vector<int> pinned;
  if (x.rows() == 0) return pinned;
  const double top = x.col(1).maxCoeff();
  for (int i = 0; i < x.rows(); ++i)
    if (x(i, 1) >= top - top_band) pinned.push_back(i);
  return pinned;
}

std::vector<Eigen::MatrixXd> nearest_body_vertex_pin_targets(const Eigen::MatrixXd& x0,
                                                             const std::vector<Eigen::MatrixXd>& body) {
  std::vector<Eigen::MatrixXd> targets;
  if (body.empty()) return targets;
  Eigen::VectorXi nearest;
  PointKdTree(body[0]).nearest(x0, &nearest);
  for (const Eigen::MatrixXd& b : body) {
    Eigen::MatrixXd x = x0;
    for (Eigen::Index i = 0; i < x0.rows(); ++i) x.row(i) += b.row(nearest(i)) - body[0].row(nearest(i));
    targets.push_back(std::move(x));
  }
  return targets;
}

}  // namespace pb4u
