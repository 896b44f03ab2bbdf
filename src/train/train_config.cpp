#include "pb4u/train/train_config.h"

#include <algorithm>
#include <cmath>

namespace pb4u {

double learning_rate(const OptimConfig& optim, int64_t step, int64_t steps) {
  double progress = steps > 1 ? std::clamp(double(step) / double(steps - 1), 0.0, 1.0) : 1.0;
  return optim.lr * std::pow(optim.lr_final / optim.lr, progress);
}

int rollout_length(const CurriculumConfig& curriculum, int64_t step) {
  int64_t r = 1 + step / curriculum.steps_per_increase;
  return static_cast<int>(std::min<int64_t>(r, curriculum.rollout_max));
}

}  // namespace pb4u
