#include "pb4u/physics/reference_solver.h"

#include <Eigen/SparseCholesky>

#include <cmath>
#include <deque>
#include <functional>

#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/quasi_newton_hessian.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

struct Pair {
  torch::Tensor s, y;
  double rho;
};

// r (3k, xyz per vertex) -> H0^-1 r.
using InverseHessian = std::function<torch::Tensor(const torch::Tensor&, const std::deque<Pair>&)>;

// L-BFGS two-loop recursion: approximately H^-1 g, starting from H0^-1.
torch::Tensor lbfgs_direction(const torch::Tensor& g, const std::deque<Pair>& history,
                              const InverseHessian& initial) {
  torch::Tensor r = g.clone();
  std::vector<double> alpha(history.size());
  for (size_t k = history.size(); k-- > 0;) {
    alpha[k] = history[k].rho * torch::dot(history[k].s, r).item<double>();
    r -= alpha[k] * history[k].y;
  }
  r = initial(r, history);
  for (size_t k = 0; k < history.size(); ++k) {
    double beta = history[k].rho * torch::dot(history[k].y, r).item<double>();
    r += (alpha[k] - beta) * history[k].s;
  }
  return -r;
}

// The elastic initial Hessian: the per-frame part (inertia + membrane) plus the contacts'
// current curvature on the diagonal, refactorised (same sparsity) only when contacts change it.
struct ElasticSolve {
  Eigen::SparseMatrix<double> base;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;

  void factorize(const torch::Tensor& contact_diagonal) {
    Eigen::SparseMatrix<double> H = base;
    if (contact_diagonal.defined()) {
      torch::Tensor c = contact_diagonal.detach().to(torch::kCPU, torch::kFloat64).contiguous();
      H.diagonal() += Eigen::Map<const Eigen::VectorXd>(c.data_ptr<double>(), c.numel());
    }
    ldlt.factorize(H);
    if (ldlt.info() != Eigen::Success)
      throw Error("reference solver: the elastic initial Hessian is not positive definite");
  }
  torch::Tensor operator()(const torch::Tensor& r) const {
    torch::Tensor c = r.detach().to(torch::kCPU, torch::kFloat64).contiguous();
    const Eigen::Index k = c.numel() / 3;
    Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> R(c.data_ptr<double>(), k, 3);
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> X = ldlt.solve(R);
    return torch::from_blob(X.data(), {k * 3}, torch::kFloat64).to(r.options()).clone();
  }
};

}  // namespace

SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config) {
  check_positions(state.x, cloth);
  check_positions(state.x_prev, cloth);
  if (!torch::isfinite(state.x).all().item<bool>() || !torch::isfinite(state.x_prev).all().item<bool>())
    throw Error("reference solver: the garment positions at t or t - dt are not finite");
  const auto opts = state.x.options();
  const int64_t n = cloth.num_vertices;

  torch::Tensor x_base = 2 * state.x - state.x_prev;  // ballistic prediction
  if (state.effects.gravity) {
    auto g = torch::tensor({state.gravity[0], state.gravity[1], state.gravity[2]}, torch::kFloat64)
                 .to(opts);
    x_base = x_base + g * (state.dt * state.dt);
  }
  torch::Tensor pinned = torch::zeros({n}, torch::TensorOptions().dtype(torch::kBool).device(state.x.device()));
  if (state.effects.pins && state.pinned.defined()) {
    if (state.pinned.numel() != n)
      throw Error("scene: pins are on but the pinned mask does not have one entry per vertex");
    pinned = state.pinned.to(state.x.device(), torch::kBool).reshape({n});
    if (pinned.any().item<bool>()) {
      if (!state.pin_targets.defined() || state.pin_targets.sizes() != state.x.sizes())
        throw Error("scene: pins are on but the pin targets are not (n, 3)");
      x_base = torch::where(pinned.unsqueeze(1), state.pin_targets.to(opts), x_base);
    }
  }
  x_base = x_base.detach();
  torch::Tensor free = torch::nonzero(~pinned).squeeze(1);
  const int64_t nf = free.size(0);

  SolverResult result;
  auto evaluate = [&](const torch::Tensor& q, torch::Tensor* grad) {
    torch::Tensor p = q.detach().reshape({nf, 3}).requires_grad_(true);
    torch::Tensor x = x_base.index_copy(0, free, p);
    torch::Tensor E = total_energy(terms, x, state, cloth, contact);
    *grad = torch::autograd::grad({E}, {p})[0].reshape({-1});
    ++result.evaluations;
    return E.item<double>();
  };

  // dt^2 / m per coordinate: the inverse inertia Hessian. Massless (unreferenced) vertices get a unit scale.
  torch::Tensor m = cloth.vertex_masses(state.material.density).index_select(0, free);
  torch::Tensor P = torch::where(m > 0, (state.dt * state.dt) / m, torch::ones_like(m))
                        .repeat_interleave(3).to(opts);
  InverseHessian initial;
  std::shared_ptr<ElasticSolve> elastic;
  if (config.initial_hessian == "elastic") {
    std::vector<int> row(n, -1);
    torch::Tensor free_cpu = free.to(torch::kCPU);
    for (int64_t k = 0; k < nf; ++k) row[free_cpu[k].item<int64_t>()] = static_cast<int>(k);
    elastic = std::make_shared<ElasticSolve>();
    elastic->base = quasi_newton_hessian(cloth, state.material, state.dt, row);
    elastic->ldlt.analyzePattern(elastic->base);
    initial = [elastic](const torch::Tensor& r, const std::deque<Pair>&) { return (*elastic)(r); };
  } else {
    // Scaled by the newest curvature pair, as in standard L-BFGS.
    initial = [P](const torch::Tensor& r, const std::deque<Pair>& history) {
      double gamma = 1.0;
      if (!history.empty())
        gamma = (1.0 / history.back().rho) /
                torch::dot(history.back().y, P * history.back().y).item<double>();
      return gamma * P * r;
    };
  }
  // Sum of the terms' contact curvature at the free vertices (undefined without contacts).
  auto contact_diagonal = [&](const torch::Tensor& q) {
    torch::Tensor x = x_base.index_copy(0, free, q.detach().reshape({nf, 3}));
    torch::Tensor sum;
    for (const auto& term : terms) {
      torch::Tensor c = term->contact_stiffness(x, state, cloth, contact);
      if (c.defined()) sum = sum.defined() ? sum + c : c;
    }
    return sum.defined() ? sum.index_select(0, free) : sum;
  };
  bool factorized = false;

  torch::Tensor q = x_base.index_select(0, free).reshape({-1});
  torch::Tensor g;
  double E = evaluate(q, &g);
  std::deque<Pair> history;
  double step_norm = 0;
  while (nf > 0) {
    if (elastic) {
      torch::Tensor c = contact_diagonal(q);
      if (!factorized || c.defined()) elastic->factorize(c);
      factorized = true;
    }
    torch::Tensor d = lbfgs_direction(g, history, initial);
    double slope = torch::dot(g, d).item<double>();
    if (!(slope < 0)) {  // lost descent (curvature noise): restart from the initial Hessian
      history.clear();
      d = lbfgs_direction(g, history, initial);
      slope = torch::dot(g, d).item<double>();
    }
    step_norm = d.abs().max().item<double>();
    if (step_norm <= config.step_tolerance || !(slope < 0) ||
        result.iterations >= config.max_iterations)
      break;
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
    ++result.iterations;
  }

  result.x_next = x_base.index_copy(0, free, q.reshape({nf, 3})).detach();
  result.energy = E;
  result.gradient_norm = nf ? g.abs().max().item<double>() : 0.0;
  result.step_norm = step_norm;
  result.converged = step_norm <= config.step_tolerance;
  return result;
}

SolverResult solve_reference_frame(const FrameState& state, const ClothGeometry& cloth,
                                   const TermList& terms, const PhysicsConfig& config) {
  std::optional<BodyContact> contact = body_contact_for(state, config);
  return solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver);
}

}  // namespace pb4u
