#pragma once
// Pb4U-GNet and its baselines (SPEC 4), one code path chosen by ModelConfig:
//   normalise -> encode -> [pb4u: propagate K steps, update f_u(v, h^K)] -> N blocks -> decode
//   -> update scaling -> acceleration.
// kind mgn skips propagation and update (the paper's MGN); kind hood too, and its blocks are
// HOOD's over the coarse edge sets (hood_block.h); kind eslr too, and each of its layers is a
// Laplacian-smoothed MeshGraphNet step (lsdmp_block.h) plus, from the same input, a geodesic
// self-attention (geodesic_attention.h); propagation_control off fixes
// K = K_base; update_scaling off sets s = 1. The calibration (Lbar_base, D = K_base Lbar_base)
// and the normaliser statistics are buffers, saved and loaded with the weights.
#include <torch/torch.h>

#include <vector>

#include "pb4u/graph/garment_topology.h"
#include "pb4u/graph/graph_batch.h"
#include "pb4u/graph/online_normalizer.h"
#include "pb4u/model/decayed_propagation.h"
#include "pb4u/model/geodesic_attention.h"
#include "pb4u/model/graph_net_block.h"
#include "pb4u/model/hood_block.h"
#include "pb4u/model/lsdmp_block.h"
#include "pb4u/model/mlp.h"
#include "pb4u/model/model_config.h"
#include "pb4u/scene/frame_state.h"

namespace pb4u {

// Wall time (ms) of each stage of one forward, for the benchmark.
struct StageTimes {
  double encode = 0, propagate = 0, blocks = 0, decode = 0;
};

struct Pb4uNetImpl : torch::nn::Module {
  // Throws pb4u::Error on an invalid config.
  explicit Pb4uNetImpl(const ModelConfig& config);

  // Fixes Lbar_base (m, the training resolution's mean rest edge length) and D = K_base Lbar_base.
  void calibrate(double mean_edge_length_base);
  bool calibrated() const { return mean_edge_length_base() > 0; }
  double mean_edge_length_base() const;  // m, 0 until calibrated
  double propagation_distance() const;   // D, m

  // Inference K for a garment of mean rest edge length Lbar (m); 0 for kind mgn.
  int64_t propagation_steps_for(double mean_edge_length) const;

  // Acceleration (n_garment, 3) m/s^2 with update scaling, from raw graph features; K
  // propagation steps (ignored for mgn). Training mode feeds the normalisers until frozen.
  // `times`, if given, receives per-stage wall times.
  torch::Tensor forward(const GraphBatch& graph, int64_t K, StageTimes* times = nullptr);

  // One inference step under InferenceMode: builds the graph, K from the calibration unless
  // k_override >= 0, Euler with pins -> x_{t+1} (n, 3) in the dtype of state.x.
  torch::Tensor step(const FrameState& state, const GarmentTopology& topology, int64_t k_override = -1);

  // Selects the per-edge first-layer form (split = node terms once per node, gathered);
  // both give the same outputs. For the benchmark.
  void set_split_first_layer(bool split);

  // Matmul FLOPs of the message passing of one forward (propagation, update and blocks; not
  // the encoders or the decoder) on a graph of `nodes` nodes, `mesh_edges` and `world_edges`
  // edges, with K propagation steps: the benchmark's measure of work per frame. NaN for hood,
  // ccraft and eslr (their coarse edges or anchors are not among the counts: the overload below
  // has them).
  double message_passing_flops(int64_t nodes, int64_t mesh_edges, int64_t world_edges, int64_t K) const;
  // The same on the graph itself: also counts hood's coarse edges and kept world edges, and
  // eslr's attention.
  double message_passing_flops(const GraphBatch& graph, int64_t K) const;

  ModelConfig config;
  OnlineNormalizer vertex_normalizer{nullptr}, mesh_normalizer{nullptr}, world_normalizer{nullptr};
  MLP vertex_encoder{nullptr}, mesh_encoder{nullptr}, world_encoder{nullptr};
  DecayedPropagation propagation{nullptr};  // pb4u only
  MLP update{nullptr};                      // f_u(v, h^K), pb4u only
  std::vector<GraphNetBlock> blocks;
  // hood and ccraft: the level embedding (levels + 1, 4; rows of norm at most 1, appended to
  // the normalised vertex features), one encoder per coarse edge set, the blocks.
  torch::Tensor level_embedding;
  std::vector<MLP> coarse_encoders;
  std::vector<HoodBlock> hood_blocks;
  OnlineNormalizer cloth_normalizer{nullptr};  // ccraft only: its cloth-to-cloth edges
  // eslr: per layer, the smoothed message passing and the attention beside it.
  std::vector<LsdmpBlock> lsdmp_blocks;
  std::vector<GeodesicAttention> attention;
  MLP cloth_encoder{nullptr};
  MLP decoder{nullptr};
  torch::Tensor lbar_base, distance;  // () float64 buffers, m

 private:
  // The hood blocks over the encoded latents (nodes, mesh and world edges, and g's coarse sets).
  torch::Tensor hood_blocks_forward(const GraphBatch& g, torch::Tensor nodes, torch::Tensor mesh_edges,
                                    torch::Tensor world_edges, const RowIndex& ms, const RowIndex& mr,
                                    const RowIndex& ws, const RowIndex& wr);
};
TORCH_MODULE(Pb4uNet);

// torch::save of the weights, buffers included, written atomically.
void save_model(Pb4uNet& model, const std::string& path);
// A model built from `config` with the weights of `path`. Throws pb4u::Error naming the path
// when the file is missing or does not match the config.
Pb4uNet load_model(const std::string& path, const ModelConfig& config);

}  // namespace pb4u
