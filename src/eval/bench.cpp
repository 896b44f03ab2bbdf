#include "pb4u/eval/bench.h"

#include <spdlog/spdlog.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include <unistd.h>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/model/pass_variants.h"
#include "pb4u/eval/score.h"
#include "pb4u/eval/stage_timing.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/util/error.h"
#include "pb4u/util/median.h"
#include "pb4u/util/progress.h"
#include "pb4u/util/remove_tree.h"
#include "pb4u/util/runtime.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

// A method run at one level.
struct Run {
  std::string method, family;
  const ModelFile* model = nullptr;  // null: the reference solver
  int64_t k_override = -1;           // fixed K, or -1 for the model's own
  int iterations = 0;
  bool with_body = true;
  double tolerance_mm = 0;  // refined_tolerance: refined until the solver's step is below this
};

BenchRow run_one(const Run& run, const RolloutInput& body_input, const RolloutInput& free_input,
                 const GarmentTopology& topology, const BenchConfig& config) {
  RolloutInput in = run.with_body ? body_input : free_input;  // a copy: it carries this run's step log
  in.minimum_every = config.minimum_every;
  PhysicsConfig physics = config.physics;
  StepFunction step;
  auto step_log = std::make_shared<ContactStepLog>();
  in.step_log = step_log;
  BenchRow row;
  row.method = run.method;
  row.family = run.family;
  row.iterations = run.iterations;
  const bool refined = run.family == "refined" || run.family == "refined_tolerance";
  if (run.model) {
    RefineConfig refine;  // the refinement's keys but the budget, for this row's and the file's own
    refine.step = config.refine_step;
    step = network_stepper(*run.model, topology, run.k_override, step_log, physics.solver, refine);
    if (refined) {
      refine.iterations = run.iterations;
      refine.tolerance_mm = run.tolerance_mm;
      step = refined_stepper(step, physics.solver, refine, step_log);
    }
    row.K = run.k_override >= 0 ? run.k_override : run.model->model->propagation_steps_for(topology.mean_edge_length);
  } else {
    physics.solver.max_iterations = run.iterations;
    // "Reference (N it)" rows are the penalty solver (as before pb4u 0.2, when it was the
    // reference), "Reference barrier (N it)" the intersection-free reference.
    physics.solver.contact = run.family == "reference_barrier" ? "barrier" : "penalty";
    step = reference_stepper(physics.solver, step_log);
  }
  RolloutResult r = run_rollout(in, step, physics);
  row.frames = int(r.reports.size());
  row.diverged = r.diverged;
  row.diverged_at_frame = r.diverged_at_frame;
  std::vector<double> latency;
  const size_t skip = r.step_ms.size() > size_t(config.warmup_frames) ? size_t(config.warmup_frames) : 0;
  for (size_t i = skip; i < r.step_ms.size(); ++i)
    latency.push_back(r.step_ms[i] + (run.model && !refined ? 0.0 : r.contact_ms[i]));  // the solver needs contact
  row.latency_ms_median = median(latency);
  row.latency_ms_min = latency.empty() ? NAN : *std::min_element(latency.begin(), latency.end());
  if (r.reports.empty()) {
    row.physics_loss = row.positive_loss = NAN;
    return row;
  }
  const EnergyReport mean = mean_report(r.reports);
  row.physics_loss = mean.total;
  row.terms = mean.terms;
  row.positive_loss = positive_energy(mean);
  row.residual_mm_median = median_residual_mm(r.reports);
  row.minimum = summarize_minimum(r.reports);
  if (!r.penetration.empty()) row.penetration = summarize_penetration(r.penetration);
  return row;
}

// Blender's cloth on the level's body input, scored with pb4u's terms (eval/score.h). The
// cloth starts at rest (Blender takes no start velocity), so it is scored from rest too.
BenchRow run_blender(const std::string& blender, int quality, int threads, const RolloutInput& in,
                     const BenchConfig& config, int level) {
  const std::string work = (fs::temp_directory_path() / ("pb4u_blender_" + std::to_string(::getpid()) + "_lv" +
                                                         std::to_string(level) + "_q" + std::to_string(quality)))
                               .string();
  const BlenderRollout b = run_blender_cloth(in, blender, quality, threads, config.blender.collision_distance, work);
  BenchRow row;
  row.method = "Blender (quality " + std::to_string(quality) + ")";
  row.family = "blender";
  row.iterations = quality;
  row.threads = threads;
  std::vector<double> latency;
  const size_t skip = b.frame_ms.size() > size_t(config.warmup_frames) ? size_t(config.warmup_frames) : 0;
  latency.assign(b.frame_ms.begin() + skip, b.frame_ms.end());
  row.latency_ms_median = median(latency);
  row.latency_ms_min = latency.empty() ? NAN : *std::min_element(latency.begin(), latency.end());
  ScoreInput score;
  score.garment_rest = in.garment_rest;
  score.frames = b.frames;
  score.body = in.effects.needs_body() ? std::vector<Eigen::MatrixXd>(in.body.begin(), in.body.begin() + b.frames.size())
                                       : std::vector<Eigen::MatrixXd>();
  score.body_faces = in.body_faces;
  score.effects = in.effects;
  score.material = in.metric_material;
  score.physics = config.physics;
  score.dt = in.dt;
  const ScoreResult r = score_sequence(score);
  row.frames = int(r.reports.size());
  row.diverged = r.nonfinite_at_frame >= 0;
  row.diverged_at_frame = r.nonfinite_at_frame;
  if (r.reports.empty()) {
    row.physics_loss = row.positive_loss = NAN;
    return row;
  }
  row.physics_loss = r.mean.total;
  row.terms = r.mean.terms;
  row.positive_loss = positive_energy(r.mean);
  if (!r.penetration.empty()) row.penetration = r.penetration_summary;
  remove_tree(work);  // kept only when Blender's run fails (its log is in it)
  return row;
}

