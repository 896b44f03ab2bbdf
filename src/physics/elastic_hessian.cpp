#include "pb4u/physics/elastic_hessian.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <array>

#include "pb4u/physics/quasi_newton_hessian.h"

namespace pb4u {

Eigen::Matrix<double, 12, 1> dihedral_angle_gradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                                     const Eigen::Vector3d& xk0, const Eigen::Vector3d& xk1,
                                                     double degenerate_area) {
  Eigen::Matrix<double, 12, 1> g = Eigen::Matrix<double, 12, 1>::Zero();
  const Eigen::Vector3d e = xj - xi;
  const Eigen::Vector3d n0 = e.cross(xk0 - xi), n1 = (xk1 - xi).cross(e);  // as dihedral_angles()
  const double a0 = n0.squaredNorm(), a1 = n1.squaredNorm(), ee = e.squaredNorm();
  const double d2 = degenerate_area * degenerate_area;
  if (a0 < d2 || a1 < d2 || ee < degenerate_area) return g;
  const double length = std::sqrt(ee);
  // Each wing turns its face about the shared edge: its gradient is along its face's normal,
  // |e| / (2 area) over its distance to the edge. The edge's ends take the rest so that the
  // gradients sum to zero (translation) and turn nothing (rotation): minus the wing's, split by
  // where the wing projects onto the edge.
  const Eigen::Vector3d gk0 = -length / a0 * n0, gk1 = -length / a1 * n1;
  const double t0 = (xk0 - xi).dot(e) / ee, t1 = (xk1 - xi).dot(e) / ee;
  g.segment<3>(0) = -(1 - t0) * gk0 - (1 - t1) * gk1;
  g.segment<3>(3) = -t0 * gk0 - t1 * gk1;
  g.segment<3>(6) = gk0;
  g.segment<3>(9) = gk1;
  return g;
}

void add_stretch_hessian(const Eigen::MatrixXd& x, const ClothGeometry& cloth, const Material& material,
                         CoordinateHessian* hessian) {
  const torch::Tensor faces = cloth.faces.to(torch::kCPU).contiguous();
  const torch::Tensor dminv = cloth.dm_inverse.to(torch::kCPU, torch::kFloat64).contiguous();
  const torch::Tensor area = cloth.face_area.to(torch::kCPU, torch::kFloat64).contiguous();
  const auto F = faces.accessor<int64_t, 2>();
  const auto D = dminv.accessor<double, 3>();
  const auto A = area.accessor<double, 1>();
  const double mu = material.mu, lambda = material.lambda;
  for (int64_t f = 0; f < faces.size(0); ++f) {
    const double scale = A[f] * material.thickness;
    if (!(scale > 0)) continue;
    const Eigen::Matrix<double, 3, 2> g =  // F = sum_a x_a g_a^T
        shape_function_gradients((Eigen::Matrix2d() << D[f][0][0], D[f][0][1], D[f][1][0], D[f][1][1]).finished());
    const std::array<int, 3> v{int(F[f][0]), int(F[f][1]), int(F[f][2])};
    Eigen::Matrix<double, 3, 2> Fd = Eigen::Matrix<double, 3, 2>::Zero();
    for (int a = 0; a < 3; ++a) Fd += x.row(v[a]).transpose() * g.row(a);
    const Eigen::Matrix2d G = 0.5 * (Fd.transpose() * Fd - Eigen::Matrix2d::Identity());
    const Eigen::Matrix2d S = 2 * mu * G + lambda * G.trace() * Eigen::Matrix2d::Identity();
    // P = scale F S; dP = scale (dF S + F (2 mu dG + lambda tr(dG) I)), dG = sym(F^T dF).
    // Columns of the 6 x 6 Hessian: dP for each unit dF (vec: entry (r, c) at 3 c + r).
    Eigen::Matrix<double, 6, 6> H;
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 3, 2> dF = Eigen::Matrix<double, 3, 2>::Zero();
      dF(k % 3, k / 3) = 1;
      const Eigen::Matrix2d dG = 0.5 * (dF.transpose() * Fd + Fd.transpose() * dF);
      const Eigen::Matrix<double, 3, 2> dP =
          scale * (dF * S + Fd * (2 * mu * dG + lambda * dG.trace() * Eigen::Matrix2d::Identity()));
      for (int c = 0; c < 2; ++c)
        for (int r = 0; r < 3; ++r) H(3 * c + r, k) = dP(r, c);
    }
    // Projected onto the positive semidefinite cone (negative eigenvalues to 0); a positive
    // definite H (a face stretched, the common case) is its own projection, which a Cholesky
    // factorisation tells at a fraction of the eigensolver's cost.
    Eigen::Matrix<double, 6, 6> projected = 0.5 * (H + H.transpose());
    if (Eigen::LLT<Eigen::Matrix<double, 6, 6>>(projected).info() != Eigen::Success) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(projected);
      projected =
          eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
    }
    // dvec(F) / dx_(a, r) = g_a[c] at 3 c + r.
    Eigen::Matrix<double, 6, 9> B = Eigen::Matrix<double, 6, 9>::Zero();
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 2; ++c)
        for (int r = 0; r < 3; ++r) B(3 * c + r, 3 * a + r) = g(a, c);
    const Eigen::Matrix<double, 9, 9> Hx = B.transpose() * projected * B;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) hessian->add(v[a], v[b], Hx.block<3, 3>(3 * a, 3 * b));
  }
}

namespace {
// Calls f(v, grad, k) for every hinge: v its four vertices (i, j, k0, k1), grad its
// dihedral_angle_gradient at x, k = k_b w its stiffness (J).
template <class F>
void for_each_hinge_gradient(const Eigen::MatrixXd& x, const ClothGeometry& cloth, const Material& material,
                             double degenerate_area, F f) {
  if (!(material.bending > 0) || cloth.hinges.size(0) == 0) return;
  const torch::Tensor hinges = cloth.hinges.to(torch::kCPU).contiguous();
  const torch::Tensor weight = cloth.hinge_weight.to(torch::kCPU, torch::kFloat64).contiguous();
  const auto H = hinges.accessor<int64_t, 2>();
  const auto w = weight.accessor<double, 1>();
  for (int64_t h = 0; h < hinges.size(0); ++h) {
    const int v[4] = {int(H[h][0]), int(H[h][1]), int(H[h][2]), int(H[h][3])};
    const Eigen::Matrix<double, 12, 1> grad = dihedral_angle_gradient(
        x.row(v[0]).transpose(), x.row(v[1]).transpose(), x.row(v[2]).transpose(), x.row(v[3]).transpose(),
        degenerate_area);
    f(v, grad, material.bending * w[h]);
  }
}
}  // namespace

void add_bending_hessian(const Eigen::MatrixXd& x, const ClothGeometry& cloth, const Material& material,
                         double degenerate_area, CoordinateHessian* hessian) {
  for_each_hinge_gradient(x, cloth, material, degenerate_area,
                          [&](const int* v, const Eigen::Matrix<double, 12, 1>& grad, double k) {
                            add_outer_product(v, 4, grad.data(), k, hessian);
                          });
}

Eigen::VectorXd bending_hessian_diagonal(const Eigen::MatrixXd& x, const ClothGeometry& cloth,
                                         const Material& material, double degenerate_area) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(x.rows());
  for_each_hinge_gradient(x, cloth, material, degenerate_area,
                          [&](const int* v, const Eigen::Matrix<double, 12, 1>& grad, double k) {
                            for (int a = 0; a < 4; ++a) d(v[a]) += k * grad.segment<3>(3 * a).squaredNorm();
                          });
  return d;
}

}  // namespace pb4u
