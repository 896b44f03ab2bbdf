// Inference-time strain limiting against closed forms: a single stretched edge ends exactly at
// the limit about its midpoint (or about its pinned end), a mesh within the limit comes back
// untouched, compressed edges stay compressed, and a violently stretched grid ends within the
// limit everywhere.
#include <gtest/gtest.h>

#include <random>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/physics/strain_limiting.h"
#include "pb4u/util/eigen_tensor.h"
#include "test_util.h"

namespace pb4u {
namespace {

// One triangle with a unit edge 0-1; x stretches that edge to `length` along x.
struct Triangle {
  TriMesh rest;
  GarmentTopology topology;
  Triangle() {
    rest.V.resize(3, 3);
    rest.V << 0, 0, 0, 1, 0, 0, 0.5, 0, 0.8;
    rest.F.resize(1, 3);
    rest.F << 0, 1, 2;
    topology = build_garment_topology(rest);
  }
};

TEST(StrainLimiting, AStretchedEdgeEndsAtTheLimitAboutItsMidpoint) {
  Triangle t;
  Eigen::MatrixXd x = t.rest.V;
  x.row(0) << -0.5, 0, 0;
  x.row(1) << 1.5, 0, 0;  // edge 0-1 at 2x its rest length; the others 1.6x and 1.7x
  x.row(2) << 0.5, 0, 0.8;
  const StrainLimitResult r = limit_edge_strain(matrix_to_tensor(x), t.topology, torch::Tensor(), 0.1);
  const Eigen::MatrixXd y = tensor_to_matrix(r.x);
  EXPECT_LE(r.max_strain, 0.1 * 1.01);
  EXPECT_GT(r.iterations, 0);
  for (auto [i, j] : {std::pair{0, 1}, {1, 2}, {2, 0}}) {
    const double rest = (t.rest.V.row(i) - t.rest.V.row(j)).norm();
    EXPECT_LE((y.row(i) - y.row(j)).norm(), 1.1 * rest * 1.01) << "edge " << i << "-" << j;
  }
  // Symmetric about x = 0.5: the midpoint stays, and nothing leaves the plane y = 0.
  EXPECT_NEAR(0.5 * (y(0, 0) + y(1, 0)), 0.5, 1e-9);
  EXPECT_NEAR(y.col(1).cwiseAbs().maxCoeff(), 0.0, 1e-12);
}

TEST(StrainLimiting, APinnedEndStaysAndTheFreeEndTakesTheCorrection) {
  Triangle t;
  Eigen::MatrixXd x = t.rest.V;
  x.row(1) << 3, 0, 0;  // edge 0-1 at 3x; vertex 2 keeps its edge to 0 at rest
  torch::Tensor pinned = torch::zeros({3}, torch::kBool);
  pinned[0] = true;
  pinned[2] = true;
  const Eigen::MatrixXd y =
      tensor_to_matrix(limit_edge_strain(matrix_to_tensor(x), t.topology, pinned, 0.25).x);
  EXPECT_EQ(y.row(0), x.row(0));
  EXPECT_EQ(y.row(2), x.row(2));
  // Vertex 1 is held by two pinned neighbours: both its edges end within the limit.
  EXPECT_LE(y.row(1).norm(), 1.25 * 1.0025 + 1e-9);
  EXPECT_LE((y.row(1) - y.row(2)).norm(), 1.25 * (t.rest.V.row(1) - t.rest.V.row(2)).norm() * 1.0025 + 1e-9);
}

TEST(StrainLimiting, ACompressedOrSlightlyStretchedMeshIsReturnedAsItIs) {
  const TriMesh rest = test::grid_mesh(6, 0.6);
  const GarmentTopology topology = build_garment_topology(rest);
  // Shrunk to 70% (every edge compressed) and stretched 5% along z: within a 10% limit.
  Eigen::MatrixXd x = rest.V * 0.7;
  x.col(2) = rest.V.col(2) * 1.05;
  const torch::Tensor in = matrix_to_tensor(x);
  const StrainLimitResult r = limit_edge_strain(in, topology, torch::Tensor(), 0.1);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_TRUE(r.x.is_same(in)) << "nothing over the limit: the input itself comes back";
  EXPECT_NEAR(r.max_strain, 0.05, 1e-6);
  // Off: the same, whatever the strain.
  const torch::Tensor far = in * 10;
  EXPECT_TRUE(limit_edge_strain(far, topology, torch::Tensor(), 0).x.is_same(far));
}

TEST(StrainLimiting, AViolentlyStretchedGridEndsWithinTheLimit) {
  const TriMesh rest = test::grid_mesh(12, 0.6);
  const GarmentTopology topology = build_garment_topology(rest);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.05);  // 5 cm against 5 cm edges
  Eigen::MatrixXd x = rest.V;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int c = 0; c < 3; ++c) x(i, c) += noise(rng);
  x.row(0) += Eigen::RowVector3d(-1, 0.5, 0);  // and one corner thrown a metre away
  const StrainLimitResult before = limit_edge_strain(matrix_to_tensor(x), topology, torch::Tensor(), 1e9);
  ASSERT_GT(before.max_strain, 10) << "the test's grid must start far beyond the limit";
  const StrainLimitResult r = limit_edge_strain(matrix_to_tensor(x), topology, torch::Tensor(), 0.1, 200);
  EXPECT_LT(r.iterations, 200);
  EXPECT_LE(r.max_strain, 0.1 * 1.01);
  const Eigen::MatrixXd y = tensor_to_matrix(r.x);
  ASSERT_TRUE(y.allFinite());
  for (int64_t e = 0; e < topology.senders.size(0); ++e) {
    const int64_t i = topology.senders[e].item<int64_t>(), j = topology.receivers[e].item<int64_t>();
    EXPECT_LE((y.row(i) - y.row(j)).norm(), 1.1 * 1.01 * topology.rest_length[e].item<double>() + 1e-9);
  }
}

}  // namespace
}  // namespace pb4u
