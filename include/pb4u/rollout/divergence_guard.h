#pragma once
// When a rollout counts as diverged (SPEC 9: stable, not merely finite): a non-finite
// position or energy, or a positive energy (stretch + bending + collision) grown past a
// multiple of where it started. `run_rollout` stops at such a frame and names it.
#include <string>

#include "pb4u/config/config_io.h"

namespace pb4u {

// YAML section `divergence` of evaluate, simulate scene and bench configs.
struct DivergenceConfig {
  // Stop when a frame's positive energy exceeds this multiple of the start (frame 1's
  // positive energy, at least energy_floor); 0 turns the energy check off.
  double energy_ratio = 1000;
  // J: the least start, so a near-zero frame 1 (a cloth at rest) does not trip the guard on
  // the first sag. 1e-3 J is a t-shirt (0.1 kg) lowered by 1 mm.
  double energy_floor = 1e-3;

  template <class V>
  void visit(V& v) {
    v("energy_ratio", energy_ratio, Check<double>([](const double& r) {
        return r == 0 || r >= 1 ? std::string() : std::string("must be 0 (off) or at least 1");
      }));
    v("energy_floor", energy_floor, positive());
  }
};

// "" when `positive` (J) is within the bound set by `start` (frame 1's positive energy, J),
// else why not, e.g. "positive energy 3.2e+04 J is 1.2e+04x frame 1's 2.7 J (limit 1000x)".
std::string energy_divergence(const DivergenceConfig& config, double start, double positive);

}  // namespace pb4u
