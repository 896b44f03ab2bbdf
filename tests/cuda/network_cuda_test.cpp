// The network on the GPU computes what it computes on the CPU: the same weights and normaliser
// statistics on the same tiny scene, graph building included, give the same outputs, parameter
// gradients and inference step within float32 rounding (CUDA's scatter-adds sum in no fixed
// order, so not bit for bit).
#include <gtest/gtest.h>

#include <algorithm>

#include "cuda/require_cuda.h"
#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/model/pb4u_net.h"

namespace pb4u {
namespace {

const torch::Device kCuda(torch::kCUDA, 0);

FrameState state_on(const FrameState& state, torch::Device device) {
  FrameState s = state;
  for (torch::Tensor* t : {&s.x, &s.x_prev, &s.pinned, &s.pin_targets, &s.body.vertices, &s.body.next_vertices,
                           &s.body.faces})
    if (t->defined()) *t = t->to(device);
  return s;
}

// max |a - b| over max |a|: a on the CPU, b on any device.
double relative_difference(const torch::Tensor& a, const torch::Tensor& b) {
  const torch::Tensor bc = b.detach().to(torch::kCPU, a.scalar_type());
  return (a.detach() - bc).abs().max().item<double>() / std::max(a.detach().abs().max().item<double>(), 1e-30);
}

// A model whose normalisers saw a few frames (so they are not the identity), and its copy on
// the GPU through save_model / load_model.
std::pair<Pb4uNet, Pb4uNet> cpu_and_cuda_model(const ModelConfig& c) {
  torch::manual_seed(7);
  Pb4uNet cpu(c);
  cpu->calibrate(0.04);
  cpu->train();
  for (unsigned i = 0; i < 3; ++i) {
    auto s = test::tiny_scene(100 + i, true);
    cpu->forward(build_graph(s.state, build_garment_topology(s.rest, "garment", c.graph_options().geodesic_anchors),
                             c.graph_options()),
                 2);
  }
  cpu->eval();
  const std::string path = test::temp_dir("cuda_net") + "/model.pt";
  save_model(cpu, path);
  Pb4uNet gpu = load_model(path, c);
  gpu->eval();
  gpu->to(kCuda);
  return {cpu, gpu};
}

TEST(CudaNetwork, ForwardBackwardAndStepMatchTheCpu) {
  PB4U_REQUIRE_CUDA();
  // Every model kind: the baselines' coarse edge sets, cloth edges and geodesic anchors too.
  for (const std::string kind : {"pb4u", "mgn", "hood", "ccraft", "eslr"}) {
    ModelConfig c = test::tiny_config(kind);
    if (kind == "ccraft") c.hood_schedule = "f,c3|f,c3";
    if (kind == "eslr") c.geodesic_anchors = 8;
    auto [cpu, gpu] = cpu_and_cuda_model(c);
    const auto s = test::tiny_scene(21, true);
    const GarmentTopology topology = build_garment_topology(s.rest, "garment", c.graph_options().geodesic_anchors);
    const GarmentTopology topology_gpu = garment_topology_to(topology, kCuda);
    const GraphBatch g_cpu = build_graph(s.state, topology, c.graph_options());
    const GraphBatch g_gpu = build_graph(state_on(s.state, kCuda), topology_gpu, c.graph_options());
    ASSERT_TRUE(g_gpu.node_features.is_cuda()) << kind;
    ASSERT_GT(g_cpu.num_world_edges(), 0) << kind;  // the body is in the graph
    EXPECT_EQ(g_gpu.num_world_edges(), g_cpu.num_world_edges()) << kind;
    EXPECT_LT(relative_difference(g_cpu.node_features, g_gpu.node_features), 1e-6) << kind;
    EXPECT_LT(relative_difference(g_cpu.world_features, g_gpu.world_features), 1e-6) << kind;

    const int64_t K = cpu->propagation_steps_for(g_cpu.mean_edge_length);
    EXPECT_EQ(gpu->propagation_steps_for(g_gpu.mean_edge_length), K) << kind;
    const torch::Tensor a = cpu->forward(g_cpu, K), b = gpu->forward(g_gpu, K);
    ASSERT_TRUE(b.is_cuda()) << kind;
    EXPECT_GT(a.abs().max().item<double>(), 1e-4) << kind;
    EXPECT_LT(relative_difference(a, b), 1e-4) << kind;

    // Gradients of one scalar of the outputs, parameter by parameter.
    const torch::Tensor w = torch::randn(a.sizes(), a.options());
    (a * w).sum().backward();
    (b * w.to(kCuda)).sum().backward();
    double largest = 0;
    for (const auto& p : cpu->parameters())
      if (p.grad().defined()) largest = std::max(largest, p.grad().abs().max().item<double>());
    ASSERT_GT(largest, 0.0) << kind;
    auto on_gpu = gpu->named_parameters();
    int compared = 0;
    for (const auto& p : cpu->named_parameters()) {
      const torch::Tensor gc = p.value().grad(), gg = on_gpu[p.key()].grad();
      ASSERT_EQ(gc.defined(), gg.defined()) << kind << " " << p.key();
      if (!gc.defined()) continue;
      ++compared;
      EXPECT_TRUE(torch::allclose(gc, gg.to(torch::kCPU), 1e-3, 1e-5 * largest))
          << kind << " " << p.key() << ": " << relative_difference(gc, gg);
    }
    EXPECT_GT(compared, 0) << kind;

    // One inference step (graph, network, update, pins) on each device.
    const torch::Tensor x_cpu = cpu->step(s.state, topology);
    const torch::Tensor x_gpu = gpu->step(state_on(s.state, kCuda), topology_gpu);
    ASSERT_TRUE(x_gpu.is_cuda()) << kind;
    EXPECT_LT(relative_difference(x_cpu, x_gpu), 1e-5) << kind;
  }
}

}  // namespace
}  // namespace pb4u
