#pragma once
// How far a step is from the minimum of the energy it is measured by: the length of one
// Newton step from x_next, the largest vertex move of H^-1 grad E, grad E the gradient of the
// active terms at x_next, pinned vertices held. H (`ResidualHessian`):
//   - newton (the default): the reference solver's own Newton Hessian at x_next, on the
//     coordinates (elastic_hessian.h: inertia M / dt^2, StVK projected per face, bending
//     Gauss-Newton; the contacts' curvature along or across their normals; the barrier pairs'
//     blocks). Where the energy is smooth an offset reads its length in any direction (a cloth
//     in the air: 1 mm up reads 1.00 mm, one vertex 1 mm out of the plane 0.89 mm). Moved out of
//     a contact, it reads long: the step from there does not see the contact's curvature that
//     holds the cloth at the minimum (a cloth resting on a sphere lifted 1 mm: 3.1 mm).
//   - quasi_newton: L-BFGS's initial Hessian (inertia + rest membrane stiffness,
//     quasi_newton_hessian.h), shared by x, y and z, plus the contacts' and the bending's
//     curvature on its diagonal. Isotropic: the membrane's stiffness holds every direction, so
//     an offset out of the cloth's plane reads short (the vertex above: 0.027 mm). About a
//     quarter of newton's cost at level 4.
// 0 at the energy's minimum; the reference solver stops below its step_tolerance (1e-6 m).
// One gradient, one sparse factorisation and one solve: any stepper's output can be measured by
// it, the network's as well as a solver's.
// With barrier contact (`barrier` given: solver.contact = barrier and a body) the energy is the
// intersection-free solver's (barrier_objective.h): the barrier at kappa = its
// barrier_stiffness over the pairs of the vertices free of the body at t + dt, the penalty term
// on the others, instead of the penalty term everywhere (whose eps a cloth resting within the
// barrier's d_hat never meets).
#include <torch/torch.h>

#include <string>
#include <vector>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct BarrierStepInput;

enum class ResidualHessian { newton, quasi_newton };
// "newton" / "quasi_newton" (physics.solver.residual_hessian); throws pb4u::Error otherwise.
ResidualHessian residual_hessian_from_name(const std::string& name);

// m. terms: build_terms(state.effects, ...); contact: body_contact_for(state, ...) or null.
// state.material is the material the energy is measured with.
// excluded (per cloth vertex, with `barrier`; empty: none): the vertices the solver that made
// x_next left out of barrier contact, measured with the penalty term alone, instead of those not free of the
// body at x_next (the solver's own objective: a vertex next to one it left inside ends an edge
// through the body, yet the solver kept it in the barrier).
double step_residual(const torch::Tensor& x_next, const FrameState& state, const ClothGeometry& cloth,
                     const TermList& terms, const BodyContact* contact, const BarrierStepInput* barrier = nullptr,
                     const std::vector<char>* excluded = nullptr,
                     ResidualHessian hessian = ResidualHessian::newton);

}  // namespace pb4u
