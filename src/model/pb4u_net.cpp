#include "pb4u/model/pb4u_net.h"

#include <chrono>
#include <fstream>
#include <limits>
#include <map>

#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/features.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/model/propagation_control.h"
#include "pb4u/model/update_scaling.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

namespace {
constexpr int64_t kLevelEmbeddingDim = 4;  // HOOD's

// Adds the milliseconds since `t0` to *slot (if timing) and restarts the clock.
struct StageClock {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  void lap(double* slot) {
    auto now = std::chrono::steady_clock::now();
    if (slot) *slot += std::chrono::duration<double, std::milli>(now - t0).count();
    t0 = now;
  }
};
}  // namespace

Pb4uNetImpl::Pb4uNetImpl(const ModelConfig& c) : config(c) {
  validate_model_config(config);
  normalised_material(Material{}, config.material_ranges);  // rejects bad ranges now
  const int64_t H = config.latent;
  const int L = config.mlp_hidden_layers;
  auto normalizer = [&](const char* name, int64_t dim) {
    return register_module(name, OnlineNormalizer(dim, config.normalizer_warmup, config.normalizer_epsilon));
  };
  vertex_normalizer = normalizer("vertex_normalizer", kVertexFeatureDim);
  mesh_normalizer = normalizer("mesh_normalizer", kMeshEdgeFeatureDim);
  const int64_t world_dim = config.graph_options().world_edge_feature_dim();
  world_normalizer = normalizer("world_normalizer", world_dim);
  auto encoder = [&](const char* name, int64_t dim) {
    return register_module(name, MLP(std::vector<int64_t>{dim}, H, H, L, true));
  };
  vertex_encoder = encoder("vertex_encoder", kVertexFeatureDim + (config.is_hierarchical() ? kLevelEmbeddingDim : 0));
  mesh_encoder = encoder("mesh_encoder", kMeshEdgeFeatureDim);
  world_encoder = encoder("world_encoder", world_dim);
  if (config.is_pb4u()) {
    propagation = register_module("propagation", DecayedPropagation(H, L, config.gamma));
    update = register_module("update", MLP(std::vector<int64_t>{H, H}, H, H, L, true));
  }
  if (config.is_hierarchical()) {
    // HOOD's nn.Embedding(levels + 1, 4) starts from N(0, 1) rows.
    const int levels = config.coarse_levels();
    level_embedding = register_parameter("level_embedding", torch::randn({levels + 1, kLevelEmbeddingDim}));
    for (int l = 0; l < levels; ++l)
      coarse_encoders.push_back(register_module("coarse" + std::to_string(l) + "_encoder",
                                                MLP(std::vector<int64_t>{kMeshEdgeFeatureDim}, H, H, L, true)));
    if (config.is_ccraft()) {
      cloth_normalizer = normalizer("cloth_normalizer", kClothEdgeFeatureDim);
      cloth_encoder = encoder("cloth_encoder", kClothEdgeFeatureDim);
    }
    const auto schedule = parse_hood_schedule(config.schedule(), levels);
    for (size_t b = 0; b < schedule.size(); ++b)
      hood_blocks.push_back(
          register_module("block" + std::to_string(b), HoodBlock(schedule[b], H, L, config.is_ccraft())));
  } else if (config.is_eslr()) {
    for (int b = 0; b < config.num_blocks; ++b) {
      lsdmp_blocks.push_back(register_module("block" + std::to_string(b), LsdmpBlock(H, L)));
      attention.push_back(register_module("attention" + std::to_string(b),
                                          GeodesicAttention(H, config.attention_heads, config.geodesic_bins,
                                                            config.geodesic_max_distance)));
    }
  } else {
    for (int b = 0; b < config.num_blocks; ++b)
      blocks.push_back(register_module("block" + std::to_string(b), GraphNetBlock(H, L)));
  }
  decoder = register_module("decoder", MLP(std::vector<int64_t>{H}, H, 3, L, false));
  lbar_base = register_buffer("mean_edge_length_base", torch::zeros({}, torch::kFloat64));
  distance = register_buffer("propagation_distance", torch::zeros({}, torch::kFloat64));
}

