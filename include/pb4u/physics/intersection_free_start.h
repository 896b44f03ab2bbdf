#pragma once
// Where an intersection-free step starts (IPC needs a start no pair of which touches): the
// cloth at t made free of the body at t, then the body moved from its pose at t to its pose at
// t + dt in CCD-certified fractions, carrying the cloth that lies on it, and finally a
// CCD-certified move towards the step's target (the ballistic prediction). Where the body
// leaves no room (it intersects itself, or pins hold the cloth in its way), the sweep stops
// short and says how far it got: the step is then solved against the body where it stopped.
#include <Eigen/Core>

#include <vector>

namespace pb4u {

struct FeasibleStart {
  Eigen::MatrixXd x;           // n x 3 m: a start no candidate pair of which touches `body`
  Eigen::MatrixXd body;        // nb x 3 m: the body pose the start is free against
  double body_progress = 1;    // fraction of the body's motion from t to t + dt reached
  double target_progress = 1;  // fraction of the move towards the target reached
  int pushed_out = 0;          // vertices inside (or within d_hat of) the body at t, moved out
  int edges_through = 0;       // cloth edges still through the body at t after the push-out
                               // (its rounds ran out): then no start is intersection-free
  int sweep_rounds = 0;
};

// x_t: cloth at t (n x 3); target: where the step would start without contact (ballistic
// prediction, pins at their targets); pinned: per vertex, held at its target. body_t /
// body_next: the body at t and t + dt (nb x 3) with outward faces body_faces. d_hat: the
// barrier's reach (m); vertices closer than it to the body at t are pushed out to it first.
FeasibleStart intersection_free_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target,
                                      const std::vector<bool>& pinned, const Eigen::MatrixXi& cloth_edges,
                                      const Eigen::MatrixXd& body_t, const Eigen::MatrixXd& body_next,
                                      const Eigen::MatrixXi& body_faces, double d_hat);

}  // namespace pb4u
