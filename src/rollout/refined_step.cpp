#include "pb4u/rollout/refined_step.h"

#include "pb4u/physics/reference_solver.h"

namespace pb4u {

namespace {
// The solver's settings for a refinement.
ReferenceSolverConfig refining_solver(const ReferenceSolverConfig& solver, const RefineConfig& refine) {
  ReferenceSolverConfig config = solver;
  // A fixed kappa: the potential the output is no higher than is the start's, at one stiffness.
  config.barrier_stiffness_max = 0;
  config.step = refine.step;
  if (refine.tolerance_mm > 0) {
    config.step_tolerance = 1e-3 * refine.tolerance_mm;
  } else {
    config.max_iterations = refine.iterations;
  }
  return config;
}

torch::Tensor refine_with(const torch::Tensor& x_step, const FrameState& state, const ClothGeometry& cloth,
                          const TermList& terms, const BodyContact* contact, const ReferenceSolverConfig& config,
                          ContactStepLog* log) {
  const torch::Tensor start = x_step.to(torch::kFloat64);
  std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config);
  if (barrier) barrier->body_t = barrier->body_next;  // the step is already at t + dt
  const SolverResult r =
      solve_reference_step(state, cloth, terms, contact, config, barrier ? &*barrier : nullptr, &start);
  if (log) *log = {r.excluded, r.caught_by_body, r.body_lag, r.excluded_vertices, r.barrier_stiffness};
  return r.x_next.to(torch::kFloat64);
}
}  // namespace

torch::Tensor refine_step(const torch::Tensor& x_step, const FrameState& state, const ClothGeometry& cloth,
                          const TermList& terms, const BodyContact* contact, const ReferenceSolverConfig& solver,
                          const RefineConfig& refine, ContactStepLog* log) {
  return refine_with(x_step, state, cloth, terms, contact, refining_solver(solver, refine), log);
}

StepFunction refined_stepper(StepFunction inner, const ReferenceSolverConfig& solver, const RefineConfig& refine,
                             std::shared_ptr<ContactStepLog> log) {
  const ReferenceSolverConfig config = refining_solver(solver, refine);
  return [inner, config, log](const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                              const BodyContact* contact) {
    return refine_with(inner(state, cloth, terms, contact), state, cloth, terms, contact, config, log.get());
  };
}

}  // namespace pb4u
