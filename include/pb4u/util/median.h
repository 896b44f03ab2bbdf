#pragma once
// The median of a sample (timings are reported as medians of repeated runs).
#include <algorithm>
#include <cmath>
#include <vector>

namespace pb4u {

// Middle value of v (mean of the two middle ones for an even count); NaN for an empty v.
inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace pb4u
