#include "pb4u/physics/additive_ccd.h"

#include <algorithm>
#include <array>

#include "pb4u/physics/primitive_distance.h"

namespace pb4u {
namespace {

using Points = std::array<Eigen::Vector3d, 4>;

// ACCD on four points with the pair's distance function; `bound` gives the upper bound on the
// distance's rate of change from the (mean-removed) displacements.
template <class Distance, class Bound>
double additive_ccd(Points x, Points dx, const Distance& distance, const Bound& bound,
                    const AdditiveCcdOptions& o) {
  // The displacement all four share moves the pair rigidly and cannot close it.
  const Eigen::Vector3d mean = (dx[0] + dx[1] + dx[2] + dx[3]) / 4;
  for (auto& d : dx) d -= mean;
  const double rate = bound(dx);  // m per unit t: no faster can the distance shrink
  if (rate <= 0) return o.t_max;
  double d = distance(x);
  if (d <= o.touching) return 0;
  const double stop = o.keep * d;
  double t = 0, step = (1 - o.keep) * d / rate;
  for (int it = 0; it < o.max_iterations; ++it) {
    for (int i = 0; i < 4; ++i) x[i] += step * dx[i];
    d = distance(x);
    if ((t > 0 && d < stop) || d <= o.touching) return t;
    t += step;
    if (t > o.t_max) return o.t_max;
    step = 0.9 * d / rate;
  }
  return t;
}

}  // namespace

double point_triangle_ccd(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& dp, const Eigen::Vector3d& da,
                          const Eigen::Vector3d& db, const Eigen::Vector3d& dc, const AdditiveCcdOptions& options) {
  return additive_ccd(
      {p, a, b, c}, {dp, da, db, dc},
      [](const Points& x) { return point_triangle_distance(x[0], x[1], x[2], x[3]).distance; },
      [](const Points& d) { return d[0].norm() + std::max({d[1].norm(), d[2].norm(), d[3].norm()}); }, options);
}

double edge_edge_ccd(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                     const Eigen::Vector3d& b1, const Eigen::Vector3d& da0, const Eigen::Vector3d& da1,
                     const Eigen::Vector3d& db0, const Eigen::Vector3d& db1, const AdditiveCcdOptions& options) {
  return additive_ccd(
      {a0, a1, b0, b1}, {da0, da1, db0, db1},
      [](const Points& x) { return edge_edge_distance(x[0], x[1], x[2], x[3]).distance; },
      [](const Points& d) { return std::max(d[0].norm(), d[1].norm()) + std::max(d[2].norm(), d[3].norm()); },
      options);
}

}  // namespace pb4u
