#include "pb4u/physics/barrier_start.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/physics/strain_barrier.h"

namespace pb4u {

BarrierStart barrier_start(const Eigen::MatrixXd& x_t, const Eigen::MatrixXd& target, const std::vector<char>& pinned,
                           bool at_next, const Eigen::MatrixXi& cloth_edges, const Eigen::MatrixXd& body_V,
                           const Eigen::MatrixXi& body_F, double d_hat) {
  BarrierStart s;
  s.at_next = at_next;
  Eigen::MatrixXd from = at_next ? target : x_t, to = target;
  if (!at_next)
    for (Eigen::Index i = 0; i < from.rows(); ++i)
      if (pinned[size_t(i)]) s.pin_rows.push_back(i);
  s.pin_now.resize(Eigen::Index(s.pin_rows.size()), 3);
  s.pin_target.resize(Eigen::Index(s.pin_rows.size()), 3);
  for (size_t j = 0; j < s.pin_rows.size(); ++j) {  // swept: the pins stay where they were at t
    s.pin_target.row(Eigen::Index(j)) = to.row(s.pin_rows[j]);
    s.pin_now.row(Eigen::Index(j)) = to.row(s.pin_rows[j]) = from.row(s.pin_rows[j]);
  }
  FeasibleStart feasible = intersection_free_start(from, to, cloth_edges, body_V, body_F, d_hat);
  for (size_t j = 0; j < s.pin_rows.size(); ++j) feasible.x.row(s.pin_rows[j]) = s.pin_now.row(Eigen::Index(j));  // no pin moved
  spdlog::debug("barrier start{}: {} pushed out, {} excluded, target reached {:.3f}", at_next ? " at the given step" : "",
                feasible.pushed_out, feasible.excluded_count, feasible.target_progress);
  s.x = std::move(feasible.x);
  s.excluded = std::move(feasible.excluded);
  s.excluded_count = feasible.excluded_count;
  s.pushed_out = feasible.pushed_out;
  return s;
}

void limit_start_strain(BarrierStart& start, const Eigen::MatrixXi& strain_edges, const Eigen::VectorXd& rest,
                        double limit, double inside, const std::vector<char>& pinned, const Eigen::MatrixXi& cloth_edges,
                        const Eigen::MatrixXd& body_V, const Eigen::MatrixXi& body_F, double d_hat, int rounds) {
  // What a start leaves out of either barrier.
  auto left_out = [&](const Eigen::MatrixXd& X, const std::vector<char>& out) {
    const std::vector<char> over = edges_over_strain(X, strain_edges, rest, limit);
    return std::count(over.begin(), over.end(), 1) + std::count(out.begin(), out.end(), 1);
  };
  Eigen::MatrixXd X = start.x;
  std::vector<char> out = start.excluded;
  auto best = left_out(X, out);
  for (int round = 0; round < rounds && best > 0; ++round) {
    const Eigen::MatrixXd shortened = shorten_overstretched_edges(X, strain_edges, rest, inside, pinned);
    FeasibleStart again = intersection_free_start(shortened, shortened, cloth_edges, body_V, body_F, d_hat);
    X = std::move(again.x);
    out = std::move(again.excluded);
    const auto now = left_out(X, out);
    if (now < best) {
      best = now;
      start.x = X;
      start.excluded = out;
    }
  }
  start.excluded_count = int(std::count(start.excluded.begin(), start.excluded.end(), 1));
}

}  // namespace pb4u
