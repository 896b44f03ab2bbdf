#include "pb4u/spatial/segments_through_surface.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {

bool segment_crosses_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d dir = q - p, e1 = b - a, e2 = c - a, h = dir.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;  // parallel: it cannot pass through the interior
  const double inv = 1 / det;
  const Eigen::Vector3d s = p - a;
  const double u = inv * s.dot(h);
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = inv * dir.dot(qv);
  if (v < 0 || u + v > 1) return false;
  const double t = inv * e2.dot(qv);
  return t >= 0 && t <= 1;
}

std::vector<int> segments_through_surface(const Eigen::MatrixXd& points, const Eigen::MatrixXi& segments,
                                          const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<int> through;
  if (F.rows() == 0 || segments.rows() == 0) return through;
  Eigen::MatrixXd centroids(F.rows(), 3);
  double face_radius = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    centroids.row(f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
    for (int k = 0; k < 3; ++k) face_radius = std::max(face_radius, (V.row(F(f, k)) - centroids.row(f)).norm());
  }
  const PointKdTree tree(centroids);
  auto corner = [&](Eigen::Index f, int k) -> Eigen::Vector3d { return V.row(F(f, k)).transpose(); };
  for (Eigen::Index e = 0; e < segments.rows(); ++e) {
    const Eigen::Vector3d p = points.row(segments(e, 0)).transpose(), q = points.row(segments(e, 1)).transpose();
    const Eigen::Vector3d mid = (p + q) / 2;
    // The crossing point lies within half the segment of its midpoint, and the crossed face's
    // centroid within face_radius of the crossing point.
    const double reach = (q - p).norm() / 2 + face_radius;
    for (int f : tree.within_radius_of(mid, reach * (1 + 1e-12) + 1e-15))
      if (segment_crosses_triangle(p, q, corner(f, 0), corner(f, 1), corner(f, 2))) {
        through.push_back(int(e));
        break;
      }
  }
  return through;
}

}  // namespace pb4u
