#include "mesh_distance.h"

#include <algorithm>
#include <cmath>

namespace pb4u::test {
namespace {

// Ericson, Real-Time Collision Detection, 5.1.5.
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                    const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

double point_mesh_distance(const Eigen::Vector3d& p, const TriMesh& m) {
  double best = 1e300;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d q = closest_on_triangle(p, m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)),
                                                  m.V.row(m.F(f, 2)));
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
