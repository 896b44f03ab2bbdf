// Material and effect sampling stay in their ranges with the right distributions.
#include <gtest/gtest.h>

#include <cmath>

#include "pb4u/train/sampling.h"

namespace pb4u {
namespace {

TEST(Sampling, MaterialsStayInRangeAndLogScaleIsLogUniform) {
  MaterialRanges r;
  std::mt19937_64 rng(5);
  int below_geometric_mid = 0;
  const int n = 4000;
  double mid = std::sqrt(r.mu[0] * r.mu[1]);
  for (int i = 0; i < n; ++i) {
    Material m = sample_material(r, Material{}, rng);
    ASSERT_GE(m.density, r.density[0]);
    ASSERT_LE(m.density, r.density[1]);
    ASSERT_GE(m.mu, r.mu[0]);
    ASSERT_LE(m.mu, r.mu[1]);
    ASSERT_GE(m.bending, r.bending[0]);
    ASSERT_LE(m.bending, r.bending[1]);
    ASSERT_DOUBLE_EQ(m.thickness, Material{}.thickness);
    below_geometric_mid += m.mu < mid;
  }
  // Log-uniform: half the samples fall below the geometric mean of the range.
  EXPECT_NEAR(below_geometric_mid / double(n), 0.5, 0.03);
}

TEST(Sampling, BadRangeIsAnError) {
  MaterialRanges r;
  r.mu = {0, 10};  // log scale needs low > 0
  std::mt19937_64 rng(1);
  EXPECT_THROW(sample_material(r, Material{}, rng), Error);
}

TEST(Sampling, EffectsFollowProbabilitiesAndFrictionNeedsABody) {
  EffectSampling s;
  s.p_gravity = 0.25;
  s.p_body = 0.5;
  s.p_friction = 1.0;
  std::mt19937_64 rng(2);
  int gravity = 0, body = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    Effects e = sample_effects(s, rng);
    gravity += e.gravity;
    body += e.collision;
    EXPECT_EQ(e.friction, e.collision);
    EXPECT_FALSE(e.pins);
  }
  EXPECT_NEAR(gravity / double(n), 0.25, 0.03);
  EXPECT_NEAR(body / double(n), 0.5, 0.03);
}

}  // namespace
}  // namespace pb4u
