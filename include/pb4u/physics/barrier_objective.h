#pragma once
// The energy the intersection-free solver minimises (solver.contact = barrier), as pieces any
// caller can add up: the active terms but the penalty collision, the barrier over the pairs of
// the vertices in barrier contact, and the penalty collision (SPEC 3.3) on the vertices left out
// of it (no free place at the start, or caught by the body). The solver
// (IncrementalPotentialSolve::evaluate, incremental_potential_solve.cpp) and the residual of a
// barrier-contact rollout (step_residual.h) measure the same objective.
#include <torch/torch.h>

#include <vector>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

// The penalty contact restricted to the excluded vertices (excluded[i] != 0).
struct PenaltyFallback {
  const CollisionTerm* term = nullptr;  // the collision term of the term list
  torch::Tensor rows;                   // (m) int64: the excluded vertices; undefined when none
  BodyContact contact;                  // their rows of the contact

  bool active() const { return term && rows.defined(); }
  // J: the penalty on those rows of x (n, 3); 0 when inactive.
  torch::Tensor energy(const torch::Tensor& x) const;
  // (n): its curvature at those rows, zero elsewhere; undefined when inactive.
  torch::Tensor stiffness(const torch::Tensor& x, const FrameState& state, const ClothGeometry& cloth,
                          const BodyContact* full_contact) const;
};

// null `contact`, no collision term or no excluded vertex: an inactive fallback.
PenaltyFallback penalty_fallback(const TermList& terms, const BodyContact* contact, const std::vector<char>& excluded);

}  // namespace pb4u
