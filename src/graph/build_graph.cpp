#include "pb4u/graph/build_graph.h"

#include <cmath>
#include <vector>

#include "pb4u/graph/cloth_edges.h"
#include "pb4u/graph/features.h"
#include "pb4u/graph/world_edges.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {

void check_points(const torch::Tensor& t, int64_t rows, const char* name) {
  if (!t.defined() || t.dim() != 2 || t.size(1) != 3 || (rows >= 0 && t.size(0) != rows)) {
    std::string want = rows >= 0 ? "(" + std::to_string(rows) + ", 3)" : "(n, 3)";
    std::string got = t.defined() ? c10::str(t.sizes()) : "undefined";
    fail_file("frame state", std::string(name) + " must be a " + want + " tensor, got " + got);
  }
  if (!torch::isfinite(t).all().item<bool>()) fail_file("frame state", std::string(name) + " is not finite");
}

// Node features shared by every node: material, effect flags, gravity (SPEC 4 / 6).
torch::Tensor scene_features(const FrameState& s, const MaterialRanges& ranges, torch::Device device) {
  auto m = normalised_material(s.material, ranges);
  const Effects& e = s.effects;
  const double g = e.gravity ? 1.0 : 0.0;
  std::vector<float> f = {float(m[0]), float(m[1]), float(m[2]), float(m[3]),
                          float(e.gravity), float(e.collision), float(e.friction), float(e.pins),
                          float(g * s.gravity[0]), float(g * s.gravity[1]), float(g * s.gravity[2])};
  return torch::tensor(f).to(device);
}

torch::Tensor one_hot_rows(int64_t rows, int64_t hot, torch::Device device) {
  auto t = torch::zeros({rows, 3}, torch::TensorOptions().device(device));
  if (rows > 0) t.select(1, hot).fill_(1);
  return t;
}

}  // namespace

