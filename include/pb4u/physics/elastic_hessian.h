#pragma once
// The second derivatives of the cloth's elastic energies at a state, on its coordinates
// (coordinate_hessian.h), for the reference solver's Newton step:
// - stretch (SPEC 3.1, StVK): each face's exact Hessian in its deformation gradient F (6 x 6),
//   projected to positive semidefinite (negative eigenvalues, from compression, set to 0), then
//   mapped to its 9 coordinates (F is linear in them);
// - bending (SPEC 3.2, 0.5 k_b w (theta - theta_0)^2 per hinge): Gauss-Newton, k_b w grad theta
//   grad theta^T (the dropped k_b w (theta - theta_0) Hess theta vanishes at the rest angle).
// Both are positive semidefinite; with the inertia M / dt^2 the sum is positive definite.
#include <Eigen/Core>

#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/scene/material.h"

namespace pb4u {

// grad theta of one hinge (ClothGeometry::hinges: shared edge i -> j, k0 and k1 opposite it in
// faces 0 and 1), 1/m, in the order (i, j, k0, k1); zero for a collapsed hinge (either face's
// doubled area, or the edge's squared length, below degenerate_area).
Eigen::Matrix<double, 12, 1> dihedral_angle_gradient(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                                     const Eigen::Vector3d& xk0, const Eigen::Vector3d& xk1,
                                                     double degenerate_area);

// x: n x 3 positions (m). Entries in N/m added to *hessian (rows 3 v + c of the n vertices).
void add_stretch_hessian(const Eigen::MatrixXd& x, const ClothGeometry& cloth, const Material& material,
                         CoordinateHessian* hessian);
void add_bending_hessian(const Eigen::MatrixXd& x, const ClothGeometry& cloth, const Material& material,
                         double degenerate_area, CoordinateHessian* hessian);
// Per vertex (N/m), the trace over its 3 x 3 diagonal block of the bending's Gauss-Newton Hessian
// above: k_b w |d theta / d x_v|^2 summed over the hinges of v (step_residual.h's isotropic H).
Eigen::VectorXd bending_hessian_diagonal(const Eigen::MatrixXd& x, const ClothGeometry& cloth,
                                         const Material& material, double degenerate_area);

}  // namespace pb4u
