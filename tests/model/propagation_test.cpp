// K control, update scaling, the propagation step by hand and the split first layer.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/model/decayed_propagation.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/model/mlp.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/model/propagation_control.h"
#include "pb4u/model/update_scaling.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

TEST(PropagationControl, HalvingTheEdgeLengthDoublesK) {
  const double base = 0.0123, D = 3 * base;
  EXPECT_EQ(propagation_steps(D, base), 3);
  EXPECT_EQ(propagation_steps(D, base / 2), 6);
  EXPECT_EQ(propagation_steps(D, base / 4), 12);
  EXPECT_EQ(propagation_steps(D, base * 1.5), 2);
  EXPECT_EQ(propagation_steps(D, base * 10), 1);  // never below one step
  EXPECT_THROW(propagation_steps(0.0, base), Error);
}

TEST(PropagationControl, CalibratedModelGivesKBaseAtTheCalibrationResolution) {
  for (double base : {0.01, 0.0137, 0.0203, 0.1 / 3}) {
    Pb4uNet model(test::tiny_config());
    model->calibrate(base);
    EXPECT_NEAR(model->propagation_distance(), 3 * base, 1e-15);
    EXPECT_EQ(model->propagation_steps_for(base), 3);
    EXPECT_EQ(model->propagation_steps_for(base / 2), 6);
  }
  ModelConfig off = test::tiny_config();
  off.propagation_control = "off";
  Pb4uNet fixed(off);
  fixed->calibrate(0.02);
  EXPECT_EQ(fixed->propagation_steps_for(0.005), 3);
  Pb4uNet mgn(test::tiny_config("mgn"));
  mgn->calibrate(0.02);
  EXPECT_EQ(mgn->propagation_steps_for(0.005), 0);
}

TEST(PropagationControl, TrainingSamplesCoverTheConfiguredRange) {
  ModelConfig c = test::tiny_config();
  std::mt19937_64 rng(7);
  std::set<int64_t> seen;
  for (int i = 0; i < 400; ++i) seen.insert(sample_propagation_steps(c, rng));
  EXPECT_EQ(seen, (std::set<int64_t>{0, 1, 2, 3, 4, 5, 6}));  // [0, 2 K_base]
  c.propagation_control = "off";
  EXPECT_EQ(sample_propagation_steps(c, rng), 3);
  EXPECT_EQ(sample_propagation_steps(test::tiny_config("mgn"), rng), 0);
  c.propagation_control = "on";
  c.train_k_range = {2.0, 1.0};
  EXPECT_THROW(sample_propagation_steps(c, rng), Error);
}

// Two models with the same weights (the second copies the first's), calibrated to 0.037 m and
// in eval mode: the configs differ only in switches that do not change shapes.
std::pair<Pb4uNet, Pb4uNet> twin_models(const ModelConfig& first, const ModelConfig& second) {
  torch::manual_seed(1);
  Pb4uNet a(first);
  Pb4uNet b(second);
  {
    torch::NoGradGuard g;
    auto pa = a->named_parameters(), pb = b->named_parameters();
    for (auto& p : pa) pb[p.key()].copy_(p.value());
  }
  for (Pb4uNet* m : {&a, &b}) {
    (*m)->calibrate(0.037);
    (*m)->eval();
  }
  return {a, b};
}

TEST(UpdateScaling, MeanIncidentRestEdgeLengthOverBase) {
  // A single right triangle with legs 0.3, 0.4: edges 0.3 (0-1), 0.4 (0-2), 0.5 (1-2).
  TriMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 0.3, 0, 0, 0, 0, 0.4;
  m.F.resize(1, 3);
  m.F << 0, 2, 1;
  GarmentTopology t = build_garment_topology(m);
  auto s = update_scale(t.vertex_mean_edge_length, 0.2, true);
  auto expected = torch::tensor({{0.35f / 0.2f}, {0.4f / 0.2f}, {0.45f / 0.2f}});
  EXPECT_TRUE(torch::allclose(s, expected, 1e-5, 1e-6));
  EXPECT_TRUE(torch::equal(update_scale(t.vertex_mean_edge_length, 0.2, false), torch::ones({3, 1})));
  EXPECT_THROW(update_scale(t.vertex_mean_edge_length, 0.0, true), Error);
}

TEST(UpdateScaling, ScalingOnIsScalingOffTimesS) {
  auto scene = test::tiny_scene(8);
  GarmentTopology t = build_garment_topology(scene.rest);
  ModelConfig on = test::tiny_config(), off = on;
  off.update_scaling = "off";
  auto [a, b] = twin_models(on, off);
  GraphBatch g = build_graph(scene.state, t, GraphOptions{});
  auto s = t.vertex_mean_edge_length.unsqueeze(1) / 0.037;
  EXPECT_TRUE(torch::allclose(a->forward(g, 3), b->forward(g, 3) * s, 1e-5, 1e-6));
}

