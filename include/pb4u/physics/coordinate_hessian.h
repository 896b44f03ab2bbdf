#pragma once
// The solver's Hessian on the cloth's coordinates (row 3 r + c: kept vertex r, coordinate c),
// for the terms whose curvature has a direction: a contact pair is stiff along its normal and
// free across it, a strain-limited edge stiff along itself. A per-vertex diagonal, the same in
// x, y and z, stiffens every direction alike and so slows sliding along the body.
#include <Eigen/Sparse>

#include <vector>

namespace pb4u {

// Entries at rows 3 v + c of the full cloth (vertex v of n, coordinate c), summed where repeated.
using CoordinateHessian = std::vector<Eigen::Triplet<double>>;

// coefficient * u u^T, u the 3 x count coordinates of `vertices[0 .. count)` in that order.
void add_outer_product(const int* vertices, int count, const double* u, double coefficient, CoordinateHessian* hessian);

// Per vertex v (of n), stiffness(v) n_v n_v^T, or stiffness(v) (I - n_v n_v^T) when `across`,
// n_v = row v of normals (unit); vertices with zero stiffness add nothing.
void add_directional_stiffness(const Eigen::VectorXd& stiffness, const Eigen::MatrixXd& normals, bool across,
                               CoordinateHessian* hessian);

// The k x k matrix `shared` by x, y and z (quasi_newton_hessian.h) as a 3k x 3k matrix on the
// coordinates, plus `diagonal` (k per vertex values added to its three coordinates; empty: none)
// and `blocks` mapped through row_of_vertex (size n; -1 leaves a vertex out, e.g. a pinned one).
Eigen::SparseMatrix<double> coordinate_hessian(const Eigen::SparseMatrix<double>& shared, const Eigen::VectorXd& diagonal,
                                               const CoordinateHessian& blocks, const std::vector<int>& row_of_vertex);

}  // namespace pb4u
