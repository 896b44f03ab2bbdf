// The hood baseline: HOOD's schedule, its coarse edge sets in the graph, its blocks and the
// whole model saving, loading, batching and stepping on a tiny garment.
#include <gtest/gtest.h>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/concat_graphs.h"
#include "pb4u/model/hood_block.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

using test::tiny_config;
using test::tiny_scene;

TEST(HoodSchedule, HoodsOwnIsAUOverTheMeshAndTwoCoarseLevels) {
  ModelConfig hood;
  hood.kind = "hood";
  EXPECT_EQ(hood.schedule(), kHoodSchedule);  // an empty hood_schedule is the kind's own
  const auto blocks = parse_hood_schedule(hood.schedule(), kHoodCoarseLevels);
  ASSERT_EQ(blocks.size(), 15u);
  const std::vector<std::vector<int>> expected{{0, 1}, {1, 2}, {2}, {1, 2}, {0, 1}};  // f,c0 | c0,c1 | c1 | ...
  for (size_t b = 0; b < 15; ++b) EXPECT_EQ(blocks[b], expected[b / 3]) << "block " << b + 1;
  // HOOD's own level marks are read and ignored.
  EXPECT_EQ(parse_hood_schedule("f,c0|d:c0,c1|u:f", 3), (std::vector<std::vector<int>>{{0, 1}, {1, 2}, {0}}));
}

TEST(HoodSchedule, BadEntriesNameTheBlockAndTheKey) {
  for (std::string bad : {"f,c3", "f|x", "f||c0", "", "f,c"}) {
    try {
      parse_hood_schedule(bad, 3);
      FAIL() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("model.hood_schedule"), std::string::npos) << e.what();
    }
  }
  ModelConfig c = tiny_config("hood");
  c.num_blocks = 3;
  try {
    Pb4uNet model(c);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("model.num_blocks"), std::string::npos) << e.what();
  }
}

TEST(HoodGraph, CarriesTheCoarseSetsAndEachNodesLevel) {
  auto s = tiny_scene(40);
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch plain = build_graph(s.state, t, tiny_config("pb4u").graph_options());
  EXPECT_TRUE(plain.coarse.empty());
  GraphBatch g = build_graph(s.state, t, tiny_config("hood").graph_options());
  ASSERT_EQ(g.coarse.size(), static_cast<size_t>(kHoodCoarseLevels));
  ASSERT_GT(g.num_world_edges(), 0);
  // The tiny garment is the 5 x 5 grid of the coarse-level test: 22 and 9 edges, both ways.
  EXPECT_EQ(g.coarse[0].senders.size(0), 44);
  EXPECT_EQ(g.coarse[1].senders.size(0), 18);
  EXPECT_EQ(g.coarse[2].senders.size(0), 0);
  ASSERT_EQ(g.vertex_level.size(0), g.num_nodes());
  EXPECT_TRUE(torch::equal(g.vertex_level.narrow(0, 0, 25), t.vertex_level));
  EXPECT_EQ(g.vertex_level.narrow(0, 25, g.num_nodes() - 25).abs().sum().item<int64_t>(), 0);
  // Features as the mesh edges': current direction, rest direction, current / rest length.
  auto x = s.state.x.to(torch::kFloat32);
  for (int64_t e : {0, 5, 17}) {
    const int64_t a = g.coarse[1].senders[e].item<int64_t>(), b = g.coarse[1].receivers[e].item<int64_t>();
    auto d = x[b] - x[a];
    auto rest = test::to_tensor(s.rest.V).to(torch::kFloat32);
    auto r = rest[b] - rest[a];
    auto f = g.coarse[1].features[e];
    EXPECT_TRUE(torch::allclose(f.narrow(0, 0, 3), d / d.norm(), 1e-5, 1e-6));
    EXPECT_TRUE(torch::allclose(f.narrow(0, 3, 3), r / r.norm(), 1e-5, 1e-6));
    EXPECT_NEAR(f[6].item<double>(), (d.norm() / r.norm()).item<double>(), 1e-5);
  }
}

