#pragma once
// The `model` config section: architecture, baselines/ablations and graph construction
// (SPEC 4). Everything that changes what the network computes lives here, so a checkpoint's
// config alone rebuilds the same network.
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/graph/graph_options.h"

namespace pb4u {

struct ModelConfig {
  // pb4u | mgn (no propagation: the paper's MGN) | hood (no propagation; HOOD's coarse edge
  // sets and U-shaped block schedule, model/hood_block.h) | ccraft (ContourCraft's stage 1: the
  // same blocks, flat over the mesh and the coarsest level, with cloth-to-cloth edges) | eslr
  // (a reconstruction of ESLR from its paper: num_blocks layers, each a MeshGraphNet step with
  // Laplacian smoothing beside a geodesic self-attention; model/lsdmp_block.h,
  // model/geodesic_attention.h)
  std::string kind = "pb4u";
  // hood / ccraft: each block's edge sets (model/hood_block.h); num_blocks must match. Empty:
  // the kind's own (kHoodSchedule, kContourCraftSchedule).
  std::string hood_schedule;
  std::string propagation_control = "on";  // on: K = max(1, floor(D / Lbar)); off: K = K_base
  // on: a = s (.) a~ (SPEC 4); off: s = 1; detail: only the acceleration's detail is scaled,
  // a = S(a~) + s (.) (a~ - S(a~)), S smoothing over smooth_distance (update_scaling.h).
  std::string update_scaling = "on";
  double smooth_distance = 0.1;            // m, the length S smooths over (detail only; ~D)
  // m; > 0: at inference each step's garment is pushed out of the body to this distance
  // (physics/contact_projection.h), 0: the network's step as it is (training never projects).
  double contact_projection = 0.0;
  // > 0: at inference no edge of a step's garment stays longer than (1 + strain_limit) times its
  // rest length (physics/strain_limiting.h; 0.1: 10%), alternated with the contact projection
  // (physics/step_constraints.h). 0: off (training never limits).
  double strain_limit = 0.0;
  // > 0: at inference each step (after the two passes above) is refined by this many
  // iterations of the reference solver (rollout/refined_step.h): the scene's or config's
  // physics.solver but the two keys below, refining as its refine section says (step,
  // release_held_cloth) but for the count and the tolerance. 0: off (training never refines).
  int refine_iterations = 0;
  // > 0: refine each step until the solver's step is below this (mm; at most the solver's
  // max_iterations), as `--refine-tolerance` does; with refine_iterations > 0 as well, at most
  // those first (fewer where the step is below this already), then on until below this. 0: off.
  double refine_tolerance_mm = 0.0;
  // The refinement's body contact: "penalty" (SPEC 3.3) or "barrier" (intersection-free), and
  // its strain limit as a barrier (physics/strain_barrier.h; 0: none). With barrier contact
  // and a limit the refined step needs neither pass above (docs/physics.md).
  std::string refine_contact = "penalty";
  double refine_strain_limit = 0.0;
  bool refines() const { return refine_iterations > 0 || refine_tolerance_mm > 0; }
  int latent = 128;                        // width of every latent vector and hidden layer
  int mlp_hidden_layers = 2;               // hidden layers per MLP
  int num_blocks = 15;                     // N MeshGraphNet blocks in the update stack
  int k_base = 4;                          // propagation steps at the calibration resolution
  double gamma = 0.9;                      // decay of the propagation residual
  double world_edge_radius = 0.03;         // m, garment<->body world edges
  std::string world_edges = "nearest";     // nearest: to the nearest body vertex; radius: all
  // on: world edges also carry the garment vertex's signed height over the body vertex's
  // tangent plane, now and at the next pose (off: the original 8 features; older models).
  std::string world_normal_distance = "off";
  // m/s^2 per decoder output unit: the decoder's natural O(1) output covers gravity-scale
  // accelerations when this is ~10 (1 = older models, which emit m/s^2 directly).
  double acceleration_unit = 1.0;
  // eslr: the attention's heads (dividing latent), the anchors every vertex attends to (all
  // vertices of a garment with fewer), and the distance bias's bins, spaced as the square over
  // [0, geodesic_max_distance] m (the last bin holds everything farther).
  int attention_heads = 4;
  int geodesic_anchors = 256;
  int geodesic_bins = 16;
  double geodesic_max_distance = 2.0;
  int normalizer_warmup = 1000;            // training forward calls that feed the normalisers
  double normalizer_epsilon = 1e-8;        // floor of a feature's standard deviation
  // Training samples K uniformly from [lo * K_base, hi * K_base] (integers).
  std::vector<double> train_k_range{0.0, 2.0};
  // Material inputs are normalised to [0, 1] with these ranges (log scale for mu, bending).
  MaterialRanges material_ranges;

