#include "pb4u/physics/reference_solver.h"

#include <cmath>
#include <deque>

#include "pb4u/physics/energy_report.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

struct Pair {
  torch::Tensor s, y;
  double rho;
};

// L-BFGS two-loop recursion: approximately H^-1 g, with the initial inverse Hessian
// gamma * P. P = dt^2 / m is the exact inverse Hessian of the inertia term, so the first
// step is already scaled like an implicit-Euler step.
torch::Tensor lbfgs_direction(const torch::Tensor& g, const std::deque<Pair>& history,
                              const torch::Tensor& P) {
  torch::Tensor r = g.clone();
  std::vector<double> alpha(history.size());
  for (size_t k = history.size(); k-- > 0;) {
    alpha[k] = history[k].rho * torch::dot(history[k].s, r).item<double>();
    r -= alpha[k] * history[k].y;
  }
  double gamma = 1.0;
  if (!history.empty()) {
    const Pair& last = history.back();
    gamma = (1.0 / last.rho) / torch::dot(last.y, P * last.y).item<double>();
  }
  r = gamma * P * r;
  for (size_t k = 0; k < history.size(); ++k) {
    double beta = history[k].rho * torch::dot(history[k].y, r).item<double>();
    r += (alpha[k] - beta) * history[k].s;
  }
  return -r;
}

}  // namespace

SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config) {
  check_positions(state.x, cloth);
  check_positions(state.x_prev, cloth);
  const auto opts = state.x.options();
  const int64_t n = cloth.num_vertices;

  torch::Tensor x_base = 2 * state.x - state.x_prev;  // ballistic prediction
  if (state.effects.gravity) {
    auto g = torch::tensor({state.gravity[0], state.gravity[1], state.gravity[2]}, torch::kFloat64)
                 .to(opts);
    x_base = x_base + g * (state.dt * state.dt);
  }
  torch::Tensor free = torch::arange(n, torch::TensorOptions().dtype(torch::kInt64).device(state.x.device()));
  if (state.effects.pins && state.pinned.defined() && state.pinned.any().item<bool>()) {
    if (!state.pin_targets.defined() || state.pin_targets.sizes() != state.x.sizes())
      throw Error("scene: pins are on but the pin targets are not (n, 3)");
    auto pinned = state.pinned.to(state.x.device(), torch::kBool);
    x_base = torch::where(pinned.unsqueeze(1), state.pin_targets.to(opts), x_base);
    free = torch::nonzero(~pinned).squeeze(1);
  }
  x_base = x_base.detach();

  SolverResult result;
  const int64_t nf = free.size(0);
  auto evaluate = [&](const torch::Tensor& q, torch::Tensor* grad) {
    torch::Tensor p = q.detach().reshape({nf, 3}).requires_grad_(true);
    torch::Tensor x = x_base.index_copy(0, free, p);
    torch::Tensor E = total_energy(terms, x, state, cloth, contact);
    *grad = torch::autograd::grad({E}, {p})[0].reshape({-1});
    ++result.evaluations;
    return E.item<double>();
  };

  torch::Tensor q = x_base.index_select(0, free).reshape({-1});
  torch::Tensor g;
  double E = evaluate(q, &g);
  // Inverse inertia Hessian per coordinate; massless (unreferenced) vertices get a unit scale.
  torch::Tensor m = cloth.vertex_masses(state.material.density).index_select(0, free);
  torch::Tensor P = torch::where(m > 0, (state.dt * state.dt) / m, torch::ones_like(m))
                        .repeat_interleave(3).to(opts);

  std::deque<Pair> history;
  double gnorm = nf ? g.abs().max().item<double>() : 0.0;
  while (gnorm > config.gradient_tolerance && result.iterations < config.max_iterations) {
    torch::Tensor d = lbfgs_direction(g, history, P);
    double slope = torch::dot(g, d).item<double>();
    if (!(slope < 0)) {  // lost descent (curvature noise): restart from the preconditioned gradient
      history.clear();
      d = -P * g;
      slope = torch::dot(g, d).item<double>();
    }
    double t = 1.0;
    bool accepted = false;
    torch::Tensor q_new, g_new;
    double E_new = E;
    for (int ls = 0; ls < config.max_line_search_steps; ++ls, t *= 0.5) {
      q_new = q + t * d;
      E_new = evaluate(q_new, &g_new);
      if (std::isfinite(E_new) && E_new <= E + config.armijo * t * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;  // no decrease left at this precision
    torch::Tensor s = q_new - q, y = g_new - g;
    double sy = torch::dot(s, y).item<double>();
    if (sy > 0) {  // keep the inverse-Hessian estimate positive definite
      history.push_back({s, y, 1.0 / sy});
      if (static_cast<int>(history.size()) > config.history) history.pop_front();
    }
    q = q_new;
    g = g_new;
    E = E_new;
    gnorm = g.abs().max().item<double>();
    ++result.iterations;
  }

  result.x_next = x_base.index_copy(0, free, q.reshape({nf, 3})).detach();
  result.energy = E;
  result.gradient_norm = gnorm;
  result.converged = gnorm <= config.gradient_tolerance;
  return result;
}

}  // namespace pb4u
