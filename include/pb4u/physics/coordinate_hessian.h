#pragma once
// The solver's Hessian on the cloth's coordinates (row 3 r + c: kept vertex r, coordinate c),
// for the terms whose curvature has a direction: a contact pair is stiff along its normal and
// free across it, a strain-limited edge stiff along itself, a face's stretch in its own plane.
// A per-vertex diagonal, the same in x, y and z, stiffens every direction alike and so slows
// sliding along the body.
//
// Accumulated as 3 x 3 blocks per vertex pair. The pairs a matrix has held stay (with zero
// blocks) after clear(), so a Newton iteration refills the same pattern: no triplet lists, no
// sorting, and the factorisation's ordering is reused while no new pair appears.
#include <Eigen/Core>
#include <Eigen/Sparse>

#include <vector>

namespace pb4u {

class CoordinateHessian {
 public:
  explicit CoordinateHessian(int num_vertices = 0);

  int num_vertices() const { return int(rows_.size()); }
  // Adds `block` at rows 3 a + i, columns 3 b + j (vertices a and b of the n).
  void add(int a, int b, const Eigen::Matrix3d& block);
  // No block added since construction or the last clear().
  bool empty() const { return added_ == 0; }
  // Every block to zero; the pairs stay.
  void clear();
  // The 3k x 3k matrix of the kept vertices: row_of_vertex (size n) maps vertex v to its row r
  // (increasing with v), -1 leaves it out (a pinned vertex).
  Eigen::SparseMatrix<double> matrix(const std::vector<int>& row_of_vertex) const;

 private:
  // Per column vertex b: the row vertices a it pairs with (sorted) and the blocks H(a, b).
  std::vector<std::vector<int>> rows_;
  std::vector<std::vector<Eigen::Matrix3d>> blocks_;
  long added_ = 0;
};

// coefficient * u u^T, u the 3 x count coordinates of `vertices[0 .. count)` in that order.
void add_outer_product(const int* vertices, int count, const double* u, double coefficient, CoordinateHessian* hessian);

// Per vertex v (of n), stiffness(v) n_v n_v^T, or stiffness(v) (I - n_v n_v^T) when `across`,
// n_v = row v of normals (unit); vertices with zero stiffness add nothing.
void add_directional_stiffness(const Eigen::VectorXd& stiffness, const Eigen::MatrixXd& normals, bool across,
                               CoordinateHessian* hessian);

// The k x k matrix `shared` by x, y and z (quasi_newton_hessian.h; rows as row_of_vertex maps
// them) added as s I blocks, and `diagonal` (k per-row values, empty: none) on the diagonal.
void add_shared(const Eigen::SparseMatrix<double>& shared, const Eigen::VectorXd& diagonal,
                const std::vector<int>& row_of_vertex, CoordinateHessian* hessian);

}  // namespace pb4u
