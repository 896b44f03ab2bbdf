#include "pb4u/physics/physics_config.h"

#include <algorithm>
#include <cmath>

namespace pb4u {

double collision_weight(const CollisionConfig& config, int64_t step) {
  if (config.ramp == "constant") return config.weight_end;
  const int64_t ramp_step = step - config.hold_steps;
  if (ramp_step < 0) return config.weight_start;
  if (config.ramp_steps <= 0) return config.weight_end;
  double t = std::clamp(static_cast<double>(ramp_step) / config.ramp_steps, 0.0, 1.0);
  if (config.ramp == "linear") return config.weight_start + t * (config.weight_end - config.weight_start);
  // Geometric: the weight spans two orders of magnitude, so each decade gets equal time.
  return config.weight_start * std::pow(config.weight_end / config.weight_start, t);
}

double repulsion_weight(const RepulsionConfig& config, int64_t step) {
  if (config.ramp_steps <= 0) return step < config.hold_steps ? config.weight_start : config.weight;
  const double t = std::clamp(static_cast<double>(step - config.hold_steps) / config.ramp_steps, 0.0, 1.0);
  return config.weight_start + t * (config.weight - config.weight_start);
}

}  // namespace pb4u
