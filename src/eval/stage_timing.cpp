#include "pb4u/eval/stage_timing.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/world_edges.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/util/error.h"
#include "pb4u/util/median.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {

using Clock = std::chrono::steady_clock;

DenseMatmul::DenseMatmul(const std::vector<int>& size) {
  if (size.size() != 3 || size[0] < 1 || size[1] < 1 || size[2] < 1)
    throw Error("matmul_size: expected three positive sizes [m, k, n]");
  c10::InferenceMode guard;
  a_ = torch::randn({size[0], size[1]});
  b_ = torch::randn({size[1], size[2]});
  c_ = torch::mm(a_, b_);  // warm-up: BLAS buffers, page faults
  flops_ = 2.0 * double(size[0]) * double(size[1]) * double(size[2]);
}

double DenseMatmul::gflops() {
  c10::InferenceMode guard;
  auto t0 = Clock::now();
  torch::mm_out(c_, a_, b_);
  return flops_ / (ms_since(t0) * 1e6);
}

double DenseMatmul::median_gflops(int repeats) {
  std::vector<double> g;
  for (int r = 0; r < repeats; ++r) g.push_back(gflops());
  return median(g);
}

// One network frame split into its stages, median over `repeats` (after one warm-up).
// The dense matmul is timed in each repeat too, so the FLOP-rate ratio compares the two under
// the same machine load.
StageRow time_stages(Pb4uNet& net, const GarmentTopology& topology, const RolloutInput& in,
                     const PhysicsConfig& physics, int repeats, DenseMatmul& matmul) {
  c10::InferenceMode guard;
  const FrameState state = rollout_start_state(in);
  const ClothGeometry cloth = make_cloth_geometry(in.garment_rest, torch::kFloat64, torch::kCPU, false,
                                                  physics.degenerate_area);
  const TermList terms = build_terms(in.effects, physics);
  const GraphOptions options = net->config.graph_options();
  const int64_t K = net->propagation_steps_for(topology.mean_edge_length);
  std::vector<double> graph, world, encode, propagate, blocks, decode, euler, contact, physics_ms, dense;
  StageRow row;
  for (int r = 0; r <= repeats; ++r) {
    double world_ms = 0;
    if (in.effects.needs_body()) {
      auto t0 = Clock::now();
      garment_body_pairs(state.x.to(torch::kFloat32), state.body.vertices, options.world_edge_radius,
                         options.nearest_body_vertex_only);
      world_ms = ms_since(t0);
    }
    auto t0 = Clock::now();
    GraphBatch g = build_graph(state, topology, options);
    const double graph_ms = ms_since(t0);
    StageTimes times;
    auto a = net->forward(g, K, &times);
    t0 = Clock::now();
    auto x_next = euler_step(state, a).to(torch::kFloat64);
    const double euler_ms = ms_since(t0);
    t0 = Clock::now();
    std::optional<BodyContact> body_contact = body_contact_for(state, physics);
    const double contact_ms = ms_since(t0);
    t0 = Clock::now();
    energy_report(terms, x_next, state, cloth, body_contact ? &*body_contact : nullptr, in.metric_material);
    const double physics_terms_ms = ms_since(t0);
    if (r == 0) {  // warm-up
      row.mesh_edges = g.mesh_senders.size(0);
      row.world_edges = g.num_world_edges();
      row.message_passing_gflops = net->message_passing_flops(g, K);
      continue;
    }
    world.push_back(world_ms);
    // build_graph runs the same world-edge query inside; the rest is feature assembly.
    graph.push_back(std::max(0.0, graph_ms - world_ms));
    encode.push_back(times.encode);
    propagate.push_back(times.propagate);
    blocks.push_back(times.blocks);
    decode.push_back(times.decode);
    euler.push_back(euler_ms);
    contact.push_back(contact_ms);
    physics_ms.push_back(physics_terms_ms);
    dense.push_back(matmul.gflops());
  }
  row.vertices = topology.num_vertices;
  row.with_body = in.effects.needs_body();
  row.K = K;
  row.graph_build = median(graph);
  row.world_edge_query = median(world);
  row.encode = median(encode);
  row.propagate = median(propagate);
  row.blocks = median(blocks);
  row.decode = median(decode);
  row.euler = median(euler);
  row.contact_query = median(contact);
  row.physics_terms = median(physics_ms);
  // Propagation + update + blocks: the message passing whose FLOP rate is compared to BLAS.
  row.message_passing_gflops /= (row.propagate + row.blocks) * 1e6;
  row.matmul_gflops = median(dense);
  return row;
}

}  // namespace pb4u
