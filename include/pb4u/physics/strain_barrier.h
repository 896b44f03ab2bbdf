#pragma once
// Strain limiting as a barrier (after C-IPC, Li et al. 2021, which bounds each triangle's
// singular values; here each edge's length): an edge may stretch at most `limit` (0.1: 10%
// longer than at rest). Its gap g = limit - (|x_i - x_j| / L - 1) carries IPC's log barrier
// b(g) = -kappa (g - g_hat)^2 ln(g / g_hat) below g_hat: zero further from the limit, infinite
// at it. A solver that filters every step by max_strain_step (the exact step at which an edge
// reaches the limit, a quadratic per edge) never lets an edge past it: the limit is part of the
// physics the solve minimises, not a pass after it (Provot's, physics/strain_limiting.h).
// Edges may compress freely.
#include <Eigen/Core>

#include <vector>

#include "pb4u/physics/coordinate_hessian.h"

namespace pb4u {

struct StrainBarrierSettings {
  double limit = 0.1;        // largest edge strain
  double gap = 0.01;         // g_hat: the barrier acts within this strain of the limit
  double stiffness = 1.0;    // kappa, J
};

struct StrainBarrierValue {
  double energy = 0;      // J
  double max_strain = 0;  // over the edges not excluded
  int active = 0;         // edges within g_hat of the limit
};

// edges: e x 2 (unique cloth edges); rest: e rest lengths (m); excluded: per edge, 1 to leave
// it out (over the limit where the step started), or empty. Infinite energy when an edge not
// excluded is at or past the limit. The gradient (n x 3, J/m) is added into *gradient, a
// per-vertex isotropic curvature (n, N/m: kappa b''(g) |dg/dx_i|^2) into *curvature, and the
// exact Hessian (N/m) into *hessian: per edge, with n its direction,
//   A = kappa (b''(g) / L^2 n n^T - b'(g) / (L |x_i - x_j|) (I - n n^T))
// at (i, i) and (j, j), -A at (i, j) and (j, i); positive semidefinite, since b' < 0.
StrainBarrierValue strain_barrier(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges, const Eigen::VectorXd& rest,
                                  const StrainBarrierSettings& settings, const std::vector<char>& excluded,
                                  Eigen::MatrixXd* gradient = nullptr, Eigen::VectorXd* curvature = nullptr,
                                  CoordinateHessian* hessian = nullptr);

// The largest fraction t in [0, 1] of the step dx that keeps every edge not excluded short of
// the limit: 0.8 of the exact fraction at which the first would reach it (IPC's margin, so a
// step never lands on the barrier's pole), 1 when none would.
double max_strain_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& edges,
                       const Eigen::VectorXd& rest, double limit, const std::vector<char>& excluded);

// Per edge, 1 where its strain is at or past `limit` in x (the edges a step starting there
// leaves out of the barrier).
std::vector<char> edges_over_strain(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges, const Eigen::VectorXd& rest,
                                    double limit);

// Provot's pass on an Eigen state, for a start the barrier can take: each edge longer than
// (1 + limit) L shortened to it, its ends moving towards each other (a pinned end, fixed[i] = 1,
// stays), Gauss-Seidel sweeps alternating direction, at most `sweeps`.
Eigen::MatrixXd shorten_overstretched_edges(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges,
                                            const Eigen::VectorXd& rest, double limit, const std::vector<char>& fixed,
                                            int sweeps = 100);

}  // namespace pb4u
