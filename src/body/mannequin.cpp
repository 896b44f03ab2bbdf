#include "pb4u/body/mannequin.h"

#include <algorithm>
#include <cmath>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/linear_blend_skinning.h"
#include "pb4u/body/marching_tetrahedra.h"
#include "pb4u/mesh/largest_component.h"
#include "pb4u/mesh/remesh.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

double lerp(double a, double b, double t) { return a + (b - a) * t; }

}  // namespace

ImplicitBody humanoid_implicit(const Skeleton& s, const HumanoidJoints& h, const Pose& bind,
                               const MannequinConfig& config, double* stature_out) {
  const MannequinProportions& p = config.proportions;
  const Eigen::MatrixXd P = joint_positions(s, bind);
  auto at = [&](int j) -> Eigen::Vector3d { return P.row(j).transpose(); };
  const double ankle_y = std::min(P(h.ankle[0], 1), P(h.ankle[1], 1));
  const double H = (P(h.head, 1) - ankle_y) / p.head_to_ankle_fraction;
  if (!(H > 0)) throw Error("mannequin: the head is not above the ankles in the bind pose");
  if (stature_out) *stature_out = H;

  ImplicitBody body;
  body.blend = config.blend * H;
  auto add = [&](Eigen::Vector3d a, Eigen::Vector3d b, double ra, double rb, int joint) {
    body.capsules.push_back({a, b, ra * H, rb * H, joint});
  };
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // Torso: horizontal capsules stacked along the spine give an oval cross-section.
  const Eigen::Vector3d pelvis = at(h.root) - Eigen::Vector3d(0, p.pelvis_drop * H, 0);
  add(pelvis - p.pelvis_half_width * H * x, pelvis + p.pelvis_half_width * H * x, p.pelvis_radius,
      p.pelvis_radius, h.root);
  const double y0 = P(h.root, 1), y1 = P(h.chest(), 1);
  for (size_t i = 0; i + 1 < h.torso.size(); ++i) {
    const Eigen::Vector3d a = at(h.torso[i]), b = at(h.torso[i + 1]);
    if ((b - a).norm() < 1e-6) continue;
    const Eigen::Vector3d mid = 0.5 * (a + b);
    const double f = std::clamp((mid.y() - y0) / std::max(y1 - y0, 1e-6), 0.0, 1.0);
    const double t = std::clamp(2.0 * f - 1.0, 0.0, 1.0);
    const double half = lerp(p.waist_half_width, p.chest_half_width, t);
    const double r = lerp(p.waist_radius, p.chest_radius, t);
    add(mid - half * H * x, mid + half * H * x, r, r, h.torso[i]);
    add(a, b, p.waist_radius, p.waist_radius, h.torso[i]);
  }
  const Eigen::Vector3d chest = at(h.chest());
  add(chest - p.chest_half_width * H * x, chest + p.chest_half_width * H * x, p.chest_radius,
      p.chest_radius, h.chest());
  // Neck and head.
  int prev = h.chest();
  for (int j : h.neck) {
    if ((at(j) - at(prev)).norm() > 1e-6) add(at(prev), at(j), p.neck_radius, p.neck_radius, prev);
    prev = j;
  }
  const Eigen::Vector3d head = at(h.head) + Eigen::Vector3d(0, p.head_lift * H, 0);
  add(head, head, p.head_radius, p.head_radius, h.head);
  for (int k = 0; k < 2; ++k) {
    add(chest, at(h.upper_arm[k]), p.collar_radius, p.collar_radius, h.collar[k]);
    add(at(h.upper_arm[k]), at(h.elbow[k]), p.upper_arm_radius, p.elbow_radius, h.upper_arm[k]);
    add(at(h.elbow[k]), at(h.wrist[k]), p.elbow_radius, p.wrist_radius, h.elbow[k]);
    const Eigen::Vector3d hand_dir = (at(h.wrist[k]) - at(h.elbow[k])).normalized();
    add(at(h.wrist[k]), at(h.wrist[k]) + p.hand_length * H * hand_dir, p.hand_radius,
        p.hand_radius, h.wrist[k]);
    add(at(h.thigh[k]), at(h.knee[k]), p.thigh_radius, p.knee_radius, h.thigh[k]);
    add(at(h.knee[k]), at(h.ankle[k]), p.knee_radius, p.ankle_radius, h.knee[k]);
    // Feet point along +z whatever the skeleton's toe joint says, so every body faces +z.
    const Eigen::Vector3d ankle = at(h.ankle[k]);
    Eigen::Vector3d toe = h.toe[k] >= 0 ? at(h.toe[k]) : ankle;
    toe.z() = std::max(toe.z(), ankle.z() + 0.06 * H);
    add(ankle, toe, p.foot_radius, p.foot_radius, h.ankle[k]);
    add(toe, toe + Eigen::Vector3d(0, 0, p.toe_length * H), p.toe_radius, p.toe_radius,
        h.toe[k] >= 0 ? h.toe[k] : h.ankle[k]);
  }
  return body;
}

Eigen::MatrixXd capsule_skin_weights(const Eigen::MatrixXd& V, const ImplicitBody& body,
                                     int num_joints, double falloff, int max_influences) {
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(V.rows(), num_joints);
  Eigen::VectorXd d(num_joints);
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    d.setConstant(1e30);
    const Eigen::Vector3d v = V.row(i).transpose();
    for (const Capsule& c : body.capsules) d[c.joint] = std::min(d[c.joint], c.distance(v));
    const double dmin = d.minCoeff();
    for (int j = 0; j < num_joints; ++j)
      if (d[j] < 1e29) W(i, j) = std::exp(-(d[j] - dmin) / falloff);
  }
  limit_and_normalize_weights(W, max_influences);
  return W;
}

Body build_mannequin(const std::string& name, const Skeleton& skeleton,
                     const MannequinConfig& config) {
  validate_skeleton(skeleton, name);
  const HumanoidJoints joints = find_humanoid_joints(skeleton, name);
  Body body;
  body.name = name;
  body.skeleton = skeleton;
  body.bind = humanoid_bind_pose(skeleton, joints, config.arm_angle_deg, config.leg_angle_deg);
  body.bind.root.setZero();
  double stature = 0;
  ImplicitBody solid = humanoid_implicit(skeleton, joints, body.bind, config, &stature);
  const Grid grid = grid_around(solid.bounds(), config.cell_size, 2 * config.cell_size + solid.blend);
  TriMesh raw = largest_component(marching_tetrahedra(grid, sample_implicit(solid, grid)));
  body.mesh = remesh_to_triangle_count(raw, 2 * config.vertices - 4);
  body.weights = capsule_skin_weights(body.mesh.V, solid, skeleton.num_joints(),
                                      config.weight_falloff * stature, config.max_influences);
  const double lift = -body.mesh.V.col(1).minCoeff();
  body.mesh.V.col(1).array() += lift;
  body.bind.root.y() += lift;
  return body;
}

ImplicitBody mannequin_implicit(const Body& body, const MannequinConfig& config) {
  const HumanoidJoints joints = find_humanoid_joints(body.skeleton, body.name);
  return humanoid_implicit(body.skeleton, joints, body.bind, config);
}

}  // namespace pb4u
