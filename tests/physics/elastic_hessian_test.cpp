// The Newton step's Hessians against finite differences of the energies' own gradients: the
// dihedral angle's gradient, StVK's exact Hessian where no face is compressed (the projection
// then changes nothing), the bending Gauss-Newton at the rest angle (where it is exact), the
// barriers' blocks, and the assembly on coordinates with pinned vertices left out.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "pb4u/mesh/edges.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/physics/elastic_hessian.h"
#include "pb4u/physics/strain_barrier.h"
#include "pb4u/physics/stretch_energy.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

// Every vertex kept, in order.
Eigen::MatrixXd dense(const CoordinateHessian& hessian) {
  std::vector<int> rows(size_t(hessian.num_vertices()));
  for (size_t v = 0; v < rows.size(); ++v) rows[v] = int(v);
  return Eigen::MatrixXd(hessian.matrix(rows));
}

// Central differences of an energy's autograd gradient: column j = d grad / d x_j (3 n x 3 n).
template <class Energy>
Eigen::MatrixXd gradient_jacobian(const Eigen::MatrixXd& x, Energy&& energy, double h) {
  auto gradient = [&](const Eigen::MatrixXd& at) {
    torch::Tensor t = test::positions_tensor(at).requires_grad_(true);
    torch::Tensor g = torch::autograd::grad({energy(t)}, {t})[0].contiguous();
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(g.data_ptr<double>(), g.numel()));  // row-major: 3 v + c
  };
  Eigen::MatrixXd J(x.size(), x.size());
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd up = x, down = x;
      up(v, c) += h;
      down(v, c) -= h;
      J.col(3 * v + c) = (gradient(up) - gradient(down)) / (2 * h);
    }
  return J;
}

TEST(ElasticHessian, DihedralAngleGradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const torch::Tensor hinge = torch::tensor({{0, 1, 2, 3}}, torch::kInt64);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::MatrixXd x(4, 3);
    x << 0, 0, 0, 1, 0, 0, 0.4, 0.8, 0, 0.6, -0.7, 0;
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 0.3 * u(rng);
    const Eigen::Matrix<double, 12, 1> g = dihedral_angle_gradient(x.row(0).transpose(), x.row(1).transpose(),
                                                                  x.row(2).transpose(), x.row(3).transpose(), 1e-12);
    const double h = 1e-6;
    for (int v = 0; v < 4; ++v)
      for (int c = 0; c < 3; ++c) {
        Eigen::MatrixXd up = x, down = x;
        up(v, c) += h;
        down(v, c) -= h;
        const double fd = (dihedral_angles(test::positions_tensor(up), hinge, 1e-12).item<double>() -
                           dihedral_angles(test::positions_tensor(down), hinge, 1e-12).item<double>()) /
                          (2 * h);
        EXPECT_NEAR(g(3 * v + c), fd, 1e-6 * std::max(1.0, std::abs(fd))) << "trial " << trial << " v " << v << " c " << c;
      }
  }
  // A collapsed face has no direction.
  EXPECT_EQ(dihedral_angle_gradient({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0.5, 1, 0}, 1e-12).norm(), 0.0);
}

TEST(ElasticHessian, StretchIsStVKsExactHessianWhereNoFaceIsCompressed) {
  const TriMesh g = test::grid_mesh(2, 0.2);
  const ClothGeometry cloth = make_cloth_geometry(g);
  const Material material;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-2e-3, 2e-3);
  Eigen::MatrixXd x = g.V;
  x.col(0) *= 1.15;  // stretched 15% in the plane (x, z), then shaken a little out of it
  x.col(2) *= 1.1;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  CoordinateHessian entries(int(x.rows()));
  add_stretch_hessian(x, cloth, material, &entries);
  const Eigen::MatrixXd H = dense(entries);
  const Eigen::MatrixXd J =
      gradient_jacobian(x, [&](const torch::Tensor& t) { return stretch_energy(t, cloth, material); }, 1e-6);
  EXPECT_LT((H - J).cwiseAbs().maxCoeff(), 1e-5 * J.cwiseAbs().maxCoeff());
  // Compressed to half: StVK is not convex there, the projected Hessian is.
  Eigen::MatrixXd squeezed = g.V;
  squeezed.col(0) *= 0.5;
  squeezed.col(2) *= 0.5;
  CoordinateHessian compressed(int(squeezed.rows()));
  add_stretch_hessian(squeezed, cloth, material, &compressed);
  const Eigen::MatrixXd Hc = dense(compressed);
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hc).eigenvalues().minCoeff(), -1e-9 * Hc.norm());
  const Eigen::MatrixXd Jc =
      gradient_jacobian(squeezed, [&](const torch::Tensor& t) { return stretch_energy(t, cloth, material); }, 1e-6);
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (Jc + Jc.transpose())).eigenvalues().minCoeff(), 0.0);
}

