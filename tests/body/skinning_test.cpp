// Skeleton, forward kinematics, linear blend skinning, procedural motions.
#include <gtest/gtest.h>

#include <random>

#include "pb4u/body/forward_kinematics.h"
#include "pb4u/body/humanoid.h"
#include "pb4u/body/linear_blend_skinning.h"
#include "pb4u/body/procedural_motion.h"
#include "pb4u/body/skeleton.h"
#include "pb4u/util/error.h"

using namespace pb4u;

namespace {

Eigen::MatrixXd random_weights(int n, int J, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd W(n, J);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < J; ++j) W(i, j) = u(rng);
  limit_and_normalize_weights(W, 4);
  return W;
}

}  // namespace

TEST(Skinning, BindPoseReproducesRestShape) {
  const Skeleton s = builtin_skeleton();
  const HumanoidJoints h = find_humanoid_joints(s, "builtin");
  const Pose bind = humanoid_bind_pose(s, h, 45.0, 4.0);
  std::mt19937 rng(1);
  const Eigen::MatrixXd V = Eigen::MatrixXd::Random(50, 3);
  const Eigen::MatrixXd W = random_weights(50, s.num_joints(), rng);
  EXPECT_LT((linear_blend_skinning(V, W, skinning_transforms(s, bind, bind)) - V).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Skinning, RigidRootMotionMovesEverythingRigidly) {
  const Skeleton s = builtin_skeleton();
  const Pose rest = rest_pose(s);
  Pose moved = rest;
  moved.root = Eigen::Vector3d(0.3, -0.1, 2.0);
  moved.rotations[0] = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const Eigen::MatrixXd V = Eigen::MatrixXd::Random(20, 3);
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(20, s.num_joints());
  W.col(0).setOnes();
  const Eigen::MatrixXd out = linear_blend_skinning(V, W, skinning_transforms(s, rest, moved));
  // A quarter turn about y: (x, y, z) -> (z, y, -x), then the translation.
  for (int i = 0; i < 20; ++i) {
    const Eigen::RowVector3d expect(V(i, 2) + 0.3, V(i, 1) - 0.1, -V(i, 0) + 2.0);
    EXPECT_LT((out.row(i) - expect).norm(), 1e-12);
  }
  // Pairwise distances are preserved.
  EXPECT_NEAR((out.row(3) - out.row(7)).norm(), (V.row(3) - V.row(7)).norm(), 1e-12);
}

TEST(Skinning, WeightsAreLimitedAndNormalised) {
  std::mt19937 rng(2);
  const Eigen::MatrixXd W = random_weights(30, 10, rng);
  for (int i = 0; i < 30; ++i) {
    EXPECT_NEAR(W.row(i).sum(), 1.0, 1e-12);
    EXPECT_LE((W.row(i).array() > 0).count(), 4);
  }
  Eigen::MatrixXd bad = Eigen::MatrixXd::Random(5, 3);
  EXPECT_THROW(linear_blend_skinning(Eigen::MatrixXd::Zero(4, 3), bad, JointTransforms(3)), Error);
}

TEST(Skeleton, BlendedPosesRunFromOneToTheOtherAlongTheShortestTurn) {
  Pose a, b;
  a.rotations = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))};
  b.rotations = {Eigen::Quaterniond(Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitY())),
                 Eigen::Quaterniond(Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitX()))};
  a.root = Eigen::Vector3d(0, 1, 0);
  b.root = Eigen::Vector3d(2, 1, -4);
  for (double s : {0.0, 0.25, 1.0}) {
    const Pose p = blend_poses(a, b, s);
    EXPECT_LT((p.root - ((1 - s) * a.root + s * b.root)).norm(), 1e-15);
    // About Y from 0 to 1.2 rad, about X from 0.2 to -0.6 rad: the angles in proportion.
    EXPECT_NEAR(p.rotations[0].angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(1.2 * s, Eigen::Vector3d::UnitY()))), 0, 1e-12);
    EXPECT_NEAR(p.rotations[1].angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(0.2 - 0.8 * s, Eigen::Vector3d::UnitX()))), 0, 1e-12);
  }
}

TEST(Humanoid, BuiltinSkeletonIsHumanAndBindPoseAimsLimbs) {
  const Skeleton s = builtin_skeleton();
  const HumanoidJoints h = find_humanoid_joints(s, "builtin");
  const Pose bind = humanoid_bind_pose(s, h, 45.0, 0.0);
  const Eigen::MatrixXd P = joint_positions(s, bind);
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector3d arm = (P.row(h.elbow[k]) - P.row(h.upper_arm[k])).transpose().normalized();
    EXPECT_NEAR(arm.y(), -std::sqrt(0.5), 1e-9);
    EXPECT_NEAR(std::abs(arm.x()), std::sqrt(0.5), 1e-9);
    EXPECT_GT(arm.x() * (k == 0 ? 1 : -1), 0);  // left is +x
    const Eigen::Vector3d shin = (P.row(h.ankle[k]) - P.row(h.knee[k])).transpose().normalized();
    EXPECT_NEAR(shin.y(), -1.0, 1e-9);
  }
  // Bone lengths are what the skeleton says, whatever the pose.
  for (int j = 1; j < s.num_joints(); ++j)
    EXPECT_NEAR((P.row(j) - P.row(s.parents[j])).norm(), s.offsets.row(j).norm(), 1e-9);
  Skeleton broken = s;
  broken.names[s.find("LeftKnee")] = "Knee2";
  EXPECT_THROW(find_humanoid_joints(broken, "x"), Error);
}

TEST(ProceduralMotion, EveryKindIsFiniteAndWalkingMovesForward) {
  const Skeleton s = builtin_skeleton();
  const Pose bind = humanoid_bind_pose(s, find_humanoid_joints(s, "b"), 45.0, 4.0);
  std::mt19937 rng(3);
  for (const std::string& kind : procedural_motion_names()) {
    MotionParams p = random_motion_params(kind, 40, MotionRanges{}, rng);
    const Motion m = procedural_motion(s, bind, p);
    ASSERT_EQ(m.num_frames(), 40);
    EXPECT_DOUBLE_EQ(m.fps, 30.0);
    for (const Pose& pose : m.frames) {
      EXPECT_TRUE(pose.root.allFinite()) << kind;
      for (const auto& q : pose.rotations) EXPECT_NEAR(q.norm(), 1.0, 1e-9) << kind;
    }
  }
  MotionParams walk;
  walk.frames = 31;
  const Motion m = procedural_motion(s, bind, walk);
  // About 1.2 m/s forward along +z over one second.
  EXPECT_GT(m.frames.back().root.z() - m.frames.front().root.z(), 0.8);
  walk.kind = "moonwalk";
  EXPECT_THROW(procedural_motion(s, bind, walk), Error);
}
