// The eslr baseline (ESLR reconstructed from its paper): Laplacian smoothing and the geodesic
// attention's distance bias on a 5-vertex graph, the anchors in the graph, and the whole model
// saving, loading, batching and stepping on a tiny garment.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/concat_graphs.h"
#include "pb4u/model/geodesic_attention.h"
#include "pb4u/model/lsdmp_block.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using test::tiny_config;
using test::tiny_scene;

ModelConfig eslr_config() {
  ModelConfig c = tiny_config("eslr");
  c.attention_heads = 2;
  c.geodesic_anchors = 8;
  return c;
}

// Edges 0-1, 1-2, 2-3, 0-2 both ways, vertex 4 alone: p_i is the mean over i's neighbours j of
// node j plus edge (j -> i); vertex 4 keeps its row.
TEST(LaplacianSmoothing, MeanOfNeighbourAndEdgeLatentsOnAFiveVertexGraph) {
  const auto s = torch::tensor({0, 1, 1, 2, 2, 3, 0, 2}, torch::kInt64);
  const auto r = torch::tensor({1, 0, 2, 1, 3, 2, 2, 0}, torch::kInt64);
  const auto nodes = torch::tensor({{1.0, 0.0}, {2.0, 1.0}, {4.0, -1.0}, {8.0, 2.0}, {16.0, 5.0}});
  auto edges = torch::arange(16, torch::kFloat32).view({8, 2}) * 0.01;
  auto e = [&](int k) { return edges[k]; };
  const std::vector<torch::Tensor> expected{
      (nodes[1] + e(1) + nodes[2] + e(7)) / 2,                  // 0 <- 1, 2
      (nodes[0] + e(0) + nodes[2] + e(3)) / 2,                  // 1 <- 0, 2
      (nodes[1] + e(2) + nodes[3] + e(5) + nodes[0] + e(6)) / 3,  // 2 <- 1, 3, 0
      nodes[2] + e(4),                                          // 3 <- 2
      nodes[4]};                                                // 4: no neighbour
  for (bool grouped : {false, true}) {
    RowIndex senders = grouped ? group_rows(s, 5) : RowIndex(s), receivers = grouped ? group_rows(r, 5) : RowIndex(r);
    auto p = laplacian_smoothing(nodes, edges, senders, receivers);
    for (int64_t i = 0; i < 5; ++i)
      EXPECT_TRUE(torch::allclose(p[i], expected[static_cast<size_t>(i)], 1e-6, 1e-6)) << "vertex " << i << " grouped " << grouped;
  }
}

// Three bins per head over [0, 4 m], spaced as the square: centres at 0, 1 and 4 m. 1 m reads the
// middle value, 0.25 m halfway between the first two, 9 m and +inf the last.
TEST(GeodesicAttention, DistanceBiasInterpolatesItsBinsAndClampsFarAndUnreachable) {
  GeodesicAttention a(4, 2, 3, 4.0);
  {
    torch::NoGradGuard no_grad;
    a->bias_table.copy_(torch::tensor({{1.0, -1.0}, {3.0, 0.0}, {7.0, 2.0}}));
  }
  const double inf = std::numeric_limits<double>::infinity();
  auto d = torch::tensor({{0.0, 1.0, 0.25}, {9.0, inf, 4.0}});
  auto b = a->distance_bias(d);
  ASSERT_EQ(b.sizes(), (std::vector<int64_t>{2, 3, 2}));
  auto expected = torch::tensor({{{1.0, -1.0}, {3.0, 0.0}, {2.0, -0.5}}, {{7.0, 2.0}, {7.0, 2.0}, {7.0, 2.0}}});
  EXPECT_TRUE(torch::allclose(b, expected.to(torch::kFloat32), 1e-6, 1e-6)) << b;
}

// With the query and key maps zero, each vertex's weights are softmax(b(d)) over the anchors: a
// 5-vertex garment (and one body node after it) against the closed form, head by head.
TEST(GeodesicAttention, ZeroQueriesWeighTheAnchorsBySoftmaxOfTheDistanceBias) {
  torch::manual_seed(3);
  GeodesicAttention a(4, 2, 3, 4.0);
  {
    torch::NoGradGuard no_grad;
    for (auto* l : {&a->query, &a->key}) {
      (*l)->weight.zero_();
      (*l)->bias.zero_();
    }
    a->bias_table.copy_(torch::tensor({{0.0, 2.0}, {-1.0, 0.5}, {1.0, -3.0}}));
  }
  auto nodes = torch::randn({6, 4});
  AnchorSet set{0, 5, torch::tensor({4, 0, 2}, torch::kInt64),
                torch::tensor({{1.0, 0.0, 2.0}, {0.5, 0.5, 1.5}, {2.0, 1.0, 0.0}, {3.0, 2.0, 1.0}, {0.0, 1.0, 2.0}})};
  auto out = a->forward(nodes, {set});
  ASSERT_EQ(out.sizes(), (std::vector<int64_t>{6, 4}));
  EXPECT_TRUE(torch::equal(out[5], torch::zeros({4})));  // the body node
  auto u = a->value(a->norm(nodes).index_select(0, set.nodes));  // (3 anchors, 4): head h is columns 2h, 2h+1
  auto bias = a->distance_bias(set.distance);                    // (5, 3, 2)
  auto mixed = torch::zeros({5, 4});
  for (int64_t h = 0; h < 2; ++h) {
    auto w = torch::softmax(bias.select(2, h), 1);  // (5, 3)
    mixed.narrow(1, 2 * h, 2).copy_(torch::mm(w, u.narrow(1, 2 * h, 2)));
  }
  EXPECT_TRUE(torch::allclose(out.narrow(0, 0, 5), a->output(mixed), 1e-5, 1e-6));
}

