// Autograd gradients of every term against central finite differences (float64), and the
// same energies in float32.
#include <gtest/gtest.h>

#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/energy_report.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

// A 3 x 3 garment patch hovering 1 mm over a floor, moving and deforming, with some vertices
// predicted below the floor: every term is non-zero and smooth around x_next.
struct Scene {
  ClothGeometry cloth;
  FrameState state;
  torch::Tensor x_next;
};

Scene make_scene(torch::Dtype dtype) {
  torch::manual_seed(3);
  TriMesh g = test::grid_mesh(3, 0.3);
  g.V.col(1).array() += 1e-3;
  Scene s;
  s.cloth = make_cloth_geometry(g, dtype);
  torch::Tensor x = test::positions_tensor(g.V, torch::kFloat64);
  s.state = test::resting_state(x);
  s.state.x_prev = x - torch::tensor({0.01, 0.002, -0.005}, torch::kFloat64);
  s.state.effects.gravity = s.state.effects.collision = s.state.effects.friction = true;
  TriMesh floor = test::grid_mesh(2, 4.0);
  floor.V.col(0).array() -= 2.0;
  floor.V.col(2).array() -= 2.0;
  s.state.body = test::static_body(floor, torch::kFloat64);
  s.state.body.next_vertices = s.state.body.vertices + torch::tensor({0.0, 0.0, 0.004}, torch::kFloat64);
  s.x_next = x + 0.01 * torch::randn({x.size(0), 3}, torch::kFloat64);
  s.state.x = s.state.x.to(dtype);
  s.state.x_prev = s.state.x_prev.to(dtype);
  s.state.body.vertices = s.state.body.vertices.to(dtype);
  s.state.body.next_vertices = s.state.body.next_vertices.to(dtype);
  s.x_next = s.x_next.to(dtype);
  return s;
}

TEST(PhysicsGradients, EveryTermMatchesCentralDifferences) {
  Scene s = make_scene(torch::kFloat64);
  PhysicsConfig config;
  auto contact = body_contact_for(s.state, config);
  ASSERT_TRUE(contact.has_value());
  ASSERT_TRUE(contact->in_contact.any().item<bool>());
  TermList terms = build_terms(s.state.effects, config);
  ASSERT_EQ(terms.size(), 6u);
  const double h = 1e-6;
  for (const auto& term : terms) {
    torch::Tensor x = s.x_next.clone().requires_grad_(true);
    torch::Tensor E = term->energy(x, s.state, s.cloth, &*contact);
    ASSERT_GT(std::abs(E.item<double>()), 0.0) << term->name();
    torch::Tensor grad = torch::autograd::grad({E}, {x})[0];
    torch::Tensor fd = torch::zeros_like(grad);
    {
      torch::NoGradGuard no_grad;
      auto flat = s.x_next.clone();
      for (int64_t i = 0; i < flat.size(0); ++i)
        for (int k = 0; k < 3; ++k) {
          double x0 = flat[i][k].item<double>();
          flat[i][k] = x0 + h;
          double ep = term->energy(flat, s.state, s.cloth, &*contact).item<double>();
          flat[i][k] = x0 - h;
          double em = term->energy(flat, s.state, s.cloth, &*contact).item<double>();
          flat[i][k] = x0;
          fd[i][k] = (ep - em) / (2 * h);
        }
    }
    double scale = grad.abs().max().item<double>();
    ASSERT_GT(scale, 0.0) << term->name();
    EXPECT_LT((grad - fd).abs().max().item<double>(), 1e-5 * scale) << term->name();
  }
}

TEST(PhysicsGradients, Float32AgreesWithFloat64) {
  PhysicsConfig config;
  Scene s64 = make_scene(torch::kFloat64), s32 = make_scene(torch::kFloat32);
  auto c64 = body_contact_for(s64.state, config);
  auto c32 = body_contact_for(s32.state, config);
  ASSERT_EQ(c32->normal.scalar_type(), torch::kFloat32);
  TermList terms = build_terms(s64.state.effects, config);
  auto e64 = term_energies(terms, s64.x_next, s64.state, s64.cloth, &*c64);
  torch::Tensor x32 = s32.x_next.clone().requires_grad_(true);
  auto e32 = term_energies(terms, x32, s32.state, s32.cloth, &*c32);
  for (size_t k = 0; k < terms.size(); ++k) {
    EXPECT_EQ(e32[k].second.scalar_type(), torch::kFloat32) << e32[k].first;
    double a = e64[k].second.item<double>(), b = e32[k].second.item<double>();
    EXPECT_NEAR(b, a, 1e-3 * std::abs(a) + 1e-9) << e32[k].first;
  }
  torch::Tensor total = total_energy(terms, x32, s32.state, s32.cloth, &*c32);
  total.backward();
  EXPECT_TRUE(torch::isfinite(x32.grad()).all().item<bool>());
}

}  // namespace
}  // namespace pb4u
