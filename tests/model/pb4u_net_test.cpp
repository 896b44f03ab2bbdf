// The whole network: invariances, serialisation, every kind/ablation, inference step.
#include <gtest/gtest.h>

#include <cstdio>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/concat_graphs.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using test::tiny_config;
using test::tiny_scene;
using test::warmed_model;

torch::Tensor predict(Pb4uNet& model, const test::TinyScene& s, int64_t K = -1) {
  GarmentTopology t = build_garment_topology(s.rest);
  const ModelConfig& c = model->config;
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  torch::NoGradGuard no_grad;
  return model->forward(g, K >= 0 ? K : model->propagation_steps_for(g.mean_edge_length));
}

TEST(Pb4uNet, InvariantToTranslatingTheScene) {
  Pb4uNet model = warmed_model(tiny_config());
  auto s = tiny_scene(11, true);
  auto a = predict(model, s);
  const Eigen::RowVector3d shift(0.7, -0.3, 1.2);
  auto shift_t = torch::tensor({0.7, -0.3, 1.2}, torch::kFloat64);
  auto moved = s;
  moved.rest.V = s.rest.V.rowwise() + shift;
  moved.state.x = s.state.x + shift_t;
  moved.state.x_prev = s.state.x_prev + shift_t;
  moved.state.pin_targets = s.state.pin_targets + shift_t;
  moved.state.body.vertices = s.state.body.vertices + shift_t;
  moved.state.body.next_vertices = s.state.body.next_vertices + shift_t;
  auto b = predict(model, moved);
  EXPECT_GT(a.abs().max().item<float>(), 1e-3f);
  EXPECT_TRUE(torch::allclose(a, b, 1e-4, 1e-4)) << (a - b).abs().max().item<float>();
}

TEST(Pb4uNet, EquivariantToRelabellingVertices) {
  Pb4uNet model = warmed_model(tiny_config());
  auto s = tiny_scene(12);
  const int n = s.rest.num_vertices();
  auto perm = torch::randperm(n, torch::kInt64);
  auto inverse = torch::empty_like(perm);
  inverse.index_put_({perm}, torch::arange(n, torch::kInt64));
  auto p = s;
  for (int i = 0; i < n; ++i) p.rest.V.row(i) = s.rest.V.row(perm[i].item<int64_t>());
  for (int f = 0; f < s.rest.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) p.rest.F(f, k) = static_cast<int>(inverse[s.rest.F(f, k)].item<int64_t>());
  p.state.x = s.state.x.index_select(0, perm);
  p.state.x_prev = s.state.x_prev.index_select(0, perm);
  auto a = predict(model, s, 3), b = predict(model, p, 3);
  EXPECT_TRUE(torch::allclose(b, a.index_select(0, perm), 1e-4, 1e-5));
}

