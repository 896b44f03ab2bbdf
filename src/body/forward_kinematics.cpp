#include "pb4u/body/forward_kinematics.h"

namespace pb4u {

JointTransforms forward_kinematics(const Skeleton& skeleton, const Pose& pose) {
  const int J = skeleton.num_joints();
  JointTransforms G(J);
  for (int j = 0; j < J; ++j) {
    Eigen::Vector3d offset = skeleton.offsets.row(j).transpose();
    if (skeleton.parents[j] < 0) offset += pose.root;
    Eigen::Affine3d local = Eigen::Affine3d::Identity();
    local.translate(offset);
    local.rotate(pose.rotations[j].normalized());
    G[j] = skeleton.parents[j] < 0 ? local : G[skeleton.parents[j]] * local;
  }
  return G;
}

Eigen::MatrixXd joint_positions(const Skeleton& skeleton, const Pose& pose) {
  JointTransforms G = forward_kinematics(skeleton, pose);
  Eigen::MatrixXd P(G.size(), 3);
  for (size_t j = 0; j < G.size(); ++j) P.row(j) = G[j].translation().transpose();
  return P;
}

JointTransforms skinning_transforms(const Skeleton& skeleton, const Pose& bind, const Pose& pose) {
  JointTransforms Gb = forward_kinematics(skeleton, bind);
  JointTransforms G = forward_kinematics(skeleton, pose);
  for (size_t j = 0; j < G.size(); ++j) G[j] = G[j] * Gb[j].inverse(Eigen::Isometry);
  return G;
}

}  // namespace pb4u
