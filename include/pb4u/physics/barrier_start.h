#pragma once
// Where the intersection-free solve's step starts (reference_solver.h): a cloth state no pair
// of which touches the body where the solve starts, with its pins' motion still to come.
//
// Swept (the solver's own start, or a given step swept from t): from the cloth at t towards the
// target against the body at t (intersection_free_start.h); the pins stay where they were at t
// and the body's moves carry them to their targets. At the given step: the step itself made
// free of the body at t + dt, its pins already at their targets.
//
// With a strain limit, the pushes out of the body stretch edges: limit_start_strain alternates
// Provot's pass (pins held) with the push out of the body, so that the start is within both
// barriers or leaves the fewest edges and vertices out of them.
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pb4u {

struct BarrierStart {
  Eigen::MatrixXd x;              // n x 3 m: free of the body but for the vertices `excluded`
  std::vector<char> excluded;     // per cloth vertex: no free place found, out of barrier contact
  int excluded_count = 0;
  int pushed_out = 0;             // vertices moved out of the body (inside or touching it)
  bool at_next = false;           // the given step at t + dt (the body at its pose), not swept from t
  std::vector<int64_t> pin_rows;  // the pins the body's moves carry (swept only)
  Eigen::MatrixXd pin_now, pin_target;  // their rows, k x 3: where they are, where they go
};

// x_t: the cloth at t (n x 3); target: where the step would start without contact (pins at their
// targets); pinned: per vertex, 1 for a pin; body_V: the body where the start is made (at t,
// or at t + dt with at_next), with outward faces body_F; d_hat: the barrier's reach (m).
BarrierStart barrier_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target, const std::vector<char>& pinned,
                           bool at_next, const Eigen::MatrixXi& cloth_edges, const Eigen::MatrixXd& body_V,
                           const Eigen::MatrixXi& body_F, double d_hat);

// The start brought within the strain limit as well: up to `rounds` rounds of Provot's pass to
// `inside` (pins held) and the push out of the body, which goes last so that contact keeps its
// guarantee; the start that leaves the fewest edges past `limit` plus vertices out of contact is
// kept. strain_edges, rest: the strained edges and their rest lengths.
void limit_start_strain(BarrierStart& start, const Eigen::MatrixXi& strain_edges, const Eigen::VectorXd& rest,
                        double limit, double inside, const std::vector<char>& pinned, const Eigen::MatrixXi& cloth_edges,
                        const Eigen::MatrixXd& body_V, const Eigen::MatrixXi& body_F, double d_hat, int rounds);

}  // namespace pb4u
