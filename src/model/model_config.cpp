#include "pb4u/model/model_config.h"

namespace pb4u {

void validate_model_config(const ModelConfig& c, const std::string& where) {
  const auto& r = c.train_k_range;
  if (r.size() != 2 || !(r[0] >= 0) || !(r[0] <= r[1]))
    throw Error(where + ".train_k_range: expected [lo, hi] with 0 <= lo <= hi (multiples of K_base)");
}

}  // namespace pb4u
