// Host cost of the per-frame body queries that a CUDA run keeps on the CPU (issue 10): the
// world-edge search (nearest body vertex within the radius, nanoflann KD-tree built per frame)
// and the collision/friction contact query (KD-tree over body face centroids), for garments of
// the paper's ~12K / 25K / 48K triangles against an SMPL-sized body (~6.9K vertices, ~13.7K
// faces), median of repeats, with the bytes a GPU run would move each way.
// Usage: world_edges_bench [repeats]
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "pb4u/graph/graph_options.h"
#include "pb4u/graph/world_edges.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/physics_config.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/runtime.h"
#include "test_util.h"

int main(int argc, char** argv) {
  using namespace pb4u;
  ensure_fast_runtime(argc, argv);
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 11;
  const int threads = configure_threads(0);
  const GraphOptions graph;
  const PhysicsConfig physics;
  // Body: a 1.2 m square of 83 x 83 vertices (6889, 13448 faces); garment 1 cm above it.
  TriMesh body = test::grid_mesh(82, 1.2);
  body.V.rowwise() += Eigen::RowVector3d(-0.1, 0.0, -0.1);
  BodyFrame frame;
  frame.vertices = matrix_to_tensor(body.V, torch::kFloat32);
  frame.next_vertices = frame.vertices + 0.003;
  frame.faces = index_matrix_to_tensor(body.F);
  std::printf("| triangles | vertices | world-edge search ms | contact query ms | host<->device bytes |\n|---|---|---|---|---|\n");
  for (int cells : {78, 112, 155}) {  // 2 cells^2 triangles: 12.2K, 25.1K, 48.1K
    TriMesh garment = test::grid_mesh(cells, 1.0);
    garment.V.rowwise() += Eigen::RowVector3d(0.0, 0.01, 0.0);
    torch::Tensor x = matrix_to_tensor(garment.V, torch::kFloat32);
    std::vector<double> search, contact;
    int64_t pairs = 0;
    for (int r = 0; r < repeats; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      pairs = garment_body_pairs(x, frame.vertices, graph.world_edge_radius, graph.nearest_body_vertex_only).size(0);
      auto t1 = std::chrono::steady_clock::now();
      query_body_contact(x, frame, physics.friction.contact_radius, physics.degenerate_area);
      auto t2 = std::chrono::steady_clock::now();
      search.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      contact.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
    std::sort(search.begin(), search.end());
    std::sort(contact.begin(), contact.end());
    // To the host: garment and body positions (float32); back: pairs and face indices (int64).
    const long long bytes = (x.numel() + frame.vertices.numel()) * 4 * 2 + (pairs * 2 + x.size(0)) * 8;
    std::printf("| %lld | %lld | %.2f | %.2f | %lld |\n", static_cast<long long>(garment.F.rows()),
                static_cast<long long>(garment.V.rows()), search[search.size() / 2], contact[contact.size() / 2], bytes);
  }
  std::printf("(%d torch threads; the queries themselves are single-threaded)\n", threads);
}
