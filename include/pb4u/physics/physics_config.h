#pragma once
// Every constant of the physics terms and the reference solver (SPEC 3, 8), as config
// sections. Defaults are the SPEC values; nothing numeric is hard-coded in the terms.
#include <cstdint>
#include <string>

#include "pb4u/config/config_io.h"

namespace pb4u {

// Cubic penalty E = w * sum max(eps - d, 0)^3 (SPEC 3.3).
struct CollisionConfig {
  double eps = 2e-3;          // m: penalty acts closer than this to the body surface
  double weight_start = 5e3;  // J/m^3: weight at training step 0
  double weight_end = 5e5;    // J/m^3: final weight, also the evaluation weight
  int hold_steps = 0;         // training steps at weight_start before the ramp begins
  int ramp_steps = 50000;     // training steps over which the weight then ramps start -> end
  std::string ramp = "exponential";  // exponential (geometric) | linear | constant (= end)
  // What d is measured against: plane (SPEC 3.3: the plane of the face with the nearest centroid
  // at t) | surface (the body's own inside and its outer surface at t + dt, which a vertex deep
  // in a limb cannot escape: physics/surface_contact.h)
  std::string measure = "plane";

  template <class V>
  void visit(V& v) {
    v("eps", eps, positive());
    v("measure", measure, one_of({"plane", "surface"}));
    v("weight_start", weight_start, positive());
    v("weight_end", weight_end, positive());
    v("hold_steps", hold_steps, int_at_least(0));
    v("ramp_steps", ramp_steps, int_at_least(0));
    v("ramp", ramp, one_of({"exponential", "linear", "constant"}));
  }
};

// E = sum mu m_i |g| |slip_tangential| over vertices in contact (SPEC 3.5).
struct FrictionConfig {
  double mu = 0.5;                // friction coefficient
  double contact_radius = 5e-3;   // m: a vertex whose signed distance at t is below this is in contact
  // m: |s| is evaluated as sqrt(|s|^2 + d^2) - d, which is 0 at zero slip like |s| but has a
  // gradient there (the solver and the finite-difference checks need one).
  double slip_smoothing = 1e-6;

  template <class V>
  void visit(V& v) {
    v("mu", mu, non_negative());
    v("contact_radius", contact_radius, positive());
    v("slip_smoothing", slip_smoothing, positive());
  }
};

// Reference solver (SPEC 8): L-BFGS on the per-frame energy with a backtracking line search.
// ContourCraft's cloth repulsion (physics/repulsion_energy.h), its stage-1 settings.
struct RepulsionConfig {
  double weight = 2e6;         // J/m^3: the final weight, also the evaluation weight
  // Training: weight_start until hold_steps, then linear to `weight` over ramp_steps (0: `weight`
  // from step 0). ContourCraft: 0, held 30000 steps, ramped over 10000.
  double weight_start = 0;
  int hold_steps = 0;
  int ramp_steps = 0;
  double eps = 3e-3;           // m: the penalty acts closer than this to the face's plane
  double radius = 1e-2;        // m: a vertex within this of a face's plane at t, over the face, is a pair
  double pinned_factor = 100;  // a pair with a pinned vertex weighs this much more (before the cube)