GraphBatch build_graph(const FrameState& state, const GarmentTopology& topology,
                       const GraphOptions& options) {
  const int64_t n = topology.num_vertices;
  check_points(state.x, n, "x");
  check_points(state.x_prev, n, "x_prev");
  if (!(state.dt > 0)) fail_file("frame state", "dt must be positive");
  if (!(state.material.density > 0)) fail_file("frame state", "material.density must be positive");
  // Velocity from the caller's dtype: float64 positions far from the origin keep their digits.
  auto v = ((state.x - state.x_prev) / state.dt).to(torch::kFloat32);
  auto x = state.x.to(torch::kFloat32);
  // Every tensor lives on x's device (graph building runs on the GPU in CUDA runs); only the
  // world-edge search goes through the host KD-tree.
  const torch::Device dev = x.device();
  const auto index_options = torch::TensorOptions().dtype(torch::kInt64).device(dev);
  auto scene = scene_features(state, options.material_ranges, dev);

  auto type = one_hot_rows(n, 0, dev);
  if (state.effects.pins && state.pinned.defined()) {
    if (state.pinned.dim() != 1 || state.pinned.size(0) != n)
      fail_file("frame state", "pinned must have one flag per garment vertex (" + std::to_string(n) + ")");
    auto pinned = state.pinned.to(torch::kBool).unsqueeze(1);
    type = torch::where(pinned.to(dev), one_hot_rows(n, 2, dev), type);
  }
  auto log_mass = torch::log(topology.vertex_area * state.material.density).unsqueeze(1);
  auto garment = torch::cat({v, vertex_normals(x, topology.faces, topology.corner_rows), type, log_mass,
                             scene.expand({n, scene.size(0)})}, 1);

  GraphBatch g;
  g.num_garment_nodes = n;
  g.mesh_senders = topology.senders;
  g.mesh_receivers = topology.receivers;
  g.mesh_sender_rows = topology.sender_rows;
  g.mesh_receiver_rows = topology.receiver_rows;
  g.mesh_features = mesh_edge_features(x, topology);
  g.vertex_mean_edge_length = topology.vertex_mean_edge_length;
  g.mean_edge_length = topology.mean_edge_length;
  g.world_senders = torch::empty({0}, index_options);
  g.world_receivers = torch::empty({0}, index_options);
  g.world_features = torch::empty({0, options.world_edge_feature_dim()}, torch::TensorOptions().device(dev));
  g.body_vertex_index = torch::empty({0}, index_options);
  g.node_features = garment;
  for (int level = 0; level < options.coarse_levels; ++level) {
    if (level >= static_cast<int>(topology.coarse.size()))
      throw Error("graph: the garment's topology has " + std::to_string(topology.coarse.size()) +
                  " coarse levels, the model asks for " + std::to_string(options.coarse_levels));
    const GarmentEdgeSet& set = topology.coarse[static_cast<size_t>(level)];
    g.coarse.push_back({set.senders, set.receivers, edge_set_features(x, set), set.sender_rows, set.receiver_rows});
  }
  // A model of fewer levels sees a vertex of a coarser one at its own coarsest.
  const torch::Tensor garment_level =
      options.coarse_levels > 0 ? topology.vertex_level.clamp_max(options.coarse_levels) : torch::Tensor();
  if (options.coarse_levels > 0) g.vertex_level = garment_level;
  if (options.geodesic_anchors > 0) {
    if (!topology.anchors.defined())
      throw Error("graph: the garment's topology has no geodesic anchors, which the model's attention needs "
                  "(build it with the model's geodesic_anchors)");
    g.anchor_sets.push_back({0, n, topology.anchors, topology.anchor_distance});
  }
  if (options.cloth_edge_radius > 0)
    g.cloth_edges = build_cloth_edges(x, x + v * state.dt, topology.faces, options.cloth_edge_radius, n);
  if (!state.effects.needs_body() || !state.body.defined()) return g;

  const BodyFrame& body = state.body;
  check_points(body.vertices, -1, "body.vertices");
  const int64_t nb = body.vertices.size(0);
  check_points(body.next_vertices, nb, "body.next_vertices");
  if (!body.faces.defined() || body.faces.dim() != 2 || body.faces.size(1) != 3)
    fail_file("frame state", "body.faces must be a (m, 3) tensor");
  auto pairs = garment_body_pairs(x, body.vertices, options.world_edge_radius,
                                  options.nearest_body_vertex_only);
  const int64_t np = pairs.size(0);
  if (np == 0) return g;

  // Only body vertices that world edges touch become nodes, numbered after the garment's.
  std::vector<int64_t> node_of(nb, -1), used;
  auto pa = pairs.accessor<int64_t, 2>();
  auto body_node = torch::empty({np}, torch::kInt64);
  auto bn = body_node.accessor<int64_t, 1>();
  for (int64_t i = 0; i < np; ++i) {
    int64_t b = pa[i][1];
    if (node_of[b] < 0) {
      node_of[b] = n + static_cast<int64_t>(used.size());
      used.push_back(b);
    }
    bn[i] = node_of[b];
  }
  auto used_t = torch::tensor(used, torch::kInt64).to(dev);
  body_node = body_node.to(dev);
  auto bx = body.vertices.to(torch::kFloat32), bx_next = body.next_vertices.to(torch::kFloat32);
  auto b_now = bx.index_select(0, used_t), b_next = bx_next.index_select(0, used_t);
  const int64_t nu = used_t.size(0);
  // The body's faces are the same at both poses: their corners are grouped once.
  const torch::Tensor body_faces = body.faces.to(torch::kInt64);
  const RowIndex body_corners = face_corner_rows(body_faces, nb);
  auto body_normals = vertex_normals(bx, body_faces, body_corners).index_select(0, used_t);
  auto body_nodes = torch::cat({(b_next - b_now) / state.dt, body_normals, one_hot_rows(nu, 1, dev),
                                torch::zeros({nu, 1}, x.options()), scene.expand({nu, scene.size(0)})}, 1);
  g.node_features = torch::cat({garment, body_nodes}, 0);
  g.body_vertex_index = used_t;
  if (options.coarse_levels > 0) g.vertex_level = torch::cat({garment_level, torch::zeros({nu}, index_options)});

  auto garment_node = pairs.select(1, 0).contiguous().to(dev);
  g.world_senders = torch::cat({body_node, garment_node});
  g.world_receivers = torch::cat({garment_node, body_node});
  g.world_sender_rows = group_rows(g.world_senders, g.num_nodes());
  g.world_receiver_rows = group_rows(g.world_receivers, g.num_nodes());
  auto p = torch::cat({x, b_now}, 0), q = torch::cat({x + v * state.dt, b_next}, 0);
  g.world_features = world_edge_features(p, q, g.world_senders, g.world_receivers);
  if (options.body_normal_distance) {
    // One value per pair, the same on both directed edges.
    auto slot = body_node - n;  // the pair's body vertex among used_t
    auto next_normals = vertex_normals(bx_next, body_faces, body_corners).index_select(0, used_t);
    auto d = body_normal_distances(x.index_select(0, garment_node), q.index_select(0, garment_node),
                                   b_now.index_select(0, slot), b_next.index_select(0, slot),
                                   body_normals.index_select(0, slot), next_normals.index_select(0, slot));
    g.world_features = torch::cat({g.world_features, torch::cat({d, d}, 0)}, 1);
  }
  return g;
}

}  // namespace pb4u
