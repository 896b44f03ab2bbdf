#include "pb4u/physics/step_residual.h"

#include <Eigen/SparseCholesky>

#include "pb4u/physics/barrier_objective.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/elastic_hessian.h"
#include "pb4u/physics/elastic_solve.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/physics/quasi_newton_hessian.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

// Per vertex, N/m: the bending's curvature, the diagonal of its Gauss-Newton Hessian, where the
// bending term is active. As a face flattens, the bending's gradient grows as 1 / its height and
// this as 1 / height^2, so the step H^-1 grad E stays a distance (without it, a face at 2.6e-7 of
// its rest area read 2.5e6 mm). Isotropic, as the contact curvature beside it; where no face is
// near collapse it is small against the inertia M / dt^2.
Eigen::VectorXd bending_curvature(const Eigen::MatrixXd& X, const ClothGeometry& cloth, const Material& material,
                                  const TermList& terms, const BarrierStepInput* barrier) {
  for (const auto& term : terms)
    if (!barrier || !barrier->drops(*term))
      if (const auto* bending = dynamic_cast<const BendingTerm*>(term.get()))
        return bending_hessian_diagonal(X, cloth, material, bending->degenerate_area());
  return Eigen::VectorXd::Zero(X.rows());
}

// Adds the reference solver's Newton Hessian at X but the inertia and the barrier pairs
// (incremental_potential_solve.cpp, contact_diagonal with step newton) into *H: the elastic
// terms' Hessians and each term's contact curvature in its direction (the penalty's on the
// vertices the barrier left to it).
void add_elastic_and_contact_hessian(const Eigen::MatrixXd& X, const torch::Tensor& x, const FrameState& state,
                                     const ClothGeometry& cloth, const TermList& terms, const BodyContact* contact,
                                     const BarrierStepInput* barrier, const PenaltyFallback& fallback,
                                     CoordinateHessian* H) {
  auto add_contact = [&](const PhysicsTerm& term, const torch::Tensor& c) {
    const Eigen::VectorXd k = tensor_to_matrix(c.reshape({-1, 1})).col(0);
    const PhysicsTerm::ContactDirection direction = term.contact_direction(state, contact);
    if (direction.normal.defined()) {
      add_directional_stiffness(k, tensor_to_matrix(direction.normal), direction.across, H);
    } else {
      for (Eigen::Index v = 0; v < k.size(); ++v)
        if (k(v) != 0) H->add(int(v), int(v), k(v) * Eigen::Matrix3d::Identity());
    }
  };
  for (const auto& term : terms) {
    if (barrier && barrier->drops(*term)) continue;
    if (term->name() == "stretch") add_stretch_hessian(X, cloth, state.material, H);
    if (const auto* bending = dynamic_cast<const BendingTerm*>(term.get()))
      add_bending_hessian(X, cloth, state.material, bending->degenerate_area(), H);
    const torch::Tensor c = term->contact_stiffness(x, state, cloth, contact);
    if (c.defined()) add_contact(*term, c);
  }
  if (fallback.active()) add_contact(*fallback.term, fallback.stiffness(x, state, cloth, contact));
}

}  // namespace

ResidualHessian residual_hessian_from_name(const std::string& name) {
  if (name == "newton") return ResidualHessian::newton;
  if (name == "quasi_newton") return ResidualHessian::quasi_newton;
  throw Error("physics.solver.residual_hessian: '" + name + "' is not newton or quasi_newton");
}

