#include "pb4u/physics/carried_by_body.h"

#include <algorithm>

#include "pb4u/physics/pair_distances.h"

namespace pb4u {
namespace {

// `ride`: a pair nearer than `keep` rides with the body unless the body leaves it faster than
// this share of the motion of the pair's fastest body point: a body sliding past the cloth, or
// turning under it, closes the gap at second order, which a first-order approach of zero misses.
constexpr double kLeavingShare = 0.25;
// Passes over the half-spaces a point's move must reach (several pairs pushing one point).
constexpr int kHalfSpacePasses = 8;

// A cloth point's move must reach `needed` along `normal` (the pair's distance gradient).
struct HalfSpace {
  int point;
  Eigen::Vector3d normal;
  double needed;
};

}  // namespace

Eigen::MatrixXd carried_by_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                                const std::vector<char>& excluded, double keep, bool ride) {
  const Eigen::Index n = x.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, 3);
  Eigen::VectorXd largest = Eigen::VectorXd::Zero(n);
  std::vector<HalfSpace> half_spaces;
  ContactCandidates c = contact_candidates(x, {}, cloth_edges, body, body_motion, keep);
  if (!excluded.empty()) drop_pairs_of(excluded, cloth_edges, &c);
  for_each_pair_distance(x, cloth_edges, body, c,
                         [&](const PrimitiveDistance& d, const std::array<int, 4>& points, int cloth_points) {
    double approach = 0;  // m: how much the body's motion shortens the distance (to first order)
    Eigen::Vector3d motion = Eigen::Vector3d::Zero();  // of the body's closest point
    double fastest = 0;  // m: the longest move of the pair's body points
    for (int i = cloth_points; i < 4; ++i) {
      approach -= d.gradient.segment<3>(3 * i).dot(body_motion.row(points[i]));
      motion -= d.weights(i) * body_motion.row(points[i]).transpose();
      fastest = std::max(fastest, body_motion.row(points[i]).norm());
    }
    const double amount = approach - std::max(d.distance - keep, 0.0);
    const bool riding = ride && d.distance < keep && fastest > 0 && approach > -kLeavingShare * fastest;
    if (!riding && !(amount > 0)) return;
    const double share = riding ? 1.0 : std::min(amount / approach, 1.0);
    for (int i = 0; i < cloth_points; ++i) {
      // A vertex moves with the closest point of its face; with `ride` each end of a cloth edge
      // with the body edge where it projects onto it, so that the edge turns as the body edge
      // does (`push`: with the closest point, as a vertex).
      Eigen::Vector3d carried = share * motion;
      if (ride && cloth_points == 2) {
        const Eigen::Vector3d b0 = point_row(body.V, points[2]), b1 = point_row(body.V, points[3]);
        const double length2 = (b1 - b0).squaredNorm();
        const double s =
            length2 > 0 ? std::clamp((point_row(x, points[i]) - b0).dot(b1 - b0) / length2, 0.0, 1.0) : 0.0;
        carried = share * ((1 - s) * point_row(body_motion, points[2]) + s * point_row(body_motion, points[3]));
      }
      const Eigen::Vector3d g = d.gradient.segment<3>(3 * i);
      if (ride && g.norm() > 0) {  // the move along the pair's normal, and what is missing of `keep`
        const Eigen::Vector3d normal = g.normalized();
        half_spaces.push_back({points[i], normal, normal.dot(carried) + std::max(keep - d.distance, 0.0)});
      }
      if (carried.norm() > largest(points[i])) {
        largest(points[i]) = carried.norm();
        out.row(points[i]) = carried.transpose();
      }
    }
  });
  // A point in several pairs takes the largest move; with `ride` then what each other pair
  // still needs along its normal (cyclic projection onto the half-spaces).
  for (int pass = 0; pass < kHalfSpacePasses; ++pass)
    for (const HalfSpace& h : half_spaces) {
      const double have = h.normal.dot(out.row(h.point).transpose());
      if (have < h.needed) out.row(h.point) += (h.needed - have) * h.normal.transpose();
    }
  return out;
}

}  // namespace pb4u
