// ContourCraft's repulsion term (physics/repulsion_energy.h): two square sheets of the same
// 3 x 3-vertex grid, the upper one shifted by 3 cm in x and z.
#include <gtest/gtest.h>

#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/repulsion_energy.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

// Sheet A (vertices 0-8, 10 cm, normals +y) and sheet B (9-17) `height` m above it, shifted by
// 3 cm in x and z. B's vertices at x, z in {0.03, 0.08} lie over A's cells, inside one face each
// (local coordinates 0.6 of a 5 cm cell, off the diagonal), and A's at {0.05, 0.1} under B's:
// 4 + 4 pairs while |height| < the radius.
TriMesh two_sheets(double height) {
  TriMesh a = test::grid_mesh(2, 0.1);
  TriMesh m;
  m.V.resize(18, 3);
  m.V << a.V, a.V.rowwise() + Eigen::RowVector3d(0.03, height, 0.03);
  m.F.resize(16, 3);
  m.F << a.F, a.F.array() + 9;
  return m;
}



TEST(Repulsion, NothingFarApart) {
  TriMesh m = two_sheets(0.05);
  auto x = test::positions_tensor(m.V);
  auto pairs = repulsion_pairs(x, test::faces_tensor(m.F), {}, 0.01, 100);
  EXPECT_EQ(pairs.size(), 0);
  EXPECT_EQ(repulsion_energy(x, test::faces_tensor(m.F), pairs, 0.003, 2e6).item<double>(), 0.0);
}

TEST(Repulsion, PairsSidesAndTheClosedForm) {
  TriMesh m = two_sheets(0.002);
  auto x = test::positions_tensor(m.V);
  auto faces = test::faces_tensor(m.F);
  auto pairs = repulsion_pairs(x, faces, {}, 0.01, 100);
  ASSERT_EQ(pairs.size(), 8);
  for (int64_t p = 0; p < 8; ++p) {
    const bool upper = pairs.vertex[p].item<int64_t>() >= 9;
    EXPECT_EQ(upper, pairs.face[p].item<int64_t>() < 8);           // a vertex of one sheet, a face of the other
    EXPECT_EQ(pairs.side[p].item<double>(), upper ? 1.0 : -1.0);  // B above A's +y normals
  }
  // 2 mm apart: each pair overlaps eps - 2 mm = 1 mm.
  EXPECT_NEAR(repulsion_energy(x, faces, pairs, 0.003, 2e6).item<double>(), 2e6 * 8 * 1e-9, 1e-12);
}

// Sheet A and one vertex (9) in no face, 2 mm over A at (0.03, 0.03): one pair.
TEST(Repulsion, AVertexThatCrossesPaysMoreAndAPinnedOneMore) {
  TriMesh a = test::grid_mesh(2, 0.1);
  TriMesh m;
  m.V.resize(10, 3);
  m.V << a.V, Eigen::RowVector3d(0.03, 0.002, 0.03);
  m.F = a.F;
  auto x = test::positions_tensor(m.V);
  auto faces = test::faces_tensor(m.F);
  auto pairs = repulsion_pairs(x, faces, {}, 0.01, 100);
  ASSERT_EQ(pairs.size(), 1);
  EXPECT_EQ(pairs.vertex[0].item<int64_t>(), 9);
  EXPECT_NEAR(repulsion_energy(x, faces, pairs, 0.003, 2e6).item<double>(), 2e6 * 1e-9, 1e-15);
  // 1 mm below A's plane at t + dt: it crossed, and the pair overlaps eps + 1 mm = 4 mm.
  auto crossed = x.clone();
  crossed[9][1] = -0.001;
  EXPECT_NEAR(repulsion_energy(crossed, faces, pairs, 0.003, 2e6).item<double>(), 2e6 * 64e-9, 1e-12);
  // 5 mm above: past eps, free.
  auto away = x.clone();
  away[9][1] = 0.005;
  EXPECT_EQ(repulsion_energy(away, faces, pairs, 0.003, 2e6).item<double>(), 0.0);
  // Pinned: 100x the overlap before the cube.
  auto pinned = torch::zeros({10}, torch::kBool);
  pinned[9] = true;
  auto weighed = repulsion_pairs(x, faces, pinned, 0.01, 100);
  EXPECT_NEAR(repulsion_energy(x, faces, weighed, 0.003, 2e6).item<double>(), 2e6 * 1e-3, 1e-9);
}

