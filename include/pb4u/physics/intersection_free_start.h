#pragma once
// Where an intersection-free step starts (IPC needs a start no pair of which touches): the
// cloth at t made free of the body at t, then moved towards the step's target (the ballistic
// prediction, pins at their targets) as far as CCD certifies. The body's own motion from t to
// t + dt is left to the solve (reference_solver.h), which moves the body and the cloth together.
//
// Free of the body: vertices inside it, or closer than a tenth of d_hat, go d_hat outside; an
// edge whose ends are both outside can still cut through the body (a chord across a hand), so
// its ends go further out, twice as far each round. Where that finds no free place within a
// few rounds (the cloth pinched between two body parts, a body that intersects itself), the
// vertices of the edges still through the body, or touching it, are excluded from contact for
// this step and counted: the step is intersection-free for every other vertex, and says how
// many it left out.
#include <Eigen/Core>

#include <vector>

namespace pb4u {

struct FeasibleStart {
  Eigen::MatrixXd x;            // n x 3 m: no candidate pair of a vertex not excluded touches the body
  std::vector<char> excluded;   // per cloth vertex: 1 where no free place was found (out of contact)
  int excluded_count = 0;
  int pushed_out = 0;           // vertices moved out of the body at t (inside or touching it)
  std::vector<char> pushed;     // per cloth vertex: 1 for those
  double target_progress = 1;   // fraction of the move towards the target reached
};

// Per cloth vertex, 1 where it is not free of the body (V, outward faces F): inside it, ending
// a cloth edge through it, or closer than a hundredth of d_hat in a vertex-face or edge-edge
// pair (rounding cannot tell such a pair's side).
std::vector<char> vertices_not_free_of(const Eigen::MatrixXd& x, const Eigen::MatrixXi& cloth_edges,
                                       const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double d_hat);

// Pinned vertices (rows `pinned` of x, n x 3) moved out of the body (V, outward faces F) until
// no edge between two of them cuts through it. A waistband skinned a few millimetres outside a
// waist is a polygon: its chords cut a curved waist (a 12 cm edge round a 12 cm waist radius
// dips 15 mm), and a pin is a hard constraint no solver can move. Each round moves both ends of
// every such edge still through the body `step` m further out, along the body's outward
// direction at its closest point, for at most `max_rounds` rounds. In place; returns how many
// edges are still through.
int push_pinned_edges_free_of_body(Eigen::MatrixXd& x, const std::vector<int>& pinned, const Eigen::MatrixXi& edges,
                                   const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double step = 1e-3,
                                   int max_rounds = 50);

// x_t: cloth at t (n x 3); target: where the step would start without contact (n x 3);
// body_t: the body at t (nb x 3) with outward faces body_faces; d_hat: the barrier's reach (m).
FeasibleStart intersection_free_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target,
                                      const Eigen::MatrixXi& cloth_edges, const Eigen::MatrixXd& body_t,
                                      const Eigen::MatrixXi& body_faces, double d_hat);

}  // namespace pb4u
