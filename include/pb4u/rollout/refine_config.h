#pragma once
// How a network's step is refined by the reference solver (refined_step.h): the config's and
// the scene's `refine` section. A model file stores only its count, tolerance and contact
// (ModelConfig::refine_*); the other keys here apply to its refinement too.
#include <string>

#include "pb4u/config/config_io.h"

namespace pb4u {

struct RefineConfig {
  int iterations = 0;        // solver iterations after each step; 0 with tolerance_mm 0: off
  double tolerance_mm = 0;   // > 0: iterate (up to the solver's max_iterations) until the
                             // solver's step is below this (mm); with iterations > 0 as well,
                             // at most those first (fewer where the step is below
                             // this already), then on until the step is below this
  // The solver's step for the refinement (physics.solver.step is the solver's own): "newton"
  // lands nearer the minimum per iteration (docs/physics.md, "The Newton step").
  std::string step = "newton";
  // The refinement's physics.solver.release_held_cloth (on by default, as the solver's own):
  // off, the body the network's step holds back gets its 24 moves and is placed at its pose,
  // catching that cloth. On beside solver.own_start_where_left_out (also on by default): alone
  // it read 1.25x the reference on the demo walk (off 1.03x), with it 0.97x (docs/physics.md,
  // "The solver's own start where the step leaves cloth out").
  bool release_held_cloth = true;
  bool enabled() const { return iterations > 0 || tolerance_mm > 0; }

  template <class V>
  void visit(V& v) {
    v("iterations", iterations, int_at_least(0));
    v("tolerance_mm", tolerance_mm, non_negative());
    v("step", step, one_of({"quasi_newton", "newton"}));
    v("release_held_cloth", release_held_cloth);
  }
};

}  // namespace pb4u