TEST(UpdateScaling, SmoothingOneRoundOnATriangleByHand) {
  // Three mutually connected vertices, f = (1, 0, 0): vertex 0 averages its neighbours' 0 with
  // its own 1 -> 0.5; vertices 1 and 2 average (1 + 0) / 2 with their own 0 -> 0.25.
  auto senders = torch::tensor({0, 1, 1, 2, 2, 0}, torch::kInt64);
  auto receivers = torch::tensor({1, 0, 2, 1, 0, 2}, torch::kInt64);
  auto f = torch::tensor({{1.0f}, {0.0f}, {0.0f}});
  auto g = smooth_over_mesh(f, senders, receivers, 1);
  EXPECT_TRUE(torch::allclose(g, torch::tensor({{0.5f}, {0.25f}, {0.25f}})));
  EXPECT_NEAR(smooth_over_mesh(f, senders, receivers, 50).sum().item<float>(), 1.0f, 1e-5);  // mean kept
  EXPECT_TRUE(torch::equal(smooth_over_mesh(f, senders, receivers, 0), f));
  EXPECT_EQ(smoothing_iterations(0.05, 0.01), 25);
  EXPECT_EQ(smoothing_iterations(0.05, 0.005), 100);  // half the edge length: 4x the rounds
  EXPECT_EQ(smoothing_iterations(0.01, 0.05), 1);
  EXPECT_THROW(smoothing_iterations(0.05, 0.0), Error);
}

TEST(UpdateScaling, InferenceSmoothingEqualsTheDifferentiableOne) {
  // Without a gradient the CPU path runs on an Eigen sparse matrix; with one, on torch ops.
  auto scene = test::tiny_scene(8);
  GarmentTopology t = build_garment_topology(scene.rest);
  torch::manual_seed(3);
  auto f = torch::randn({t.num_vertices, 3});
  auto fast = smooth_over_mesh(f, t.senders, t.receivers, 17);
  auto g = f.clone().requires_grad_(true);
  auto slow = smooth_over_mesh(g, t.senders, t.receivers, 17);
  EXPECT_TRUE(torch::allclose(fast, slow.detach(), 1e-5, 1e-6));
  slow.sum().backward();
  EXPECT_TRUE(g.grad().defined());
}

TEST(UpdateScaling, DetailScalingKeepsTheSmoothFieldAndScalesTheDetail) {
  auto scene = test::tiny_scene(8);
  GarmentTopology t = build_garment_topology(scene.rest);
  const int64_t n = t.num_vertices;
  auto s = torch::full({n, 1}, 0.25f);
  // A uniform field (gravity, a rigid push) is smooth: unscaled at any resolution.
  auto uniform = torch::tensor({0.0f, -9.8f, 1.0f}).expand({n, 3}).contiguous();
  auto a = detail_update_scaling(uniform, s, t.senders, t.receivers, t.mean_edge_length, 0.2);
  EXPECT_TRUE(torch::allclose(a, uniform, 1e-5, 1e-5));
  // A one-vertex spike is detail: mostly scaled by s; the scaled field is S(f) + s (f - S(f)).
  auto spike = torch::zeros({n, 3});
  spike[n / 2][1] = 1.0f;
  auto b = detail_update_scaling(spike, s, t.senders, t.receivers, t.mean_edge_length, 0.2);
  auto smooth = smooth_over_mesh(spike, t.senders, t.receivers, smoothing_iterations(0.2, t.mean_edge_length));
  EXPECT_TRUE(torch::allclose(b, smooth + s * (spike - smooth), 1e-6, 1e-6));
  EXPECT_LT(b[n / 2][1].item<float>(), 0.5f);
  EXPECT_GT(b[n / 2][1].item<float>(), 0.25f);
  // The model applies it: detail = S(a_off) + s (a_off - S(a_off)) with the same weights.
  ModelConfig detail = test::tiny_config(), off = detail;
  detail.update_scaling = "detail";
  detail.smooth_distance = 0.1;
  off.update_scaling = "off";
  auto [net_detail, net_off] = twin_models(detail, off);
  GraphBatch g = build_graph(scene.state, t, GraphOptions{});
  auto a_off = net_off->forward(g, 3);
  auto sm = smooth_over_mesh(a_off, g.mesh_senders, g.mesh_receivers, smoothing_iterations(0.1, g.mean_edge_length));
  auto scale = t.vertex_mean_edge_length.unsqueeze(1) / 0.037;
  EXPECT_TRUE(torch::allclose(net_detail->forward(g, 3), sm + scale * (a_off - sm), 1e-5, 1e-6));
}