const MotionRecord& find_motion(const Dataset& data, const BenchConfig& config) {
  for (const auto& m : data.motions)
    if (config.motion.empty() ? m.split == "test" : m.name == config.motion) {
      if (m.motion.num_frames() < config.start_frame + 2)
        throw Error("motion: " + m.name + " has too few frames to start at frame " +
                    std::to_string(config.start_frame));
      return m;
    }
  throw Error(config.dataset + ": " +
              (config.motion.empty() ? std::string("no test-split motion") : "no motion named '" + config.motion + "'"));
}


}  // namespace

BenchResult run_bench(const BenchConfig& config, const std::function<void(const BenchResult&)>& on_level) {
  if (config.levels.empty()) throw Error("levels: no level to benchmark");
  for (const auto& a : config.ablations)
    if (a != "no_update_scaling" && a != "no_propagation_control")
      throw Error("ablations: unknown ablation '" + a + "' (no_update_scaling | no_propagation_control)");
  for (int it : config.reference_iterations)
    if (it < 1) throw Error("reference_iterations: budgets must be at least 1");
  for (int it : config.refine_iterations)
    if (it < 1) throw Error("refine_iterations: budgets must be at least 1");
  for (double mm : config.refine_tolerances_mm)
    if (!(mm > 0)) throw Error("refine_tolerances_mm: tolerances must be positive (mm)");
  for (const auto& c : config.reference_contacts)
    if (c != "penalty" && c != "barrier")
      throw Error("reference_contacts: unknown contact '" + c + "' (penalty | barrier)");
  for (int k : config.k_values)
    if (k < 0) throw Error("k_values: K must be non-negative");

  std::vector<ModelFile> files;
  for (const auto& path : config.checkpoints) files.push_back(load_model_file(path));
  const std::vector<ModelFile> models = pass_variants(files, config.passes);
  if (config.names.size() > models.size()) throw Error("names: more names than checkpoint runs");
  const std::vector<std::string> names = method_names(models, config.names);
  // Geodesic anchors (eslr) are found once per level, as many as any model asks for.
  int anchors = 0;
  for (const auto& m : models) anchors = std::max(anchors, m.config.graph_options().geodesic_anchors);
  const ModelFile* pb4u = nullptr;
  for (const auto& m : models)
    if (m.config.is_pb4u()) {
      pb4u = &m;
      break;
    }
  if (!pb4u && (!config.k_values.empty() || !config.ablations.empty()))
    throw Error("k_values / ablations: need a Pb4U checkpoint in checkpoints");
  // Ablations: the same weights with a switch flipped at inference (not retrained models).
  std::vector<ModelFile> ablated;
  for (const auto& a : config.ablations) {
    ModelFile m = load_model_file(pb4u->path);
    if (a == "no_update_scaling") m.config.update_scaling = "off";
    else m.config.propagation_control = "off";
    m.model->config = m.config;
    ablated.push_back(std::move(m));
  }

  const Dataset data = read_dataset(config.dataset);
  const MotionRecord& motion = find_motion(data, config);
  const BodyRecord* record = data.find_body(motion.body);
  if (!record) throw Error(config.dataset + ": motion " + motion.name + " names a missing body " + motion.body);
  const GarmentLevels* garment = nullptr;
  for (const auto& g : record->garments)
    if (g.name == config.garment) garment = &g;
  if (!garment) throw Error("garment: no garment '" + config.garment + "' on body " + record->body.name);
  const Effects effects = Effects::from_names(config.effects, "effects");
  Effects free_effects = effects;
  free_effects.collision = free_effects.friction = false;
  const int steps = std::min(config.frames, motion.motion.num_frames() - 1 - config.start_frame);

  BenchResult result;
  result.threads = torch::get_num_threads();
  result.blas_core = blas_core_name();
  DenseMatmul matmul(config.matmul_size);
  result.matmul_gflops = matmul.median_gflops(7);

  std::string blender;
  if (config.blender.enabled != "off" && !config.blender.qualities.empty()) {
    blender = find_blender(config.blender.executable);
    if (blender.empty() && config.blender.enabled == "on")
      throw Error("blender.executable: '" + config.blender.executable + "' not found (install Blender or set blender.enabled: off)");
    if (blender.empty()) spdlog::info("bench: Blender ('{}') not found on PATH: no Blender rows", config.blender.executable);
  }
  for (int q : config.blender.qualities)
    if (q < 1) throw Error("blender.qualities: Blender's steps per frame must be at least 1");

  for (int level : config.levels) {
    if (level < 1 || level > int(garment->levels.size()))
      throw Error("levels: level " + std::to_string(level) + " is not in " + config.dataset + " (it has " +
                  std::to_string(garment->levels.size()) + " levels)");
    const auto level_start = Clock::now();
    const Garment& g = garment->levels[level - 1];
    const GarmentTopology topology = build_garment_topology(g.mesh, g.name, anchors);
    RolloutInput body_input = lbs_rollout_input(record->body, g, motion.motion, config.start_frame, steps, effects,
                                                config.material, config.push_out_gap);
    RolloutInput free_input = lbs_rollout_input(record->body, g, motion.motion, config.start_frame, steps,
                                                free_effects, config.material, config.push_out_gap);
    body_input.divergence = free_input.divergence = config.divergence;
    std::vector<Run> runs;
    for (size_t i = 0; i < models.size(); ++i) runs.push_back({names[i], "network", &models[i]});
    for (int k : config.k_values) runs.push_back({method_name(pb4u->config) + " (fixed K)", "fixed_k", pb4u, k});
    for (const auto& m : ablated) runs.push_back({method_name(m.config) + " (same weights)", "ablation", &m});
    for (const auto& contact : config.reference_contacts)
      for (int it : config.reference_iterations)
        runs.push_back(contact == "barrier"
                           ? Run{"Reference barrier (" + std::to_string(it) + " it)", "reference_barrier", nullptr, -1, it}
                           : Run{"Reference (" + std::to_string(it) + " it)", "reference", nullptr, -1, it});
    // Every network refined the same way: MGN gets the refinement Pb4U gets.
    for (size_t i = 0; i < models.size(); ++i)
      for (int it : config.refine_iterations)
        runs.push_back({names[i] + " + " + std::to_string(it) + " it", "refined", &models[i], -1, it});
    for (size_t i = 0; i < models.size(); ++i)
      for (double mm : config.refine_tolerances_mm)
        runs.push_back({names[i] + " + to " + fmt::format("{:g}", mm) + " mm", "refined_tolerance", &models[i], -1, 0,
                        true, mm});
    if (config.no_body_variant && effects.needs_body() && !models.empty()) {
      runs.push_back({names[0] + " (no body)", "no_body", &models[0], -1, 0, false});
      if (!config.reference_iterations.empty() && !config.reference_contacts.empty())
        runs.push_back({"Reference (" + std::to_string(config.reference_iterations.back()) + " it) (no body)",
                        "no_body", nullptr, -1, config.reference_iterations.back(), false});
    }
    const int stage_runs = int(models.size()) + (config.no_body_variant && effects.needs_body() && !models.empty());
    const int blender_runs = blender.empty() ? 0 : int(config.blender.qualities.size());
    Progress bar("Lv." + std::to_string(level), int64_t(runs.size()) + stage_runs + blender_runs, "run");
    for (const Run& run : runs) {
      const auto run_start = Clock::now();
      BenchRow row = run_one(run, body_input, free_input, topology, config);
      spdlog::debug("Lv.{} {}: K {}, {} frames, {:.1f} ms/frame, loss {:.4g} J ({:.1f} s)", level, run.method, row.K,
                    row.frames, row.latency_ms_median, row.physics_loss,
                    std::chrono::duration<double>(Clock::now() - run_start).count());
      row.level = level;
      row.triangles = g.mesh.F.rows();
      row.vertices = g.mesh.V.rows();
      row.threads = result.threads;
      result.rows.push_back(std::move(row));
      bar.step(1, run.method);
    }
    for (int q = 0; q < blender_runs; ++q) {
      BenchRow row = run_blender(blender, config.blender.qualities[q], result.threads, body_input, config, level);
      row.level = level;
      row.triangles = g.mesh.F.rows();
      row.vertices = g.mesh.V.rows();
      bar.step(1, row.method);
      result.rows.push_back(std::move(row));
    }
    auto add_stages = [&](const ModelFile& m, const std::string& name, const RolloutInput& in) {
      Pb4uNet net = m.model;
      StageRow s = time_stages(net, topology, in, config.physics, config.stage_repeats, matmul);
      s.level = level;
      s.method = name;
      result.stages.push_back(s);
      bar.step(1, name + " stages");
    };
    for (size_t i = 0; i < models.size(); ++i) add_stages(models[i], names[i], body_input);
    if (config.no_body_variant && effects.needs_body() && !models.empty())
      add_stages(models[0], names[0] + " (no body)", free_input);
    bar.finish();
    spdlog::info("Lv.{} ({} triangles): {} runs and {} stage breakdowns in {:.0f} s", level, g.mesh.F.rows(),
                 runs.size() + blender_runs, stage_runs, std::chrono::duration<double>(Clock::now() - level_start).count());
    if (on_level) on_level(result);
  }
  return result;
}

}  // namespace pb4u
