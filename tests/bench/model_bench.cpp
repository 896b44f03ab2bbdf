// Per-stage latency of one inference step (graph build, encoders, propagation + update, blocks,
// decoder) for the CPU-scale and paper-scale model configs, median of repeated runs, with the
// per-edge first layer split (node terms once per node, gathered) and concatenated.
// Usage: model_bench [repeats] [scale: cpu|paper|all] [threads, 0 = all cores]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "model/tiny_scene.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/model/pb4u_net.h"
#include "pb4u/util/runtime.h"

namespace {

using namespace pb4u;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A cells x cells cloth square (2 cells^2 triangles) 1 cm above a finer-spaced body square, so
// the world-edge count is realistic (most garment vertices touch the body).
test::TinyScene bench_scene(int cells) {
  test::TinyScene s;
  s.rest = test::grid_mesh(cells, 1.0);
  s.rest.V.rowwise() += Eigen::RowVector3d(0.0, 0.01, 0.0);
  TriMesh body = test::grid_mesh(60, 1.2);
  body.V.rowwise() += Eigen::RowVector3d(-0.1, 0.0, -0.1);
  auto x = test::to_tensor(s.rest.V) + 0.002 * torch::randn({s.rest.num_vertices(), 3}, torch::kFloat64);
  s.state.x = x;
  s.state.x_prev = x - 0.01 * torch::randn_like(x);
  s.state.body.vertices = test::to_tensor(body.V);
  s.state.body.next_vertices = s.state.body.vertices + torch::tensor({0.0, 0.003, 0.0}, torch::kFloat64);
  s.state.body.faces = test::faces_tensor(body.F);
  return s;
}

struct Scale {
  const char* name;
  int latent, blocks, cells;  // cells: grid resolution of the garment
};

struct Samples {
  std::vector<double> graph, encode, propagate, blocks, decode, total;
};

// Per repeat, one step with the concatenated first layer and one with the split one, so both
// see the same machine load (the benchmark machine is shared); kind mgn runs split only.
void run(const Scale& scale, const std::string& kind, int repeats) {
  ModelConfig c;
  c.kind = kind;
  c.latent = scale.latent;
  c.num_blocks = scale.blocks;
  torch::manual_seed(0);
  Pb4uNet model(c);
  model->eval();
  auto s = bench_scene(scale.cells);
  GarmentTopology topo = build_garment_topology(s.rest);
  model->calibrate(topo.mean_edge_length);
  const int64_t K = model->propagation_steps_for(topo.mean_edge_length);
  const std::vector<bool> modes = kind == "mgn" ? std::vector<bool>{true} : std::vector<bool>{false, true};
  std::vector<Samples> samples(modes.size());
  std::vector<double> block_ratio;
  GraphBatch g;
  for (int r = 0; r <= repeats; ++r) {  // r = 0 warms up
    std::vector<double> blocks_ms;
    for (size_t m = 0; m < modes.size(); ++m) {
      model->set_split_first_layer(modes[m]);
      c10::InferenceMode guard;
      auto t0 = std::chrono::steady_clock::now();
      g = build_graph(s.state, topo, c.graph_options());
      double graph_ms = ms_since(t0);
      StageTimes t;
      model->forward(g, K, &t);
      if (r == 0) continue;
      Samples& x = samples[m];
      x.graph.push_back(graph_ms);
      x.encode.push_back(t.encode);
      x.propagate.push_back(t.propagate);
      x.blocks.push_back(t.blocks);
      x.decode.push_back(t.decode);
      x.total.push_back(ms_since(t0));
      blocks_ms.push_back(t.blocks + t.propagate);
    }
    if (r > 0 && modes.size() == 2) block_ratio.push_back(blocks_ms[1] / blocks_ms[0]);
  }
  for (size_t m = 0; m < modes.size(); ++m) {
    const Samples& x = samples[m];
    std::printf("| %s | %s | %s | %d | %d | %lld | %lld | %lld | %lld | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |\n",
                scale.name, kind.c_str(), modes[m] ? "split" : "concat", scale.latent, scale.blocks,
                (long long)s.rest.num_faces(), (long long)g.num_garment_nodes,
                (long long)g.num_world_edges(), (long long)K, median(x.graph), median(x.encode),
                median(x.propagate), median(x.blocks), median(x.decode), median(x.total));
  }
  if (!block_ratio.empty())
    std::printf("|   | split / concat time of propagation + blocks, median of paired runs: %.2f |\n",
                median(block_ratio));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  pb4u::ensure_fast_runtime(argc, argv);
  // PB4U_DEFAULT_MALLOC=1 measures with glibc's default allocator settings.
  const bool tune_malloc = !std::getenv("PB4U_DEFAULT_MALLOC");
  pb4u::tune_allocator();
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 7;
  const std::string which = argc > 2 ? argv[2] : "all";
  const int threads = pb4u::configure_threads(argc > 3 ? std::atoi(argv[3]) : 0);
  // CPU scale: Lv.1 of the CPU levels (~2K triangles), width 64, 8 blocks.
  // Paper scale: Lv.1 of the paper (~11K triangles), width 128, 15 blocks (SPEC 4).
  const std::vector<Scale> scales = {{"cpu", 64, 8, 32}, {"paper", 128, 15, 74}};
  std::printf("model_bench: median of %d runs, %d threads, BLAS core %s, torch %s, malloc %s\n",
              repeats, threads, pb4u::blas_core_name().c_str(), TORCH_VERSION,
              tune_malloc ? "tuned" : "default");
  std::printf("| scale | kind | first layer | width | blocks | triangles | vertices | world edges | K | "
              "graph ms | encode ms | propagate ms | blocks ms | decode ms | total ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Scale& scale : scales) {
    if (which != "all" && which != scale.name) continue;
    run(scale, "pb4u", repeats);
    run(scale, "mgn", repeats);
  }
  return 0;
}
