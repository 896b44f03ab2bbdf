#include "pb4u/model/model_config.h"

#include "pb4u/model/hood_schedule.h"

namespace pb4u {

void validate_model_config(const ModelConfig& c, const std::string& where) {
  const auto& r = c.train_k_range;
  if (r.size() != 2 || !(r[0] >= 0) || !(r[0] <= r[1]))
    throw Error(where + ".train_k_range: expected [lo, hi] with 0 <= lo <= hi (multiples of K_base)");
  if (c.is_hood()) {
    const size_t blocks = parse_hood_schedule(c.hood_schedule, kCoarseLevels, where + ".hood_schedule").size();
    if (static_cast<size_t>(c.num_blocks) != blocks)
      throw Error(where + ".num_blocks: " + std::to_string(c.num_blocks) + ", but " + where + ".hood_schedule has " +
                  std::to_string(blocks) + " blocks");
  }
}

}  // namespace pb4u
