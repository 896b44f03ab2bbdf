#pragma once
// A stepper's step (the network's) refined by the reference solver: the solve starts from the
// step instead of the ballistic prediction. With the intersection-free contact (solver.contact
// = barrier, a body) the step is first made free of the body (intersection_free_start.h):
// where it stands, against the body at its pose at t + dt, or swept from the cloth at t
// against the moving body (solver.given_start; by default where it stands for a fixed count,
// and in the solve to a tolerance swept where that leaves fewer vertices out). So for
// any number of iterations the output is intersection-free (but for the vertices the start
// could not free, which the penalty term holds) and its incremental potential, the solver's
// objective, is no higher than the start's (the line search only takes steps that lower it;
// kappa stays at solver.barrier_stiffness, as an adaptive one would change the potential
// mid-way). Without a body it is the solver from the step. Its step (RefineConfig::step) is
// Newton unless set otherwise.
#include <memory>
#include <string>

#include "pb4u/physics/physics_config.h"
#include "pb4u/rollout/refine_config.h"
#include "pb4u/rollout/rollout.h"

namespace pb4u {

// One step x_step (n, 3) refined as `refine` says by the solver `solver` (its contact, barrier
// or penalty, as configured): float64 on the CPU, as the state. `log`, when given, gets the
// solver's account of the step.
torch::Tensor refine_step(const torch::Tensor& x_step, const FrameState& state, const ClothGeometry& cloth,
                          const TermList& terms, const BodyContact* contact, const ReferenceSolverConfig& solver,
                          const RefineConfig& refine, ContactStepLog* log = nullptr);

// `inner`'s step refined by refine_step. `log`, when given, gets the solver's account of each
// step.
StepFunction refined_stepper(StepFunction inner, const ReferenceSolverConfig& solver, const RefineConfig& refine,
                             std::shared_ptr<ContactStepLog> log = nullptr);

}  // namespace pb4u
