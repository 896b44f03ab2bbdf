#pragma once
// The reference physics solver (SPEC 8): optimisation-based implicit time stepping on the
// same energy as the network's loss. Each frame minimises the active terms' total energy
// over x_{t+1} with L-BFGS and a backtracking (Armijo) line search, pinned vertices held at
// their targets. L-BFGS starts each step from a fixed approximate Hessian (inertia + rest
// membrane stiffness, quasi_newton_hessian.h): on stiff cloth this cuts the energy gap after
// 50 iterations 8-17x against a mass-only start (docs/physics.md).
#include <torch/torch.h>

#include <Eigen/Core>

#include <limits>
#include <optional>

#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_term.h"

namespace pb4u {

struct SolverResult {
  torch::Tensor x_next;      // (n, 3) m, detached, the cloth's dtype
  int iterations = 0;        // L-BFGS iterations used
  int evaluations = 0;       // energy + gradient evaluations (line search included)
  double energy = 0;         // J, total energy reached
  double gradient_norm = 0;  // N: max |dE/dx| over free coordinates at x_next
  double step_norm = 0;      // m: max |quasi-Newton step| at x_next (H^-1-scaled gradient)
  bool converged = false;    // step_norm <= step_tolerance
  // Barrier contact only (0 / infinity / 0 / 0 otherwise):
  double body_lag = 0;       // m: how far the body still was from its pose at t + dt when the
                             // cloth left it no room and it was placed there (0: it got there)
  double min_distance = std::numeric_limits<double>::infinity();  // m, cloth to body at x_next
                             // over the vertices in contact (the excluded ones left out)
  double barrier_stiffness = 0;  // J/m^2: kappa at the end of the step (solver.barrier_stiffness_max)
  int pushed_out = 0;        // vertices moved out of the body at t before the step
  int excluded = 0;          // vertices left out of barrier contact this step (the penalty term
                             // holds them): no free place at the start (intersection_free_start.h),
  int caught_by_body = 0;    // or, of those, held by the body: pinched as it moved (left out so
                             // that it could move on) or cut or held by the body placed at its pose
  int released = 0;          // vertices that held a body move back and left barrier contact so
                             // that the body could move on (those the body, at its pose, left
                             // room for rejoined it and are not in `excluded`)
  int readmitted_at_rest = 0;  // vertices out of contact that rejoined it where the solve had
                               // stopped (solver.readmit_at_rest; no longer in `excluded`)
  std::vector<char> excluded_vertices;  // per cloth vertex, 1 for those left out (empty: none)
  // Strain barrier only (solver.strain_limit > 0; 0 / 0 otherwise):
  double max_strain = 0;     // largest edge strain at x_next over the edges in the barrier
  int strain_excluded = 0;   // edges left out of it: at or past the limit after the start's
                             // Provot pass (both ends pinned) or carried there by the body
  // Area barrier only (solver.area_barrier_gap > 0; 1 / 0 otherwise): the smallest area ratio
  // A / A0 at x_next over the faces in the barrier, and the faces left out of it (in its band
  // where the step started or after a body move).
  double min_area_ratio = 1;
  int area_excluded = 0;
  bool swept_start = false;  // a given step's start was swept from the cloth at t (GivenStart)
  // Without barrier contact (no body, or the penalty term): a given step starts the solve only
  // where it is lower in the objective than the solver's own start (the ballistic prediction,
  // pins at their targets); true where the own start was used. With barrier contact and
  // solver.own_start_where_left_out: true where the given step's start left vertices out of
  // contact and the solve started as the solver's own does instead.
  bool own_start = false;
  // Without barrier contact: the solve started from the cloth where it stands at t (pins at
  // their targets), which was lower in the objective than the prediction (or the given step).
  bool standing_start = false;
};

// The body of one step as intersection-free contact sees it: the body at t and t + dt, its
// outward faces, the cloth's unique edges and the barrier.
struct BarrierStepInput {
  Eigen::MatrixXd body_t, body_next;
  Eigen::MatrixXi body_faces, cloth_edges;
  BarrierSettings settings;
  // The penalty collision term stays in the objective on every vertex (barrier_keeps_penalty);
  // else it holds only the vertices left out of barrier contact.
  bool keeps_penalty = false;
  // Whether a term is left out of the barrier objective (the penalty collision term, unless kept).
  bool drops(const PhysicsTerm& term) const;
  // Where a solve from a given step (x_start, a network's) starts:
  //   at_step: the step itself, at t + dt, made free of the body placed at its pose there;
  //   swept: from the cloth at t towards the step against the body at t, as the solver's own
  //     start sweeps towards the ballistic prediction; the body then moves to its pose;
  //   fewer_left_out: at_step, unless it leaves vertices out of contact and swept leaves fewer;
  //   swept_if_left_out: at_step, unless it leaves any vertex out of contact; then swept.
  enum class GivenStart { at_step, swept, fewer_left_out, swept_if_left_out };
  GivenStart given_start = GivenStart::at_step;
  // solver.penalty_faces = outer, where the body at t + dt crosses itself: the rows of
  // body_faces no other part covers then (body/outer_faces.h); empty otherwise.
  std::vector<int64_t> outer_faces;
  // The contact the solve measures the penalty and friction terms with: `contact` (the step's,
  // over all faces, of the cloth at t) measured again against outer_faces where there are any
  // (contact_on_faces); std::nullopt where it stays `contact`.
  std::optional<BodyContact> solved_contact(const FrameState& state, const BodyContact* contact) const;
};

// One frame. terms: build_terms(state.effects, ...); contact: body_contact_for(state, ...)
// (null without a body). Pins apply when state.effects.pins and state.pinned is defined.
// Starts from the ballistic prediction (plus g dt^2 with gravity on). With `barrier` (terms
// then without the penalty collision term) the step is intersection-free: it starts from
// intersection_free_start(); the body moves to its pose at t + dt in CCD-certified moves that
// carry the cloth it touches (carried_by_body.h), between quasi-Newton steps of the cloth, and
// every line-search step is cut to what CCD certifies. Vertices left out of barrier contact
// (SolverResult::excluded) fall back to the penalty term.
// x_start, when given (n, 3), is where the solve starts instead of the ballistic prediction
// (pinned vertices still at their targets): a network's step to refine (rollout/refined_step.h);
// with barrier contact, where it stands or swept from t as barrier->given_start says.
SolverResult solve_reference_step(const FrameState& state, const ClothGeometry& cloth,
                                  const TermList& terms, const BodyContact* contact,
                                  const ReferenceSolverConfig& config,
                                  const BarrierStepInput* barrier = nullptr,
                                  const torch::Tensor* x_start = nullptr);

// The barrier input of a step when config.contact is barrier and the step's effects collide
// with a body; std::nullopt otherwise (the penalty term then handles contact, if any).
std::optional<BarrierStepInput> barrier_step_input(const FrameState& state, const ClothGeometry& cloth,
                                                   const ReferenceSolverConfig& config);

// The same frame with the step's body contact computed from the state (none when its effects
// need no body): what a rollout (`simulate --method reference`, `bench`) calls per frame.
// config.solver.contact = barrier replaces the collision term by the barrier.
SolverResult solve_reference_frame(const FrameState& state, const ClothGeometry& cloth,
                                   const TermList& terms, const PhysicsConfig& config);

}  // namespace pb4u
