#pragma once
// How far a step is from the minimum of the energy it is measured by: the length of one
// quasi-Newton step from x_next, the largest vertex move of H^-1 grad E, with H the reference
// solver's initial Hessian (inertia + rest membrane stiffness, quasi_newton_hessian.h) plus the
// terms' contact curvature and the bending's (the diagonal of its Gauss-Newton Hessian, which
// keeps the step a distance where a face has flattened and the bending's gradient is large),
// and grad E the gradient of the active terms at x_next, pinned
// vertices held. 0 at the energy's minimum; the reference solver stops below its
// step_tolerance (1e-6 m). One gradient, one sparse factorisation and one solve: any stepper's
// output can be measured by it, the network's as well as a solver's.
// With barrier contact (`barrier` given: solver.contact = barrier and a body) the energy is the
// intersection-free solver's (barrier_objective.h): the barrier at kappa = its
// barrier_stiffness over the pairs of the vertices free of the body at t + dt, the penalty term
// on the others, instead of the penalty term everywhere (whose eps a cloth resting within the
// barrier's d_hat never meets).
#include <torch/torch.h>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct BarrierStepInput;

// m. terms: build_terms(state.effects, ...); contact: body_contact_for(state, ...) or null.
// state.material is the material the energy is measured with.
// excluded (per cloth vertex, with `barrier`; empty: none): the vertices the solver that made
// x_next left out of barrier contact, measured with the penalty term alone, instead of those not free of the
// body at x_next (the solver's own objective: a vertex next to one it left inside ends an edge
// through the body, yet the solver kept it in the barrier).
double step_residual(const torch::Tensor& x_next, const FrameState& state, const ClothGeometry& cloth,
                     const TermList& terms, const BodyContact* contact, const BarrierStepInput* barrier = nullptr,
                     const std::vector<char>* excluded = nullptr);

}  // namespace pb4u
