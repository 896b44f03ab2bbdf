#include "pb4u/physics/coordinate_hessian.h"

#include <algorithm>

#include "pb4u/util/error.h"

namespace pb4u {

CoordinateHessian::CoordinateHessian(int num_vertices) : rows_(size_t(num_vertices)), blocks_(size_t(num_vertices)) {}

void CoordinateHessian::add(int a, int b, const Eigen::Matrix3d& block) {
  std::vector<int>& rows = rows_[size_t(b)];
  auto it = std::lower_bound(rows.begin(), rows.end(), a);
  const size_t at = size_t(it - rows.begin());
  if (it == rows.end() || *it != a) {
    rows.insert(it, a);
    blocks_[size_t(b)].insert(blocks_[size_t(b)].begin() + long(at), Eigen::Matrix3d::Zero());
  }
  blocks_[size_t(b)][at] += block;
  ++added_;
}

void CoordinateHessian::clear() {
  for (auto& column : blocks_)
    for (auto& block : column) block.setZero();
  added_ = 0;
}

Eigen::SparseMatrix<double> CoordinateHessian::matrix(const std::vector<int>& row_of_vertex) const {
  if (row_of_vertex.size() != rows_.size()) throw Error("coordinate Hessian: the row map is not one entry per vertex");
  std::vector<int> vertex_of_row;
  for (size_t v = 0; v < row_of_vertex.size(); ++v)
    if (row_of_vertex[v] >= 0) {
      if (row_of_vertex[v] != int(vertex_of_row.size()))
        throw Error("coordinate Hessian: the row map does not number the kept vertices in order");
      vertex_of_row.push_back(int(v));
    }
  const int k = int(vertex_of_row.size());
  Eigen::SparseMatrix<double> H(3 * k, 3 * k);
  std::vector<int> kept(size_t(k), 0);  // per column vertex: its kept row vertices
  long nonzeros = 0;
  for (int r = 0; r < k; ++r) {
    for (int a : rows_[size_t(vertex_of_row[size_t(r)])]) kept[size_t(r)] += row_of_vertex[size_t(a)] >= 0;
    nonzeros += 9L * kept[size_t(r)];
  }
  H.resizeNonZeros(nonzeros);
  int* outer = H.outerIndexPtr();
  int* inner = H.innerIndexPtr();
  double* value = H.valuePtr();
  long at = 0;
  for (int r = 0; r < k; ++r) {
    const int b = vertex_of_row[size_t(r)];
    for (int j = 0; j < 3; ++j) {
      outer[3 * r + j] = int(at);
      for (size_t p = 0; p < rows_[size_t(b)].size(); ++p) {
        const int ra = row_of_vertex[size_t(rows_[size_t(b)][p])];
        if (ra < 0) continue;
        for (int i = 0; i < 3; ++i) {
          inner[at] = 3 * ra + i;
          value[at] = blocks_[size_t(b)][p](i, j);
          ++at;
        }
      }
    }
  }
  outer[3 * k] = int(at);
  return H;
}

void add_outer_product(const int* vertices, int count, const double* u, double coefficient, CoordinateHessian* hessian) {
  for (int a = 0; a < count; ++a)
    for (int b = 0; b < count; ++b) {
      const Eigen::Map<const Eigen::Vector3d> ua(u + 3 * a), ub(u + 3 * b);
      hessian->add(vertices[a], vertices[b], coefficient * ua * ub.transpose());
    }
}

void add_directional_stiffness(const Eigen::VectorXd& stiffness, const Eigen::MatrixXd& normals, bool across,
                               CoordinateHessian* hessian) {
  for (Eigen::Index v = 0; v < stiffness.size(); ++v) {
    if (!(stiffness(v) != 0)) continue;
    const Eigen::Vector3d n = normals.row(v).transpose();
    Eigen::Matrix3d block = n * n.transpose();
    if (across) block = Eigen::Matrix3d::Identity() - block;
    hessian->add(int(v), int(v), stiffness(v) * block);
  }
}

void add_shared(const Eigen::SparseMatrix<double>& shared, const Eigen::VectorXd& diagonal,
                const std::vector<int>& row_of_vertex, CoordinateHessian* hessian) {
  std::vector<int> vertex_of_row(size_t(shared.rows()), -1);
  for (size_t v = 0; v < row_of_vertex.size(); ++v)
    if (row_of_vertex[v] >= 0) vertex_of_row[size_t(row_of_vertex[v])] = int(v);
  for (int col = 0; col < shared.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(shared, col); it; ++it)
      hessian->add(vertex_of_row[size_t(it.row())], vertex_of_row[size_t(it.col())],
                   it.value() * Eigen::Matrix3d::Identity());
  for (Eigen::Index r = 0; r < diagonal.size(); ++r)
    hessian->add(vertex_of_row[size_t(r)], vertex_of_row[size_t(r)], diagonal(r) * Eigen::Matrix3d::Identity());
}

}  // namespace pb4u
