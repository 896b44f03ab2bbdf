#include "pb4u/data/levels.h"

namespace pb4u {

void validate_levels(const LevelsConfig& levels, const std::string& where) {
  const auto& t = levels.triangles;
  if (t.empty()) throw Error(where + ": levels.triangles: at least one level is needed");
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] < 8) throw Error(where + ": levels.triangles[" + std::to_string(i) + "]: must be >= 8");
    if (i > 0 && t[i] <= t[i - 1])
      throw Error(where + ": levels.triangles[" + std::to_string(i) + "]: levels must increase");
  }
}

}  // namespace pb4u
