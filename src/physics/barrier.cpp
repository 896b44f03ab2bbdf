#include "pb4u/physics/barrier.h"

#include <cmath>
#include <limits>

namespace pb4u {

double barrier(double d, double d_hat) {
  if (d >= d_hat) return 0;
  if (d <= 0) return std::numeric_limits<double>::infinity();
  return -(d - d_hat) * (d - d_hat) * std::log(d / d_hat);
}

double barrier_derivative(double d, double d_hat) {
  if (d >= d_hat) return 0;
  const double e = d - d_hat;
  return -2 * e * std::log(d / d_hat) - e * e / d;
}

double barrier_second_derivative(double d, double d_hat) {
  if (d >= d_hat) return 0;
  const double e = d - d_hat;
  return -2 * std::log(d / d_hat) - 4 * e / d + e * e / (d * d);
}

}  // namespace pb4u
