#pragma once
// The roles of a humanoid skeleton's joints, found by name (CMU BVH conventions: both
// "LeftShoulder/LeftElbow/LeftWrist" and "LeftArm/LeftForeArm/LeftHand" styles), and the
// canonical bind pose the mannequin and garments are built in.
#include <array>
#include <string>
#include <vector>

#include "pb4u/body/skeleton.h"

namespace pb4u {

// Index 0 of each pair is the left side (+x), 1 the right side (-x).
struct HumanoidJoints {
  int root = 0;
  std::vector<int> torso;  // root ... chest: the chain from the root to where the arms branch
  std::vector<int> neck;   // chest ... head (exclusive of chest, inclusive of head)
  int head = -1;
  std::array<int, 2> collar{}, upper_arm{}, elbow{}, wrist{};
  std::array<int, 2> thigh{}, knee{}, ankle{}, toe{-1, -1};  // toe may be missing (-1)
  int chest() const { return torso.back(); }
};

// Throws pb4u::Error naming `where` and the missing joint when the skeleton is not humanoid.
HumanoidJoints find_humanoid_joints(const Skeleton& skeleton, const std::string& where);

// The rest pose with limbs re-aimed: upper arms and forearms in the xy plane at
// `arm_angle_deg` from straight down (45 = A-pose), thighs and shins at `leg_angle_deg`
// outwards, feet and hands keeping their rest orientation relative to the world / forearm.
// The root stays at the origin.
Pose humanoid_bind_pose(const Skeleton& skeleton, const HumanoidJoints& joints,
                        double arm_angle_deg, double leg_angle_deg);

// A 1.7 m humanoid with CMU subject-131 joint names (no fingers), facing +z, y up.
Skeleton builtin_skeleton();

}  // namespace pb4u