double step_residual(const torch::Tensor& x_next, const FrameState& state, const ClothGeometry& cloth,
                     const TermList& terms, const BodyContact* contact, const BarrierStepInput* barrier,
                     const std::vector<char>* excluded_by_solver, ResidualHessian metric) {
  const int64_t n = cloth.num_vertices;
  std::vector<char> pinned(size_t(n), 0);
  if (state.effects.pins && state.pinned.defined()) {
    const torch::Tensor p = state.pinned.to(torch::kCPU, torch::kBool).reshape({n}).contiguous();
    for (int64_t i = 0; i < n; ++i) pinned[size_t(i)] = p.data_ptr<bool>()[i];
  }
  std::vector<int> row(size_t(n), -1);
  int k = 0;
  for (int64_t i = 0; i < n; ++i)
    if (!pinned[size_t(i)]) row[size_t(i)] = k++;
  if (k == 0) return 0;
  // The contact the barrier solve measured its penalty and friction with (solver.penalty_faces).
  const std::optional<BodyContact> solved = barrier ? barrier->solved_contact(state, contact) : std::nullopt;
  if (solved) contact = &*solved;

  torch::Tensor x = x_next.detach().to(torch::kFloat64).clone().requires_grad_(true);
  // Barrier contact: the vertices not free of the body leave the barrier for the penalty term.
  Eigen::MatrixXd X;
  ContactSurface body;
  ContactCandidates candidates;
  PenaltyFallback fallback;
  if (barrier) {
    X = tensor_to_matrix(x.detach());
    body = make_contact_surface(barrier->body_next, barrier->body_faces);
    // The solver's set as it gave it (empty: it left none out), else who is not free at x_next.
    std::vector<char> excluded = excluded_by_solver ? *excluded_by_solver
                                                    : vertices_not_free_of(X, barrier->cloth_edges, body.V,
                                                                           body.F, barrier->settings.d_hat);
    if (excluded.empty()) excluded.assign(size_t(n), 0);
    candidates = contact_candidates(X, {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
    drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
    if (!barrier->keeps_penalty) fallback = penalty_fallback(terms, contact, excluded);
  }
  torch::Tensor E = torch::zeros({}, x.options());
  for (const auto& term : terms)
    if (!barrier || !barrier->drops(*term)) E = E + term->energy(x, state, cloth, contact);
  E = E + fallback.energy(x);
  Eigen::MatrixXd G = tensor_to_matrix(torch::autograd::grad({E}, {x})[0]);
  if (metric == ResidualHessian::newton) {
    torch::NoGradGuard no_grad;
    if (!X.size()) X = tensor_to_matrix(x.detach());
    // The solver's own Newton solve: inertia M / dt^2, then the blocks above and the barrier's.
    const std::shared_ptr<ElasticSolve> solve =
        newton_elastic_solve(cloth.vertex_masses(state.material.density), state.dt, row, k);
    add_elastic_and_contact_hessian(X, x.detach(), state, cloth, terms, contact, barrier, fallback, &solve->hessian);
    if (barrier) {  // its gradient and its blocks in one pass over the pairs
      Eigen::MatrixXd barrier_gradient = Eigen::MatrixXd::Zero(n, 3);
      barrier_potential(X, barrier->cloth_edges, body, candidates, barrier->settings, &barrier_gradient, nullptr,
                        &solve->hessian);
      G += barrier_gradient;
    }
    try {
      solve->factorize(torch::Tensor());  // with the diagonal shifted where rounding loses a pivot
    } catch (const Error&) {
      return std::numeric_limits<double>::quiet_NaN();
    }
    Eigen::VectorXd r(3 * k);
    for (int64_t i = 0; i < n; ++i)
      if (row[size_t(i)] >= 0) r.segment<3>(3 * row[size_t(i)]) = G.row(i).transpose();
    const Eigen::VectorXd d = solve->ldlt.solve(r);
    return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(d.data(), k, 3)
        .rowwise()
        .norm()
        .maxCoeff();
  }
  Eigen::VectorXd barrier_curvature = Eigen::VectorXd::Zero(n);
  if (barrier) {
    Eigen::MatrixXd barrier_gradient = Eigen::MatrixXd::Zero(n, 3);
    barrier_potential(X, barrier->cloth_edges, body, candidates, barrier->settings, &barrier_gradient,
                      &barrier_curvature);
    G += barrier_gradient;
  }

  Eigen::SparseMatrix<double> H = quasi_newton_hessian(cloth, state.material, state.dt, row);
  {
    torch::NoGradGuard no_grad;
    torch::Tensor contact_curvature;
    for (const auto& term : terms) {
      if (barrier && barrier->drops(*term)) continue;
      torch::Tensor c = term->contact_stiffness(x.detach(), state, cloth, contact);
      if (c.defined()) contact_curvature = contact_curvature.defined() ? contact_curvature + c : c;
    }
    const torch::Tensor held = fallback.stiffness(x.detach(), state, cloth, contact);
    if (held.defined()) contact_curvature = contact_curvature.defined() ? contact_curvature + held : held;
    const Eigen::VectorXd diagonal =
        barrier_curvature +
        bending_curvature(X.size() ? X : tensor_to_matrix(x.detach()), cloth, state.material, terms, barrier);
    for (int64_t i = 0; i < n; ++i)
      if (row[size_t(i)] >= 0) H.coeffRef(row[size_t(i)], row[size_t(i)]) += diagonal(i);
    if (contact_curvature.defined()) {
      const torch::Tensor c = contact_curvature.to(torch::kCPU, torch::kFloat64).contiguous();
      for (int64_t i = 0; i < n; ++i)
        if (row[size_t(i)] >= 0) H.coeffRef(row[size_t(i)], row[size_t(i)]) += c.data_ptr<double>()[i];
    }
  }
  Eigen::MatrixXd R(k, 3);
  for (int64_t i = 0; i < n; ++i)
    if (row[size_t(i)] >= 0) R.row(row[size_t(i)]) = G.row(i);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
  if (ldlt.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::MatrixXd D = ldlt.solve(R);
  return D.rowwise().norm().maxCoeff();
}

}  // namespace pb4u
