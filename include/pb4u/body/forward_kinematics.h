#pragma once
// Joint transforms of a posed skeleton and the matrices that skin a mesh with them.
#include <Eigen/Geometry>
#include <vector>

#include "pb4u/body/skeleton.h"

namespace pb4u {

using JointTransforms = std::vector<Eigen::Affine3d>;

// Global (world) transform of every joint: G_j = G_parent * T(offset_j) * R_j; the root
// adds pose.root to its offset.
JointTransforms forward_kinematics(const Skeleton& skeleton, const Pose& pose);

// J x 3 world joint positions (m) of the pose.
Eigen::MatrixXd joint_positions(const Skeleton& skeleton, const Pose& pose);

// Skinning matrices M_j = G_j(pose) * G_j(bind)^-1: they move a point bound at the bind
// pose along with joint j.
JointTransforms skinning_transforms(const Skeleton& skeleton, const Pose& bind, const Pose& pose);

}  // namespace pb4u
