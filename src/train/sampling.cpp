#include "pb4u/train/sampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "pb4u/scene/pins.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

void check_range(const std::vector<double>& r, const char* key, bool log_scale) {
  if (r.size() != 2 || !(r[0] <= r[1]) || (log_scale && !(r[0] > 0)))
    throw Error(std::string("materials.") + key + ": expected [low, high] with low <= high" +
                (log_scale ? " and low > 0" : ""));
}

double uniform(const std::vector<double>& r, std::mt19937_64& rng) {
  return std::uniform_real_distribution<double>(r[0], r[1])(rng);
}

double log_uniform(const std::vector<double>& r, std::mt19937_64& rng) {
  return std::exp(std::uniform_real_distribution<double>(std::log(r[0]), std::log(r[1]))(rng));
}

}  // namespace

Material sample_material(const MaterialRanges& ranges, const Material& base, std::mt19937_64& rng) {
  check_range(ranges.density, "density", false);
  check_range(ranges.mu, "mu", true);
  check_range(ranges.lambda, "lambda", false);
  check_range(ranges.bending, "bending", true);
  Material m = base;
  m.density = uniform(ranges.density, rng);
  m.mu = log_uniform(ranges.mu, rng);
  m.lambda = uniform(ranges.lambda, rng);
  m.bending = log_uniform(ranges.bending, rng);
  return m;
}

Effects sample_effects(const EffectSampling& s, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Effects e;
  e.gravity = u(rng) < s.p_gravity;
  bool body = u(rng) < s.p_body;
  e.collision = body;
  e.friction = body && u(rng) < s.p_friction;
  e.pins = s.p_pins > 0 && u(rng) < s.p_pins;
  e.self_collision = s.p_self_collision > 0 && u(rng) < s.p_self_collision;
  return e;
}

std::vector<int> sample_pinned_vertices(const Eigen::MatrixXd& V, std::mt19937_64& rng) {
  const int n = static_cast<int>(V.rows());
  if (n == 0) throw Error("pins: the garment has no vertices");
  std::uniform_real_distribution<double> u(0, 1);
  if (u(rng) < 0.5) return top_band_vertices(V, 0.01 + 0.03 * u(rng));
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return V(a, 1) > V(b, 1); });
  const int top = std::max(1, n / 10);
  const int points = std::min(top, std::uniform_int_distribution<int>(2, 4)(rng));
  std::vector<int> candidates(order.begin(), order.begin() + top);
  std::shuffle(candidates.begin(), candidates.end(), rng);
  std::vector<int> pinned(candidates.begin(), candidates.begin() + points);
  std::sort(pinned.begin(), pinned.end());
  return pinned;
}

}  // namespace pb4u
