#include "pb4u/physics/intersection_free_start.h"

#include <algorithm>

#include "pb4u/physics/barrier_potential.h"
#include "pb4u/spatial/point_kd_tree.h"
#include "pb4u/spatial/signed_distance_to_surface.h"

namespace pb4u {
namespace {

constexpr int kMaxSweepRounds = 64;
// Rounds of pushing edges that cut through the body at t further out (the offset doubles).
constexpr int kMaxPushRounds = 16;
// The sweep carries cloth vertices within this many d_hat of the body along with it.
constexpr double kCarryReach = 20;

// Moves the cloth by t * dx and returns the fraction of dx taken: as much of it as CCD allows.
double safe_move(Eigen::MatrixXd& x, const Eigen::MatrixXd& dx, const Eigen::MatrixXi& cloth_edges,
                 const ContactSurface& body, const Eigen::MatrixXd& body_motion) {
  const ContactCandidates c = contact_candidates(x, dx, cloth_edges, body, body_motion, 0.0);
  const double t = max_safe_step(x, dx, cloth_edges, body, body_motion, c);
  x += t * dx;
  return t;
}

}  // namespace

FeasibleStart intersection_free_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target,
                                      const std::vector<bool>& pinned, const Eigen::MatrixXi& cloth_edges,
                                      const Eigen::MatrixXd& body_t, const Eigen::MatrixXd& body_next,
                                      const Eigen::MatrixXi& body_faces, double d_hat) {
  FeasibleStart out;
  out.x = x_t;
  const Eigen::Index n = x_t.rows();
  // 1. Free of the body at t: what is inside or within d_hat goes to d_hat outside. An edge
  //    whose ends are both outside can still cut through the body (a chord of a convex part):
  //    its ends go further out, twice as far each round, until no edge crosses.
  ContactSurface body = make_contact_surface(body_t, body_faces);  // moves with the sweep below
  {
    std::vector<char> moved(size_t(n), 0);
    double offset = d_hat;
    std::vector<char> push(size_t(n), 0);
    for (int round = 0; round < kMaxPushRounds; ++round, offset *= 2) {
      const SurfaceProjection p = project_onto_surface(out.x, body_t, body_faces);
      bool any = false;
      for (Eigen::Index i = 0; i < n; ++i)
        if (p.distance(i) < d_hat || push[size_t(i)]) {
          out.x.row(i) = p.closest.row(i) + (std::max(p.distance(i), 0.0) + offset) * p.outward.row(i);
          moved[size_t(i)] = 1;
          any = true;
        }
      std::fill(push.begin(), push.end(), 0);
      const std::vector<int> through = cloth_edges_through_body(out.x, cloth_edges, body);
      for (int e : through) push[size_t(cloth_edges(e, 0))] = push[size_t(cloth_edges(e, 1))] = 1;
      // The edges through the body after this round's moves: what is left if the rounds run out.
      out.edges_through = int(through.size());
      if (!any && through.empty()) break;
    }
    out.pushed_out = int(std::count(moved.begin(), moved.end(), 1));
  }
  // 2. The body from t to t + dt, carrying the cloth on it (each near vertex moves with its
  //    nearest body vertex), in fractions CCD certifies.
  const Eigen::MatrixXd motion = body_next - body_t;
  const PointKdTree body_points(body_t);  // nearest body vertex, looked up at t
  double progress = 0;
  while (progress < 1 && out.sweep_rounds < kMaxSweepRounds) {
    ++out.sweep_rounds;
    const Eigen::MatrixXd remaining = (1 - progress) * motion;
    const SurfaceProjection p = project_onto_surface(out.x, body.V, body.F);
    Eigen::VectorXi nearest;
    body_points.nearest(out.x, &nearest);
    Eigen::MatrixXd carry = Eigen::MatrixXd::Zero(n, 3);
    for (Eigen::Index i = 0; i < n; ++i)
      if (!pinned[size_t(i)] && p.distance(i) < kCarryReach * d_hat) carry.row(i) = remaining.row(nearest(i));
    const ContactCandidates c = contact_candidates(out.x, carry, cloth_edges, body, remaining, 0.0);
    const double t = max_safe_step(out.x, carry, cloth_edges, body, remaining, c);
    out.x += t * carry;
    body.V += t * remaining;
    progress += t * (1 - progress);
    if (t >= 1) progress = 1;
  }
  out.body_progress = progress;
  out.body = body.V;
  // 3. Towards the target (pins included), as far as CCD allows.
  out.target_progress = safe_move(out.x, target - out.x, cloth_edges, body, Eigen::MatrixXd());
  return out;
}

}  // namespace pb4u
