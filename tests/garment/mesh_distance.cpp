#include "mesh_distance.h"

#include <algorithm>
#include <cmath>

#include "pb4u/mesh/closest_point_on_triangle.h"

namespace pb4u::test {

double point_mesh_distance(const Eigen::Vector3d& p, const TriMesh& m) {
  double best = 1e300;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d q = closest_point_on_triangle(p, m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)),
                                                        m.V.row(m.F(f, 2))).point;
    best = std::min(best, (p - q).squaredNorm());
  }
  return std::sqrt(best);
}

double signed_distance(const Eigen::Vector3d& p, const TriMesh& m) {
  double w = 0;  // solid angle sum (Van Oosterom & Strackee)
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)).transpose() - p;
    const Eigen::Vector3d b = m.V.row(m.F(f, 1)).transpose() - p;
    const Eigen::Vector3d c = m.V.row(m.F(f, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    w += 2.0 * std::atan2(num, den);
  }
  const double d = point_mesh_distance(p, m);
  return w / (4 * M_PI) > 0.5 ? -d : d;
}

double hausdorff_distance(const TriMesh& a, const TriMesh& b) {
  double h = 0;
  for (int i = 0; i < a.num_vertices(); ++i) h = std::max(h, point_mesh_distance(a.V.row(i), b));
  for (int i = 0; i < b.num_vertices(); ++i) h = std::max(h, point_mesh_distance(b.V.row(i), a));
  return h;
}

}  // namespace pb4u::test
