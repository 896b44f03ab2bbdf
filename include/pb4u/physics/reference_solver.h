#pragma once
// The reference physics solver (SPEC 8): optimisation-based implicit time stepping on the
// same energy as the network's loss. Each frame minimises the active terms' total energy
// over x_{t+1} with L-BFGS and a backtracking (Armijo) line search, pinned vertices held at
// their targets.
#include <torch/torch.h>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct SolverResult {
  torch::Tensor x_next;      // (n, 3) m, detached, the cloth's dtype
  int iterations = 0;        // L-BFGS iterations used
  int evaluations = 0;       // energy + gradient evaluations (line search included)
  double energy = 0;         // J, total energy reached
  double gradient_norm = 0;  // N: max |dE/dx| over free coordinates at x_next
  bool converged = false;    // gradient_norm <= gradient_tolerance
};

// One frame. terms: build_terms(state.effects, ...); contact: body_contact_for(state, ...)
// (null without a body). Pins apply when state.effects.pins and state.pinned is defined.
// Starts from the ballistic prediction (plus g dt^2 with gravity on).
SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config);

}  // namespace pb4u
