// One frame's solve: its start, its objective and its iterations.
#include "pb4u/physics/incremental_potential_solve.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <string>

#include "pb4u/mesh/edges.h"
#include "pb4u/physics/barrier_objective.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/barrier_start.h"
#include "pb4u/physics/area_barrier.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/physics/elastic_hessian.h"
#include "pb4u/physics/elastic_solve.h"
#include "pb4u/physics/strain_barrier.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {
namespace reference_solve {

torch::Tensor free_coordinates(const Eigen::MatrixXd& rows, const torch::Tensor& free, const torch::TensorOptions& opts) {
  return matrix_to_tensor(rows, opts.dtype().toScalarType(), opts.device()).index_select(0, free).reshape({-1});
}

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

IncrementalPotentialSolve::IncrementalPotentialSolve(const FrameState& state_, const ClothGeometry& cloth_,
                                                     const TermList& terms_, const BodyContact* contact_,
                                                     const ReferenceSolverConfig& config_,
                                                     const BarrierStepInput* barrier_, const torch::Tensor* x_start)
    : state(state_),
      cloth(cloth_),
      terms(terms_),
      contact(contact_),
      config(config_),
      barrier(barrier_),
      opts(state_.x.options()),
      n(cloth_.num_vertices),
      strain_settings{config_.strain_limit, config_.strain_barrier_gap, config_.strain_barrier_stiffness},
      area_settings{config_.area_barrier_gap, config_.area_barrier_stiffness} {
  check_positions(state.x, cloth);
  check_positions(state.x_prev, cloth);
  if (!torch::isfinite(state.x).all().item<bool>() || !torch::isfinite(state.x_prev).all().item<bool>())
    throw Error("reference solver: the garment positions at t or t - dt are not finite");
  place_ballistic_start(x_start);
  shorten_start_edges();
  if (barrier && config.initial_hessian != "elastic")
    throw Error("reference solver: solver.contact: barrier needs solver.initial_hessian: elastic");
  settings = barrier ? barrier->settings : BarrierSettings{};
  if (barrier) make_barrier_start(x_start);
  if (strain) exclude_overstretched(tensor_to_matrix(x_base));
  // Area barrier: a face already in the barrier's band where the solve starts, or after a body
  // move, stays out of it until its area is back above the band. The barrier keeps the solve from
  // collapsing a face; it must not hold a face the start left folded over its neighbours (a
  // fold undone through a collapse), which it would lock in.
  area = config.area_barrier_gap > 0;
  if (area) {
    area_faces = index_tensor_to_matrix(cloth.faces);
    rest_area = tensor_to_matrix(cloth.face_area.to(torch::kCPU, torch::kFloat64).reshape({-1, 1})).col(0);
    exclude_compressed(tensor_to_matrix(x_base));
  }
  // The vertices out of barrier contact (the start found them no free place, or the placed body
  // caught them) fall back to the penalty term (SPEC 3.3) until a later step frees them.
  set_fallback();
  // Per vertex: free or held, and its row among the free coordinates (-1 when held).
  free_flags.assign(size_t(n), 0);
  row.assign(size_t(n), -1);
  {
    const torch::Tensor free_cpu = free.to(torch::kCPU).contiguous();
    const int64_t* index = free_cpu.data_ptr<int64_t>();
    for (int64_t k = 0; k < nf; ++k) {
      free_flags[size_t(index[k])] = 1;
      row[size_t(index[k])] = static_cast<int>(k);
    }
  }
  make_inverse_hessian();
  pick_start();
  stopped_by = nf > 0 ? "the iteration limit" : "nothing to solve (every vertex held)";
}

// x_base: the ballistic prediction (or the given step, x_start), pins on their targets.
void IncrementalPotentialSolve::place_ballistic_start(const torch::Tensor* x_start) {
  x_base = 2 * state.x - state.x_prev;  // ballistic prediction
  if (state.effects.gravity) {
    auto gravity = torch::tensor({state.gravity[0], state.gravity[1], state.gravity[2]}, torch::kFloat64)
                       .to(opts);
    x_base = x_base + gravity * (state.dt * state.dt);
  }
  pinned = torch::zeros({n}, torch::TensorOptions().dtype(torch::kBool).device(state.x.device()));
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
  if (!barrier) x_standing = torch::where(pinned.unsqueeze(1), x_base, state.x.to(opts)).detach();
  if (x_start) {  // a given step (the network's) instead of the ballistic prediction; pins as held
    if (x_start->sizes() != state.x.sizes()) throw Error("reference solver: the start step is not (n, 3)");
    if (!barrier) x_own = x_base;
    if (barrier && config.own_start_where_left_out) x_ballistic = x_base.detach();
    x_base = torch::where(pinned.unsqueeze(1), x_base, x_start->to(opts));
  }
  x_base = x_base.detach();
  free = torch::nonzero(~pinned).squeeze(1);
  nf = free.size(0);
  const torch::Tensor pinned_cpu = pinned.to(torch::kCPU).contiguous();
  pinned_flags.assign(pinned_cpu.data_ptr<bool>(), pinned_cpu.data_ptr<bool>() + n);
}

// Strain barrier: the start's overstretched edges shortened (Provot, pins held) to half the
// barrier's band inside the limit; an edge still past it (between two pins) stays out.
void IncrementalPotentialSolve::shorten_start_edges() {
  strain = config.strain_limit > 0;
  if (!strain) return;
  strain_edges = barrier ? barrier->cloth_edges : unique_edges(index_tensor_to_matrix(cloth.faces));
  rest_length = tensor_to_matrix(cloth.edge_rest_length.to(torch::kCPU, torch::kFloat64).reshape({-1, 1})).col(0);
  const double inside = std::max(0.0, config.strain_limit - 0.5 * config.strain_barrier_gap);
  for (torch::Tensor* x : {&x_base, &x_own, &x_standing, &x_ballistic})
    if (x->defined())
      *x = matrix_to_tensor(shorten_overstretched_edges(tensor_to_matrix(*x), strain_edges, rest_length, inside, pinned_flags),
                            opts.dtype().toScalarType(), state.x.device());
}

// Barrier contact: the solve starts from an intersection-free cloth (pins where it could bring
// them) and the body at t. The body's motion to t + dt is a boundary condition (IPC's
// kinematic objects): each iteration first moves the body by what is left of it, the cloth it
// touches carried along (carried_by_body.h), as far as CCD certifies; then one quasi-Newton
// step of the cloth against the body where it stands. Where the cloth leaves the body no room
// (pinched between two body parts) a body still short of its pose after the moves it is
// allowed is placed there, and the cloth it then cuts or holds leaves barrier contact; with
// solver.release_held_cloth the cloth that holds a move back leaves it first and the body
// moves on (SolverResult::caught_by_body counts both).
// Pins start where they were at t (where the body at t left them room) and reach their targets
// with the body's motion. A given step (x_start) started where it stands is already at t + dt
// with the body placed there, and its pins at their targets.
void IncrementalPotentialSolve::make_barrier_start(const torch::Tensor* x_start) {
  // From the cloth at t towards x_base against the body at t (the solver's own start, and a
  // given step swept), or from the given step itself against the body at t + dt.
  using GivenStart = BarrierStepInput::GivenStart;
  const Eigen::MatrixXd x_t = tensor_to_matrix(state.x), target = tensor_to_matrix(x_base);
  // towards: the given step or prediction (target), or the ballistic prediction (own start).
  auto make_start = [&](bool at_next, const Eigen::MatrixXd& towards) {
    return barrier_start(x_t, towards, pinned_flags, at_next, barrier->cloth_edges,
                         at_next ? barrier->body_next : barrier->body_t, barrier->body_faces, barrier->settings.d_hat);
  };
  BarrierStart start = make_start(x_start && barrier->given_start != GivenStart::swept, target);
  if (x_start && barrier->given_start == GivenStart::fewer_left_out && start.excluded_count > 0) {
    BarrierStart swept = make_start(false, target);
    if (swept.excluded_count < start.excluded_count) start = std::move(swept);
  }
  // Where the step left cloth inside the body with no free place near (pinched where the body
  // crosses itself, or deep in a body that went through it), the body's own motion from t
  // decides where that cloth goes.
  if (x_start && barrier->given_start == GivenStart::swept_if_left_out && start.excluded_count > 0)
    start = make_start(false, target);
  // own_start_where_left_out: cloth the given step left with no free place goes where the
  // solver's own motion takes it; the step is dropped for this solve. Taken whether or not the
  // own start leaves fewer vertices out at its start: the release (release_held_cloth) frees
  // cloth during the solve that both starts leave out, and on the tank top's CMU walk a rule
  // that compared the two starts read 1.62x the reference against 1.46x (docs/physics.md).
  if (x_start && x_ballistic.defined() && start.excluded_count > 0) {
    spdlog::debug("barrier start: the given step leaves {} vertices out; the solver's own start instead",
                  start.excluded_count);
    start = make_start(false, tensor_to_matrix(x_ballistic));
    result.own_start = true;
  }
  spdlog::debug("barrier start chosen after {:.0f} ms", ms_since(start_time));
  result.swept_start = x_start && !start.at_next;
  body_start = start.at_next ? &barrier->body_next : &barrier->body_t;
  result.pushed_out = start.pushed_out;
  if (strain)  // the pushes out of the body stretch edges: the start within both barriers
    limit_start_strain(start, strain_edges, rest_length, config.strain_limit,
                       std::max(0.0, config.strain_limit - 0.5 * config.strain_barrier_gap), pinned_flags,
                       barrier->cloth_edges, *body_start, barrier->body_faces, barrier->settings.d_hat, kStartRounds);
  result.excluded = start.excluded_count;
  excluded = start.excluded;
  pin_rows = std::move(start.pin_rows);
  pin_now = std::move(start.pin_now);
  pin_target = std::move(start.pin_target);
  pin_index = torch::tensor(pin_rows, torch::kInt64).to(state.x.device());
  body = make_contact_surface(*body_start, barrier->body_faces);
  x_base = matrix_to_tensor(start.x, opts.dtype().toScalarType(), state.x.device());
  candidates = contact_candidates(start.x, {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
}

// H0^-1 of the step: the elastic Hessian factorised (with the contact curvature added each
// iteration), for Newton at the current state, or else the inverse inertia scaled as in L-BFGS.
void IncrementalPotentialSolve::make_inverse_hessian() {
  // dt^2 / m per coordinate: the inverse inertia Hessian. Massless (unreferenced) vertices get a unit scale.
  torch::Tensor m = cloth.vertex_masses(state.material.density).index_select(0, free);
  torch::Tensor P = torch::where(m > 0, (state.dt * state.dt) / m, torch::ones_like(m))
                        .repeat_interleave(3).to(opts);
  newton = config.step == "newton" || (config.step == "auto" && barrier);
  if (newton) {  // the elastic terms' Hessian at the current state joins the inertia every iteration
    elastic = newton_elastic_solve(cloth.vertex_masses(state.material.density), state.dt, row, nf);
    initial = [e = elastic](const torch::Tensor& r, const std::deque<Pair>&) { return (*e)(r); };
  } else if (config.initial_hessian == "elastic") {
    elastic = quasi_newton_elastic_solve(cloth, state.material, state.dt, row,
                                         (barrier || strain || area) && config.barrier_hessian == "blocks");
    initial = [e = elastic](const torch::Tensor& r, const std::deque<Pair>&) { return (*e)(r); };
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
}

// q, g, E at the start; a given step above the solver's own start is not the better start, and
// neither is a ballistic prediction above the cloth where it stands.
void IncrementalPotentialSolve::pick_start() {
  q = x_base.index_select(0, free).reshape({-1});
  E = evaluate(q, &g);
  // Takes `x` as the start where it is lower in the objective than the one so far.
  auto lower = [&](const torch::Tensor& x, const char* what) {
    torch::Tensor g_x;
    const torch::Tensor q_x = x.index_select(0, free).reshape({-1});
    const double E_x = evaluate(q_x, &g_x);
    if (!(E_x < E || (!std::isfinite(E) && std::isfinite(E_x)))) return false;
    spdlog::debug("reference solver: starting from {} ({:.6g} J), lower than {:.6g} J", what, E_x, E);
    q = q_x;
    g = g_x;
    E = E_x;
    return true;
  };
  if (x_own.defined()) result.own_start = lower(x_own, "its own start (the given step is higher)");
  // Where the prediction carries a velocity the elastic terms resist hard, e.g. across a sliver
  // triangle whose rest height is 1e-8 m, doubling a residual offset from the last step costs
  // more than the kinetic energy that standing still gives up.
  if (x_standing.defined()) result.standing_start = lower(x_standing, "the cloth where it stands");
}

void IncrementalPotentialSolve::exclude_overstretched(const Eigen::MatrixXd& X) {
  const std::vector<char> over = edges_over_strain(X, strain_edges, rest_length, config.strain_limit);
  if (strain_excluded.empty()) strain_excluded.assign(over.size(), 0);
  for (size_t e = 0; e < over.size(); ++e)
    if (over[e] && !strain_excluded[e]) {
      strain_excluded[e] = 1;
      ++result.strain_excluded;
    }
}

void IncrementalPotentialSolve::exclude_compressed(const Eigen::MatrixXd& X) {
  const std::vector<char> collapsed = faces_below_area(X, area_faces, rest_area, config.area_barrier_gap);
  if (area_excluded.empty()) area_excluded.assign(collapsed.size(), 0);
  for (size_t f = 0; f < collapsed.size(); ++f)
    if (collapsed[f] && !area_excluded[f] && rest_area(Eigen::Index(f)) > 0) {  // (no rest area: never in it)
      area_excluded[f] = 1;
      ++result.area_excluded;
    }
}

// An edge left out of the strain barrier that the stretch term has pulled back out of the
// barrier's band rejoins it (its energy there is zero, so E stands); a face left out of the area
// barrier rejoins it once its area is back above the band.
void IncrementalPotentialSolve::readmit_relaxed_edges_and_faces() {
  if (strain && result.strain_excluded > 0) {
    const std::vector<char> near = edges_over_strain(positions(q), strain_edges, rest_length,
                                                     config.strain_limit - config.strain_barrier_gap);
    for (size_t e = 0; e < near.size(); ++e)
      if (strain_excluded[e] && !near[e]) strain_excluded[e] = 0;
  }
  if (area && result.area_excluded > 0) {
    const std::vector<char> small = faces_below_area(positions(q), area_faces, rest_area, config.area_barrier_gap);
    for (size_t f = 0; f < small.size(); ++f)
      if (area_excluded[f] && !small[f]) area_excluded[f] = 0;
  }
}

void IncrementalPotentialSolve::set_fallback() {
  if (barrier && !barrier->keeps_penalty) fallback = penalty_fallback(terms, contact, excluded);
}

Eigen::MatrixXd IncrementalPotentialSolve::positions(const torch::Tensor& q_) const {
  return tensor_to_matrix(x_base.index_copy(0, free, q_.detach().reshape({nf, 3})));
}

// The objective at q and its gradient. With the barrier, it takes the penalty collision term's
// place unless kept.
double IncrementalPotentialSolve::evaluate(const torch::Tensor& q_, torch::Tensor* grad) {
  torch::Tensor p = q_.detach().reshape({nf, 3}).requires_grad_(true);
  torch::Tensor x = x_base.index_copy(0, free, p);
  torch::Tensor energy_t = torch::zeros({}, x.options());
  for (const auto& term : terms)
    if (!barrier || !barrier->drops(*term)) energy_t = energy_t + term->energy(x, state, cloth, contact);
  if (fallback.active()) energy_t = energy_t + fallback.energy(x);
  *grad = torch::autograd::grad({energy_t}, {p})[0].reshape({-1});
  ++result.evaluations;
  double energy = energy_t.item<double>();
  if (barrier || strain || area) {
    const Eigen::MatrixXd X = positions(q_);
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 3);
    if (barrier) {
      const BarrierValue b = barrier_potential(X, barrier->cloth_edges, body, candidates, settings, &G);
      energy += b.energy;
      closest = b.min_distance;
    }
    if (strain) energy += strain_barrier(X, strain_edges, rest_length, strain_settings, strain_excluded, &G).energy;
    if (area) energy += area_barrier(X, area_faces, rest_area, area_settings, area_excluded, &G).energy;
    *grad += free_coordinates(G, free, opts);
  }
  return energy;
}

// Sum of the terms' contact curvature at the free vertices (undefined without contacts); the
// barriers' goes into *blocks instead when given.
torch::Tensor IncrementalPotentialSolve::contact_diagonal(const torch::Tensor& q_, CoordinateHessian* blocks) {
  torch::Tensor x = x_base.index_copy(0, free, q_.detach().reshape({nf, 3}));
  torch::Tensor sum;
  // A term's curvature c: along or across its contact normal into *blocks where it has one and
  // blocks are kept, else isotropic into sum.
  auto add_curvature = [&](const PhysicsTerm& term, const torch::Tensor& c) {
    const PhysicsTerm::ContactDirection direction =
        blocks ? term.contact_direction(state, contact) : PhysicsTerm::ContactDirection{};
    if (direction.normal.defined())
      add_directional_stiffness(tensor_to_matrix(c.reshape({-1, 1})).col(0), tensor_to_matrix(direction.normal),
                                direction.across, blocks);
    else
      sum = sum.defined() ? sum + c : c;
  };
  for (const auto& term : terms) {
    if (barrier && barrier->drops(*term)) continue;
    const torch::Tensor c = term->contact_stiffness(x, state, cloth, contact);
    if (c.defined()) add_curvature(*term, c);
  }
  // The penalty's curvature at the vertices it holds, in the penalty term's direction.
  if (fallback.active()) add_curvature(*fallback.term, fallback.stiffness(x, state, cloth, contact));
  Eigen::MatrixXd X;  // the cloth where the Hessians below are taken
  if (newton || barrier || strain || area) X = positions(q_);
  if (newton) {  // the elastic terms' Hessian at the current state
    for (const auto& term : terms) {
      if (term->name() == "stretch") add_stretch_hessian(X, cloth, state.material, blocks);
      if (const auto* bending = dynamic_cast<const BendingTerm*>(term.get()))
        add_bending_hessian(X, cloth, state.material, bending->degenerate_area(), blocks);
    }
  }
  if (barrier || strain || area) {
    Eigen::VectorXd curvature = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd* diagonal = blocks ? nullptr : &curvature;
    if (barrier) barrier_potential(X, barrier->cloth_edges, body, candidates, settings, nullptr, diagonal, blocks);
    if (strain) strain_barrier(X, strain_edges, rest_length, strain_settings, strain_excluded, nullptr, diagonal, blocks);
    if (area) area_barrier(X, area_faces, rest_area, area_settings, area_excluded, nullptr, diagonal, blocks);
    if (curvature.maxCoeff() > 0) {
      torch::Tensor c = torch::from_blob(curvature.data(), {n}, torch::kFloat64).clone().to(opts);
      sum = sum.defined() ? sum + c : c;
    }
  }
  return sum.defined() ? sum.index_select(0, free) : sum;
}

// The elastic Hessian (with the contact curvature) factorised again where it changed.
void IncrementalPotentialSolve::factorize() {
  if (!elastic) return;
  CoordinateHessian* blocks = nullptr;
  if (elastic->coordinates) {
    elastic->hessian.clear();
    blocks = &elastic->hessian;
  }
  torch::Tensor c = contact_diagonal(q, blocks);
  const bool any_blocks = blocks && !blocks->empty();
  if (!factorized || newton || c.defined() || any_blocks || had_blocks) elastic->factorize(c);
  factorized = true;
  had_blocks = any_blocks;
}

// The share of the step d that crosses nothing: no pair through the body (CCD), no edge past the
// strain limit, no face through a collapse. 0, with *blocked_by saying which, when nothing of d
// can be taken.
double IncrementalPotentialSolve::feasible_step(const torch::Tensor& d, const char** blocked_by) {
  double t = 1.0;
  step_bound = "nothing";
  if (barrier) {
    // Every pair the step can bring within d_hat, and the part of the step CCD certifies.
    // A step moves no vertex more than kMaxContactStep: the broad phase stays local and
    // CCD has few pairs to clear (a large quasi-Newton step is taken over several iterations).
    const Eigen::MatrixXd X = positions(q);
    Eigen::MatrixXd D = positions(q + d) - X;
    const double longest = D.rowwise().norm().maxCoeff();
    if (longest > kMaxContactStep) D *= kMaxContactStep / longest;
    candidates = contact_candidates(X, D, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
    drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
    t = max_safe_step(X, D, barrier->cloth_edges, body, {}, candidates);
    if (!(t > 0)) {  // pressed against the body along d: nothing left to take
      *blocked_by = "CCD (no safe step along the direction)";
      return 0;
    }
    if (t < 1) step_bound = "CCD";
    if (longest > kMaxContactStep) {
      t *= kMaxContactStep / longest;
      if (step_bound[0] == 'n') step_bound = "the move cap";
    }
  }
  if (strain) {  // no edge past the limit anywhere along the step
    const Eigen::MatrixXd X = positions(q);
    const double s = max_strain_step(X, positions(q + t * d) - X, strain_edges, rest_length, config.strain_limit,
                                     strain_excluded);
    if (s < 1) step_bound = "the strain limit";
    t = std::min(t, s * t);
    if (!(t > 0)) {  // an edge at the limit along d: nothing left to take
      *blocked_by = "the strain limit (no step along the direction)";
      return 0;
    }
  }
  if (area) {  // no face through a collapse anywhere along the step
    const Eigen::MatrixXd X = positions(q);
    const double s = max_area_step(X, positions(q + t * d) - X, area_faces, area_excluded);
    if (s < 1) step_bound = "the area barrier";
    t = std::min(t, s * t);
    if (!(t > 0)) {
      *blocked_by = "the area barrier (no step along the direction)";
      return 0;
    }
  }
  return t;
}

// Backtracking from t along d to the Armijo condition; false when no step decreased E.
bool IncrementalPotentialSolve::line_search(const torch::Tensor& d, double slope, double t, torch::Tensor* q_new,
                                            torch::Tensor* g_new, double* E_new) {
  for (int ls = 0; ls < config.max_line_search_steps; ++ls, t *= 0.5) {
    *q_new = q + t * d;
    *E_new = evaluate(*q_new, g_new);
    if (std::isfinite(*E_new) && *E_new <= E + config.armijo * t * slope) return true;
  }
  return false;
}

// The step taken: the curvature pair kept (L-BFGS), the barriers' left-out edges and faces
// readmitted where they relaxed, the barrier stiffened where a pair still closes in.
void IncrementalPotentialSolve::accept(const torch::Tensor& q_new, const torch::Tensor& g_new, double E_new) {
  torch::Tensor s = q_new - q, y = g_new - g;
  double sy = torch::dot(s, y).item<double>();
  if (sy > 0 && !newton) {  // keep the inverse-Hessian estimate positive definite
    history.push_back({s, y, 1.0 / sy});
    if (static_cast<int>(history.size()) > config.history) history.pop_front();
  }
  q = q_new;
  g = g_new;
  E = E_new;
  ++result.iterations;
  readmit_relaxed_edges_and_faces();
  adapt_barrier_stiffness();
}

void IncrementalPotentialSolve::trace_iteration(const torch::Tensor& d, const torch::Tensor& q_new, double t_feasible,
                                                double E_new, double slope) const {
  const double moved = (q_new - q).abs().max().item<double>();
  const int64_t vertex = free[d.abs().argmax().item<int64_t>() / 3].item<int64_t>();
  const long halvings = moved > 0 ? std::lround(std::log2(t_feasible * step_norm / moved)) : 0;
  const std::string contact =
      barrier ? fmt::format(", closest pair {:.3g} mm, kappa {:.3g}", 1e3 * closest, settings.stiffness) : "";
  spdlog::trace("  iteration {}: step {:.3g} mm (vertex {}), {:.3g} of it feasible ({} cut it), {:.3g} mm taken "
                "({} halvings), energy {:+.3g} J (slope {:.3g} J){}",
                result.iterations, 1e3 * step_norm, vertex, t_feasible, step_bound, 1e3 * moved, halvings, E_new - E,
                slope, contact);
}

// IPC's adaptive stiffness: a pair still closing in below barrier_gap x d_hat doubles kappa
// (up to barrier_stiffness_max), which moves the objective: the curvature pairs go.
void IncrementalPotentialSolve::adapt_barrier_stiffness() {
  if (barrier && closest < config.barrier_gap * settings.d_hat && closest < accepted_closest &&
      settings.stiffness * 2 <= config.barrier_stiffness_max) {
    settings.stiffness *= 2;
    history.clear();
    E = evaluate(q, &g);
  }
  accepted_closest = closest;
}

SolverResult IncrementalPotentialSolve::run() {
  while (nf > 0) {
    factorize();
    bool body_moved = false;
    if (barrier && move_body()) {
      body_moved = true;
      if (strain) exclude_overstretched(positions(q));  // edges the carried cloth stretched past the limit
      if (area) exclude_compressed(positions(q));
      history.clear();  // the objective moved with the body
      E = evaluate(q, &g);
    }
    torch::Tensor d = lbfgs_direction(g, history, initial);
    double slope = torch::dot(g, d).item<double>();
    if (!(slope < 0)) {  // lost descent (curvature noise): restart from the initial Hessian
      history.clear();
      d = lbfgs_direction(g, history, initial);
      slope = torch::dot(g, d).item<double>();
    }
    step_norm = d.abs().max().item<double>();
    if (result.iterations >= config.max_iterations) break;
    // Done when the cloth is at rest and the body at its pose (a body held up tries again).
    const bool body_home = !barrier || body_left() <= 0;
    last_slope = slope;
    const bool small_step = step_norm <= config.step_tolerance && result.iterations >= config.min_iterations;
    const bool at_rest = small_step || !(slope < 0) || small_decrease(slope);
    if (at_rest && !body_moved && body_home) {
      if (readmit_at_rest()) continue;  // cloth out of contact freed where it rests: go on
      // No descent left along the Hessian's direction although the step is not small: not a
      // minimum (a barrier pair nearly touching can leave the solve without one).
      stopped_by = small_step || small_decrease(slope) ? "rest" : "lost descent";
      break;
    }
    if (!body_home) body_moved = true;  // keep going: the next iteration moves or places the body
    if (at_rest) {
      ++result.iterations;
      continue;  // the cloth is at rest against the body where it stands: move the body on
    }
    const char* blocked_by = nullptr;
    const double t = feasible_step(d, &blocked_by);
    torch::Tensor q_new, g_new;
    double E_new = E;
    if (!blocked_by && line_search(d, slope, t, &q_new, &g_new, &E_new)) {
      if (spdlog::should_log(spdlog::level::trace)) trace_iteration(d, q_new, t, E_new, slope);
      accept(q_new, g_new, E_new);
      continue;
    }
    if (body_moved) {  // nothing of d to take where the body stands: move it on
      ++result.iterations;
      continue;
    }
    if (readmit_at_rest()) continue;
    stopped_by = blocked_by ? blocked_by : "the line search (no decrease along the direction)";
    break;  // no decrease left at this precision
  }
  return finish();
}

SolverResult IncrementalPotentialSolve::finish() {
  result.barrier_stiffness = barrier ? settings.stiffness : 0.0;
  if (barrier && result.excluded > 0) result.excluded_vertices = excluded;

  if (barrier && body_left() > 0) place_body(body_left());  // the iterations ran out first
  result.x_next = x_base.index_copy(0, free, q.reshape({nf, 3})).detach();
  if (strain)
    result.max_strain = strain_barrier(positions(q), strain_edges, rest_length, strain_settings, strain_excluded).max_strain;
  if (area)
    result.min_area_ratio = area_barrier(positions(q), area_faces, rest_area, area_settings, area_excluded).min_ratio;
  result.gradient_norm = nf ? g.abs().max().item<double>() : 0.0;
  if (barrier) {
    const Eigen::MatrixXd X = positions(q);
    ContactCandidates last = contact_candidates(X, {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
    drop_pairs_of(excluded, barrier->cloth_edges, &last);
    result.min_distance = barrier_potential(X, barrier->cloth_edges, body, last, settings).min_distance;
    spdlog::debug("barrier step: {} iterations, {} evaluations, {} candidate pairs last, min distance {:.3g} mm, "
                  "{} released for the body's moves, {} readmitted where the solve stopped, body placed {:.3g} mm short, kappa {:.3g}, max strain {:.3g} ({} edges out of the strain barrier), "
                  "smallest area ratio {:.3g} ({} faces out of the area barrier), "
                  "stopped by {} (step {:.3g} mm, largest gradient {:.3g} N), {:.0f} ms",
                  result.iterations, result.evaluations, candidates.size(), 1e3 * result.min_distance,
                  result.released, result.readmitted_at_rest, 1e3 * result.body_lag, settings.stiffness, result.max_strain, result.strain_excluded,
                  result.min_area_ratio, result.area_excluded,
                  stopped_by, 1e3 * step_norm, result.gradient_norm, ms_since(start_time));
  }
  if (!barrier)
    spdlog::debug("solver step: {} iterations, {} evaluations, stopped by {} (step {:.3g} mm, largest gradient {:.3g} N), "
                  "{:.0f} ms",
                  result.iterations, result.evaluations, stopped_by, 1e3 * step_norm, result.gradient_norm,
                  ms_since(start_time));
  result.energy = E;
  result.step_norm = step_norm;
  result.converged = step_norm <= config.step_tolerance || small_decrease(last_slope);
  return result;
}

}  // namespace reference_solve
}  // namespace pb4u
