// Gathers and sums by a grouped row index against torch's index_select / index_add_: the same
// bits forward and backward, and the same network outputs and gradients.
#include <gtest/gtest.h>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/row_index.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace {

bool same_bits(const torch::Tensor& a, const torch::Tensor& b) {
  return a.sizes() == b.sizes() && a.scalar_type() == b.scalar_type() && torch::equal(a, b);
}

TEST(RowIndex, GroupsEntriesByRowInIncreasingOrder) {
  auto index = torch::tensor({2, 0, 2, 3, 0, 2}, torch::kInt64);
  RowIndex ix = group_rows(index, 5);
  ASSERT_TRUE(ix.grouped());
  EXPECT_EQ(ix.rows(), 5);
  EXPECT_TRUE(torch::equal(ix.offsets, torch::tensor({0, 2, 2, 5, 6, 6}, torch::kInt64)));
  EXPECT_TRUE(torch::equal(ix.order, torch::tensor({1, 4, 0, 2, 5, 3}, torch::kInt64)));
  EXPECT_THROW(group_rows(index, 3), Error);                                    // row 3 of 3
  EXPECT_THROW(group_rows(torch::tensor({0, -1}, torch::kInt64), 2), Error);   // negative
  EXPECT_FALSE(RowIndex(index).grouped());
}

TEST(RowIndex, GatherAndSumGiveTorchsBitsForwardAndBackward) {
  for (int threads : {1, 2}) {
    torch::set_num_threads(threads);
    for (auto dtype : {torch::kFloat32, torch::kFloat64}) {
      torch::manual_seed(3);
      const int64_t rows = 300, E = 2000;
      auto index = torch::randint(0, rows - 20, {E}, torch::kInt64);  // the last rows get nothing
      RowIndex grouped = group_rows(index, rows - 20);
      auto x = torch::randn({rows, 7}, torch::TensorOptions().dtype(dtype));
      auto upstream = torch::randn({E, 7}, x.options());

      auto xa = x.clone().requires_grad_(true), xb = x.clone().requires_grad_(true);
      auto ga = gather_rows(xa, grouped), gb = xb.index_select(0, index);
      EXPECT_TRUE(same_bits(ga, gb));
      (ga * upstream).sum().backward();
      (gb * upstream).sum().backward();
      EXPECT_TRUE(same_bits(xa.grad(), xb.grad())) << "gather backward, " << threads << " threads";

      auto va = upstream.clone().requires_grad_(true), vb = upstream.clone().requires_grad_(true);
      auto sa = sum_rows_at(va, grouped, rows);
      auto sb = torch::zeros({rows, 7}, x.options()).index_add_(0, index, vb);
      EXPECT_TRUE(same_bits(sa, sb)) << "sum, " << threads << " threads";
      EXPECT_EQ(sa.narrow(0, rows - 20, 20).abs().sum().item<double>(), 0.0);
      (sa * x).sum().backward();
      (sb * x).sum().backward();
      EXPECT_TRUE(same_bits(va.grad(), vb.grad()));
    }
  }
  torch::set_num_threads(1);
}

TEST(RowIndex, NoEntriesAndRowsOfAnyShape) {
  RowIndex none = group_rows(torch::zeros({0}, torch::kInt64), 4);
  auto sum = sum_rows_at(torch::zeros({0, 2, 3}), none, 4);
  EXPECT_EQ(sum.sizes(), (std::vector<int64_t>{4, 2, 3}));
  EXPECT_EQ(sum.abs().sum().item<double>(), 0.0);
  EXPECT_EQ(gather_rows(torch::ones({4, 2}), none).size(0), 0);
  auto index = torch::tensor({1, 1, 3}, torch::kInt64);
  auto values = torch::arange(12, torch::kFloat32).view({3, 2, 2});
  EXPECT_TRUE(torch::equal(sum_rows_at(values, group_rows(index, 4), 4),
                           torch::zeros({4, 2, 2}).index_add_(0, index, values)));
}

TEST(RowIndex, FewerRowsThanTheGroupsFallBackToTorchsChecks) {
  auto index = torch::tensor({0, 4}, torch::kInt64);
  RowIndex grouped = group_rows(index, 5);
  EXPECT_THROW(sum_rows_at(torch::ones({2, 3}), grouped, 3), c10::Error);  // row 4 of 3
  EXPECT_EQ(sum_rows_at(torch::ones({2, 3}), grouped, 7).size(0), 7);
  EXPECT_THROW(gather_rows(torch::ones({3, 3}), grouped), c10::Error);
}

// The network on a graph with grouped indices and on the same graph with bare ones: the same
// acceleration and the same parameter gradients, bit for bit.
TEST(RowIndex, NetworkOutputsAndGradientsMatchTheBareIndices) {
  for (const char* kind : {"pb4u", "mgn"}) {
    ModelConfig c = test::tiny_config(kind);
    torch::manual_seed(5);
    Pb4uNet model(c);
    model->calibrate(0.04);
    auto s = test::tiny_scene(31, true);
    GarmentTopology t = build_garment_topology(s.rest);
    GraphBatch grouped = build_graph(s.state, t, c.graph_options());
    ASSERT_TRUE(grouped.mesh_receiver_rows.grouped());
    ASSERT_GT(grouped.num_world_edges(), 0);
    ASSERT_TRUE(grouped.world_receiver_rows.grouped());
    GraphBatch bare = grouped;
    bare.mesh_sender_rows = bare.mesh_receiver_rows = bare.world_sender_rows = bare.world_receiver_rows = RowIndex();

    auto run = [&](const GraphBatch& g) {
      model->zero_grad();
      model->eval();
      auto a = model->forward(g, 3);
      (a * a).sum().backward();
      std::vector<torch::Tensor> grads;
      for (const auto& p : model->parameters()) grads.push_back(p.grad().defined() ? p.grad().clone() : torch::Tensor());
      return std::make_pair(a.detach(), grads);
    };
    auto [a1, g1] = run(grouped);
    auto [a2, g2] = run(bare);
    EXPECT_TRUE(same_bits(a1, a2)) << kind;
    ASSERT_EQ(g1.size(), g2.size());
    for (size_t i = 0; i < g1.size(); ++i) {
      ASSERT_EQ(g1[i].defined(), g2[i].defined());
      if (g1[i].defined()) EXPECT_TRUE(same_bits(g1[i], g2[i])) << kind << " parameter " << i;
    }
  }
}

}  // namespace
}  // namespace pb4u
