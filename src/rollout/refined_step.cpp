#include "pb4u/rollout/refined_step.h"

#include "pb4u/physics/reference_solver.h"

namespace pb4u {

StepFunction refined_stepper(StepFunction inner, const ReferenceSolverConfig& solver, const RefineConfig& refine,
                             std::shared_ptr<ContactStepLog> log) {
  ReferenceSolverConfig config = solver;
  // A fixed kappa: the potential the output is no higher than is the start's, at one stiffness.
  config.barrier_stiffness_max = 0;
  if (refine.tolerance_mm > 0) {
    config.step_tolerance = 1e-3 * refine.tolerance_mm;
  } else {
    config.max_iterations = refine.iterations;
  }
  return [inner, config, log](const FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                              const BodyContact* contact) {
    const torch::Tensor step = inner(state, cloth, terms, contact).to(torch::kFloat64);
    std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config);
    if (barrier) barrier->body_t = barrier->body_next;  // the step is already at t + dt
    const SolverResult r =
        solve_reference_step(state, cloth, terms, contact, config, barrier ? &*barrier : nullptr, &step);
    if (log) *log = {r.excluded, r.caught_by_body, r.body_lag};
    return r.x_next.to(torch::kFloat64);
  };
}

}  // namespace pb4u
