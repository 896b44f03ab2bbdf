#include "pb4u/physics/reference_solver.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>

#include "pb4u/body/outer_faces.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/physics/barrier_objective.h"
#include "pb4u/physics/barrier_start.h"
#include "pb4u/physics/area_barrier.h"
#include "pb4u/physics/bending_energy.h"
#include "pb4u/physics/body_offset.h"
#include "pb4u/physics/carried_by_body.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/coordinate_hessian.h"
#include "pb4u/physics/elastic_hessian.h"
#include "pb4u/physics/elastic_solve.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/physics/strain_barrier.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {
namespace {

// m: the longest move of a vertex (cloth or body) in one line search of the intersection-free solve.
constexpr double kMaxContactStep = 5e-2;
// CCD-certified body moves per step (with solver.release_held_cloth: beyond the ones its motion
// needs at kMaxContactStep each; a limb swinging 70 cm in a frame needs 14), a move cut and
// tried again smaller not counted (kShrinkBelow); a body not at its pose after them is placed
// there.
constexpr int kMaxBodyMoves = 24;
// A body move that some cloth allows less than this fraction of is held back by it (pinched
// between two body parts, or an edge dragged against a body edge it cannot pass); rounds of
// leaving that cloth out of barrier contact before the move is taken as it is.
constexpr double kHeldBelow = 0.1;
constexpr int kReleaseRounds = 4;
// A body move cut by CCD below kShrinkBelow of itself is followed by one of what CCD allowed
// (at least a tenth of it, and no less than kMinBodyMove), one taken whole by one twice as long
// (up to kMaxContactStep), from iteration to iteration; only a move at kMinBodyMove that is cut
// counts towards kMaxBodyMoves. The carry (carried_by_body.h) is exact to first order in the
// move: a 5 cm move of a limb that turns under a 13 cm cloth edge ends its pairs nearer than
// the carry kept them, and CCD then cut every move that followed to a sliver (the hard cases'
// jump at speed 2 from the settled start: its first frame's body stalled 246 mm short of its
// pose, 61 vertices caught); in moves of a centimetre, the cloth relaxing between them, those
// pairs stay apart. Where few iterations are left (a refinement's 10) an iteration's move is
// made of up to kMoveParts such parts, each counted as a move, until it has made what the body
// needs a move to get home.
constexpr double kShrinkBelow = 0.5;
constexpr double kMinBodyMove = 1e-3;
constexpr int kMoveParts = 8;
// Rounds of Provot's pass and the push out of the body that make a start both intersection-free
// and within the strain limit (solver.strain_limit).
constexpr int kStartRounds = 10;

// The rows `free` of an n x 3 matrix, flat (3 x free rows): the solver's coordinates.
torch::Tensor free_coordinates(const Eigen::MatrixXd& rows, const torch::Tensor& free, const torch::TensorOptions& opts) {
  return matrix_to_tensor(rows, opts.dtype().toScalarType(), opts.device()).index_select(0, free).reshape({-1});
}

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

// One frame's solve: argmin over the free cloth coordinates of the incremental potential (the
// physics terms, with barrier contact the barriers of solver.contact / strain_limit /
// area_barrier_gap), by L-BFGS or projected Newton. With barrier contact the body and the pins
// are kinematic: each iteration first moves them on towards their pose at t + dt as far as CCD
// certifies (move_body), then takes one step of the cloth where they stand.
// The members are the solve's state; the constructor sets up the start, run() iterates.
class IncrementalPotentialSolve {
 public:
  IncrementalPotentialSolve(const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                            const BodyContact* contact, const ReferenceSolverConfig& config,
                            const BarrierStepInput* barrier, const torch::Tensor* x_start);
  SolverResult run();

 private:
  // --- the start ---
  void place_ballistic_start(const torch::Tensor* x_start);
  void shorten_start_edges();
  void make_barrier_start(const torch::Tensor* x_start);
  void make_inverse_hessian();
  void pick_start();
  // --- edges and faces left out of their barriers ---
  void exclude_overstretched(const Eigen::MatrixXd& X);
  void exclude_compressed(const Eigen::MatrixXd& X);
  void readmit_relaxed_edges_and_faces();
  void set_fallback();
  // --- the objective ---
  Eigen::MatrixXd positions(const torch::Tensor& q) const;
  double evaluate(const torch::Tensor& q, torch::Tensor* grad);
  torch::Tensor contact_diagonal(const torch::Tensor& q, CoordinateHessian* blocks);
  void factorize();
  // --- the body and the pins, kinematic ---
  Eigen::MatrixXd pins_left() const { return pin_target - pin_now; }
  void move_pins(const Eigen::MatrixXd& to);
  Eigen::MatrixXd pushed_out_of_body(const std::vector<char>& moved) const;
  void place_body(double left);
  double body_left() const;
  void readmit_released();
  bool move_body();
  double move_body_part(double size, double left, bool* moved);
  // --- one iteration's step ---
  double feasible_step(const torch::Tensor& d, const char** blocked_by);
  bool line_search(const torch::Tensor& d, double slope, double t, torch::Tensor* q_new, torch::Tensor* g_new,
                   double* E_new);
  void accept(const torch::Tensor& q_new, const torch::Tensor& g_new, double E_new);
  void adapt_barrier_stiffness();
  SolverResult finish();
  bool small_decrease(double slope) const {
    return config.decrease_tolerance > 0 && -0.5 * slope < config.decrease_tolerance;
  }

