#include "pb4u/model/propagation_control.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "pb4u/util/error.h"

namespace pb4u {

int64_t propagation_steps(double distance, double mean_edge_length) {
  if (!(distance > 0) || !(mean_edge_length > 0))
    throw Error("propagation control: needs a calibrated distance D and a positive mean edge "
                "length (got D = " + std::to_string(distance) + " m, Lbar = " +
                std::to_string(mean_edge_length) + " m)");
  // D / Lbar at the calibration mesh is K_base up to rounding; the relative slack keeps
  // floor() from dropping it to K_base - 1.
  constexpr double kRelativeSlack = 1e-9;
  const double ratio = distance / mean_edge_length * (1.0 + kRelativeSlack);
  return std::max<int64_t>(1, static_cast<int64_t>(std::floor(ratio)));
}

int64_t inference_propagation_steps(const ModelConfig& config, double distance,
                                    double mean_edge_length) {
  if (!config.is_pb4u()) return 0;
  if (!config.propagation_control_on()) return config.k_base;
  return propagation_steps(distance, mean_edge_length);
}

int64_t sample_propagation_steps(const ModelConfig& config, std::mt19937_64& rng, double depth) {
  if (!config.is_pb4u()) return 0;
  if (!config.propagation_control_on()) return config.k_base;
  validate_model_config(config);
  if (!(depth > 0)) throw Error("sample_propagation_steps: the depth factor must be positive");
  const double k = config.k_base * depth;
  const auto lo = static_cast<int64_t>(std::ceil(config.train_k_range[0] * k - 1e-9));
  const auto hi = static_cast<int64_t>(std::floor(config.train_k_range[1] * k + 1e-9));
  return std::uniform_int_distribution<int64_t>(lo, std::max(lo, hi))(rng);
}

}  // namespace pb4u