void Pb4uNetImpl::calibrate(double base) {
  if (!(base > 0)) throw Error("model calibration: the mean edge length must be positive");
  torch::NoGradGuard no_grad;
  lbar_base.fill_(base);
  distance.fill_(config.k_base * base);
}

double Pb4uNetImpl::mean_edge_length_base() const { return lbar_base.item<double>(); }
double Pb4uNetImpl::propagation_distance() const { return distance.item<double>(); }

int64_t Pb4uNetImpl::propagation_steps_for(double mean_edge_length) const {
  return inference_propagation_steps(config, propagation_distance(), mean_edge_length);
}

torch::Tensor Pb4uNetImpl::forward(const GraphBatch& g, int64_t K, StageTimes* times) {
  StageClock clock;
  const int64_t H = config.latent;
  LatentGraph latent;
  torch::Tensor vertex_in = vertex_normalizer(g.node_features);
  if (config.is_hierarchical()) {
    if (!g.vertex_level.defined() || static_cast<int>(g.coarse.size()) != config.coarse_levels() ||
        (config.is_ccraft() && !g.cloth_edges.senders.defined()))
      throw Error(config.kind + " model: the graph lacks its coarse levels or cloth edges (build it with the model's "
                  "graph options)");
    // nn.Embedding's max_norm: rows longer than 1 scaled back to 1.
    auto scale = level_embedding.norm(2, 1, true).clamp_min(1.0).reciprocal();
    vertex_in = torch::cat({vertex_in, (level_embedding * scale).index_select(0, g.vertex_level)}, 1);
  }
  latent.nodes = vertex_encoder->forward({vertex_in});
  latent.mesh_edges = mesh_encoder->forward({mesh_normalizer(g.mesh_features)});
  latent.world_edges = g.num_world_edges() > 0
                           ? world_encoder->forward({world_normalizer(g.world_features)})
                           : torch::zeros({0, H}, latent.nodes.options());
  clock.lap(times ? &times->encode : nullptr);
  // A graph put together by hand may lack the grouped indices: then the bare ones serve.
  auto rows = [](const RowIndex& grouped, const torch::Tensor& bare) {
    return grouped.index.defined() ? grouped : RowIndex(bare);
  };
  const RowIndex ms = rows(g.mesh_sender_rows, g.mesh_senders), mr = rows(g.mesh_receiver_rows, g.mesh_receivers);
  const RowIndex ws = rows(g.world_sender_rows, g.world_senders),
                 wr = rows(g.world_receiver_rows, g.world_receivers);
  if (config.is_pb4u()) {
    auto h = propagation(latent.nodes, latent.mesh_edges, ms, mr, K);
    latent.nodes = update->forward({latent.nodes, h});
  }
  clock.lap(times ? &times->propagate : nullptr);
  if (config.is_hierarchical()) {
    latent.nodes = hood_blocks_forward(g, latent.nodes, latent.mesh_edges, latent.world_edges, ms, mr, ws, wr);
  } else if (config.is_eslr()) {
    if (g.anchor_sets.empty())
      throw Error("eslr model: the graph lacks its geodesic anchors (build it with the model's graph options)");
    for (size_t b = 0; b < lsdmp_blocks.size(); ++b) {
      // The two halves read the same input; their updates add up.
      auto long_range = attention[b](latent.nodes, g.anchor_sets);
      latent = lsdmp_blocks[b](latent, ms, mr, ws, wr);
      latent.nodes = latent.nodes + long_range;
    }
  } else {
    for (auto& block : blocks)
      latent = block(latent, ms, mr, ws, wr);
  }
  clock.lap(times ? &times->blocks : nullptr);
  auto a = decoder->forward({latent.nodes.narrow(0, 0, g.num_garment_nodes)});
  auto s = update_scale(g.vertex_mean_edge_length, mean_edge_length_base(), config.update_scaling_on());
  if (config.update_scaling == "detail")
    a = detail_update_scaling(a, s, g.mesh_senders, g.mesh_receivers, g.mean_edge_length, config.smooth_distance);
  else
    a = a * s;
  a = a * config.acceleration_unit;
  clock.lap(times ? &times->decode : nullptr);
  return a;
}