  const FrameState& state;
  const ClothGeometry& cloth;
  const TermList& terms;
  const BodyContact* contact;
  const ReferenceSolverConfig& config;
  const BarrierStepInput* barrier;
  const torch::TensorOptions opts;
  const int64_t n;
  const std::chrono::steady_clock::time_point start_time = std::chrono::steady_clock::now();

  SolverResult result;
  torch::Tensor x_base;  // (n, 3): the start, and where the held rows stay
  // The solver's own start, kept beside a given step: without barrier contact both are feasible,
  // and the solve starts from whichever is lower in its objective (SolverResult::own_start).
  torch::Tensor x_own;
  // The cloth where it stands at t, pins at their targets: without barrier contact, a third start
  // where the ballistic prediction is higher (SolverResult::standing_start).
  torch::Tensor x_standing;
  torch::Tensor pinned;  // (n,) bool
  torch::Tensor free;    // the free rows; q holds their coordinates
  int64_t nf = 0;
  std::vector<char> pinned_flags;  // per vertex: the start's Provot passes hold them, the barrier moves them
  std::vector<char> free_flags;
  std::vector<int> row;  // vertex -> its free row, -1 when held

  // Strain barrier (solver.strain_limit).
  bool strain = false;
  Eigen::MatrixXi strain_edges;
  Eigen::VectorXd rest_length;
  std::vector<char> strain_excluded;
  StrainBarrierSettings strain_settings;
  // Area barrier (solver.area_barrier_gap).
  bool area = false;
  AreaBarrierSettings area_settings;
  Eigen::MatrixXi area_faces;
  Eigen::VectorXd rest_area;
  std::vector<char> area_excluded;
  // Barrier contact: the body where it stands, the pairs within reach, the cloth left out.
  ContactSurface body;
  ContactCandidates candidates;
  BarrierSettings settings;
  double closest = std::numeric_limits<double>::infinity();  // m: nearest pair at the last evaluation
  double accepted_closest = std::numeric_limits<double>::infinity();
  std::vector<char> excluded;
  PenaltyFallback fallback;
  // Pins are kinematic under barrier contact, as the body is. pin_now / pin_target: the pinned
  // rows, k x 3.
  std::vector<int64_t> pin_rows;
  Eigen::MatrixXd pin_now, pin_target;
  torch::Tensor pin_index;
  const Eigen::MatrixXd* body_start = nullptr;  // the body where the solve starts
  int body_moves = 0, moves_allowed = 0;
  double move_size = kMaxContactStep;  // m: the next part of a body move (kShrinkBelow)
  std::vector<char> released;  // per cloth vertex: left out of contact so that the body could move on

