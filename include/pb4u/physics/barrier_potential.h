#pragma once
// IPC's contact potential between cloth and a body (Li et al. 2020): kappa times the log
// barrier of the distance of every candidate pair, cloth vertex to body face and cloth edge to
// body edge, summed. Infinite at contact, zero beyond d_hat: a solver that only takes steps
// CCD certifies (max_safe_step) never lets the cloth touch or cross the body.
// Simplification: a vertex near a body edge or corner is counted once per face around it (IPC
// proper sorts pairs by their closest features); the barrier stays a barrier, only its
// stiffness there is multiplied.
#include <Eigen/Core>

#include <vector>

#include "pb4u/physics/contact_candidates.h"
#include "pb4u/physics/coordinate_hessian.h"

namespace pb4u {

struct BarrierSettings {
  double d_hat = 1e-3;      // m: the barrier acts below this distance
  double stiffness = 1000;  // kappa, J/m^2 (the barrier is in m^2)
};

struct BarrierValue {
  double energy = 0;          // J
  double min_distance = 0;    // m over the candidates (infinity without any)
  int active = 0;             // pairs closer than d_hat
};

// The potential at cloth positions x (n x 3) against `body` over `candidates`; its gradient
// (n x 3, J/m) is added into *gradient when given (sized n x 3), a per-vertex isotropic
// curvature (n, N/m: kappa b''(d) |grad_i d|^2, the Gauss-Newton diagonal) into *curvature, and
// the Gauss-Newton Hessian kappa b''(d) grad d grad d^T over each pair's cloth coordinates (N/m,
// positive semidefinite; the dropped kappa b'(d) Hess d is negative semidefinite) into *hessian.
BarrierValue barrier_potential(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                               const ContactSurface& body, const ContactCandidates& candidates,
                               const BarrierSettings& settings, Eigen::MatrixXd* gradient = nullptr,
                               Eigen::VectorXd* curvature = nullptr, CoordinateHessian* hessian = nullptr);

// The largest fraction t in [0, 1] of a step, cloth by dx and body by body_motion (empty:
// still), that keeps every candidate pair apart (additive CCD per pair, the smallest time).
double max_safe_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& cloth_edges,
                     const ContactSurface& body, const Eigen::MatrixXd& body_motion,
                     const ContactCandidates& candidates);

// Per cloth vertex, 1 where a candidate pair it belongs to allows less than `below` of that
// step on its own (additive CCD of that pair alone): the cloth that holds a step back.
std::vector<char> vertices_holding_step(const Eigen::MatrixXd& x, const Eigen::MatrixXd& dx,
                                        const Eigen::MatrixXi& cloth_edges, const ContactSurface& body,
                                        const Eigen::MatrixXd& body_motion, const ContactCandidates& candidates,
                                        double below);

// The rows of the cloth edges that pass through a body triangle (segment-triangle
// intersection): none for an intersection-free state.
std::vector<int> cloth_edges_through_body(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                          const ContactSurface& body);

}  // namespace pb4u