torch::Tensor Pb4uNetImpl::hood_blocks_forward(const GraphBatch& g, torch::Tensor nodes, torch::Tensor mesh_edges,
                                               torch::Tensor world_edges, const RowIndex& ms, const RowIndex& mr,
                                               const RowIndex& ws, const RowIndex& wr) {
  HoodLatents latent{std::move(nodes), {std::move(mesh_edges)}, std::move(world_edges), {}};
  HoodIndices full;
  full.senders = {ms};
  full.receivers = {mr};
  const int levels = config.coarse_levels();
  if (config.is_ccraft()) {
    const GraphEdges& cloth = g.cloth_edges;
    latent.cloth_edges = cloth.senders.size(0) > 0 ? cloth_encoder->forward({cloth_normalizer(cloth.features)})
                                                   : torch::zeros({0, config.latent}, latent.nodes.options());
    full.cloth_senders = cloth.sender_rows.index.defined() ? cloth.sender_rows : RowIndex(cloth.senders);
    full.cloth_receivers = cloth.receiver_rows.index.defined() ? cloth.receiver_rows : RowIndex(cloth.receivers);
  }
  std::vector<bool> used(levels + 1, false);
  for (auto& block : hood_blocks)
    for (int s : block->sets) used[static_cast<size_t>(s)] = true;
  for (int l = 0; l < levels; ++l) {
    const GraphEdges& set = g.coarse[static_cast<size_t>(l)];
    // A level no block reads (HOOD's schedule never reads c2) is not encoded.
    latent.edge_sets.push_back(used[static_cast<size_t>(l) + 1]
                                   ? coarse_encoders[static_cast<size_t>(l)]->forward({mesh_normalizer(set.features)})
                                   : torch::Tensor());
    full.senders.push_back(set.sender_rows.index.defined() ? set.sender_rows : RowIndex(set.senders));
    full.receivers.push_back(set.receiver_rows.index.defined() ? set.receiver_rows : RowIndex(set.receivers));
  }
  // The world edges each block keeps, by its finest set: all for the mesh edges, else those
  // whose garment vertex (the end of higher level: a body node's is 0) is in that level.
  const int64_t n = g.num_nodes();
  std::vector<HoodIndices> by_finest(levels + 1);
  auto indices_for = [&](int finest) -> const HoodIndices& {
    HoodIndices& ix = by_finest[static_cast<size_t>(finest)];
    if (ix.senders.empty()) {
      ix.senders = full.senders;
      ix.receivers = full.receivers;
      ix.cloth_senders = full.cloth_senders;
      ix.cloth_receivers = full.cloth_receivers;
      const int64_t ew = g.num_world_edges();
      if (finest == 0 || ew == 0) {
        ix.world_kept = torch::arange(ew, g.world_senders.options());
        ix.world_senders = ws;
        ix.world_receivers = wr;
      } else {
        auto level = torch::maximum(g.vertex_level.index_select(0, g.world_senders),
                                    g.vertex_level.index_select(0, g.world_receivers));
        ix.world_kept = torch::nonzero(level >= finest).view({-1});
        ix.world_senders = group_rows(g.world_senders.index_select(0, ix.world_kept), n);
        ix.world_receivers = group_rows(g.world_receivers.index_select(0, ix.world_kept), n);
      }
    }
    return ix;
  };
  for (auto& block : hood_blocks) latent = block(latent, indices_for(block->finest_set()));
  return latent.nodes;
}

torch::Tensor Pb4uNetImpl::step(const FrameState& state, const GarmentTopology& topology,
                                int64_t k_override) {
  c10::InferenceMode guard;
  auto g = build_graph(state, topology, config.graph_options());
  const int64_t K = k_override >= 0 ? k_override : propagation_steps_for(g.mean_edge_length);
  return euler_step(state, forward(g, K));
}

void Pb4uNetImpl::set_split_first_layer(bool split) {
  if (propagation) propagation->split_first_layer = split;
  for (auto& b : blocks) b->split_first_layer = split;
}