TEST(ElasticHessian, BendingGaussNewtonIsExactAtTheRestAngle) {
  const TriMesh g = test::grid_mesh(2, 0.2);
  Material material;
  material.bending = 1e-3;
  // Rest angles from a copy curved out of its plane (x, z), evaluated there: theta = theta_0.
  TriMesh folded = g;
  for (Eigen::Index i = 0; i < folded.V.rows(); ++i) folded.V(i, 1) = 3 * folded.V(i, 0) * folded.V(i, 0);
  const ClothGeometry cloth = make_cloth_geometry(folded, torch::kFloat64, torch::kCPU, /*with_rest_angles=*/true);
  CoordinateHessian entries(int(folded.V.rows()));
  add_bending_hessian(folded.V, cloth, material, 1e-12, &entries);
  const Eigen::MatrixXd H = dense(entries);
  const Eigen::MatrixXd J = gradient_jacobian(
      folded.V, [&](const torch::Tensor& t) { return bending_energy(t, cloth, material, 1e-12); }, 1e-6);
  ASSERT_GT(J.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((H - J).cwiseAbs().maxCoeff(), 1e-5 * J.cwiseAbs().maxCoeff());
}

TEST(ElasticHessian, StrainBarrierBlocksAreItsExactHessian) {
  const TriMesh g = test::grid_mesh(2, 0.2);
  const Eigen::MatrixXi E = unique_edges(g.F);
  Eigen::VectorXd L(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) L(e) = (g.V.row(E(e, 0)) - g.V.row(E(e, 1))).norm();
  Eigen::MatrixXd x = g.V;
  x.col(0) *= 1.095;  // the x edges in the band (9%-10%), a little out of plane
  x(4, 2) += 1e-3;
  const StrainBarrierSettings s{0.1, 0.01, 2.0};
  CoordinateHessian entries(int(x.rows()));
  ASSERT_GT(strain_barrier(x, E, L, s, {}, nullptr, nullptr, &entries).active, 0);
  const Eigen::MatrixXd H = dense(entries);
  const double h = 1e-7;
  Eigen::MatrixXd J(x.size(), x.size());
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd up = x, down = x, Gu = Eigen::MatrixXd::Zero(x.rows(), 3), Gd = Gu;
      up(v, c) += h;
      down(v, c) -= h;
      strain_barrier(up, E, L, s, {}, &Gu);
      strain_barrier(down, E, L, s, {}, &Gd);
      const Eigen::MatrixXd D = (Gu - Gd) / (2 * h);
      for (Eigen::Index w = 0; w < x.rows(); ++w)
        for (int d = 0; d < 3; ++d) J(3 * w + d, 3 * v + c) = D(w, d);
    }
  EXPECT_LT((H - J).cwiseAbs().maxCoeff(), 1e-5 * J.cwiseAbs().maxCoeff());
}

TEST(ElasticHessian, CoordinateAssemblyLeavesPinnedVerticesOut) {
  // Vertices 0, 1, 2; vertex 1 pinned: rows 0 -> 0, 2 -> 1.
  Eigen::SparseMatrix<double> shared(2, 2);
  shared.insert(0, 0) = 4;
  shared.insert(0, 1) = -1;
  shared.insert(1, 0) = -1;
  shared.insert(1, 1) = 5;
  const Eigen::VectorXd diagonal = (Eigen::VectorXd(2) << 0.5, 0.25).finished();
  CoordinateHessian blocks(3);
  const int vertices[2] = {2, 1};
  const double u[6] = {1, 2, 3, 7, 7, 7};
  add_outer_product(vertices, 2, u, 2.0, &blocks);
  add_shared(shared, diagonal, {0, -1, 1}, &blocks);
  const Eigen::MatrixXd H = Eigen::MatrixXd(blocks.matrix({0, -1, 1}));
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 6);
  for (int c = 0; c < 3; ++c) {
    expected(c, c) = 4.5;
    expected(3 + c, 3 + c) = 5.25;
    expected(c, 3 + c) = expected(3 + c, c) = -1;
  }
  const Eigen::Vector3d w(1, 2, 3);  // vertex 2's part of u; vertex 1's is dropped
  expected.bottomRightCorner(3, 3) += 2.0 * w * w.transpose();
  EXPECT_LT((H - expected).cwiseAbs().maxCoeff(), 1e-12);
  // Cleared, the pairs stay (zero blocks): the same pattern, so the ordering can be reused.
  blocks.clear();
  EXPECT_TRUE(blocks.empty());
  const Eigen::SparseMatrix<double> zero = blocks.matrix({0, -1, 1});
  EXPECT_EQ(zero.nonZeros(), 36);
  EXPECT_EQ(Eigen::MatrixXd(zero).norm(), 0.0);
}

TEST(ElasticHessian, DirectionalContactStiffnessSplitsAlongAndAcrossTheNormal) {
  const Eigen::VectorXd k = (Eigen::VectorXd(2) << 3.0, 0.0).finished();
  Eigen::MatrixXd normals(2, 3);
  normals << 0, 0.6, 0.8, 1, 0, 0;
  CoordinateHessian along(2), across(2);
  add_directional_stiffness(k, normals, false, &along);
  add_directional_stiffness(k, normals, true, &across);
  const Eigen::MatrixXd A = dense(along), C = dense(across);
  const Eigen::Vector3d n(0, 0.6, 0.8), t(1, 0, 0);
  EXPECT_NEAR(n.dot(A.topLeftCorner(3, 3) * n), 3.0, 1e-12);  // stiff along the normal
  EXPECT_NEAR((A.topLeftCorner(3, 3) * t).norm(), 0.0, 1e-12);
  EXPECT_NEAR((C.topLeftCorner(3, 3) * n).norm(), 0.0, 1e-12);  // free along it across
  EXPECT_NEAR(t.dot(C.topLeftCorner(3, 3) * t), 3.0, 1e-12);
  EXPECT_LT(((A + C).topLeftCorner(3, 3) - 3.0 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(A.bottomRightCorner(3, 3).norm(), 0.0);  // zero stiffness adds nothing
}

}  // namespace
}  // namespace pb4u