  // The step.
  InverseHessian initial;
  std::shared_ptr<ElasticSolve> elastic;
  bool newton = false;
  bool factorized = false;
  bool had_blocks = false;  // the last factorisation held barrier blocks
  torch::Tensor q, g;
  double E = 0;
  std::deque<Pair> history;
  double step_norm = 0;
  double last_slope = 0;  // g.d of the last direction
  const char* stopped_by = nullptr;  // why the loop ended (the debug log says)
};

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
  for (torch::Tensor* x : {&x_base, &x_own, &x_standing})
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
  auto make_start = [&](bool at_next) {
    return barrier_start(x_t, target, pinned_flags, at_next, barrier->cloth_edges,
                         at_next ? barrier->body_next : barrier->body_t, barrier->body_faces, barrier->settings.d_hat);
  };
  BarrierStart start = make_start(x_start && barrier->given_start != GivenStart::swept);
  if (x_start && barrier->given_start == GivenStart::fewer_left_out && start.excluded_count > 0) {
    BarrierStart swept = make_start(false);
    if (swept.excluded_count < start.excluded_count) start = std::move(swept);
  }
  // Where the step left cloth inside the body with no free place near (pinched where the body
  // crosses itself, or deep in a body that went through it), the body's own motion from t
  // decides where that cloth goes.
  if (x_start && barrier->given_start == GivenStart::swept_if_left_out && start.excluded_count > 0)
    start = make_start(false);
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

// What is left of the pins' motion is pins_left(); the pins moved to `to` (k x 3).
void IncrementalPotentialSolve::move_pins(const Eigen::MatrixXd& to) {
  if (pin_rows.empty()) return;
  pin_now = to;
  x_base = x_base.index_copy(0, pin_index, matrix_to_tensor(pin_now, opts.dtype().toScalarType(), state.x.device()));
}

// The cloth pushed out of the body where it stands, as a start is (intersection_free_start):
// the rows `moved` selects (empty: every vertex); pins stay on their targets.
Eigen::MatrixXd IncrementalPotentialSolve::pushed_out_of_body(const std::vector<char>& moved) const {
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd out = intersection_free_start(X, X, barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat).x;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!free_flags[size_t(i)] || (!moved.empty() && !moved[size_t(i)])) out.row(i) = X.row(i);
  return out;
}

// Where the body is still short of its pose after the moves it is allowed (cloth that left it
// no room and that no release freed) it is placed there; the cloth it now cuts or holds (pushed
// out of it first as a start is, with solver.push_out_caught) leaves barrier contact for the
// penalty term (SolverResult::excluded).
void IncrementalPotentialSolve::place_body(double left) {
  body.V = barrier->body_next;
  move_pins(pin_target);
  if (config.push_out_caught)  // the cloth the placed body now cuts or holds pushed out of it first
    q = free_coordinates(pushed_out_of_body({}), free, opts);
  const std::vector<char> caught =
      vertices_not_free_of(positions(q), barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat);
  for (size_t i = 0; i < caught.size(); ++i)
    if (caught[i] && !excluded[i]) {
      excluded[i] = 1;
      ++result.excluded;
      ++result.caught_by_body;
    }
  set_fallback();
  candidates = contact_candidates(positions(q), {}, barrier->cloth_edges, body, {}, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
  result.body_lag = left;
}

// m: the longest move left to the body or a pin.
double IncrementalPotentialSolve::body_left() const {
  const double pins = pin_rows.empty() ? 0.0 : pins_left().rowwise().norm().maxCoeff();
  return std::max((barrier->body_next - body.V).rowwise().norm().maxCoeff(), pins);
}

// Once the body is at its pose, the cloth it passed over is pushed out of it as a start is;
// what that frees rejoins barrier contact (the rest stays with the penalty term).
void IncrementalPotentialSolve::readmit_released() {
  if (released.empty()) return;
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd out = pushed_out_of_body(released);
  const std::vector<char> still = vertices_not_free_of(out, barrier->cloth_edges, body.V, body.F, barrier->settings.d_hat);
  int back = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (released[size_t(i)] && !still[size_t(i)]) {
      excluded[size_t(i)] = released[size_t(i)] = 0;
      ++back;
    } else if (released[size_t(i)]) {
      out.row(i) = X.row(i);
    }
  if (back == 0) return;
  result.excluded -= back;
  result.caught_by_body -= back;
  q = free_coordinates(out, free, opts);
  set_fallback();
}

// The body's move of this iteration, the cloth it touches carried along and the pins by the
// same share of what is left of theirs, in CCD-certified parts (move_body_part; kShrinkBelow).
// False when nothing moved.
bool IncrementalPotentialSolve::move_body() {
  double left = body_left();
  if (left <= 0) return false;
  if (body_moves == 0)
    moves_allowed = kMaxBodyMoves + (config.release_held_cloth ? int(std::ceil(left / kMaxContactStep)) : 0);
  if (++body_moves > moves_allowed) {
    place_body(left);
    return true;
  }
  // One part, unless the iterations left need more of the motion in this one to bring the
  // body home (a refinement's few): then parts until that much is made.
  const double needed = left / double(std::max(1, config.max_iterations - result.iterations));
  double done = 0;
  bool moved = false;
  for (int part = 0; part < kMoveParts && left > 0; ++part) {
    if (part > 0 && ++body_moves > moves_allowed) {  // each part is a move
      place_body(left);
      return true;
    }
    const double size = std::min(move_size, left);
    const double t = move_body_part(size, left, &moved);
    const bool cut = t < kShrinkBelow;
    move_size = cut ? std::max(kMinBodyMove, move_size * std::max(0.1, t)) : std::min(kMaxContactStep, 2 * move_size);
    if (cut && move_size > kMinBodyMove) --body_moves;  // held back, tried again smaller: not counted
    if (!(t > 0) && move_size <= kMinBodyMove) break;
    done += t * size;
    left = body_left();
    if (done >= needed) break;
  }
  return moved;
}

// One part of a body move: `size` m of the `left` still to go, cut to what CCD certifies.
// Returns the share of the part taken; *moved is set when the body, a pin or the cloth's
// contact changed.
double IncrementalPotentialSolve::move_body_part(double size, double left, bool* moved) {
  const double share = left > size ? size / left : 1.0;
  const Eigen::MatrixXd DB = share * (barrier->body_next - body.V);
  const Eigen::MatrixXd X = positions(q);
  Eigen::MatrixXd D = carried_by_body(X, barrier->cloth_edges, body, DB, excluded, barrier->settings.d_hat / 2,
                                      config.body_carry == "ride");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!free_flags[size_t(i)]) D.row(i).setZero();
  const Eigen::MatrixXd DP = share * pins_left();
  for (size_t j = 0; j < pin_rows.size(); ++j) D.row(pin_rows[j]) = DP.row(Eigen::Index(j));
  candidates = contact_candidates(X, D, barrier->cloth_edges, body, DB, barrier->settings.d_hat);
  drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
  double t = max_safe_step(X, D, barrier->cloth_edges, body, DB, candidates);
  // Cloth that holds the move back would stall the body for the rest of the step, and the
  // body would then be placed at its pose onto everything in its way. With
  // solver.release_held_cloth the vertices of the pairs that allow less than kHeldBelow of
  // the move leave barrier contact (caught by the body, for the penalty term), and the move
  // is certified again without them.
  bool released_now = false;
  for (int round = 0; config.release_held_cloth && round < kReleaseRounds && t < kHeldBelow; ++round) {
    const std::vector<char> holding =
        vertices_holding_step(X, D, barrier->cloth_edges, body, DB, candidates, kHeldBelow);
    int newly = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      if (holding[size_t(i)] && !excluded[size_t(i)]) {  // a pin too: it stays on its path, out of contact
        if (released.empty()) released.assign(size_t(n), 0);
        excluded[size_t(i)] = released[size_t(i)] = 1;
        ++newly;
      }
    if (newly == 0) break;
    result.excluded += newly;
    result.caught_by_body += newly;
    result.released += newly;
    released_now = true;
    drop_pairs_of(excluded, barrier->cloth_edges, &candidates);
    t = max_safe_step(X, D, barrier->cloth_edges, body, DB, candidates);
  }
  if (released_now) {
    set_fallback();  // the objective changed: the caller evaluates it again
    *moved = true;
  }
  if (!(t > 0)) return 0;
  // A full step lands exactly on the pose and the pins' targets (no rounding left over).
  const bool home = t >= 1 && share >= 1;
  body.V = home ? barrier->body_next : Eigen::MatrixXd(body.V + t * DB);
  move_pins(home ? pin_target : Eigen::MatrixXd(pin_now + t * DP));
  q = q + t * free_coordinates(D, free, opts);
  if (home) readmit_released();
  *moved = true;
  return std::min(t, 1.0);
}

