#pragma once
// The fixed initial Hessian of the reference solver's quasi-Newton iteration (after Liu, Bouaziz
// and Kavan 2017, "Quasi-Newton methods for real-time simulation of hyperelastic materials"):
// the inertia Hessian plus the rest-state linear-elastic stiffness of the membrane. It is
// constant over a frame, so it is factorised once and each L-BFGS step costs one sparse solve.
#include <Eigen/Core>
#include <Eigen/Sparse>

#include <vector>

#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/scene/material.h"

namespace pb4u {

// The gradients (1/m) of a face's linear shape functions at rest, from its Dm^-1: row a for its
// vertex a, so that its deformation gradient is F = sum_a x_a g_a^T (vertex 1 <-> row 0 of
// Dm^-1, vertex 2 <-> row 1, vertex 0 <-> minus their sum).
inline Eigen::Matrix<double, 3, 2> shape_function_gradients(const Eigen::Matrix2d& dm_inverse) {
  Eigen::Matrix<double, 3, 2> g;
  g.row(1) = dm_inverse.row(0);
  g.row(2) = dm_inverse.row(1);
  g.row(0) = -(g.row(1) + g.row(2));
  return g;
}

// H = M / dt^2 + sum_f A_f h (2 mu + lambda) G_f^T G_f, shared by x, y and z: G_f (2 x 3) holds
// the gradients (1/m) of face f's linear shape functions at rest, M the lumped masses (kg),
// dt in s, so H is in N/m (a massless vertex, touching only zero-area faces, gets 1 N/m on its
// diagonal). row_of_vertex (size n): the row of each vertex, -1 to leave it
// out (pinned vertices); the result is k x k with k the number of kept vertices.
Eigen::SparseMatrix<double> quasi_newton_hessian(const ClothGeometry& cloth,
                                                 const Material& material, double dt,
                                                 const std::vector<int>& row_of_vertex);

}  // namespace pb4u