TEST(HoodBlock, KeepsOnlyTheWorldEdgesItIsGivenAndTheirLatentsAlone) {
  torch::manual_seed(41);
  HoodBlock block(std::vector<int>{2}, 8, 1);
  HoodLatents g{torch::randn({6, 8}), {torch::randn({2, 8}), torch::randn({2, 8}), torch::randn({4, 8})},
                torch::randn({4, 8})};
  HoodIndices ix;
  ix.senders = {RowIndex(torch::tensor({0, 1})), RowIndex(torch::tensor({1, 2})), RowIndex(torch::tensor({0, 2, 2, 4}))};
  ix.receivers = {RowIndex(torch::tensor({1, 0})), RowIndex(torch::tensor({2, 1})), RowIndex(torch::tensor({2, 0, 4, 2}))};
  ix.world_kept = torch::tensor({0, 2});
  ix.world_senders = RowIndex(torch::tensor({5, 2}));
  ix.world_receivers = RowIndex(torch::tensor({2, 5}));
  torch::NoGradGuard no_grad;
  HoodLatents out = block(g, ix);
  EXPECT_EQ(block->finest_set(), 2);
  // Only its own set moves; the world edges it was not given keep their latents.
  EXPECT_TRUE(torch::equal(out.edge_sets[0], g.edge_sets[0]));
  EXPECT_TRUE(torch::equal(out.edge_sets[1], g.edge_sets[1]));
  EXPECT_FALSE(torch::equal(out.edge_sets[2], g.edge_sets[2]));
  for (int64_t e : {1, 3}) EXPECT_TRUE(torch::equal(out.world_edges[e], g.world_edges[e]));
  for (int64_t e : {0, 2}) EXPECT_FALSE(torch::equal(out.world_edges[e], g.world_edges[e]));
  // Node 3 has no edge in any set: its update sees only zero sums.
  auto zero = torch::zeros({1, 8});
  auto alone = g.nodes.narrow(0, 3, 1) + block->node->forward({g.nodes.narrow(0, 3, 1), zero, zero});
  EXPECT_TRUE(torch::allclose(out.nodes.narrow(0, 3, 1), alone, 1e-6, 1e-6));
}

TEST(HoodNet, SavesLoadsBatchesStepsAndEveryReadPartLearns) {
  Pb4uNet model = test::warmed_model(tiny_config("hood"), 42);
  EXPECT_EQ(model->propagation_steps_for(0.05), 0);
  EXPECT_TRUE(std::isnan(model->message_passing_flops(25, 80, 10, 0)));
  auto s = tiny_scene(43, true);
  GarmentTopology t = build_garment_topology(s.rest);
  const GraphOptions options = model->config.graph_options();
  GraphBatch g = build_graph(s.state, t, options);
  torch::Tensor a;
  {
    torch::NoGradGuard no_grad;
    a = model->forward(g, 0);
  }
  EXPECT_TRUE(torch::isfinite(a).all().item<bool>());
  const std::string path = test::temp_dir("hood") + "/hood.pt";
  save_model(model, path);
  Pb4uNet loaded = load_model(path, model->config);
  loaded->eval();
  {
    torch::NoGradGuard no_grad;
    EXPECT_TRUE(torch::equal(loaded->forward(g, 0), a));
    // A batch of two graphs (one without a body) predicts what each does.
    auto b = tiny_scene(44);
    b.state.effects.collision = b.state.effects.friction = false;
    GraphBatch gb = build_graph(b.state, t, options);
    auto batch = model->forward(concat_graphs({g, gb}), 0);
    EXPECT_TRUE(torch::allclose(batch, torch::cat({a, model->forward(gb, 0)}), 1e-5, 1e-5));
  }
  // Pins are followed, and the step is under inference mode.
  auto x_next = model->step(s.state, t);
  EXPECT_TRUE(torch::equal(x_next.narrow(0, 0, 5), s.state.pin_targets.narrow(0, 0, 5)));
  // Every parameter the schedule reads gets a gradient; the encoder of coarse level 2, which
  // "f,c0|c1" never reads, is not run.
  model->train();
  model->forward(g, 0).square().sum().backward();
  for (auto& p : model->named_parameters()) {
    const bool unread = p.key().rfind("coarse2_encoder", 0) == 0;
    EXPECT_EQ(p.value().grad().defined(), !unread) << p.key();
  }
}

// HOOD's blocks on the graph's own counts: block 1 ("f,c0") reads the mesh edges, coarse level
// 0 and every world edge; block 2 ("c1") coarse level 1 and the world edges whose garment
// vertex is in level 1 (vertex level 2 or more). Per edge MLP as MGN's; the node MLP has a part
// per set plus the node and the world sum.
TEST(HoodNet, MessagePassingFlopsCountTheCoarseAndKeptWorldEdges) {
  ModelConfig c = tiny_config("hood");
  c.mlp_hidden_layers = 3;
  Pb4uNet net(c);
  auto s = tiny_scene(45);
  // The body moved under the garment's last row (level 2): body vertices under garment (1, 1),
  // (1, 4), (4, 1), (4, 4).
  const auto shift = torch::tensor({-0.05, 0.0, -0.05}, torch::kFloat64);
  s.state.body.vertices = s.state.body.vertices + shift;
  s.state.body.next_vertices = s.state.body.next_vertices + shift;
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  const double H = c.latent, L = c.mlp_hidden_layers, n = double(g.num_nodes());
  const double Em = double(g.mesh_senders.size(0)), E0 = double(g.coarse[0].senders.size(0)),
               E1 = double(g.coarse[1].senders.size(0)), Ew = double(g.num_world_edges());
  auto level = torch::maximum(g.vertex_level.index_select(0, g.world_senders), g.vertex_level.index_select(0, g.world_receivers));
  const double Ew1 = (level >= 2).sum().item<double>();
  ASSERT_GT(Ew1, 0);
  ASSERT_LT(Ew1, Ew);
  auto edge_mlp = [&](double E) { return 4.0 * n * H * H + 2.0 * E * H * H + 2.0 * E * H * H * L; };
  auto node_mlp = [&](double parts) { return 2.0 * parts * n * H * H + 2.0 * n * H * H * L; };
  const double expected = edge_mlp(Em) + edge_mlp(E0) + edge_mlp(Ew) + node_mlp(4) +  // block 1
                          edge_mlp(E1) + edge_mlp(Ew1) + node_mlp(3);                  // block 2
  EXPECT_DOUBLE_EQ(net->message_passing_flops(g, 0), expected);
  EXPECT_TRUE(std::isnan(net->message_passing_flops(int64_t(n), int64_t(Em), int64_t(Ew), 0)));
}