  template <class V>
  void visit(V& v) {
    v("weight", weight, non_negative());
    v("weight_start", weight_start, non_negative());
    v("hold_steps", hold_steps, int_at_least(0));
    v("ramp_steps", ramp_steps, int_at_least(0));
    v("eps", eps, positive());
    v("radius", radius, positive());
    v("pinned_factor", pinned_factor, positive());
  }
};

struct ReferenceSolverConfig {
  int max_iterations = 200;  // iteration budget per frame
  // m: converged when the quasi-Newton step max_i |(H^-1 dE/dx)_i| (the energy gradient in the
  // solver's Hessian metric: the correction still to make) is below this. Unlike a force in N
  // it does not shrink with the vertex masses as the mesh is refined.
  double step_tolerance = 1e-6;
  // Iterations taken before step_tolerance may stop the solve (not a key: a refinement's count
  // with a tolerance takes its first Newton step however small, rollout/refined_step.h).
  int min_iterations = 0;
  // J: also converged when the step's predicted decrease of the energy, -g.d / 2 (half the
  // Newton decrement squared for the Newton step), is below this; 0: off. The last iterations
  // of a step otherwise go to sub-micro-joule buckling modes that move no vertex by much.
  double decrease_tolerance = 0;
  int history = 10;                 // L-BFGS memory (pairs)
  int max_line_search_steps = 30;   // halvings before a step is given up
  double armijo = 1e-4;             // sufficient-decrease constant c1
  // Initial inverse Hessian of L-BFGS: "elastic" = inertia + rest membrane stiffness,
  // factorised once per frame (see quasi_newton_hessian.h); "inertia" = dt^2 / m only.
  std::string initial_hessian = "elastic";
  // Body contact: "barrier" (the reference) = intersection-free contact: IPC's log barrier on
  // vertex-face and edge-edge distances with every line-search step filtered by CCD, from a
  // start made intersection-free (intersection_free_start.h); "penalty" (`--method penalty`) =
  // SPEC 3.3's plane term alone (it stops paying once a vertex is past the plane of its nearest
  // face, so the cloth can sit inside the body).
  std::string contact = "barrier";
  double barrier_distance = 1e-3;   // m: d_hat, where the barrier starts to act
  // m: the body as the barrier sees it is moved out by this along its vertex normals where it
  // has room in front (a contact offset, as C-IPC's thickness; body_offset.h), so that the cloth
  // rests this far off the body: with the collision term's eps (3 mm) the SPEC 3.3 term no
  // longer charges the barrier's rest. 0: off.
  double barrier_offset = 0;
  // true: SPEC 3.3's penalty collision term stays in the objective on every vertex beside the
  // barrier, so the solver minimises the energy every method is measured on (the network's loss,
  // the penalty solver's objective), and the barrier with CCD forbids crossing the body. false:
  // the barrier takes the penalty's place (IPC) and the penalty holds only the vertices left out
  // of barrier contact; the cloth then rests within d_hat, inside the term's eps.
  bool barrier_keeps_penalty = true;
  double barrier_stiffness = 1000;  // J/m^2: kappa at the start of each step
  // J/m^2: kappa may double up to this within a step (IPC's adaptive stiffness): whenever an
  // accepted step leaves the closest pair nearer than barrier_gap x d_hat and nearer than the
  // step before. 0: kappa stays fixed.
  double barrier_stiffness_max = 1e5;
  double barrier_gap = 0.1;
  // true: a rollout's next step starts at the kappa the last one ended with (IPC keeps kappa
  // from step to step), not at barrier_stiffness; the reference's stepper carries it. Newton
  // takes few iterations a step, too few for the doubling to catch a heavy cloth within one.
  bool barrier_stiffness_carries = false;
  // Strain limiting as a barrier (strain_barrier.h, after C-IPC): no cloth edge longer than
  // (1 + strain_limit) x its rest length at the end of any line-search step; 0: off (SPEC 8's
  // solver has no limit). The barrier acts within strain_barrier_gap of the limit.
  double strain_limit = 0;
  double strain_barrier_gap = 0.01;
  double strain_barrier_stiffness = 1.0;  // J
  // The barrier against collapse (area_barrier.h): no cloth triangle's area reaches zero in any
  // line-search step; it acts below area_barrier_gap x the rest area (0: off, the default), with
  // a stiffness per rest area. At 0.1 it ends the stall a collapsed triangle caused at the finest
  // level, but the demo walk at level 1 then fell into a high-stretch state after frame 210 in
  // 3 of 4 runs of 300 frames, against none of 2 without it (docs/physics.md).
  double area_barrier_gap = 0;
  double area_barrier_stiffness = 1e4;  // J/m^2
  // Where a solve from a given step (a network's, `--refine`) starts, with barrier contact:
  // "at_step" = the step itself, made free of the body at its pose at t + dt; "swept" = from the
  // cloth at t towards the step against the body at t (as the solver's own start sweeps towards
  // the ballistic prediction), the body then moving to its pose; "fewer_left_out" = at_step,
  // unless that leaves vertices out of contact and the swept start leaves fewer, and then, where
  // the swept solve's body caught cloth, the solve from at_step too, keeping the one that left
  // fewer out; "swept_if_left_out" = at_step, unless that leaves any vertex out of contact, then
  // swept; "fewer_left_out_to_tolerance" (the default) = at_step for a refinement's fixed count
  // of iterations, fewer_left_out for its solve to the tolerance, which then also runs where the
  // count left vertices out (a solve from a given step outside a refinement: at_step). A step
  // checked only where it ends can have passed through a fast body or be pinched where the body
  // crosses itself, which the swept start undoes; but a swept start leaves the body's whole
  // motion to the solve, which a few iterations do not finish (fewer_left_out diverges on the demo
  // walk at one iteration a frame). docs/physics.md, "Where a refinement starts", has the figures.
  std::string given_start = "fewer_left_out_to_tolerance";
  // Where a given step's start, chosen by given_start, still leaves vertices out of barrier
  // contact (no free place near: pinched where the body crosses itself, or threaded through a
  // limb): true (the default) = the step is dropped for that solve, which starts as the
  // solver's own does (the ballistic prediction, swept from the cloth at t;
  // SolverResult::own_start). The cloth the network left with no free place then goes where the
  // solver's own motion takes it. Under fewer_left_out_to_tolerance only the solve to the
  // tolerance takes it. It works beside the refinement's release_held_cloth (on by default):
  // on the tank top's CMU walk the refined file stopped at frame 40 without the two and ran the
  // 300 frames with them (docs/physics.md, "The solver's own start where the step leaves cloth
  // out").
  bool own_start_where_left_out = true;
  // Where the body, held up by the cloth, is placed at its pose after its moves: true = the
  // cloth it then cuts or holds is first pushed out of it as a start is (intersection_free_start:
  // out of the body, edges through it pushed further), and only what that leaves is caught
  // (left out of barrier contact for the penalty term); false (the default) = all of it is
  // caught. On the hard cases' spin it cuts the caught cloth from 10-68 to 2-9 vertices a frame
  // and the most edges through the body from 95 to 29; on the demo walk's first 150 frames it
  // catches 221 vertices instead of 996 but reads 12% more energy (a frame 2.5x), with the same
  // share inside (docs/physics.md).
  bool push_out_caught = false;
  // Cloth that holds a body move back (CCD allows the move less than a tenth of what it tries:
  // pinched between two body parts, a cloth edge dragged against a body edge, a pin in the
  // body's path): true (the default) = it leaves barrier contact and the body moves on, allowed
  // as many moves as its motion needs at 5 cm each and 24 more; once the body is at its pose
  // that cloth is pushed out of it as a start is, and what that frees rejoins barrier contact.
  // false = the body gets 24 moves and is then placed at its pose, the cloth it holds caught
  // inside; on the held-out run and jump that stopped the solver (frames 60 and 27). A
  // refinement reads its own switch, also on by default (RefineConfig, rollout/refine_config.h).
  // docs/physics.md, "Releasing the cloth that holds the body back", has the figures.
  bool release_held_cloth = true;
  // Where a barrier solve stops (at rest, or no decrease left) with cloth out of barrier contact
  // (no free place at its start, released or caught by the body): true (the default) = the whole
  // cloth is pushed out of the body as a start is; where that frees some of the cloth left out
  // and leaves all the cloth in contact free, the freed vertices rejoin contact and the solve
  // goes on from there (twice a step at most). false = they stay with the penalty term to the
  // step's end. On the jump at the training edge the landing's three shoulder vertices were
  // still 10.5 mm inside at the end of frame 30 (docs/physics.md, "Cloth left out, readmitted
  // where the solve stops").
  bool readmit_at_rest = true;
  // How a body move carries the cloth it touches (carried_by_body.h): "push" (the default) =
  // each pair the body approaches (to first order) moves its cloth with the body's closest point;
  // "ride" = cloth nearer than d_hat / 2 also rides where the body slides or turns under it, each
  // end of a cloth edge moves with the body edge where it projects onto it, and a point pushed
  // by several pairs meets each. On the hard cases' spin, "ride" gets the body to its pose on
  // every frame with nothing inside (push: placed short on 6 of 15, 1.74% inside); on the demo
  // walk's first 150 frames, where the hand enters the hip, it catches 2044 vertices instead of
  // 996, and 195 with push_out_caught beside it (docs/physics.md, "Carrying the cloth the body
  // slides and turns under").
  std::string body_carry = "push";
  // Which body faces a barrier solve measures SPEC 3.3's penalty (and friction's slip) against:
  // "all" (SPEC 3.3: the face with the nearest centroid) or "outer" = only the faces no other
  // part of the body covers at t + dt (body/outer_faces.h). Where the body crosses itself (a
  // hand sunk into a hip), cloth pinched between the two parts is inside one of them wherever
  // it is, and its nearest face can be a covered one, whose plane pushes it deeper into the
  // other part; "outer" pushes it towards the surface of the body as a whole. The same faces
  // where the body does not cross itself. The figures a rollout reports stay SPEC 3.3's.
  std::string penalty_faces = "all";
  // How the barriers' curvature (contact, strain) enters L-BFGS's elastic initial Hessian:
  // "diagonal" = one isotropic value per vertex; "blocks" = their Hessians on the coordinates
  // (coordinate_hessian.h; stiff along a contact's normal and an edge's direction, free across;
  // what the Newton step always uses). Blocks were no better on the garment scenes and worse on
  // the hard cases' spin and jump (docs/physics.md, "The Newton step").
  std::string barrier_hessian = "diagonal";
  // The step: "quasi_newton" = L-BFGS from the initial Hessian above; "newton" = projected
  // Newton: each iteration solves with the Hessian at the current state (elastic_hessian.h:
  // inertia, StVK projected per face, bending Gauss-Newton; the contacts' curvature and the
  // barriers' blocks), no curvature history; "auto" = Newton with barrier contact (L-BFGS
  // stalls there: the demo walk's frames 210-300 end 5-12 mm from the minimum), L-BFGS with
  // the penalty term alone (converged there, and 1.8x faster than Newton).
  std::string step = "auto";
  // The Hessian of every rollout's per-frame residual (step_residual.h, `residual_mm`):
  // "newton" = this solver's Newton Hessian at the step (where the energy is smooth an offset
  // reads its length in any direction; on the network's steps 1.43x the true distance, median);
  // "quasi_newton" = L-BFGS's isotropic initial Hessian (the residual until 2026-12-05; it reads
  // an offset out of the cloth's plane short, 0.68x; docs/physics.md).
  std::string residual_hessian = "newton";

