#include "pb4u/body/skeleton.h"

#include <algorithm>
#include <cmath>

#include "pb4u/util/error.h"

namespace pb4u {

int Skeleton::find(const std::string& name) const {
  auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

std::vector<int> Skeleton::children(int j) const {
  std::vector<int> out;
  for (int c = 0; c < num_joints(); ++c)
    if (parents[c] == j) out.push_back(c);
  return out;
}

Pose rest_pose(const Skeleton& skeleton) {
  Pose pose;
  pose.rotations.assign(skeleton.num_joints(), Eigen::Quaterniond::Identity());
  return pose;
}

Pose blend_poses(const Pose& a, const Pose& b, double s) {
  Pose p;
  p.root = (1 - s) * a.root + s * b.root;
  p.rotations.resize(a.rotations.size());
  for (size_t j = 0; j < a.rotations.size(); ++j) p.rotations[j] = a.rotations[j].slerp(s, b.rotations[j]).normalized();
  return p;
}

Motion resample_motion(const Motion& motion, double fps) {
  if (!(fps > 0)) throw Error("resample_motion: fps must be positive");
  if (motion.frames.size() < 2 || std::abs(fps - motion.fps) < 1e-9) {
    Motion out = motion;
    out.fps = fps;
    return out;
  }
  Motion out;
  out.fps = fps;
  const double duration = motion.duration();
  const int count = static_cast<int>(std::floor(duration * fps + 1e-6)) + 1;
  const int last = motion.num_frames() - 1;
  for (int k = 0; k < count; ++k) {
    const double s = std::min(k / fps * motion.fps, static_cast<double>(last));
    const int i = std::min(static_cast<int>(std::floor(s)), last);
    const int i1 = std::min(i + 1, last);
    const double a = s - i;
    out.frames.push_back(blend_poses(motion.frames[i], motion.frames[i1], a));
  }
  return out;
}

void validate_skeleton(const Skeleton& s, const std::string& where) {
  const int J = s.num_joints();
  if (J == 0) throw Error(where + ": skeleton has no joints");
  if (static_cast<int>(s.parents.size()) != J || s.offsets.rows() != J || s.offsets.cols() != 3)
    throw Error(where + ": skeleton arrays disagree in size");
  if (s.parents[0] != -1) throw Error(where + ": joint 0 must be the root");
  for (int j = 1; j < J; ++j)
    if (s.parents[j] < 0 || s.parents[j] >= j)
      throw Error(where + ": joint '" + s.names[j] + "' has a parent that does not precede it");
  if (!s.offsets.allFinite()) throw Error(where + ": non-finite joint offset");
}

}  // namespace pb4u