// Fixed weights: f_m(h_i, h_j, e) = relu(relu(h_i + h_j)) (identity layers, zero biases), so
// for positive latents f_m = h_i + h_j; LayerNorm without affine change (weight 1, bias 0).
TEST(DecayedPropagation, OneStepOnAPathGraphByHand) {
  DecayedPropagation prop(/*latent=*/2, /*hidden_layers=*/1, /*gamma=*/0.9);
  {
    torch::NoGradGuard g;
    for (auto& p : prop->named_parameters()) p.value().zero_();
    auto& f = *prop->message;
    f.first_weights[0].copy_(torch::eye(2));
    f.first_weights[1].copy_(torch::eye(2));
    for (auto& p : f.rest->named_parameters())
      if (p.key().find("weight") != std::string::npos) p.value().copy_(torch::eye(2));
    prop->norm->weight.fill_(1);
  }
  // Path 0 - 1 - 2, both directions.
  auto senders = torch::tensor({0, 1, 1, 2}, torch::kInt64), receivers = torch::tensor({1, 0, 2, 1}, torch::kInt64);
  auto h0 = torch::tensor({{1.0f, 2.0f}, {3.0f, 1.0f}, {2.0f, 5.0f}});
  auto e = torch::randn({4, 2});  // W_e = 0: edge latents do not matter here
  auto h1 = prop(h0, e, senders, receivers, 1);
  // Sums: vertex 0: h0 + h1 = (4, 3); vertex 1: 2 h1 + h0 + h2 = (9, 9); vertex 2: h2 + h1 = (5, 6).
  // LayerNorm of (a, b) is (+-|a-b|/2) / sqrt((a-b)^2/4 + eps): (1, -1), (0, 0), (-1, 1) up to eps.
  const double eps = 1e-5;
  auto ln = [&](double a, double b) {
    double m = (a + b) / 2, var = ((a - m) * (a - m) + (b - m) * (b - m)) / 2;
    return std::make_pair((a - m) / std::sqrt(var + eps), (b - m) / std::sqrt(var + eps));
  };
  auto [a0, b0] = ln(4, 3);
  auto [a1, b1] = ln(9, 9);
  auto [a2, b2] = ln(5, 6);
  auto expected = torch::tensor({{0.9 * 1 + a0, 0.9 * 2 + b0}, {0.9 * 3 + a1, 0.9 * 1 + b1},
                                 {0.9 * 2 + a2, 0.9 * 5 + b2}}, torch::kFloat32);
  EXPECT_TRUE(torch::allclose(h1, expected, 1e-5, 1e-5));
  EXPECT_NEAR(expected[0][0].item<double>(), 1.9, 1e-4);  // the closed form above
  EXPECT_TRUE(torch::equal(prop(h0, e, senders, receivers, 0), h0));
}

TEST(Mlp, SplitFirstLayerEqualsConcatenation) {
  torch::manual_seed(9);
  MLP f(std::vector<int64_t>{8, 8, 5}, 16, 8, 2, true);
  auto nodes = torch::randn({10, 8}), edges = torch::randn({30, 5});
  auto s = torch::randint(0, 10, {30}, torch::kInt64), r = torch::randint(0, 10, {30}, torch::kInt64);
  auto split = edge_mlp(*f, nodes, edges, s, r, {}, true);
  auto concat = edge_mlp(*f, nodes, edges, s, r, {}, false);
  auto direct = f->forward({nodes.index_select(0, r), nodes.index_select(0, s), edges});
  EXPECT_TRUE(torch::allclose(split, concat, 1e-5, 1e-5));
  EXPECT_TRUE(torch::allclose(split, direct, 1e-5, 1e-5));
}

TEST(EulerStep, ClosedFormAndPins) {
  auto s = test::tiny_scene(10, /*pins=*/true);
  const int64_t n = s.state.x.size(0);
  auto a = torch::randn({n, 3}, torch::kFloat64);
  auto x_next = euler_step(s.state, a);
  const double dt = s.state.dt;
  auto expected = 2 * s.state.x - s.state.x_prev + a * dt * dt;
  EXPECT_TRUE(torch::allclose(x_next.narrow(0, 5, n - 5), expected.narrow(0, 5, n - 5), 1e-12, 1e-12));
  EXPECT_TRUE(torch::equal(x_next.narrow(0, 0, 5), s.state.pin_targets.narrow(0, 0, 5)));
}

}  // namespace
}  // namespace pb4u