  bool is_pb4u() const { return kind == "pb4u"; }
  bool is_hood() const { return kind == "hood"; }
  bool is_ccraft() const { return kind == "ccraft"; }
  bool is_eslr() const { return kind == "eslr"; }
  // hood and ccraft: the blocks of model/hood_block.h over coarse edge sets.
  bool is_hierarchical() const { return is_hood() || is_ccraft(); }
  int coarse_levels() const { return is_hood() ? kHoodCoarseLevels : is_ccraft() ? kCoarseLevels : 0; }
  std::string schedule() const;  // hood_schedule, or the kind's own when it is empty
  bool propagation_control_on() const { return propagation_control == "on"; }
  bool update_scaling_on() const { return update_scaling != "off"; }
  GraphOptions graph_options() const {
    return {world_edge_radius, world_edges == "nearest", material_ranges, world_normal_distance == "on",
            coarse_levels(), is_ccraft() ? 0.03 : 0.0, is_eslr() ? geodesic_anchors : 0};
  }

  template <class V>
  void visit(V& v) {
    v("kind", kind, one_of({"pb4u", "mgn", "hood", "ccraft", "eslr"}));
    v("hood_schedule", hood_schedule);
    v("propagation_control", propagation_control, one_of({"on", "off"}));
    v("update_scaling", update_scaling, one_of({"on", "off", "detail"}));
    v("smooth_distance", smooth_distance, positive());
    v("contact_projection", contact_projection, in_range(0.0, 0.05));
    v("strain_limit", strain_limit, in_range(0.0, 10.0));
    v("refine_iterations", refine_iterations, int_at_least(0));
    v("refine_tolerance_mm", refine_tolerance_mm, non_negative());
    v("refine_contact", refine_contact, one_of({"penalty", "barrier"}));
    v("refine_strain_limit", refine_strain_limit, non_negative());
    v("latent", latent, int_at_least(1));
    v("mlp_hidden_layers", mlp_hidden_layers, int_at_least(1));
    v("num_blocks", num_blocks, int_at_least(0));
    v("k_base", k_base, int_at_least(1));
    v("gamma", gamma, in_range(0.0, 1.0));
    v("world_edge_radius", world_edge_radius, positive());
    v("world_edges", world_edges, one_of({"nearest", "radius"}));
    v("world_normal_distance", world_normal_distance, one_of({"on", "off"}));
    v("acceleration_unit", acceleration_unit, positive());
    v("attention_heads", attention_heads, int_at_least(1));
    v("geodesic_anchors", geodesic_anchors, int_at_least(1));
    v("geodesic_bins", geodesic_bins, int_at_least(2));
    v("geodesic_max_distance", geodesic_max_distance, positive());
    v("normalizer_warmup", normalizer_warmup, int_at_least(0));
    v("normalizer_epsilon", normalizer_epsilon, positive());
    v("train_k_range", train_k_range);
    v("material_ranges", material_ranges);
  }
};

// Checks what per-key checks cannot (list lengths, ordered ranges); throws pb4u::Error naming
// `where` + the key, e.g. "model.train_k_range".
void validate_model_config(const ModelConfig& config, const std::string& where = "model");

}  // namespace pb4u
