// The mannequin: closed, outward, genus 0, human-sized, feet on the ground, facing +z.
#include <gtest/gtest.h>

#include "pb4u/body/bvh.h"
#include "pb4u/body/mannequin.h"
#include "pb4u/body/marching_tetrahedra.h"
#include "pb4u/body/procedural_motion.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/topology.h"
#include "pb4u/util/error.h"

#include <random>

using namespace pb4u;

namespace {

double signed_volume(const TriMesh& m) {
  double v = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

void expect_closed_genus0(const TriMesh& m) {
  const Eigen::VectorXi counts = edge_face_counts(m.F);
  EXPECT_EQ((counts.array() != 2).count(), 0) << "every edge must have two faces";
  EXPECT_TRUE(check_manifold(m.F, m.num_vertices()).oriented());
  const int euler = m.num_vertices() - static_cast<int>(counts.size()) + m.num_faces();
  EXPECT_EQ(euler, 2) << "genus 0 means V - E + F = 2";
  int components = 0;
  connected_components(m.F, m.num_vertices(), &components);
  EXPECT_EQ(components, 1);
}

MannequinConfig small_config() {
  MannequinConfig c;
  c.vertices = 700;
  c.cell_size = 0.012;
  return c;
}

}  // namespace

TEST(MarchingTetrahedra, SphereIsClosedOutwardAndAccurate) {
  ImplicitBody ball;
  ball.capsules.push_back({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.5, 0.5, 0});
  const Grid grid = grid_around(ball.bounds(), 0.05, 0.1);
  const TriMesh m = marching_tetrahedra(grid, sample_implicit(ball, grid));
  expect_closed_genus0(m);
  // Vertices interpolate the exact distance linearly, so they sit within a cell of r.
  const Eigen::VectorXd r = m.V.rowwise().norm();
  EXPECT_LT((r.array() - 0.5).abs().maxCoeff(), 0.01);
  EXPECT_NEAR(signed_volume(m), 4.0 / 3.0 * M_PI * 0.125, 0.02);
}

TEST(Mannequin, BuiltinIsClosedOutwardGenus0AndHumanSized) {
  const Body body = build_mannequin("builtin", builtin_skeleton(), small_config());
  expect_closed_genus0(body.mesh);
  EXPECT_GT(signed_volume(body.mesh), 0.03);  // outward; a person is ~0.06 m^3
  EXPECT_NEAR(body.mesh.num_vertices(), 700, 70);
  const Eigen::Matrix<double, 2, 3> box = bounding_box(body.mesh.V);
  EXPECT_NEAR(box(0, 1), 0.0, 1e-12);  // feet at y = 0
  EXPECT_NEAR(box(1, 1), 1.7, 0.1);
  // Facing +z: the feet stick out forwards, not backwards.
  double front = -1e9, back = 1e9;
  for (int i = 0; i < body.mesh.num_vertices(); ++i)
    if (body.mesh.V(i, 1) < 0.05) front = std::max(front, body.mesh.V(i, 2)), back = std::min(back, body.mesh.V(i, 2));
  EXPECT_GT(front, 2.0 * std::abs(back));
  // Weights: rows sum to one, and LBS at the bind pose is the identity.
  EXPECT_LT((body.weights.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  EXPECT_LT((pose_body(body, body.bind) - body.mesh.V).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Mannequin, WeightsAreSmoothAcrossEdges) {
  const Body body = build_mannequin("builtin", builtin_skeleton(), small_config());
  const Eigen::MatrixXi E = unique_edges(body.mesh.F);
  const Eigen::VectorXd lengths = edge_lengths(body.mesh.V, E);
  double worst = 0;  // largest weight change per metre
  for (int e = 0; e < E.rows(); ++e)
    worst = std::max(worst, (body.weights.row(E(e, 0)) - body.weights.row(E(e, 1))).cwiseAbs().maxCoeff() / lengths[e]);
  // No hard seams: the softmax over 1-Lipschitz capsule distances changes at most ~1/falloff
  // per metre (a seam would jump by up to 1 over one edge, ~30 / m here).
  const double falloff = small_config().weight_falloff * 1.7;
  EXPECT_LT(worst, 1.0 / falloff);
  // A walking pose moves the body without tearing it: edge lengths stay within 3x.
  const Motion walk = procedural_motion(body.skeleton, body.bind, MotionParams{});
  const Eigen::MatrixXd Vp = pose_body(body, walk.frames[10]);
  const Eigen::VectorXd l0 = edge_lengths(body.mesh.V, E), l1 = edge_lengths(Vp, E);
  EXPECT_LT((l1.array() / l0.array()).maxCoeff(), 3.0);
}

TEST(Mannequin, BvhSkeletonDrivesItsOwnMannequin) {
  const BvhFile bvh = read_bvh(std::string(PB4U_MOCAP_DATA) + "/cmu_131_01.bvh", 30.0);
  const Body body = build_mannequin("cmu", bvh.skeleton, small_config());
  expect_closed_genus0(body.mesh);
  EXPECT_GT(signed_volume(body.mesh), 0.0);
  const Eigen::MatrixXd V = pose_body(body, bvh.motion.frames[100]);
  EXPECT_TRUE(V.allFinite());
  Skeleton tail;
  tail.names = {"Root", "Tail"};
  tail.parents = {-1, 0};
  tail.offsets = Eigen::MatrixXd::Zero(2, 3);
  EXPECT_THROW(build_mannequin("tail", tail, small_config()), Error);
}

TEST(Mannequin, ImplicitFieldIsOneLipschitzSoOffsetsNeverPenetrate) {
  const Skeleton s = builtin_skeleton();
  const HumanoidJoints h = find_humanoid_joints(s, "builtin");
  const MannequinConfig config;
  const ImplicitBody body =
      humanoid_implicit(s, h, humanoid_bind_pose(s, h, 45.0, 4.0), config);
  const Eigen::Matrix<double, 2, 3> box = body.bounds();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Vector3d p, q;
    for (int a = 0; a < 3; ++a) p[a] = box(0, a) + u(rng) * (box(1, a) - box(0, a));
    q = p + 0.05 * Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    worst = std::max(worst, std::abs(body.value(p) - body.value(q)) / (p - q).norm());
  }
  // Tapered capsules exceed 1 by sqrt(1 + taper^2) - 1, well under 1 % here.
  EXPECT_LT(worst, 1.01);
  EXPECT_GT(worst, 0.5);  // the samples do see the field change
}
