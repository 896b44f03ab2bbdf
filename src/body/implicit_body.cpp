#include "pb4u/body/implicit_body.h"

#include <algorithm>
#include <cmath>

namespace pb4u {

double Capsule::distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm() - (ra + t * (rb - ra));
}

double smooth_min(double a, double b, double k) {
  if (k <= 0) return std::min(a, b);
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double ImplicitBody::value(const Eigen::Vector3d& p) const {
  double v = 1e30;
  for (const Capsule& c : capsules) v = smooth_min(v, c.distance(p), blend);
  return v;
}

Eigen::Matrix<double, 2, 3> ImplicitBody::bounds() const {
  Eigen::Matrix<double, 2, 3> box;
  box.row(0).setConstant(1e30);
  box.row(1).setConstant(-1e30);
  for (const Capsule& c : capsules) {
    const double r = std::max(c.ra, c.rb);
    for (const Eigen::Vector3d& p : {c.a, c.b}) {
      box.row(0) = box.row(0).cwiseMin((p.array() - r).matrix().transpose());
      box.row(1) = box.row(1).cwiseMax((p.array() + r).matrix().transpose());
    }
  }
  return box;
}

Grid grid_around(const Eigen::Matrix<double, 2, 3>& bounds, double cell, double margin) {
  Grid g;
  g.cell = cell;
  g.origin = bounds.row(0).transpose().array() - margin;
  const Eigen::Vector3d extent = (bounds.row(1) - bounds.row(0)).transpose().array() + 2 * margin;
  g.nx = static_cast<int>(std::ceil(extent.x() / cell)) + 1;
  g.ny = static_cast<int>(std::ceil(extent.y() / cell)) + 1;
  g.nz = static_cast<int>(std::ceil(extent.z() / cell)) + 1;
  return g;
}

Eigen::VectorXd sample_implicit(const ImplicitBody& body, const Grid& grid, double exact_up_to) {
  // Far from every capsule the exact value is irrelevant; `far` only has to be positive
  // and larger than anything a neighbouring node within reach could hold.
  const double reach = body.blend + 2.0 * grid.cell + std::max(exact_up_to, 0.0);
  const double far = 4.0 * reach;
  Eigen::VectorXd values = Eigen::VectorXd::Constant(grid.size(), far);
  for (const Capsule& c : body.capsules) {
    const double r = std::max(c.ra, c.rb) + reach;
    Eigen::Vector3d lo = c.a.cwiseMin(c.b).array() - r, hi = c.a.cwiseMax(c.b).array() + r;
    auto index_range = [&](int axis, int n, int* i0, int* i1) {
      *i0 = std::max(0, static_cast<int>(std::floor((lo[axis] - grid.origin[axis]) / grid.cell)));
      *i1 = std::min(n - 1, static_cast<int>(std::ceil((hi[axis] - grid.origin[axis]) / grid.cell)));
    };
    int x0, x1, y0, y1, z0, z1;
    index_range(0, grid.nx, &x0, &x1);
    index_range(1, grid.ny, &y0, &y1);
    index_range(2, grid.nz, &z0, &z1);
    for (int i = x0; i <= x1; ++i)
      for (int j = y0; j <= y1; ++j)
        for (int k = z0; k <= z1; ++k) {
          const Eigen::Index n = (Eigen::Index(i) * grid.ny + j) * grid.nz + k;
          const double d = c.distance(grid.node(i, j, k));
          values[n] = values[n] >= far ? d : smooth_min(values[n], d, body.blend);
        }
  }
  return values;
}

}  // namespace pb4u
