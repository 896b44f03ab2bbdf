#include "pb4u/spatial/points_over_faces.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {

std::vector<PointOverFace> points_over_faces(const Eigen::MatrixXd& points, const Eigen::MatrixXd& V,
                                             const Eigen::MatrixXi& F, double radius, bool same_mesh) {
  std::vector<PointOverFace> out;
  if (F.rows() == 0 || points.rows() == 0) return out;
  Eigen::MatrixXd centroid(F.rows(), 3);
  double reach = 0;  // the farthest corner from its face's centroid
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    centroid.row(f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
    for (int k = 0; k < 3; ++k) reach = std::max(reach, (V.row(F(f, k)) - centroid.row(f)).norm());
  }
  // A point within `radius` of a face's plane and over the face is within radius + reach of
  // its centroid.
  const PointKdTree tree(centroid);
  for (const auto& [i, f] : tree.within_radius(points, radius + reach)) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (same_mesh && (i == a || i == b || i == c)) continue;
    const Eigen::Vector3d e1 = V.row(b) - V.row(a), e2 = V.row(c) - V.row(a), p = points.row(i) - V.row(a);
    const Eigen::Vector3d n = e1.cross(e2);
    const double n2 = n.squaredNorm();
    if (!(n2 > 0)) continue;
    const double d = p.dot(n) / std::sqrt(n2);
    if (!(std::abs(d) < radius)) continue;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), p1 = p.dot(e1), p2 = p.dot(e2);
    const double den = d11 * d22 - d12 * d12;
    const double beta = (d22 * p1 - d12 * p2) / den, gamma = (d11 * p2 - d12 * p1) / den;
    if (beta < 0 || gamma < 0 || beta + gamma > 1) continue;
    out.push_back({i, f, d});
  }
  return out;
}

}  // namespace pb4u
