#include "pb4u/rollout/divergence_guard.h"

#include <algorithm>
#include <cstdio>

namespace pb4u {

std::string energy_divergence(const DivergenceConfig& config, double start, double positive) {
  if (config.energy_ratio <= 0) return "";
  const double reference = std::max(start, config.energy_floor);
  if (positive <= config.energy_ratio * reference) return "";
  char why[160];
  if (start >= config.energy_floor)
    std::snprintf(why, sizeof why, "positive energy %.3g J is %.3gx frame 1's %.3g J (limit %gx)", positive,
                  positive / reference, start, config.energy_ratio);
  else
    std::snprintf(why, sizeof why, "positive energy %.3g J is %.3gx the floor %.3g J (frame 1's %.3g J is below it; limit %gx)",
                  positive, positive / reference, reference, start, config.energy_ratio);
  return why;
}

}  // namespace pb4u