// ContourCraft's stage 1: its own schedule is 15 flat blocks on f and c3.
TEST(CcraftSchedule, FifteenFlatBlocksOnTheMeshAndTheCoarsestLevel) {
  ModelConfig c;
  c.kind = "ccraft";
  const auto blocks = parse_hood_schedule(c.schedule(), c.coarse_levels());
  ASSERT_EQ(blocks.size(), 15u);
  for (const auto& b : blocks) EXPECT_EQ(b, (std::vector<int>{0, 4}));
  EXPECT_EQ(c.graph_options().coarse_levels, 4);
  EXPECT_DOUBLE_EQ(c.graph_options().cloth_edge_radius, 0.03);
  c.kind = "hood";
  EXPECT_THROW(parse_hood_schedule("f,c3", c.coarse_levels()), Error);  // HOOD has three levels
}

// The tiny garment (5 cm cells) folded: its last row moved 7 cm back and 1 cm up, over the
// cells between rows 2 and 3. Cloth edges join vertices to the nearest vertex of faces of the
// same cloth they lie over, from row 2 on, and nothing while the cloth lies flat.
TEST(ClothEdges, JoinClothLyingOverItsOwnFacesAndNothingElse) {
  auto s = tiny_scene(46);
  s.state.x = test::to_tensor(s.rest.V);
  s.state.x_prev = s.state.x.clone();
  ModelConfig c = tiny_config("ccraft");
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch flat = build_graph(s.state, t, c.graph_options());
  ASSERT_TRUE(flat.cloth_edges.senders.defined());
  EXPECT_EQ(flat.cloth_edges.senders.size(0), 0);
  for (int64_t j = 0; j < 5; ++j) {  // row 4: vertices 20-24
    s.state.x[20 + j][1] = s.state.x[20 + j][1] + 0.01;
    s.state.x[20 + j][2] = s.state.x[20 + j][2] - 0.07;
  }
  s.state.x_prev = s.state.x.clone();
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  ASSERT_GT(g.cloth_edges.senders.size(0), 0);
  EXPECT_GT((g.cloth_edges.senders >= 20).sum().item<int64_t>(), 0);  // the moved row over rows 2-3
  EXPECT_EQ(g.cloth_edges.features.size(1), kClothEdgeFeatureDim);
  auto x = s.state.x.to(torch::kFloat32);
  for (int64_t e = 0; e < g.cloth_edges.senders.size(0); ++e) {
    const int64_t a = g.cloth_edges.senders[e].item<int64_t>(), b = g.cloth_edges.receivers[e].item<int64_t>();
    EXPECT_TRUE(a >= 10 && b >= 10) << a << "-" << b;
    auto f = g.cloth_edges.features[e];
    EXPECT_TRUE(torch::allclose(f.narrow(0, 0, 3), x[b] - x[a], 1e-5, 1e-6));
    EXPECT_LT(f[11].item<double>(), 0.03);  // |d| within the radius
  }
}

TEST(CcraftNet, SavesLoadsBatchesAndSteps) {
  ModelConfig c = tiny_config("ccraft");
  c.hood_schedule = "f,c3|f,c3";
  Pb4uNet model = test::warmed_model(c, 47);
  EXPECT_TRUE(model->cloth_encoder);
  auto s = tiny_scene(48, true);
  GarmentTopology t = build_garment_topology(s.rest);
  GraphBatch g = build_graph(s.state, t, c.graph_options());
  torch::NoGradGuard no_grad;
  auto a = model->forward(g, 0);
  EXPECT_TRUE(torch::isfinite(a).all().item<bool>());
  const std::string path = test::temp_dir("ccraft") + "/ccraft.pt";
  save_model(model, path);
  Pb4uNet loaded = load_model(path, c);
  loaded->eval();
  EXPECT_TRUE(torch::equal(loaded->forward(g, 0), a));
  auto b = tiny_scene(49);
  GraphBatch gb = build_graph(b.state, t, c.graph_options());
  EXPECT_TRUE(torch::allclose(model->forward(concat_graphs({g, gb}), 0), torch::cat({a, model->forward(gb, 0)}), 1e-5,
                              1e-5));
  EXPECT_TRUE(std::isfinite(model->message_passing_flops(g, 0)));
  auto x_next = model->step(s.state, t);
  EXPECT_TRUE(torch::equal(x_next.narrow(0, 0, 5), s.state.pin_targets.narrow(0, 0, 5)));
}

}  // namespace
}  // namespace pb4u
