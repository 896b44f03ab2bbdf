#pragma once
// Wall-clock milliseconds since a steady_clock time point (stage and frame timings).
#include <chrono>

namespace pb4u {

inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace pb4u