  template <class V>
  void visit(V& v) {
    v("max_iterations", max_iterations, int_at_least(0));
    v("step_tolerance", step_tolerance, positive());
    v("decrease_tolerance", decrease_tolerance, non_negative());
    v("history", history, int_at_least(1));
    v("max_line_search_steps", max_line_search_steps, int_at_least(1));
    v("armijo", armijo, in_range(1e-8, 0.5));
    v("initial_hessian", initial_hessian, one_of({"elastic", "inertia"}));
    v("contact", contact, one_of({"penalty", "barrier"}));
    v("barrier_distance", barrier_distance, positive());
    v("barrier_offset", barrier_offset, non_negative());
    v("barrier_keeps_penalty", barrier_keeps_penalty);
    v("barrier_stiffness", barrier_stiffness, positive());
    v("barrier_stiffness_max", barrier_stiffness_max, non_negative());
    v("barrier_gap", barrier_gap, in_range(0.0, 1.0));
    v("barrier_stiffness_carries", barrier_stiffness_carries);
    v("strain_limit", strain_limit, non_negative());
    v("strain_barrier_gap", strain_barrier_gap, positive());
    v("strain_barrier_stiffness", strain_barrier_stiffness, positive());
    v("area_barrier_gap", area_barrier_gap, in_range(0.0, 1.0));
    v("area_barrier_stiffness", area_barrier_stiffness, positive());
    v("given_start", given_start,
      one_of({"at_step", "swept", "fewer_left_out", "swept_if_left_out", "fewer_left_out_to_tolerance"}));
    v("own_start_where_left_out", own_start_where_left_out);
    v("push_out_caught", push_out_caught);
    v("release_held_cloth", release_held_cloth);
    v("readmit_at_rest", readmit_at_rest);
    v("body_carry", body_carry, one_of({"push", "ride"}));
    v("penalty_faces", penalty_faces, one_of({"all", "outer"}));
    v("barrier_hessian", barrier_hessian, one_of({"blocks", "diagonal"}));
    v("step", step, one_of({"auto", "quasi_newton", "newton"}));
    v("residual_hessian", residual_hessian, one_of({"newton", "quasi_newton"}));
  }
};

// m^2: PhysicsConfig::degenerate_area's default (and BodyContact's where none was given).
constexpr double kDefaultDegenerateArea = 1e-14;

struct PhysicsConfig {
  CollisionConfig collision;
  FrictionConfig friction;
  RepulsionConfig repulsion;
  ReferenceSolverConfig solver;
  // m^2: a face whose doubled area is below this counts as degenerate; its normal is not
  // normalised and hinges touching it bend by 0 (keeps sqrt / atan2 gradients finite).
  double degenerate_area = kDefaultDegenerateArea;

  template <class V>
  void visit(V& v) {
    v("collision", collision);
    v("friction", friction);
    v("repulsion", repulsion);
    v("solver", solver);
    v("degenerate_area", degenerate_area, positive());
  }
};

// The collision weight at a training step: weight_start for hold_steps, then the configured
// ramp over ramp_steps; the final weight (weight_end) from hold_steps + ramp_steps on.
// Evaluation uses weight_end.
double collision_weight(const CollisionConfig& config, int64_t step);
// The repulsion weight (J/m^3) at training step `step` (RepulsionConfig).
double repulsion_weight(const RepulsionConfig& config, int64_t step);

}  // namespace pb4u