double Pb4uNetImpl::message_passing_flops(int64_t nodes, int64_t mesh_edges, int64_t world_edges,
                                          int64_t K) const {
  const double n = double(nodes), Em = double(mesh_edges), Ew = double(world_edges);
  if (config.is_hierarchical() || config.is_eslr()) return std::numeric_limits<double>::quiet_NaN();
  double flops = 0;
  if (propagation) {
    flops += propagation->matmul_flops(n, Em, K);
    flops += update->first_layer_flops(0, n) + update->first_layer_flops(1, n) + update->finish_flops(n);
  }
  for (const auto& b : blocks) flops += b->matmul_flops(n, Em, Ew);
  return flops;
}

double Pb4uNetImpl::message_passing_flops(const GraphBatch& g, int64_t K) const {
  const int64_t ew = g.num_world_edges();
  if (config.is_eslr()) {
    double flops = 0;
    for (const auto& b : lsdmp_blocks) flops += b->matmul_flops(double(g.num_nodes()), double(g.mesh_senders.size(0)), double(ew));
    for (const auto& a : attention)
      for (const AnchorSet& set : g.anchor_sets) flops += a->matmul_flops(double(set.num_nodes), double(set.nodes.size(0)));
    return flops;
  }
  if (!config.is_hierarchical()) return message_passing_flops(g.num_nodes(), g.mesh_senders.size(0), ew, K);
  std::vector<double> set_edges{double(g.mesh_senders.size(0))};
  for (const GraphEdges& set : g.coarse) set_edges.push_back(double(set.senders.size(0)));
  torch::Tensor level;  // the higher level of each world edge's two ends (its garment vertex's)
  if (ew > 0)
    level = torch::maximum(g.vertex_level.index_select(0, g.world_senders),
                           g.vertex_level.index_select(0, g.world_receivers));
  double flops = 0;
  for (const auto& block : hood_blocks) {
    const int finest = block->finest_set();
    const double kept = ew == 0 ? 0.0 : finest == 0 ? double(ew) : (level >= finest).sum().item<double>();
    const double cloth = g.cloth_edges.senders.defined() ? double(g.cloth_edges.senders.size(0)) : 0.0;
    flops += block->matmul_flops(double(g.num_nodes()), set_edges, kept, cloth);
  }
  return flops;
}

void save_model(Pb4uNet& model, const std::string& path) {
  const std::string temp = temp_path_for(path);
  try {
    torch::save(model, temp);
  } catch (const c10::Error& e) {
    std::remove(temp.c_str());
    fail_file(path, "cannot write the model: " + std::string(e.what_without_backtrace()));
  }
  commit_file(temp, path);
}

Pb4uNet load_model(const std::string& path, const ModelConfig& config) {
  if (!std::ifstream(path).good()) fail_file(path, "cannot open the model file");
  Pb4uNet model(config);
  // torch::load replaces tensors wholesale (set_), shapes included, so a checkpoint of another
  // width would load silently: compare every shape with the config's.
  std::map<std::string, std::vector<int64_t>> expected;
  for (const auto& p : model->named_parameters()) expected[p.key()] = p.value().sizes().vec();
  for (const auto& b : model->named_buffers()) expected[b.key()] = b.value().sizes().vec();
  try {
    torch::load(model, path, torch::Device(torch::kCPU));  // a model saved from a GPU loads anywhere
  } catch (const c10::Error& e) {
    std::string why = e.what_without_backtrace();
    fail_file(path, "not a model of this config (" + why.substr(0, why.find('\n')) + ")");
  }
  auto check = [&](const std::string& key, const torch::Tensor& t) {
    if (t.sizes().vec() != expected[key])
      fail_file(path, "not a model of this config (" + key + " has shape " + c10::str(t.sizes()) +
                          ", the config gives " + c10::str(c10::IntArrayRef(expected[key])) + ")");
  };
  for (const auto& p : model->named_parameters()) check(p.key(), p.value());
  for (const auto& b : model->named_buffers()) check(b.key(), b.value());
  return model;
}

}  // namespace pb4u
