#include "pb4u/physics/coordinate_hessian.h"

namespace pb4u {

void add_outer_product(const int* vertices, int count, const double* u, double coefficient, CoordinateHessian* hessian) {
  for (int a = 0; a < count; ++a)
    for (int b = 0; b < count; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          hessian->emplace_back(3 * vertices[a] + i, 3 * vertices[b] + j, coefficient * u[3 * a + i] * u[3 * b + j]);
}

void add_directional_stiffness(const Eigen::VectorXd& stiffness, const Eigen::MatrixXd& normals, bool across,
                               CoordinateHessian* hessian) {
  for (Eigen::Index v = 0; v < stiffness.size(); ++v) {
    if (!(stiffness(v) != 0)) continue;
    const Eigen::Vector3d n = normals.row(v).transpose();
    Eigen::Matrix3d block = n * n.transpose();
    if (across) block = Eigen::Matrix3d::Identity() - block;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) hessian->emplace_back(3 * int(v) + i, 3 * int(v) + j, stiffness(v) * block(i, j));
  }
}

Eigen::SparseMatrix<double> coordinate_hessian(const Eigen::SparseMatrix<double>& shared, const Eigen::VectorXd& diagonal,
                                               const CoordinateHessian& blocks, const std::vector<int>& row_of_vertex) {
  const Eigen::Index k = shared.rows();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(size_t(shared.nonZeros()) * 3 + size_t(diagonal.size()) * 3 + blocks.size());
  for (int col = 0; col < shared.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(shared, col); it; ++it)
      for (int c = 0; c < 3; ++c) entries.emplace_back(3 * int(it.row()) + c, 3 * int(it.col()) + c, it.value());
  for (Eigen::Index r = 0; r < diagonal.size(); ++r)
    for (int c = 0; c < 3; ++c) entries.emplace_back(3 * int(r) + c, 3 * int(r) + c, diagonal(r));
  for (const auto& e : blocks) {
    const int ra = row_of_vertex[size_t(e.row() / 3)], rb = row_of_vertex[size_t(e.col() / 3)];
    if (ra >= 0 && rb >= 0) entries.emplace_back(3 * ra + e.row() % 3, 3 * rb + e.col() % 3, e.value());
  }
  Eigen::SparseMatrix<double> H(3 * k, 3 * k);
  H.setFromTriplets(entries.begin(), entries.end());
  return H;
}

}  // namespace pb4u