TEST(Repulsion, GradientMatchesFiniteDifferences) {
  TriMesh m = two_sheets(0.0015);
  auto faces = test::faces_tensor(m.F);
  auto x = test::positions_tensor(m.V);
  auto pairs = repulsion_pairs(x, faces, {}, 0.01, 100);
  ASSERT_GT(pairs.size(), 0);
  torch::manual_seed(3);
  auto x_next = (x + 5e-4 * torch::randn_like(x)).requires_grad_(true);
  auto e = repulsion_energy(x_next, faces, pairs, 0.003, 2e6);
  ASSERT_GT(e.item<double>(), 0);
  auto g = torch::autograd::grad({e}, {x_next})[0];
  const double h = 1e-7;
  for (int64_t i = 0; i < 18; ++i)
    for (int64_t k = 0; k < 3; ++k) {
      auto plus = x_next.detach().clone(), minus = x_next.detach().clone();
      plus[i][k] += h;
      minus[i][k] -= h;
      const double fd = (repulsion_energy(plus, faces, pairs, 0.003, 2e6).item<double>() -
                         repulsion_energy(minus, faces, pairs, 0.003, 2e6).item<double>()) / (2 * h);
      EXPECT_NEAR(g[i][k].item<double>(), fd, 1e-5 * std::max(1.0, std::abs(fd))) << i << " " << k;
    }
}

TEST(Repulsion, OnlyTheSelfCollisionEffectBuildsIt) {
  PhysicsConfig physics;
  Effects effects;
  for (const auto& t : build_terms(effects, physics)) EXPECT_NE(t->name(), "repulsion");
  effects = Effects::from_names({"gravity", "self_collision"}, "scene.effects");
  EXPECT_TRUE(effects.self_collision);
  EXPECT_EQ(effects.names(), (std::vector<std::string>{"gravity", "self_collision"}));
  const auto names = term_names(build_terms(effects, physics));
  EXPECT_EQ(names.back(), "repulsion");
  // As a term: the pairs from the state at t, the energy of x_next.
  TriMesh m = two_sheets(0.002);
  ClothGeometry cloth = make_cloth_geometry(m);
  FrameState state = test::resting_state(test::positions_tensor(m.V));
  state.effects = effects;
  RepulsionTerm term(physics.repulsion);
  EXPECT_NEAR(term.energy(state.x, state, cloth, nullptr).item<double>(), 2e6 * 8 * 1e-9, 1e-12);
  // The pairs are kept for one state only: sheets moved apart (a new state, then the same one
  // changed in place) find none.
  const auto apart = test::positions_tensor(two_sheets(0.05).V);
  state.x = apart.clone();
  EXPECT_EQ(term.energy(state.x, state, cloth, nullptr).item<double>(), 0.0);
  state.x.copy_(test::positions_tensor(m.V));
  EXPECT_NEAR(term.energy(state.x, state, cloth, nullptr).item<double>(), 2e6 * 8 * 1e-9, 1e-12);
}

// ContourCraft's schedule shape: held at the start weight, then linear to the final one; the
// term built for a training step carries that step's weight.
TEST(Repulsion, WeightHoldsThenRampsLinearly) {
  RepulsionConfig r;
  EXPECT_DOUBLE_EQ(repulsion_weight(r, 0), r.weight);  // no ramp: the final weight throughout
  r.weight_start = 0;
  r.hold_steps = 1000;
  r.ramp_steps = 3000;
  EXPECT_DOUBLE_EQ(repulsion_weight(r, 999), 0.0);
  EXPECT_DOUBLE_EQ(repulsion_weight(r, 2500), 1e6);
  EXPECT_DOUBLE_EQ(repulsion_weight(r, 4000), 2e6);
  EXPECT_DOUBLE_EQ(repulsion_weight(r, 100000), 2e6);
  PhysicsConfig physics;
  physics.repulsion = r;
  Effects effects = Effects::from_names({"self_collision"}, "scene.effects");
  TriMesh m = two_sheets(0.002);
  ClothGeometry cloth = make_cloth_geometry(m);
  FrameState state = test::resting_state(test::positions_tensor(m.V));
  state.effects = effects;
  TermList half = build_terms(effects, physics, -1.0, repulsion_weight(r, 2500));
  EXPECT_NEAR(half.back()->energy(state.x, state, cloth, nullptr).item<double>(), 1e6 * 8 * 1e-9, 1e-12);
}

}  // namespace
}  // namespace pb4u
