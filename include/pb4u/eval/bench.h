#pragma once
// `pb4u bench` (Table 3 / Figure 5): what accuracy costs in time. At each resolution level one
// garment rolls out one held-out motion under every method: the networks with resolution-aware
// K, the first Pb4U network at fixed K values (Figure 5), inference-time ablations, and the
// reference solver at several iteration budgets. Each run reports the physics loss (SPEC 3,
// mean per frame; total and positive part) and the per-frame latency (median and min over the
// frames after warm-up). A per-stage breakdown of one frame shows where the time goes, and a
// variant without a body shows what skipping world edges and contact saves.
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pb4u/config/config_io.h"
#include "pb4u/eval/blender_cloth.h"
#include "pb4u/rollout/divergence_guard.h"
#include "pb4u/scene/material.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/physics/physics_config.h"

namespace pb4u {

struct BenchConfig {
  std::string dataset = "data/generated/quick/quick.h5";  // written by `pb4u generate`
  std::vector<int> levels{1, 2, 3, 4};  // 1-based, as in the dataset
  std::string garment = "tshirt";       // template name
  std::string motion;                   // a motion of the dataset; empty: the first test motion
  int start_frame = 1;                  // LBS-initialised start (needs the frame before it)
  int frames = 20;                      // frames rolled out per run (loss and latency)
  int warmup_frames = 2;                // first frames left out of the latency (allocation)
  double push_out_gap = 0.004;          // m, as in training and evaluation
  std::vector<std::string> checkpoints;  // models run with their own K (training or export files)
  // Each checkpoint under these inference passes (model/pass_variants.h: shipped | none |
  // projection_strain | refined), its variants together; e.g. [none, shipped]: each network
  // alone beside the file's own passes.
  std::vector<std::string> passes{"shipped"};
  std::vector<std::string> names;        // names of the first runs of those (optional), in order
  std::vector<int> k_values;             // fixed-K runs of the first Pb4U checkpoint (Figure 5)
  // Inference-time switches on the first Pb4U checkpoint's weights: no_update_scaling,
  // no_propagation_control (K = K_base).
  std::vector<std::string> ablations;
  // Iteration budgets of the reference solver (physics.solver.step: auto takes Newton steps
  // with barrier contact, L-BFGS with the penalty term alone)
  std::vector<int> reference_iterations{5, 20};
  // Its contact models, one row per budget each: "penalty", the penalty solver (rows
  // "Reference (N it)", the reference before pb4u 0.2), and "barrier", the intersection-free
  // reference with the penalty kept beside it (rows "Reference barrier (N it)").
  std::vector<std::string> reference_contacts{"penalty"};
  std::vector<int> refine_iterations;  // every checkpoint's steps refined by that many solver
                                       // iterations (rollout/refined_step.h, physics.solver's
                                       // contact), one row each: "<name> + N it"
  // and refined until the solver's step is below each of these (mm, rollout/refined_step.h's
  // tolerance_mm), one row each: "<name> + to T mm" (family refined_tolerance)
  std::vector<double> refine_tolerances_mm;
  std::string refine_step = "newton";  // the refinement's solver step: newton | quasi_newton
  bool no_body_variant = true;  // also run the first checkpoint with gravity only (no body)
  int stage_repeats = 7;        // frames timed for the per-stage breakdown (median)
  std::vector<int> matmul_size{36000, 384, 128};  // dense matmul the FLOP rate is compared to
  std::vector<std::string> effects{"gravity", "collision", "friction"};
  Material material;      // the evaluation material (SPEC 2 defaults)
  PhysicsConfig physics;  // solver defaults; the budget is overridden per run
  DivergenceConfig divergence;  // when a run stops as diverged
  // > 0: every minimum_every-th frame of each pb4u run (not Blender's), its step solved on to
  // the energy's minimum (to 0.001 mm, from the step where it stands): the distance and energy
  // gap beside the residual in bench_details.csv and the table. Outside the timed step.
  int minimum_every = 0;
  // Blender's cloth per level (scripts/blender_cloth.py), scored with pb4u's terms; skipped
  // with one log line when Blender is not found (enabled: auto).
  BlenderConfig blender;

