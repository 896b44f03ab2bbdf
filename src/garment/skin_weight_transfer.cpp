#include "pb4u/garment/skin_weight_transfer.h"

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {

Eigen::MatrixXd transfer_skin_weights(const Eigen::MatrixXd& V, const Body& body) {
  PointKdTree tree(body.mesh.V);
  Eigen::VectorXi nearest;
  tree.nearest(V, &nearest);
  Eigen::MatrixXd W(V.rows(), body.weights.cols());
  for (Eigen::Index i = 0; i < V.rows(); ++i) W.row(i) = body.weights.row(nearest[i]);
  return W;
}

}  // namespace pb4u
