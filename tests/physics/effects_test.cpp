// Effects decide which terms and queries exist (SPEC 6); body queries against brute force;
// the energy report; the collision-weight schedule.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/util/error.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

using Names = std::vector<std::string>;

TEST(Effects, TermsFollowTheSceneEffects) {
  PhysicsConfig config;
  Effects none;
  none.gravity = none.collision = none.friction = false;
  EXPECT_EQ(term_names(build_terms(none, config)), (Names{"stretch", "bending", "inertia"}));
  Effects gravity_only = none;
  gravity_only.gravity = true;
  EXPECT_EQ(term_names(build_terms(gravity_only, config)),
            (Names{"stretch", "bending", "inertia", "gravity"}));
  Effects all;
  all.gravity = all.collision = all.friction = true;
  EXPECT_EQ(term_names(build_terms(all, config)),
            (Names{"stretch", "bending", "collision", "inertia", "gravity", "friction"}));
}

TEST(Effects, NoBodyMeansNoKdTreeNoContactAndReportOfActiveTermsOnly) {
  TriMesh g = test::grid_mesh(3, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = true;  // gravity, no body
  PhysicsConfig config;
  const int64_t trees_before = body_kd_trees_built();
  auto contact = body_contact_for(state, config);
  EXPECT_FALSE(contact.has_value());
  TermList terms = build_terms(state.effects, config);
  torch::Tensor x_next = state.x + torch::tensor({0.0, -0.01, 0.0}, torch::kFloat64);
  EnergyReport r = energy_report(terms, x_next, state, cloth, nullptr);
  EXPECT_EQ(body_kd_trees_built(), trees_before);
  Names listed;
  double sum = 0;
  for (const auto& [name, v] : r.terms) {
    listed.push_back(name);
    sum += v;
  }
  EXPECT_EQ(listed, (Names{"stretch", "bending", "inertia", "gravity"}));
  EXPECT_FALSE(r.has("collision"));
  EXPECT_FALSE(r.has("friction"));
  EXPECT_THROW(r.value("friction"), Error);
  EXPECT_NEAR(r.total, sum, 1e-15);
  EXPECT_LT(r.value("gravity"), 0.0);  // the sheet dropped 1 cm
  EXPECT_GT(r.value("inertia"), 0.0);

  // With a body the same call does build a tree.
  state.effects.collision = true;
  EXPECT_THROW(body_contact_for(state, config), Error);  // collision asked for, no body given
  TriMesh floor = test::grid_mesh(2, 4.0);
  floor.V.array() -= 2.0;
  state.body = test::static_body(floor);
  EXPECT_TRUE(body_contact_for(state, config).has_value());
  EXPECT_EQ(body_kd_trees_built(), trees_before + 1);
}

TEST(Effects, TermsNeedingContactRejectANullOne) {
  TriMesh g = test::grid_mesh(2, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  Effects all;
  TermList terms = build_terms(all, PhysicsConfig{});
  EXPECT_THROW(total_energy(terms, state.x, state, cloth, nullptr), Error);
  EXPECT_THROW(total_energy(terms, state.x.narrow(0, 0, 3), state, cloth, nullptr), Error);
}

TEST(EnergyReport, EvaluatesUnderTheEvaluationMaterialAndAverages) {
  TriMesh g = test::grid_mesh(2, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = true;
  state.material.density = 0.6;  // a sampled training material
  TermList terms = build_terms(state.effects, PhysicsConfig{});
  torch::Tensor x_next = state.x * 1.05;
  EnergyReport eval = energy_report(terms, x_next, state, cloth, nullptr);
  EnergyReport sampled = energy_report(terms, x_next, state, cloth, nullptr, state.material);
  EXPECT_NEAR(sampled.value("inertia") / eval.value("inertia"), 0.6 / Material{}.density, 1e-12);
  EnergyReport mean = mean_report({eval, sampled});
  EXPECT_NEAR(mean.value("stretch"), eval.value("stretch"), 1e-15);
  EXPECT_NEAR(mean.total, 0.5 * (eval.total + sampled.total), 1e-15);
  EXPECT_THROW(mean_report({}), Error);
}

TEST(BodyQueries, NearestFaceVertexAndWorldEdgesMatchBruteForce) {
  TriMesh body = test::icosphere(0.3, 2, Eigen::RowVector3d(0.1, 0.2, -0.1));
  torch::manual_seed(5);
  torch::Tensor x = 0.5 * torch::randn({60, 3}, torch::kFloat64);
  torch::Tensor B = test::positions_tensor(body.V);
  torch::Tensor d2;
  torch::Tensor nearest = nearest_body_vertex(x, B, &d2);
  torch::Tensor all_d2 = torch::cdist(x, B).pow(2);
  EXPECT_TRUE(torch::equal(nearest, std::get<1>(all_d2.min(1))));
  EXPECT_TRUE(torch::allclose(d2, std::get<0>(all_d2.min(1))));

  BodyFrame frame = test::static_body(body);
  BodyContact c = query_body_contact(x, frame, 5e-3, 1e-14);
  torch::Tensor F = frame.faces;
  torch::Tensor centroids = (B.index_select(0, F.select(1, 0)) + B.index_select(0, F.select(1, 1)) +
                             B.index_select(0, F.select(1, 2))) / 3.0;
  EXPECT_TRUE(torch::equal(c.face, std::get<1>(torch::cdist(x, centroids).min(1))));
  // Outward normals: the signed distance has the sign of (|x - centre| - r) away from the surface.
  torch::Tensor radial = (x - torch::tensor({0.1, 0.2, -0.1}, torch::kFloat64)).norm(2, 1) - 0.3;
  torch::Tensor clear = radial.abs() > 0.05;
  EXPECT_TRUE(torch::equal((c.distance > 0).masked_select(clear), (radial > 0).masked_select(clear)));
  EXPECT_TRUE(torch::equal(c.in_contact, c.distance < 5e-3));
}

TEST(BodyQueries, RejectNonFiniteOrMisshapenInput) {
  TriMesh body = test::icosphere(0.3, 1, Eigen::RowVector3d::Zero());
  BodyFrame frame = test::static_body(body);
  torch::Tensor x = torch::zeros({4, 3}, torch::kFloat64);
  x[2][1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(query_body_contact(x, frame, 5e-3, 1e-14), Error);
  EXPECT_THROW(nearest_body_vertex(torch::zeros({4, 2}, torch::kFloat64), frame.vertices), Error);
  BodyFrame bad = frame;
  bad.faces = bad.faces.clone();
  bad.faces[0][0] = 10000;
  EXPECT_THROW(query_body_contact(torch::zeros({4, 3}, torch::kFloat64), bad, 5e-3, 1e-14), Error);
}

TEST(CollisionWeight, RampsFromStartToEnd) {
  CollisionConfig c;
  EXPECT_DOUBLE_EQ(collision_weight(c, 0), c.weight_start);
  EXPECT_DOUBLE_EQ(collision_weight(c, c.ramp_steps), c.weight_end);
  EXPECT_DOUBLE_EQ(collision_weight(c, 10 * c.ramp_steps), c.weight_end);
  EXPECT_NEAR(collision_weight(c, c.ramp_steps / 2), std::sqrt(c.weight_start * c.weight_end), 1e-6);
  c.ramp = "linear";
  EXPECT_NEAR(collision_weight(c, c.ramp_steps / 2), 0.5 * (c.weight_start + c.weight_end), 1e-9);
  // A hold keeps the start weight, then the same ramp follows, shifted.
  c.hold_steps = 1000;
  EXPECT_DOUBLE_EQ(collision_weight(c, 999), c.weight_start);
  EXPECT_DOUBLE_EQ(collision_weight(c, 1000), c.weight_start);
  EXPECT_NEAR(collision_weight(c, 1000 + c.ramp_steps / 2), 0.5 * (c.weight_start + c.weight_end), 1e-9);
  EXPECT_DOUBLE_EQ(collision_weight(c, 1000 + c.ramp_steps), c.weight_end);
  // The built term carries the weight it was given; evaluation gets the final one.
  Effects all;
  TermList t = build_terms(all, PhysicsConfig{}, 7e3);
  ASSERT_EQ(t[2]->name(), "collision");
  EXPECT_EQ(dynamic_cast<const CollisionTerm&>(*t[2]).weight(), 7e3);
  TermList eval = build_terms(all, PhysicsConfig{});
  EXPECT_EQ(dynamic_cast<const CollisionTerm&>(*eval[2]).weight(), c.weight_end);
}

TEST(PhysicsConfig, RejectsBadValuesNamingTheKey) {
  std::string dir = test::temp_dir("physcfg");
  test::write_file(dir + "/c.yaml", "collision:\n  eps: -1\n");
  try {
    load_config<PhysicsConfig>(dir + "/c.yaml");
    FAIL() << "negative eps accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("collision.eps"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_config<PhysicsConfig>("", {"friction.muu=0.3"}), Error);
  EXPECT_EQ(load_config<PhysicsConfig>("", {"solver.max_iterations=7"}).solver.max_iterations, 7);
}

TEST(ClothGeometry, RejectsBadMeshes) {
  TriMesh empty;
  EXPECT_THROW(make_cloth_geometry(empty), Error);
  TriMesh bad = test::grid_mesh(1, 1.0);
  bad.F(0, 0) = 99;
  EXPECT_THROW(make_cloth_geometry(bad), Error);
  TriMesh g = test::grid_mesh(2, 1.0);
  ClothGeometry c = make_cloth_geometry(g, torch::kFloat32);
  EXPECT_EQ(c.dm_inverse.scalar_type(), torch::kFloat32);
  EXPECT_NEAR(c.vertex_area.sum().item<double>(), 1.0, 1e-6);  // the sheet's area, 1 m^2
  EXPECT_EQ(c.hinges.size(0), 8);  // 16 edges of a 2 x 2 grid, 8 on the boundary
}

}  // namespace
}  // namespace pb4u
