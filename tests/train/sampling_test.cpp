// Material and effect sampling stay in their ranges with the right distributions.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Core>

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
    EXPECT_FALSE(e.pins) << "p_pins defaults to 0";
  }
  EXPECT_NEAR(gravity / double(n), 0.25, 0.03);
  EXPECT_NEAR(body / double(n), 0.5, 0.03);
}

TEST(Sampling, PinsAreSampledWithTheirProbability) {
  EffectSampling s;
  s.p_pins = 0.3;
  std::mt19937_64 rng(3);
  int pins = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) pins += sample_effects(s, rng).pins;
  EXPECT_NEAR(pins / double(n), 0.3, 0.03);
}

TEST(Sampling, PinnedVerticesAreABandOrPointsAtTheTop) {
  // A 21 x 21 vertex sheet hanging in the xy plane, 1 m tall, rows 5 cm apart.
  Eigen::MatrixXd V(21 * 21, 3);
  for (int r = 0; r < 21; ++r)
    for (int c = 0; c < 21; ++c) V.row(r * 21 + c) << 0.05 * c, 1.0 - 0.05 * r, 0.0;
  std::mt19937_64 rng(4);
  int bands = 0, point_sets = 0;
  for (int i = 0; i < 200; ++i) {
    const std::vector<int> p = sample_pinned_vertices(V, rng);
    ASSERT_FALSE(p.empty());
    for (int v : p) ASSERT_GE(V(v, 1), 0.9 - 1e-12) << "within the top 10%";
    if (int(p.size()) == 21) {
      ++bands;  // a 1-4 cm band holds exactly the top row here
      for (int v : p) EXPECT_DOUBLE_EQ(V(v, 1), 1.0);
    } else {
      ++point_sets;
      EXPECT_GE(p.size(), 2u);
      EXPECT_LE(p.size(), 4u);
    }
  }
  EXPECT_GT(bands, 60);
  EXPECT_GT(point_sets, 60);
}

}  // namespace
}  // namespace pb4u
