#include "pb4u/mesh/rest_frames.h"

#include <Eigen/Geometry>
#include <cmath>

namespace pb4u {

Eigen::MatrixXd rest_dm_inverse(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(F.rows(), 4);
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d x0 = V.row(F(f, 0)), x1 = V.row(F(f, 1)), x2 = V.row(F(f, 2));
    Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0;
    double l1 = e1.norm();
    Eigen::Vector3d n = e1.cross(e2);
    double nn = n.norm();
    if (l1 <= 0 || nn <= 0) continue;
    Eigen::Vector3d u = e1 / l1;
    Eigen::Vector3d v = (n / nn).cross(u);
    // Dm = [[l1, e2.u], [0, e2.v]] with e2.v > 0 for a non-degenerate face.
    double a = l1, b = e2.dot(u), d = e2.dot(v);
    double det = a * d;
    if (!(std::abs(det) > 0)) continue;
    out.row(f) << d / det, -b / det, 0.0, a / det;
  }
  return out;
}

}  // namespace pb4u
