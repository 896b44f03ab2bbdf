// The reference solver (SPEC 8) on two small scenes: a cloth hanging from two pins, and a
// cloth dropped onto a sphere.
#include <gtest/gtest.h>

#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/reference_solver.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

double kinetic_energy(const FrameState& s, const ClothGeometry& cloth) {
  return 0.5 * (cloth.vertex_masses(s.material.density) * s.velocity().pow(2).sum(1)).sum().item<double>();
}

// Advances `state` by one solved frame; returns the solve.
SolverResult step(FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                  const PhysicsConfig& config) {
  auto contact = body_contact_for(state, config);
  SolverResult r = solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver);
  state.x_prev = state.x;
  state.x = r.x_next;
  return r;
}

TEST(ReferenceSolver, PinnedClothSettlesIntoADrapeBelowThePins) {
  const int n = 6;
  TriMesh g = test::grid_mesh(n, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = state.effects.pins = true;
  state.pinned = torch::zeros({cloth.num_vertices}, torch::kBool);
  state.pinned[0] = true;
  state.pinned[n] = true;  // the two corners of one side
  state.pin_targets = state.x.clone();
  PhysicsConfig config;
  TermList terms = build_terms(state.effects, config);

  std::vector<double> kinetic;
  SolverResult last;
  for (int frame = 0; frame < 60; ++frame) {
    last = step(state, cloth, terms, config);
    kinetic.push_back(kinetic_energy(state, cloth));
  }
  double peak = *std::max_element(kinetic.begin(), kinetic.end());
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(kinetic.back(), 0.05 * peak) << "kinetic energy did not decay";
  EXPECT_TRUE(last.converged) << "gradient norm " << last.gradient_norm;
  EXPECT_LE(last.gradient_norm, config.solver.gradient_tolerance);
  // Pins held exactly; everything else hangs below them.
  EXPECT_TRUE(torch::equal(state.x[0], state.pin_targets[0]));
  EXPECT_TRUE(torch::equal(state.x[n], state.pin_targets[n]));
  double lowest = state.x.select(1, 1).min().item<double>();
  EXPECT_LT(lowest, -0.3) << "the cloth should hang about its length (0.5 m) below the pins";
  EXPECT_GT(lowest, -0.6) << "stretched far beyond its length";
}

TEST(ReferenceSolver, ClothDroppedOnASphereRestsOnItWithoutPenetratingDeeperThanEps) {
  const double radius = 0.25;
  TriMesh sphere = test::icosphere(radius, 3, Eigen::RowVector3d::Zero());
  TriMesh g = test::grid_mesh(6, 0.3);
  g.V.col(0).array() -= 0.15;
  g.V.col(2).array() -= 0.15;
  g.V.col(1).array() += radius + 0.01;
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = state.effects.collision = state.effects.friction = true;
  state.body = test::static_body(sphere);
  PhysicsConfig config;
  TermList terms = build_terms(state.effects, config);
  for (int frame = 0; frame < 20; ++frame) step(state, cloth, terms, config);

  // Measured against the body's faces as the terms see them, at the final positions.
  BodyContact c = query_body_contact(state.x, state.body, config.friction.contact_radius,
                                     config.degenerate_area);
  EXPECT_GT(c.distance.min().item<double>(), -config.collision.eps);
  EXPECT_TRUE(c.in_contact.any().item<bool>()) << "the cloth should touch the sphere";
  // Resting on top: the centre vertex is just above the sphere's pole, not fallen through.
  double centre_y = state.x[24][1].item<double>();
  EXPECT_GT(centre_y, radius - config.collision.eps);
  EXPECT_LT(centre_y, radius + 0.01);
  EXPECT_LT(kinetic_energy(state, cloth), 1e-3);
}

}  // namespace
}  // namespace pb4u
