#include "pb4u/train/train_config.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pb4u {

Check<std::vector<double>> scale_factors() {
  return [](const std::vector<double>& scales) -> std::string {
    if (scales.empty()) return "expected at least one factor ([1] = as generated)";
    for (double c : scales)
      if (!(c > 0 && c <= 10)) {
        std::ostringstream why;  // the factor as given: -0.5, not -0.500000
        why << c << " is not a factor in (0, 10]";
        return why.str();
      }
    return "";
  };
}

double learning_rate(const OptimConfig& optim, int64_t step, int64_t steps) {
  double progress = steps > 1 ? std::clamp(double(step) / double(steps - 1), 0.0, 1.0) : 1.0;
  return optim.lr * std::pow(optim.lr_final / optim.lr, progress);
}

int rollout_length(const CurriculumConfig& curriculum, int64_t step) {
  int64_t r = 1 + step / curriculum.steps_per_increase;
  return static_cast<int>(std::min<int64_t>(r, curriculum.rollout_max));
}

}  // namespace pb4u
