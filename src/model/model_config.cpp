#include "pb4u/model/model_config.h"

#include "pb4u/model/hood_schedule.h"

namespace pb4u {

std::string ModelConfig::schedule() const {
  if (!hood_schedule.empty()) return hood_schedule;
  return is_ccraft() ? kContourCraftSchedule : kHoodSchedule;
}

void validate_model_config(const ModelConfig& c, const std::string& where) {
  const auto& r = c.train_k_range;
  if (r.size() != 2 || !(r[0] >= 0) || !(r[0] <= r[1]))
    throw Error(where + ".train_k_range: expected [lo, hi] with 0 <= lo <= hi (multiples of K_base)");
  if (c.is_eslr() && c.latent % c.attention_heads != 0)
    throw Error(where + ".attention_heads: " + std::to_string(c.attention_heads) + " does not divide " + where +
                ".latent (" + std::to_string(c.latent) + ")");
  if (c.is_hierarchical()) {
    const size_t blocks = parse_hood_schedule(c.schedule(), c.coarse_levels(), where + ".hood_schedule").size();
    if (static_cast<size_t>(c.num_blocks) != blocks)
      throw Error(where + ".num_blocks: " + std::to_string(c.num_blocks) + ", but " + where + ".hood_schedule has " +
                  std::to_string(blocks) + " blocks");
  }
}

}  // namespace pb4u
