#include "pb4u/garment/skin_weight_transfer.h"

#include <cmath>
#include <vector>

#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/lazy_averaging.h"
#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/util/error.h"

namespace pb4u {

Eigen::MatrixXd transfer_skin_weights(const Eigen::MatrixXd& V, const Body& body) {
  PointKdTree tree(body.mesh.V);
  Eigen::VectorXi nearest;
  tree.nearest(V, &nearest);
  Eigen::MatrixXd W(V.rows(), body.weights.cols());
  for (Eigen::Index i = 0; i < V.rows(); ++i) W.row(i) = body.weights.row(nearest[i]);
  return W;
}

Eigen::MatrixXd smooth_skin_weights(const TriMesh& mesh, const Eigen::MatrixXd& W, double length) {
  if (W.rows() != mesh.V.rows()) throw Error("skin weights: one row per garment vertex expected");
  if (!(length > 0) || mesh.F.rows() == 0) return W;
  const double lbar = mean_edge_length(mesh.V, mesh.F);
  if (!(lbar > 0)) return W;
  const auto P = lazy_averaging_matrix<double>(W.rows(), unique_edges(mesh.F));
  const int steps = static_cast<int>(std::ceil(2.0 * (length / lbar) * (length / lbar)));
  Eigen::MatrixXd cur = W, next(W.rows(), W.cols());
  for (int s = 0; s < steps; ++s) {
    next.noalias() = P * cur;
    cur.swap(next);
  }
  for (Eigen::Index i = 0; i < cur.rows(); ++i) {
    const double total = cur.row(i).sum();
    if (total > 0) cur.row(i) /= total;
  }
  return cur;
}

Eigen::MatrixXd inpaint_skin_weights(const TriMesh& mesh, const Eigen::MatrixXd& W,
                                     const std::vector<bool>& known) {
  if (W.rows() != mesh.V.rows() || known.size() != size_t(W.rows()))
    throw Error("skin weights: one row and one flag per garment vertex expected");
  const Eigen::MatrixXi E = unique_edges(mesh.F);
  std::vector<std::vector<int>> neighbours(W.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    neighbours[E(e, 0)].push_back(E(e, 1));
    neighbours[E(e, 1)].push_back(E(e, 0));
  }
  // Unknown rows start as the mean of the known ones, then Gauss-Seidel sweeps of the
  // graph Laplace equation with the known rows fixed, until the largest change is tiny.
  Eigen::MatrixXd cur = W;
  bool any_known = false;
  for (bool k : known) any_known |= k;
  if (!any_known) return W;
  for (int sweep = 0; sweep < 20000; ++sweep) {
    double change = 0;
    for (Eigen::Index i = 0; i < cur.rows(); ++i) {
      if (known[i] || neighbours[i].empty()) continue;
      Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(cur.cols());
      for (int j : neighbours[i]) mean += cur.row(j);
      mean /= double(neighbours[i].size());
      change = std::max(change, (mean - cur.row(i)).cwiseAbs().maxCoeff());
      cur.row(i) = mean;
    }
    if (change < 1e-6) break;
  }
  return cur;
}

Eigen::MatrixXd garment_skin_weights(const TriMesh& mesh, const Body& body, const SkinWeightOptions& options) {
  const double inpaint_distance = options.inpaint_distance;
  PointKdTree tree(body.mesh.V);
  Eigen::VectorXi nearest;
  Eigen::VectorXd d2;
  tree.nearest(mesh.V, &nearest, &d2);
  Eigen::MatrixXd W(mesh.V.rows(), body.weights.cols());
  std::vector<bool> known(mesh.V.rows());
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    W.row(i) = body.weights.row(nearest[i]);
    known[i] = !(inpaint_distance > 0) || (d2[i] <= inpaint_distance * inpaint_distance);
  }
  return smooth_skin_weights(mesh, inpaint_skin_weights(mesh, W, known), options.smoothing);
}

}  // namespace pb4u