// The share of the step d that crosses nothing: no pair through the body (CCD), no edge past the
// strain limit, no face through a collapse. 0, with *blocked_by saying which, when nothing of d
// can be taken.
double IncrementalPotentialSolve::feasible_step(const torch::Tensor& d, const char** blocked_by) {
  double t = 1.0;
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
    if (longest > kMaxContactStep) t *= kMaxContactStep / longest;
  }
  if (strain) {  // no edge past the limit anywhere along the step
    const Eigen::MatrixXd X = positions(q);
    t = std::min(t, max_strain_step(X, positions(q + t * d) - X, strain_edges, rest_length, config.strain_limit,
                                    strain_excluded) * t);
    if (!(t > 0)) {  // an edge at the limit along d: nothing left to take
      *blocked_by = "the strain limit (no step along the direction)";
      return 0;
    }
  }
  if (area) {  // no face through a collapse anywhere along the step
    const Eigen::MatrixXd X = positions(q);
    t = std::min(t, max_area_step(X, positions(q + t * d) - X, area_faces, area_excluded) * t);
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
    const bool at_rest = step_norm <= config.step_tolerance || !(slope < 0) || small_decrease(slope);
    if (at_rest && !body_moved && body_home) {
      // No descent left along the Hessian's direction although the step is not small: not a
      // minimum (a barrier pair nearly touching can leave the solve without one).
      stopped_by = step_norm <= config.step_tolerance || small_decrease(slope) ? "rest" : "lost descent";
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
      accept(q_new, g_new, E_new);
      continue;
    }
    if (body_moved) {  // nothing of d to take where the body stands: move it on
      ++result.iterations;
      continue;
    }
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
                  "{} released for the body's moves, body placed {:.3g} mm short, kappa {:.3g}, max strain {:.3g} ({} edges out of the strain barrier), "
                  "smallest area ratio {:.3g} ({} faces out of the area barrier), "
                  "stopped by {} (step {:.3g} mm, largest gradient {:.3g} N), {:.0f} ms",
                  result.iterations, result.evaluations, candidates.size(), 1e3 * result.min_distance,
                  result.released, 1e3 * result.body_lag, settings.stiffness, result.max_strain, result.strain_excluded,
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

// solver.penalty_faces = outer: the rows of the body's faces no other part of it covers at
// t + dt; empty where none is covered.
std::vector<int64_t> uncovered_face_rows(const FrameState& state) {
  const std::vector<char> covered =
      covered_faces(tensor_to_matrix(state.body.next_vertices), index_tensor_to_matrix(state.body.faces));
  std::vector<int64_t> rows;
  if (std::find(covered.begin(), covered.end(), char(1)) == covered.end()) return rows;
  for (size_t f = 0; f < covered.size(); ++f)
    if (!covered[f]) rows.push_back(int64_t(f));
  return rows;
}

}  // namespace

SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config, const BarrierStepInput* barrier,
                                  const torch::Tensor* x_start) {
  const std::optional<BodyContact> outer = barrier ? barrier->solved_contact(state, contact) : std::nullopt;
  return IncrementalPotentialSolve(state, cloth, terms, outer ? &*outer : contact, config, barrier, x_start).run();
}

std::optional<BodyContact> BarrierStepInput::solved_contact(const FrameState& state, const BodyContact* contact) const {
  if (outer_faces.empty() || !contact) return std::nullopt;
  return contact_on_faces(*contact, state.x, state.body, outer_faces);  // the step's degenerate area
}

bool BarrierStepInput::drops(const PhysicsTerm& term) const { return !keeps_penalty && term.name() == "collision"; }

std::optional<BarrierStepInput> barrier_step_input(const FrameState& state, const ClothGeometry& cloth,
                                                   const ReferenceSolverConfig& config) {
  if (config.contact != "barrier" || !state.effects.collision || !state.body.defined()) return std::nullopt;
  BarrierStepInput input;
  input.body_t = tensor_to_matrix(state.body.vertices);
  input.body_next = tensor_to_matrix(state.body.next_vertices);
  input.body_faces = index_tensor_to_matrix(state.body.faces);
  if (config.barrier_offset > 0) {  // the body moved out along its normals where it has room
    input.body_t = offset_where_room(input.body_t, input.body_faces, config.barrier_offset);
    input.body_next = offset_where_room(input.body_next, input.body_faces, config.barrier_offset);
  }
  input.cloth_edges = unique_edges(index_tensor_to_matrix(cloth.faces));
  input.settings.d_hat = config.barrier_distance;
  input.settings.stiffness = config.barrier_stiffness;
  input.keeps_penalty = config.barrier_keeps_penalty;
  using GivenStart = BarrierStepInput::GivenStart;
  input.given_start = config.given_start == "at_step"            ? GivenStart::at_step
                      : config.given_start == "swept"            ? GivenStart::swept
                      : config.given_start == "fewer_left_out"   ? GivenStart::fewer_left_out
                      : config.given_start == "swept_if_left_out" ? GivenStart::swept_if_left_out
                                                                 : GivenStart::at_step;
  // fewer_left_out_to_tolerance is at_step here: a refinement (refined_step) gives its solve to
  // the tolerance fewer_left_out itself.
  if (config.penalty_faces == "outer") input.outer_faces = uncovered_face_rows(state);
  if (config.barrier_stiffness_max > 0 && config.barrier_stiffness_max < config.barrier_stiffness)
    throw Error("reference solver: solver.barrier_stiffness_max (" + std::to_string(config.barrier_stiffness_max) +
                ") is below solver.barrier_stiffness (" + std::to_string(config.barrier_stiffness) + ")");
  return input;
}

SolverResult solve_reference_frame(const FrameState& state, const ClothGeometry& cloth,
                                   const TermList& terms, const PhysicsConfig& config) {
  std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config.solver);
  return solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver,
                              barrier ? &*barrier : nullptr);
}

}  // namespace pb4u
