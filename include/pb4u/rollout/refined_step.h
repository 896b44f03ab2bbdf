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

#include "pb4u/config/config_io.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/rollout/rollout.h"

namespace pb4u {

struct RefineConfig {
  int iterations = 0;        // solver iterations after each step; 0 with tolerance_mm 0: off
  double tolerance_mm = 0;   // > 0: iterate (up to the solver's max_iterations) until the
                             // solver's step is below this (mm); with iterations > 0 as well,
                             // those first, then on until the step is below this
  // The solver's step for the refinement (physics.solver.step is the solver's own): "newton"
  // lands nearer the minimum per iteration (docs/physics.md, "The Newton step").
  std::string step = "newton";
  // The refinement's physics.solver.release_held_cloth (the solver's own is on by default):
  // off, the body the network's step holds back gets its 24 moves and is placed at its pose.
  // On the demo walk the refined file read 1.25x the reference with it on, 1.03x off
  // (docs/physics.md, "Releasing the cloth that holds the body back").
  bool release_held_cloth = false;
  bool enabled() const { return iterations > 0 || tolerance_mm > 0; }

  template <class V>
  void visit(V& v) {
    v("iterations", iterations, int_at_least(0));
    v("tolerance_mm", tolerance_mm, non_negative());
    v("step", step, one_of({"quasi_newton", "newton"}));
    v("release_held_cloth", release_held_cloth);
  }
};

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
