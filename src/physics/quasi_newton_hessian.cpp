#include "pb4u/physics/quasi_newton_hessian.h"

namespace pb4u {

Eigen::SparseMatrix<double> quasi_newton_hessian(const ClothGeometry& cloth,
                                                 const Material& material, double dt,
                                                 const std::vector<int>& row_of_vertex) {
  torch::Tensor faces = cloth.faces.to(torch::kCPU).contiguous();
  torch::Tensor dminv = cloth.dm_inverse.to(torch::kCPU, torch::kFloat64).contiguous();
  torch::Tensor area = cloth.face_area.to(torch::kCPU, torch::kFloat64).contiguous();
  torch::Tensor mass = cloth.vertex_masses(material.density).to(torch::kCPU, torch::kFloat64).contiguous();
  auto F = faces.accessor<int64_t, 2>();
  auto D = dminv.accessor<double, 3>();
  auto A = area.accessor<double, 1>();
  auto m = mass.accessor<double, 1>();
  int k = 0;
  for (int r : row_of_vertex) k = std::max(k, r + 1);

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(faces.size(0)) * 9 + row_of_vertex.size());
  // A vertex touching only zero-area faces has no mass and no stiffness: a unit diagonal
  // (the solver's inertia preconditioner uses the same unit scale) keeps H positive definite.
  for (size_t v = 0; v < row_of_vertex.size(); ++v)
    if (row_of_vertex[v] >= 0)
      entries.emplace_back(row_of_vertex[v], row_of_vertex[v], m[v] > 0 ? m[v] / (dt * dt) : 1.0);
  const double modulus = material.thickness * (2 * material.mu + material.lambda);
  for (int64_t f = 0; f < faces.size(0); ++f) {
    const Eigen::Matrix<double, 3, 2> g =
        shape_function_gradients((Eigen::Matrix2d() << D[f][0][0], D[f][0][1], D[f][1][0], D[f][1][1]).finished());
    for (int a = 0; a < 3; ++a) {
      int ra = row_of_vertex[F[f][a]];
      if (ra < 0) continue;
      for (int b = 0; b < 3; ++b) {
        int rb = row_of_vertex[F[f][b]];
        if (rb < 0) continue;
        entries.emplace_back(ra, rb, A[f] * modulus * g.row(a).dot(g.row(b)));
      }
    }
  }
  Eigen::SparseMatrix<double> H(k, k);
  H.setFromTriplets(entries.begin(), entries.end());
  return H;
}

}  // namespace pb4u