TEST(Pb4uNet, SaveLoadRoundTripGivesIdenticalOutputs) {
  ModelConfig c = tiny_config();
  Pb4uNet model = warmed_model(c, 3);
  const std::string path = test::temp_dir("model") + "/model.pt";
  save_model(model, path);
  Pb4uNet loaded = load_model(path, c);
  loaded->eval();
  EXPECT_DOUBLE_EQ(loaded->propagation_distance(), model->propagation_distance());
  EXPECT_TRUE(torch::equal(loaded->vertex_normalizer->sum, model->vertex_normalizer->sum));
  auto s = tiny_scene(13, true);
  EXPECT_TRUE(torch::equal(predict(model, s), predict(loaded, s)));
  // A checkpoint of another shape is a clear error naming the file.
  ModelConfig wider = c;
  wider.latent = 32;
  try {
    load_model(path, wider);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  EXPECT_THROW(load_model(path + ".missing", c), Error);
}

TEST(Pb4uNet, FiniteOutputsForEveryKindAndAblation) {
  for (std::string kind : {"pb4u", "mgn", "hood"})
    for (std::string control : {"on", "off"})
      for (std::string scaling : {"on", "off"}) {
        ModelConfig c = tiny_config(kind);
        c.propagation_control = control;
        c.update_scaling = scaling;
        Pb4uNet model = warmed_model(c, 4);
        for (bool body : {true, false}) {
          auto s = tiny_scene(14);
          s.state.x = s.state.x + 0.05 * torch::randn_like(s.state.x);
          s.state.effects.collision = s.state.effects.friction = body;
          auto a = predict(model, s);
          EXPECT_EQ(a.sizes(), s.state.x.sizes());
          EXPECT_TRUE(torch::isfinite(a).all().item<bool>()) << kind << control << scaling << body;
        }
      }
}

TEST(Pb4uNet, PropagationDepthMattersOnlyForPb4u) {
  auto s = tiny_scene(15);
  Pb4uNet pb4u = warmed_model(tiny_config(), 5);
  EXPECT_FALSE(torch::allclose(predict(pb4u, s, 1), predict(pb4u, s, 5)));
  Pb4uNet mgn = warmed_model(tiny_config("mgn"), 5);
  EXPECT_TRUE(torch::equal(predict(mgn, s, 1), predict(mgn, s, 5)));
  EXPECT_LT(mgn->parameters().size(), pb4u->parameters().size());
}

TEST(Pb4uNet, StepRunsUnderInferenceModeAndFollowsPins) {
  Pb4uNet model = warmed_model(tiny_config(), 6);
  auto s = tiny_scene(16, true);
  GarmentTopology t = build_garment_topology(s.rest);
  model->train();  // even in training mode an inference step must not touch the statistics
  auto before = model->vertex_normalizer->count.item<double>();
  auto x_next = model->step(s.state, t);
  EXPECT_TRUE(x_next.is_inference());
  EXPECT_EQ(model->vertex_normalizer->count.item<double>(), before);
  EXPECT_TRUE(torch::equal(x_next.narrow(0, 0, 5), s.state.pin_targets.narrow(0, 0, 5)));
  // Explicit K override: a different depth, a different prediction.
  EXPECT_FALSE(torch::allclose(model->step(s.state, t, 1), model->step(s.state, t, 6)));
}

TEST(Pb4uNet, NormalisersFreezeAfterWarmupAndGradientsFlow) {
  ModelConfig c = tiny_config();
  c.normalizer_warmup = 2;
  Pb4uNet model(c);
  model->calibrate(0.04);
  auto s = tiny_scene(17);
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  for (int i = 0; i < 4; ++i) model->forward(g, 3);
  EXPECT_EQ(model->vertex_normalizer->accumulations.item<int64_t>(), 2);
  EXPECT_TRUE(model->vertex_normalizer->frozen());
  auto loss = model->forward(g, 3).square().sum();
  loss.backward();
  for (auto& p : model->named_parameters())
    ASSERT_TRUE(p.value().grad().defined()) << p.key();
}

TEST(Pb4uNet, ABatchOfGraphsPredictsWhatEachGraphDoes) {
  Pb4uNet model = warmed_model(tiny_config(), 7);
  auto a = tiny_scene(19, true), b = tiny_scene(20);
  b.rest = test::grid_mesh(3, 0.15);  // another garment, another resolution
  b.state.x = test::to_tensor(b.rest.V) + 0.01;
  b.state.x_prev = b.state.x - 0.001;
  auto c = tiny_scene(21);
  c.state.effects.collision = c.state.effects.friction = false;  // no body at all
  std::vector<GraphBatch> graphs;
  std::vector<torch::Tensor> expected;
  torch::NoGradGuard no_grad;
  for (auto* s : {&a, &b, &c}) {
    GarmentTopology t = build_garment_topology(s->rest);
    graphs.push_back(build_graph(s->state, t, model->config.graph_options()));
    expected.push_back(model->forward(graphs.back(), 3));
  }
  ASSERT_GT(graphs[0].num_world_edges(), 0);
  GraphBatch batch = concat_graphs(graphs);
  EXPECT_EQ(batch.num_nodes(), graphs[0].num_nodes() + graphs[1].num_nodes() + graphs[2].num_nodes());
  EXPECT_TRUE(torch::allclose(model->forward(batch, 3), torch::cat(expected), 1e-5, 1e-5));
  EXPECT_THROW(concat_graphs({}), Error);
}

TEST(Pb4uNet, UncalibratedModelIsAClearError) {
  Pb4uNet model(tiny_config());
  auto s = tiny_scene(18);
  GarmentTopology t = build_garment_topology(s.rest);
  EXPECT_THROW(model->step(s.state, t), Error);
  ModelConfig bad = tiny_config();
  bad.train_k_range = {1.0};
  EXPECT_THROW(Pb4uNet{bad}, Error);
}

// model.acceleration_unit scales the decoder's output and nothing else: the same weights give
// u times the acceleration. With world_normal_distance on, the world encoder takes 10 inputs.
TEST(Pb4uNet, AccelerationUnitScalesTheOutputAndNormalDistanceWidensWorldEdges) {
  ModelConfig c = tiny_config();
  Pb4uNet a = warmed_model(c, 3);
  c.acceleration_unit = 10.0;
  Pb4uNet b = warmed_model(c, 3);
  auto s = tiny_scene(12, true);
  EXPECT_TRUE(torch::allclose(predict(b, s), 10.0 * predict(a, s), 1e-5, 1e-6));
  c.world_normal_distance = "on";
  Pb4uNet wide = warmed_model(c, 3);
  EXPECT_EQ(wide->world_encoder->first_weights[0].size(1), 10);
  EXPECT_TRUE(torch::isfinite(predict(wide, s)).all().item<bool>());
}

}  // namespace
}  // namespace pb4u

namespace pb4u {
namespace {

// The message passing's matmul FLOPs, read off the layers, against the closed form for MLPs of
// L layers of width H (2 per multiply-add): an edge MLP costs its two node terms per node, its
// edge term per edge (once for all K propagation steps) and L H x H layers per edge; a node
// MLP three H x H first-layer terms and L layers per node; the update two terms and L layers.
TEST(Pb4uNet, MessagePassingFlopsMatchTheClosedForm) {
  for (const std::string kind : {"pb4u", "mgn"}) {
    ModelConfig c = tiny_config(kind);
    c.latent = 16;
    c.mlp_hidden_layers = 3;
    c.num_blocks = 2;
    Pb4uNet net(c);
    const double H = c.latent, L = c.mlp_hidden_layers, n = 50, Em = 140;
    auto edge_mlp = [&](double E, bool edge_term) {
      return 4.0 * n * H * H + (edge_term ? 2.0 * E * H * H : 0.0) + 2.0 * E * H * H * L;
    };
    for (const double Ew : {0.0, 30.0})
      for (const int64_t K : {0, 1, 5}) {
        double expected = 0;
        if (kind == "pb4u") {
          if (K > 0) expected += 2.0 * Em * H * H + double(K) * edge_mlp(Em, false);
          expected += 4.0 * n * H * H + 2.0 * n * H * H * L;
        }
        for (int b = 0; b < c.num_blocks; ++b)
          expected += edge_mlp(Em, true) + (Ew > 0 ? edge_mlp(Ew, true) : 0.0) + 6.0 * n * H * H + 2.0 * n * H * H * L;
        EXPECT_DOUBLE_EQ(net->message_passing_flops(int64_t(n), int64_t(Em), int64_t(Ew), K), expected)
            << kind << " K " << K << " world edges " << Ew;
      }
  }
}

}  // namespace
}  // namespace pb4u
