#pragma once
// A joint hierarchy, a pose of it, and a motion (a pose per frame).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace pb4u {

// Joints in topological order (a parent comes before its children; joint 0 is the root).
// offsets.row(j) is joint j's position in its parent's frame at the rest pose (m); for the
// root it is added to the root translation. The rest pose has identity local rotations.
struct Skeleton {
  std::vector<std::string> names;
  std::vector<int> parents;  // -1 for the root
  Eigen::MatrixXd offsets;   // J x 3, metres

  int num_joints() const { return static_cast<int>(names.size()); }
  // Index of the joint called `name`, or -1.
  int find(const std::string& name) const;
  // Children of joint j, in index order.
  std::vector<int> children(int j) const;
};

// Local joint rotations (relative to the rest pose, in the parent's frame) and the root's
// translation (m).
struct Pose {
  std::vector<Eigen::Quaterniond> rotations;  // J
  Eigen::Vector3d root = Eigen::Vector3d::Zero();
};

// The identity pose: every joint at rest, root at the origin.
Pose rest_pose(const Skeleton& skeleton);

// A pose per frame, sampled at `fps` frames per second.
struct Motion {
  double fps = 30.0;
  std::vector<Pose> frames;
  int num_frames() const { return static_cast<int>(frames.size()); }
  double duration() const { return frames.empty() ? 0.0 : (frames.size() - 1) / fps; }
};

// The pose a fraction s of the way from a to b (s in [0, 1]): root translation linearly,
// each joint's rotation by slerp. a and b must have as many rotations.
Pose blend_poses(const Pose& a, const Pose& b, double s);

// Resamples to `fps` (s^-1): root translation interpolated linearly, rotations by slerp.
// The first frame is kept; the last output frame is the last one at or before the end.
Motion resample_motion(const Motion& motion, double fps);

// Checks that `skeleton` is well formed (parents before children, sizes agree); throws
// pb4u::Error naming `where` otherwise.
void validate_skeleton(const Skeleton& skeleton, const std::string& where);

}  // namespace pb4u
