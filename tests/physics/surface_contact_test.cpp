// The collision term measured against the body's own surface (collision.measure: surface):
// inside wherever the body wraps the vertex, deep by the distance to the outer faces, with the
// cubic penalty's closed form and gradient; the plane measure's blind spot for comparison.
#include <gtest/gtest.h>

#include <cmath>

#include "pb4u/config/config_io.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/collision_energy.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/physics/surface_contact.h"
#include "pb4u/train/train_config.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "physics/physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

constexpr double kEps = 2e-3, kWeight = 5e5;

double surface_energy(const torch::Tensor& x, const BodyFrame& body) {
  return collision_energy(x, query_surface_contact(x, body, kEps), kEps, kWeight).item<double>();
}

TEST(SurfaceContact, CubicInsideAndWithinEpsZeroBeyond) {
  const BodyFrame box = test::static_body(test::box_mesh({0, 0, 0}, {1, 1, 1}));
  for (double d : {1e-3, -3e-3, -0.1}) {  // signed distance to the x = 1 side
    auto x = torch::tensor({{1.0 + d, 0.5, 0.4}}, torch::kFloat64);
    EXPECT_NEAR(surface_energy(x, box), kWeight * std::pow(kEps - d, 3), 1e-9 * kWeight) << d;
  }
  EXPECT_EQ(surface_energy(torch::tensor({{1.0 + kEps + 1e-6, 0.5, 0.4}}, torch::kFloat64), box), 0.0);
  // Far outside the bounding box: not measured at all.
  const SurfaceContact far = query_surface_contact(torch::tensor({{3.0, 0.5, 0.5}}, torch::kFloat64), box, kEps);
  EXPECT_EQ(far.vertex.size(0), 0);
}

TEST(SurfaceContact, GradientMatchesFiniteDifferences) {
  const BodyFrame box = test::static_body(test::box_mesh({0, 0, 0}, {1, 1, 1}));
  // One vertex 3 mm inside near an edge, one 1 mm outside a face, one well clear.
  auto x0 = torch::tensor({{0.997, 0.999, 0.3}, {0.4, 1.001, 0.6}, {0.5, 1.5, 0.5}}, torch::kFloat64);
  auto x = x0.clone().requires_grad_(true);
  const SurfaceContact contact = query_surface_contact(x, box, kEps);
  collision_energy(x, contact, kEps, kWeight).backward();
  const double h = 1e-7;
  for (int64_t i = 0; i < 3; ++i)
    for (int64_t c = 0; c < 3; ++c) {
      auto plus = x0.clone(), minus = x0.clone();
      plus[i][c] += h;
      minus[i][c] -= h;
      // The contact (closest point, direction) is held, as the term holds it within a step.
      const double fd = (collision_energy(plus, contact, kEps, kWeight).item<double>() -
                         collision_energy(minus, contact, kEps, kWeight).item<double>()) / (2 * h);
      EXPECT_NEAR(x.grad()[i][c].item<double>(), fd, 1e-6 * (1 + std::abs(fd))) << i << "," << c;
    }
  EXPECT_EQ(x.grad()[2].abs().sum().item<double>(), 0.0);
}

// A vertex inside one part of a body that crosses itself, whose matched face (at t) belongs to
// the other part: the plane of that face puts it 5 cm outside and SPEC 3.3's term pays nothing.
// The surface measure finds it 30 cm deep, to the nearest face no part covers.
TEST(SurfaceContact, SeesAVertexThePlaneMeasureCallsOutside) {
  const TriMesh body = test::joined(test::box_mesh({0, 0, 0}, {1, 1, 1}), test::box_mesh({0.8, 0.2, 0.2}, {1.8, 0.8, 0.8}));
  FrameState state;
  state.body = test::static_body(body);
  state.effects.collision = true;
  auto x = torch::tensor({{0.75, 0.5, 0.5}, {0.75, 0.5, 2.0}, {0.76, 0.5, 2.0}}, torch::kFloat64);
  TriMesh cloth;
  cloth.V = tensor_to_matrix(x);
  cloth.F = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  const ClothGeometry geometry = make_cloth_geometry(cloth);
  // The contact SPEC 3.3 would hold for vertex 0: the second box's x = 0.8 side (outward -x).
  BodyContact plane;
  plane.point = torch::tensor({{0.8, 0.5, 0.5}, {0.75, 0.5, 1.0}, {0.76, 0.5, 1.0}}, torch::kFloat64);
  plane.normal = torch::tensor({{-1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}}, torch::kFloat64);

  PhysicsConfig config;
  config.collision.eps = kEps;
  auto energy_with = [&](const std::string& measure) {
    config.collision.measure = measure;
    TermList terms = build_terms(state.effects, config, kWeight);
    for (const auto& t : terms)
      if (t->name() == "collision") return t->energy(x, state, geometry, &plane).item<double>();
    ADD_FAILURE() << "no collision term";
    return 0.0;
  };
  EXPECT_EQ(energy_with("plane"), 0.0);
  const double depth = std::hypot(0.05, 0.3);  // to the second box's y = 0.2 side, at (0.8, 0.2, 0.5)
  EXPECT_NEAR(energy_with("surface"), kWeight * std::pow(kEps + depth, 3), 1e-9 * kWeight * std::pow(depth, 3));
}

TEST(SurfaceContact, ConfigNamesTheMeasure) {
  EXPECT_EQ(PhysicsConfig{}.collision.measure, "plane");  // SPEC 3.3 unless asked
  const std::string config = test::kSource + "/configs/train/tiny.yaml";
  EXPECT_EQ(load_config<TrainConfig>(config, {"physics.collision.measure=surface"}).physics.collision.measure, "surface");
  try {
    load_config<TrainConfig>(config, {"physics.collision.measure=nearest"});
    ADD_FAILURE() << "an unknown measure was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("measure"), std::string::npos) << e.what();
  }
  BodyFrame empty = test::static_body(test::box_mesh({0, 0, 0}, {1, 1, 1}));
  empty.faces = torch::zeros({0, 3}, torch::kInt64);
  EXPECT_THROW(query_surface_contact(torch::zeros({1, 3}, torch::kFloat64), empty, kEps), Error);
}

}  // namespace
}  // namespace pb4u
