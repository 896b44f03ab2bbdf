#include "pb4u/body/humanoid.h"

#include <algorithm>
#include <cmath>

#include "pb4u/body/bvh.h"
#include "pb4u/body/forward_kinematics.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

int find_any(const Skeleton& s, const std::vector<std::string>& names) {
  for (const auto& n : names) {
    int j = s.find(n);
    if (j >= 0) return j;
  }
  return -1;
}

int require(const Skeleton& s, const std::vector<std::string>& names, const std::string& where) {
  int j = find_any(s, names);
  if (j < 0)
    throw Error(where + ": skeleton has no joint named " + names.front() +
                " (a humanoid with CMU-style joint names is needed)");
  return j;
}

std::vector<int> path_to_root(const Skeleton& s, int j) {
  std::vector<int> path;
  for (; j >= 0; j = s.parents[j]) path.push_back(j);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace

HumanoidJoints find_humanoid_joints(const Skeleton& s, const std::string& where) {
  HumanoidJoints h;
  const char* side[2] = {"Left", "Right"};
  for (int k = 0; k < 2; ++k) {
    const std::string p = side[k];
    h.elbow[k] = require(s, {p + "Elbow", p + "ForeArm"}, where);
    h.wrist[k] = require(s, {p + "Wrist", p + "Hand"}, where);
    h.knee[k] = require(s, {p + "Knee", p + "Leg"}, where);
    h.ankle[k] = require(s, {p + "Ankle", p + "Foot"}, where);
    h.toe[k] = find_any(s, {p + "Toe", p + "ToeBase"});
    h.upper_arm[k] = s.parents[h.elbow[k]];
    h.thigh[k] = s.parents[h.knee[k]];
    h.collar[k] = s.parents[h.upper_arm[k]];
    if (h.upper_arm[k] < 0 || h.collar[k] < 0 || h.thigh[k] < 0 ||
        s.parents[h.wrist[k]] != h.elbow[k] || s.parents[h.ankle[k]] != h.knee[k])
      throw Error(where + ": " + p + " arm or leg joints are not a chain");
  }
  h.head = require(s, {"Head"}, where);
  // The chest is the deepest common ancestor of both upper arms.
  std::vector<int> a = path_to_root(s, h.upper_arm[0]), b = path_to_root(s, h.upper_arm[1]);
  size_t n = 0;
  while (n < a.size() && n < b.size() && a[n] == b[n]) ++n;
  if (n == 0) throw Error(where + ": arms do not share an ancestor");
  h.torso.assign(a.begin(), a.begin() + n);
  h.root = h.torso.front();
  std::vector<int> head_path = path_to_root(s, h.head);
  if (head_path.size() <= n || head_path[n - 1] != h.chest())
    throw Error(where + ": the head does not hang off the chest (" + s.names[h.chest()] + ")");
  h.neck.assign(head_path.begin() + n, head_path.end());
  return h;
}

Pose humanoid_bind_pose(const Skeleton& s, const HumanoidJoints& h, double arm_angle_deg,
                        double leg_angle_deg) {
  Pose pose = rest_pose(s);
  const double arm = arm_angle_deg * M_PI / 180.0, leg = leg_angle_deg * M_PI / 180.0;
  auto aim = [&](int j, int child, const Eigen::Vector3d& dir) {
    Eigen::Vector3d bone = s.offsets.row(child).transpose();
    if (bone.norm() < 1e-9) return;
    JointTransforms G = forward_kinematics(s, pose);
    Eigen::Quaterniond parent(G[s.parents[j]].rotation());
    Eigen::Quaterniond global = Eigen::Quaterniond::FromTwoVectors(bone, dir);
    pose.rotations[j] = (parent.conjugate() * global).normalized();
  };
  auto keep_world = [&](int j) {
    JointTransforms G = forward_kinematics(s, pose);
    pose.rotations[j] = Eigen::Quaterniond(G[s.parents[j]].rotation()).conjugate().normalized();
  };
  for (int k = 0; k < 2; ++k) {
    const double sx = k == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d arm_dir(sx * std::sin(arm), -std::cos(arm), 0.0);
    const Eigen::Vector3d leg_dir(sx * std::sin(leg), -std::cos(leg), 0.0);
    aim(h.upper_arm[k], h.elbow[k], arm_dir);
    aim(h.elbow[k], h.wrist[k], arm_dir);
    aim(h.thigh[k], h.knee[k], leg_dir);
    aim(h.knee[k], h.ankle[k], leg_dir);
    keep_world(h.ankle[k]);
  }
  return pose;
}

namespace {
// CMU subject 131's hierarchy (fingers and thumbs dropped); scaled to 1.7 m on load.
const char* kBuiltinBvh = R"(HIERARCHY
ROOT Hips { OFFSET 0 0 0 CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
 JOINT LHipJoint { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
  JOINT LeftHip { OFFSET 0.070429 -0.092715 0.040477 CHANNELS 3 Zrotation Yrotation Xrotation
   JOINT LeftKnee { OFFSET 0.140731 -0.386656 0 CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT LeftAnkle { OFFSET 0.133642 -0.367180 0 CHANNELS 3 Zrotation Yrotation Xrotation
     JOINT LeftToe { OFFSET 0.008365 -0.022983 0.124964 CHANNELS 3 Zrotation Yrotation Xrotation
      End Site { OFFSET 0 0 0.064059 } } } } } }
 JOINT RHipJoint { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
  JOINT RightHip { OFFSET -0.070429 -0.092715 0.040477 CHANNELS 3 Zrotation Yrotation Xrotation
   JOINT RightKnee { OFFSET -0.140731 -0.386656 0 CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT RightAnkle { OFFSET -0.133642 -0.367180 0 CHANNELS 3 Zrotation Yrotation Xrotation
     JOINT RightToe { OFFSET -0.008365 -0.022983 0.124964 CHANNELS 3 Zrotation Yrotation Xrotation
      End Site { OFFSET 0 0 0.064059 } } } } } }
 JOINT lowerback { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
  JOINT Chest { OFFSET -0.001301 0.112132 0.000180 CHANNELS 3 Zrotation Yrotation Xrotation
   JOINT Chest2 { OFFSET -0.000405 0.112342 -0.000301 CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT lowerneck { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
     JOINT Neck { OFFSET 0.000054 0.090883 0.006038 CHANNELS 3 Zrotation Yrotation Xrotation
      JOINT Head { OFFSET -0.000598 0.090268 0.000743 CHANNELS 3 Zrotation Yrotation Xrotation
       End Site { OFFSET 0 0.092175 0 } } } }
    JOINT LeftCollar { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
     JOINT LeftShoulder { OFFSET 0.172369 0.083022 -0.000958 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftElbow { OFFSET 0 -0.239947 0 CHANNELS 3 Zrotation Xrotation Yrotation
       JOINT LeftWrist { OFFSET 0 -0.184906 0 CHANNELS 3 Zrotation Xrotation Yrotation
        End Site { OFFSET 0 -0.067 0 } } } } }
    JOINT RightCollar { OFFSET 0 0 0 CHANNELS 3 Zrotation Yrotation Xrotation
     JOINT RightShoulder { OFFSET -0.172369 0.083022 -0.000958 CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT RightElbow { OFFSET 0 -0.239947 0 CHANNELS 3 Zrotation Xrotation Yrotation
       JOINT RightWrist { OFFSET 0 -0.184906 0 CHANNELS 3 Zrotation Xrotation Yrotation
        End Site { OFFSET 0 -0.067 0 } } } } } } } } }
MOTION
Frames: 1
Frame Time: 0.0333333
)";
// Subject 131 stands about 1.49 m; this brings the built-in figure to 1.7 m.
constexpr double kBuiltinScale = 1.7 / 1.49;
}  // namespace

Skeleton builtin_skeleton() {
  std::string text = kBuiltinBvh;
  const int channels = 6 + 3 * 24;
  for (int i = 0; i < channels; ++i) text += "0 ";
  return parse_bvh(text, "<builtin skeleton>", kBuiltinScale).skeleton;
}

}  // namespace pb4u
