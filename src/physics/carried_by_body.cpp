#include "pb4u/physics/carried_by_body.h"

#include <algorithm>

#include "pb4u/physics/primitive_distance.h"

namespace pb4u {
Eigen::MatrixXd carried_by_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                                const std::vector<char>& excluded, double keep) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd largest = Eigen::VectorXd::Zero(n);
  ContactCandidates c = contact_candidates(x, {}, cloth_edges, body, body_motion, keep);
  if (!excluded.empty()) drop_pairs_of(excluded, cloth_edges, &c);
  // points: the pair's cloth points then its body points, as the distance's gradient orders them.
  auto push = [&](const PrimitiveDistance& d, const std::array<int, 4>& points, int cloth_points) {
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
  };
  for (const auto& [v, f] : c.vertex_face)
    push(point_triangle_distance(point_row(x, v), point_row(body.V, body.F(f, 0)), point_row(body.V, body.F(f, 1)),
                                 point_row(body.V, body.F(f, 2))),
         {v, body.F(f, 0), body.F(f, 1), body.F(f, 2)}, 1);
  for (const auto& [e, be] : c.edge_edge) {
    const int a = cloth_edges(e, 0), b = cloth_edges(e, 1);
    push(edge_edge_distance(point_row(x, a), point_row(x, b), point_row(body.V, body.E(be, 0)), point_row(body.V, body.E(be, 1))),
         {a, b, body.E(be, 0), body.E(be, 1)}, 2);
  }
  return out;
}

}  // namespace pb4u