TEST(EslrGraph, CarriesEachGarmentsAnchorsAndNeedsThemInItsTopology) {
  auto s = tiny_scene(60);
  const ModelConfig c = eslr_config();
  EXPECT_EQ(c.graph_options().geodesic_anchors, 8);
  EXPECT_EQ(tiny_config("pb4u").graph_options().geodesic_anchors, 0);
  GarmentTopology bare = build_garment_topology(s.rest);
  EXPECT_FALSE(bare.anchors.defined());
  try {
    build_graph(s.state, bare, c.graph_options());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("geodesic anchors"), std::string::npos) << e.what();
  }
  GarmentTopology t = build_garment_topology(s.rest, "garment", 8);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  ASSERT_EQ(g.anchor_sets.size(), 1u);
  EXPECT_EQ(g.anchor_sets[0].num_nodes, 25);
  EXPECT_EQ(g.anchor_sets[0].nodes.size(0), 8);
  EXPECT_EQ(g.anchor_sets[0].distance.sizes(), (std::vector<int64_t>{25, 8}));
  // Each anchor is at distance 0 from itself; the 5 x 5 grid's corners are 0.2 m apart.
  for (int64_t k = 0; k < 8; ++k) EXPECT_EQ(g.anchor_sets[0].distance[g.anchor_sets[0].nodes[k]][k].item<float>(), 0.0f);
  EXPECT_FLOAT_EQ(g.anchor_sets[0].distance.max().item<float>(), 0.4f);  // an L-path corner to corner
  // A batch renumbers the second garment's anchors after the first garment's nodes.
  GraphBatch b = concat_graphs({g, g});
  ASSERT_EQ(b.anchor_sets.size(), 2u);
  EXPECT_EQ(b.anchor_sets[1].first_node, 25);
  EXPECT_TRUE(torch::equal(b.anchor_sets[1].nodes, g.anchor_sets[0].nodes + 25));
  EXPECT_THROW(concat_graphs({g, build_graph(s.state, t, tiny_config("pb4u").graph_options())}), Error);
}

TEST(EslrNet, SavesLoadsBatchesStepsAndEveryPartLearns) {
  const ModelConfig c = eslr_config();
  Pb4uNet model = test::warmed_model(c, 61);
  ASSERT_EQ(model->lsdmp_blocks.size(), 2u);
  ASSERT_EQ(model->attention.size(), 2u);
  EXPECT_TRUE(model->blocks.empty());
  EXPECT_EQ(model->propagation_steps_for(0.01), 0);  // no propagation
  auto s = tiny_scene(62, true);
  GarmentTopology t = build_garment_topology(s.rest, "garment", c.geodesic_anchors);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  torch::Tensor a;
  {
    torch::NoGradGuard no_grad;
    a = model->forward(g, 0);
  }
  EXPECT_TRUE(torch::isfinite(a).all().item<bool>());
  const std::string path = test::temp_dir("eslr") + "/eslr.pt";
  save_model(model, path);
  Pb4uNet loaded = load_model(path, c);
  loaded->eval();
  {
    torch::NoGradGuard no_grad;
    EXPECT_TRUE(torch::equal(loaded->forward(g, 0), a));
    auto b = tiny_scene(63);
    b.state.effects.collision = b.state.effects.friction = false;
    GraphBatch gb = build_graph(b.state, t, c.graph_options());
    auto batch = model->forward(concat_graphs({g, gb}), 0);
    EXPECT_TRUE(torch::allclose(batch, torch::cat({a, model->forward(gb, 0)}), 1e-5, 1e-5));
  }
  // Another head count is another model.
  ModelConfig other = c;
  other.attention_heads = 4;
  EXPECT_THROW(load_model(path, other), Error);
  auto x_next = model->step(s.state, t);
  EXPECT_TRUE(torch::equal(x_next.narrow(0, 0, 5), s.state.pin_targets.narrow(0, 0, 5)));
  model->train();
  model->forward(g, 0).square().sum().backward();
  for (auto& p : model->named_parameters()) EXPECT_TRUE(p.value().grad().defined()) << p.key();
  // The attention's distance bias learns from the start (its table starts at zero).
  EXPECT_GT(model->attention[0]->bias_table.grad().abs().sum().item<double>(), 0.0);
}

TEST(EslrNet, ConfigChecksAndFlops) {
  ModelConfig c = eslr_config();
  c.attention_heads = 3;  // does not divide 16
  try {
    Pb4uNet model(c);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("model.attention_heads"), std::string::npos) << e.what();
  }
  c = eslr_config();
  c.mlp_hidden_layers = 3;
  Pb4uNet net(c);
  auto s = tiny_scene(64);
  GarmentTopology t = build_garment_topology(s.rest, "garment", c.geodesic_anchors);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  const double H = c.latent, L = c.mlp_hidden_layers, n = double(g.num_nodes()), ng = 25, M = 8;
  const double Em = double(g.mesh_senders.size(0)), Ew = double(g.num_world_edges());
  auto edge_mlp = [&](double E) { return 4.0 * n * H * H + 2.0 * E * H * H + 2.0 * E * H * H * L; };
  auto node_mlp = [&](double parts) { return 2.0 * parts * n * H * H + 2.0 * n * H * H * L; };
  const double attention = 2.0 * H * H * (2 * ng + 2 * M) + 4.0 * ng * M * H;
  const double layer = edge_mlp(Em) + edge_mlp(Ew) + node_mlp(3) + node_mlp(1) + attention;
  EXPECT_DOUBLE_EQ(net->message_passing_flops(g, 0), 2 * layer);
  EXPECT_TRUE(std::isnan(net->message_passing_flops(int64_t(n), int64_t(Em), int64_t(Ew), 0)));
}

}  // namespace
}  // namespace pb4u