  template <class V>
  void visit(V& v) {
    v("dataset", dataset);
    v("levels", levels);
    v("garment", garment);
    v("motion", motion);
    v("start_frame", start_frame, int_at_least(1));
    v("frames", frames, int_at_least(1));
    v("warmup_frames", warmup_frames, int_at_least(0));
    v("push_out_gap", push_out_gap, in_range(0, 0.05));
    v("checkpoints", checkpoints);
    v("passes", passes);
    v("names", names);
    v("k_values", k_values);
    v("ablations", ablations);
    v("reference_iterations", reference_iterations);
    v("reference_contacts", reference_contacts);
    v("refine_iterations", refine_iterations);
    v("refine_tolerances_mm", refine_tolerances_mm);
    v("refine_step", refine_step, one_of({"quasi_newton", "newton"}));
    v("no_body_variant", no_body_variant);
    v("stage_repeats", stage_repeats, int_at_least(1));
    v("matmul_size", matmul_size);
    v("effects", effects);
    v("material", material);
    v("physics", physics);
    v("divergence", divergence);
    v("blender", blender);
    v("minimum_every", minimum_every, int_at_least(0));
  }
};

// One method at one level.
struct BenchRow {
  int level = 0;
  int64_t triangles = 0, vertices = 0;
  std::string method;             // e.g. "Pb4U", "Pb4U (fixed K)", "MGN", "Reference (20 it)"
  std::string family;             // network | fixed_k | ablation | reference | no_body | blender
  int64_t K = 0;                  // propagation steps (0: MGN, reference)
  int iterations = 0;             // reference solver budget, Blender's quality (0: a network)
  int threads = 1;                // torch intra-op threads
  double latency_ms_median = 0, latency_ms_min = 0;  // per frame, after warm-up
  double physics_loss = 0;        // J: SPEC 3 total, mean per frame (NaN when nothing finite)
  double positive_loss = 0;       // J: stretch + bending + collision, mean per frame
  std::vector<std::pair<std::string, double>> terms;  // J, mean per frame
  int frames = 0;                 // finite frames
  bool diverged = false;
  int diverged_at_frame = -1;
  std::optional<PenetrationSummary> penetration;  // with a body
  // mm: the median over the frames of the step's residual (EnergyReport::residual_mm; NaN where
  // not measured, as on Blender's rows), and the frames sampled with minimum_every.
  double residual_mm_median = NAN;
  MinimumSummary minimum;
};

// Median wall time (ms) of each stage of one network frame at one level.
struct StageRow {
  int level = 0;
  int64_t vertices = 0, mesh_edges = 0, world_edges = 0;
  std::string method;
  bool with_body = true;
  int64_t K = 0;
  double graph_build = 0, world_edge_query = 0, encode = 0, propagate = 0, blocks = 0,
         decode = 0, euler = 0, contact_query = 0, physics_terms = 0;
  double message_passing_gflops = 0;  // matmul FLOP rate of propagation + update + blocks
  double matmul_gflops = 0;           // dense matmul (config.matmul_size), timed in the same repeats
};

struct BenchResult {
  std::vector<BenchRow> rows;
  std::vector<StageRow> stages;
  int threads = 1;
  std::string device = "cpu";
  std::string blas_core;
  double matmul_gflops = 0;  // dense float matmul of config.matmul_size, median, same threads
};

// Runs the benchmark (progress bar per level); `on_level`, if given, sees the rows so far after
// each level (the CLI writes its files then, so a long run leaves results as it goes). Throws
// pb4u::Error on bad config / data.
BenchResult run_bench(const BenchConfig& config, const std::function<void(const BenchResult&)>& on_level = {});

}  // namespace pb4u
