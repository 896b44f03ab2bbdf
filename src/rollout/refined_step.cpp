#include "pb4u/rollout/refined_step.h"

#include <limits>
#include <optional>
#include <utility>

#include "pb4u/physics/reference_solver.h"

namespace pb4u {

namespace {
// The solver's settings for a refinement by a fixed count (tolerance_mm 0) or to a tolerance.
ReferenceSolverConfig refining_solver(const ReferenceSolverConfig& solver, int iterations, double tolerance_mm) {
  ReferenceSolverConfig config = solver;
  // A fixed kappa: the potential the output is no higher than is the start's, at one stiffness.
  config.barrier_stiffness_max = 0;
  if (tolerance_mm > 0) {
    config.step_tolerance = 1e-3 * tolerance_mm;
  } else {
    config.max_iterations = iterations;
  }
  return config;
}

torch::Tensor refine_with(const torch::Tensor& x_step, const FrameState& state, const ClothGeometry& cloth,
                          const TermList& terms, const BodyContact* contact, const ReferenceSolverConfig& config,
                          ContactStepLog* log, double* step_norm = nullptr, int* excluded = nullptr) {
  const torch::Tensor start = x_step.to(torch::kFloat64);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config);
  SolverResult r = solve_reference_step(state, cloth, terms, contact, config, barrier ? &*barrier : nullptr, &start);
  // fewer_left_out: where the swept start's body, moving from t, was held up and caught cloth,
  // the step where it stands is solved too, and the solve that left fewer vertices out is kept
  // (not where the solver's own start replaced the step, which the step where it stands would again).
  using GivenStart = BarrierStepInput::GivenStart;
  if (barrier && barrier->given_start == GivenStart::fewer_left_out && r.swept_start && !r.own_start &&
      r.caught_by_body > 0) {
    BarrierStepInput at_step = *barrier;
    at_step.given_start = GivenStart::at_step;
    SolverResult other = solve_reference_step(state, cloth, terms, contact, config, &at_step, &start);
    if (other.excluded <= r.excluded) r = std::move(other);
  }
  if (log) *log = {r.excluded, r.caught_by_body, r.body_lag, r.excluded_vertices, r.barrier_stiffness, r.own_start};
  if (step_norm) *step_norm = r.step_norm;
  if (excluded) *excluded = r.excluded;
  return r.x_next.to(torch::kFloat64);
}

// A refinement's solver settings: a fixed count, a tolerance, or the count and then the tolerance.
struct RefiningSolvers {
  std::optional<ReferenceSolverConfig> fixed, to_tolerance;
  double tolerance_m = 0;
  // given_start fewer_left_out_to_tolerance: the solve to the tolerance also runs where the
  // count reached it but left vertices out of contact.
  bool on_where_left_out = false;
};

RefiningSolvers refining_solvers(const ReferenceSolverConfig& solver, const RefineConfig& refine) {
  RefiningSolvers s;
  ReferenceSolverConfig base = solver;
  base.step = refine.step;
  base.release_held_cloth = refine.release_held_cloth;
  // A count of 0 without a tolerance still makes the step feasible (intersection-free start).
  // fewer_left_out_to_tolerance: a fixed count starts from the step where it stands (the solver
  // reads the rule as at_step); the solve to the tolerance may start swept. A swept start leaves
  // the body its whole motion to make, cloth carried along, which a few iterations do not finish
  // (docs/physics.md, "Where a refinement starts").
  const bool to_tolerance_only = solver.given_start == "fewer_left_out_to_tolerance";
  // The solver's own start (own_start_where_left_out) is swept too: under this rule only the
  // solve to the tolerance takes it.
  if (refine.iterations > 0 || !(refine.tolerance_mm > 0)) {
    s.fixed = refining_solver(base, refine.iterations, 0);
    if (to_tolerance_only) s.fixed->own_start_where_left_out = false;
    // With a tolerance too, the count is a most: it stops where its step is below the
    // tolerance, as the solve to the tolerance would. Its first Newton step is taken however
    // small: on a stiff cloth near rest a frame's whole sag can be under the tolerance, and a
    // count stopped at once would keep the cloth where it started (docs/physics.md).
    if (refine.tolerance_mm > 0) {
      s.fixed->step_tolerance = 1e-3 * refine.tolerance_mm;
      s.fixed->min_iterations = 1;
    }
  }
  if (refine.tolerance_mm > 0) {
    s.to_tolerance = refining_solver(base, 0, refine.tolerance_mm);
    s.tolerance_m = 1e-3 * refine.tolerance_mm;
    if (to_tolerance_only) s.to_tolerance->given_start = "fewer_left_out";
    s.on_where_left_out = to_tolerance_only;
  }
  return s;
}

torch::Tensor refine_by(const RefiningSolvers& s, const torch::Tensor& x_step, const FrameState& state,
                        const ClothGeometry& cloth, const TermList& terms, const BodyContact* contact,
                        ContactStepLog* log) {
  torch::Tensor x = x_step;
  double step_norm = std::numeric_limits<double>::infinity();
  int excluded = 0;
  if (s.fixed) x = refine_with(x, state, cloth, terms, contact, *s.fixed, log, &step_norm, &excluded);
  const bool own_start = log && log->own_start;
  // Past the fixed count, on to the tolerance unless the count already got there (with nothing
  // left out, where the rule says so).
  if (s.to_tolerance && (!(step_norm <= s.tolerance_m) || (s.on_where_left_out && excluded > 0))) {
    x = refine_with(x, state, cloth, terms, contact, *s.to_tolerance, log);
    if (log) log->own_start = log->own_start || own_start;
  }
  return x;
}
}  // namespace

torch::Tensor refine_step(const torch::Tensor& x_step, const FrameState& state, const ClothGeometry& cloth,
                          const TermList& terms, const BodyContact* contact, const ReferenceSolverConfig& solver,
                          const RefineConfig& refine, ContactStepLog* log) {
  return refine_by(refining_solvers(solver, refine), x_step, state, cloth, terms, contact, log);
}

StepFunction refined_stepper(StepFunction inner, const ReferenceSolverConfig& solver, const RefineConfig& refine,
                             std::shared_ptr<ContactStepLog> log) {
  const RefiningSolvers solvers = refining_solvers(solver, refine);
  return [inner, solvers, log](const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                               const BodyContact* contact) {
    return refine_by(solvers, inner(state, cloth, terms, contact), state, cloth, terms, contact, log.get());
  };
}

}  // namespace pb4u
