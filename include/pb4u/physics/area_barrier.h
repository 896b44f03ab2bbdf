#pragma once
// A barrier against collapse: no cloth triangle may flatten to a line or a point. StVK charges
// little for it (its energy stays finite as a triangle flattens), while a collapsed triangle's
// normal turns without bound under its vertices, and with it the bending term's hinge angles
// (gradients ~1 / altitude). A solve that lets a triangle collapse can stall there with no
// descent left (docs/physics.md, "A barrier against collapse").
//
// Per triangle, its area ratio r = A / A0 carries IPC's log barrier below g_hat
// (pb4u/physics/barrier.h), with a stiffness per rest area:
//   E = kappa A0 b(r, g_hat):  zero from r = g_hat on, infinite at r = 0.
// C-IPC bounds a triangle's strain from above (its largest singular value); this bounds its
// area from below. A solver that filters every step by max_area_step never lets a triangle
// pass through a collapse.
#include <Eigen/Core>

#include <vector>

#include "pb4u/physics/coordinate_hessian.h"

namespace pb4u {

struct AreaBarrierSettings {
  double gap = 0.1;            // g_hat: the barrier acts below this fraction of the rest area
  double stiffness = 1e4;      // kappa, J/m^2 of rest area
};

struct AreaBarrierValue {
  double energy = 0;           // J
  double min_ratio = 1;        // smallest A / A0 over the triangles not excluded
  int active = 0;              // triangles below g_hat
};

// A triangle's area and its gradient (9: d/dx0, d/dx1, d/dx2) and Hessian (9 x 9, exact:
// indefinite in general). Zero gradient and Hessian for a degenerate triangle.
double triangle_area(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                     Eigen::Matrix<double, 9, 1>* gradient = nullptr, Eigen::Matrix<double, 9, 9>* hessian = nullptr);

// faces: m x 3; rest_area: m (m^2); excluded: per face, 1 to leave it out, or empty. Infinite
// energy when a face not excluded has zero area. The gradient (n x 3, J/m) is added into
// *gradient, a per-vertex isotropic curvature (kappa A0 b''(r) |dr/dx_i|^2, N/m) into
// *curvature, and the Hessian projected to positive semidefinite per face (N/m) into *hessian.
AreaBarrierValue area_barrier(const Eigen::MatrixXd& x, const Eigen::MatrixXi& faces, const Eigen::VectorXd& rest_area,
                              const AreaBarrierSettings& settings, const std::vector<char>& excluded,
                              Eigen::MatrixXd* gradient = nullptr, Eigen::VectorXd* curvature = nullptr,
                              CoordinateHessian* hessian = nullptr);

// The largest fraction t in [0, 1] of the step dx that keeps every face not excluded from
// collapsing: 0.8 of the first t at which a face's area, projected on the plane it had at the
// step's start, reaches zero (a quadratic per face; its true area is at least that projection,
// so it cannot collapse before), 1 when none would.
double max_area_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& faces,
                     const std::vector<char>& excluded);

// Per face, 1 where its area is at or below `ratio` x its rest area in x, or its rest area is 0.
std::vector<char> faces_below_area(const Eigen::MatrixXd& x, const Eigen::MatrixXi& faces,
                                   const Eigen::VectorXd& rest_area, double ratio);

}  // namespace pb4u
