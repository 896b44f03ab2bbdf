#include "pb4u/physics/carried_by_body.h"

#include <algorithm>

#include "pb4u/physics/pair_distances.h"

namespace pb4u {
Eigen::MatrixXd carried_by_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                                const std::vector<char>& excluded, double keep) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd largest = Eigen::VectorXd::Zero(n);
  ContactCandidates c = contact_candidates(x, {}, cloth_edges, body, body_motion, keep);
  if (!excluded.empty()) drop_pairs_of(excluded, cloth_edges, &c);
  for_each_pair_distance(x, cloth_edges, body, c,
                         [&](const PrimitiveDistance& d, const std::array<int, 4>& points, int cloth_points) {
    double approach = 0;  // m: how much the body's motion shortens the distance (to first order)
    Eigen::Vector3d motion = Eigen::Vector3d::Zero();  // of the body's closest point
    for (int i = cloth_points; i < 4; ++i) {
      approach -= d.gradient.segment<3>(3 * i).dot(body_motion.row(points[i]));
      motion -= d.weights(i) * body_motion.row(points[i]).transpose();
    }
    const double amount = approach - std::max(d.distance - keep, 0.0);
    if (!(amount > 0)) return;
    const Eigen::Vector3d carried = std::min(amount / approach, 1.0) * motion;
    for (int i = 0; i < cloth_points; ++i)
      if (carried.norm() > largest(points[i])) {
        largest(points[i]) = carried.norm();
        out.row(points[i]) = carried.transpose();
      }
  });
  return out;
}

}  // namespace pb4u
