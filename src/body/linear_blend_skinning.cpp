#include "pb4u/body/linear_blend_skinning.h"

#include <algorithm>
#include <numeric>

#include "pb4u/util/error.h"

namespace pb4u {

Eigen::MatrixXd linear_blend_skinning(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                      const JointTransforms& M) {
  if (W.rows() != V.rows() || W.cols() != static_cast<Eigen::Index>(M.size()))
    throw Error("linear_blend_skinning: weights are " + std::to_string(W.rows()) + " x " +
                std::to_string(W.cols()) + ", expected " + std::to_string(V.rows()) + " x " +
                std::to_string(M.size()));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (Eigen::Index j = 0; j < W.cols(); ++j) {
    const Eigen::Matrix3d A = M[j].linear();
    const Eigen::RowVector3d t = M[j].translation().transpose();
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      const double w = W(i, j);
      if (w == 0.0) continue;
      out.row(i) += w * (V.row(i) * A.transpose() + t);
    }
  }
  return out;
}

void limit_and_normalize_weights(Eigen::MatrixXd& W, int max_influences, int fallback_joint) {
  const int J = static_cast<int>(W.cols());
  std::vector<int> order(J);
  for (Eigen::Index i = 0; i < W.rows(); ++i) {
    std::iota(order.begin(), order.end(), 0);
    const int keep = std::min(max_influences, J);
    std::partial_sort(order.begin(), order.begin() + keep, order.end(),
                      [&](int a, int b) { return W(i, a) > W(i, b); });
    for (int k = keep; k < J; ++k) W(i, order[k]) = 0.0;
    for (int j = 0; j < J; ++j) W(i, j) = std::max(W(i, j), 0.0);
    const double sum = W.row(i).sum();
    if (sum > 0) {
      W.row(i) /= sum;
    } else {
      W.row(i).setZero();
      W(i, fallback_joint) = 1.0;
    }
  }
}

}  // namespace pb4u
