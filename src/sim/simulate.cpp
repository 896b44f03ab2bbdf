#include "pb4u/sim/simulate.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "pb4u/rollout/rollout.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/median.h"
#include "pb4u/io/preview.h"
#include "pb4u/util/plot_script.h"
#include "pb4u/util/progress.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

// Figure 3: log energies vs time.
void plot_energies(const std::string& csv, const std::string& png, std::vector<std::string>* files) {
  if (run_plot_script("plot_energies.py", {csv, png}) && fs::exists(png)) files->push_back(png);
}

}  // namespace

RolloutInput scene_rollout_input(const SceneConfig& scene, const SceneSetup& setup) {
  RolloutInput in;
  in.garment_rest = setup.garment;
  in.x0 = setup.x0;
  in.x_prev = setup.x_prev;
  in.body = setup.body;
  in.body_faces = setup.body_faces;
  in.pinned = setup.pinned;
  in.pin_targets = setup.pin_targets;
  in.effects = setup.effects;
  in.material = scene.material;
  in.metric_material = scene.material;
  in.steps = scene.frames;
  in.divergence = scene.divergence;
  return in;
}

SimulateResult simulate(const SceneConfig& scene, const std::string& scene_path, const ModelFile* model,
                        const std::string& out_dir) {
  SceneSetup setup = build_scene(scene, scene_path);
  ensure_output_dir(out_dir);
  RolloutOutputs outputs;
  outputs.mesh_format = scene.outputs.mesh_format;
  outputs.point_cache = scene.outputs.point_cache;
  outputs.usd_cache = scene.outputs.usd;
  outputs.hdf5 = scene.outputs.hdf5;
  outputs.energies_csv = scene.outputs.energies_csv;
  const bool body_written = !setup.body.empty();
  RolloutInput in = scene_rollout_input(scene, setup);
  in.measure_residual = scene.outputs.residual;
  in.minimum_every = scene.outputs.minimum_every;
  outputs.fps = 1.0 / in.dt;
  RolloutWriter writer(out_dir, setup.garment.F, body_written ? setup.body_faces : Eigen::MatrixXi(), outputs);

  GarmentTopology topology;
  StepFunction step;
  std::shared_ptr<ContactStepLog> contact_log;
  if (model) {
    topology = build_garment_topology(setup.garment, "garment", model->config.graph_options().geodesic_anchors);
    contact_log = std::make_shared<ContactStepLog>();
    step = network_stepper(*model, topology, -1, model->config.refines() ? contact_log : nullptr,
                           scene.physics.solver, scene.refine);
    if (scene.refine.enabled()) {
      step = refined_stepper(step, scene.physics.solver, scene.refine, contact_log);
    }
  } else {
    contact_log = std::make_shared<ContactStepLog>();
    step = reference_stepper(scene.physics.solver, contact_log);
  }
  in.step_log = contact_log;
  // The intersection-free solver's per-frame account of the cloth it left out of barrier contact.
  const bool file_refines = model && !scene.refine.enabled() && model->config.refines();
  const bool barrier_columns =
      (!model || scene.refine.enabled() || file_refines) &&
      (file_refines ? model->config.refine_contact : scene.physics.solver.contact) == "barrier" &&
      setup.effects.collision && body_written;
  std::vector<std::string> terms;
  for (const auto& t : build_terms(setup.effects, scene.physics)) terms.push_back(t->name());

  // Frame 0 is the start state, which no step produced: its energies (and, with a body, its
  // penetration) are "nan" (not computed).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::pair<std::string, double>> zero;
  for (const auto& t : terms) zero.emplace_back(t, nan);
  zero.emplace_back("total", nan);
  zero.emplace_back("residual_mm", nan);
  if (in.minimum_every > 0) {
    zero.emplace_back("distance_to_minimum_mm", nan);
    zero.emplace_back("energy_gap_j", nan);
  }
  if (body_written) {
    zero.emplace_back("penetrating_fraction", nan);
    zero.emplace_back("max_penetration_mm", nan);
    zero.emplace_back("edges_through_body", nan);
    zero.emplace_back("body_self_crossing_faces", nan);
  }
  if (barrier_columns) {
    zero.emplace_back("contact_excluded", nan);
    zero.emplace_back("caught_by_body", nan);
    zero.emplace_back("body_lag_mm", nan);
  }
  const Eigen::MatrixXd none;
  writer.set_rest_and_previous(setup.garment.V, setup.x_prev);
  writer.add_frame(setup.x0, body_written ? setup.body[0] : none, zero);

  int excluded_frames = 0, excluded_max = 0;
  Progress bar("simulate", scene.frames, "frame");
  RolloutResult r = run_rollout(in, step, physics_measured_for(scene.physics, model, scene.refine.enabled()),
                                [&](int frame, const Eigen::MatrixXd& x, const EnergyReport& report,
                                    const PenetrationFigures* penetration) {
                                  auto row = report.terms;
                                  row.emplace_back("total", report.total);
                                  row.emplace_back("residual_mm", report.residual_mm);
                                  if (in.minimum_every > 0) {
                                    row.emplace_back("distance_to_minimum_mm", report.minimum_distance_mm);
                                    row.emplace_back("energy_gap_j", report.minimum_gap_j);
                                  }
                                  if (penetration) {
                                    row.emplace_back("penetrating_fraction", penetration->penetrating_fraction);
                                    row.emplace_back("max_penetration_mm", penetration->max_penetration_mm);
                                    row.emplace_back("edges_through_body", penetration->edges_through);
                                    row.emplace_back("body_self_crossing_faces", penetration->body_self_crossing_faces);
                                  }
                                  if (barrier_columns) {
                                    row.emplace_back("contact_excluded", contact_log->excluded);
                                    row.emplace_back("caught_by_body", contact_log->caught_by_body);
                                    row.emplace_back("body_lag_mm", 1e3 * contact_log->body_lag);
                                    excluded_frames += contact_log->excluded > 0;
                                    excluded_max = std::max(excluded_max, contact_log->excluded);
                                  }
                                  writer.add_frame(x, body_written ? setup.body[frame] : none, row);
                                  char status[48];
                                  std::snprintf(status, sizeof status, "total %.3e J", report.total);
                                  bar.step(1, status);
                                });
  bar.finish();
  SimulateResult result;
  result.terms = terms;
  result.files = writer.finish();
  result.frames = writer.num_frames();
  result.diverged = r.diverged;
  result.diverged_at_frame = r.diverged_at_frame;
  result.diverged_reason = r.diverged_reason;
  result.worst_vertex = r.worst_vertex;
  result.with_body = body_written;
  result.barrier_contact = barrier_columns;
  result.excluded_frames = excluded_frames;
  result.excluded_max = excluded_max;
  const PositiveEnergyRange positive = positive_energy_range(r.reports);
  result.positive_mean = positive.mean;
  result.positive_max = positive.max;
  if (!r.penetration.empty()) {
    const PenetrationSummary s = summarize_penetration(r.penetration);
    result.penetrating_mean = s.penetrating_fraction;
    result.penetrating_max = s.max_penetrating_fraction;
    result.deepest_mm = s.max_penetration_mm;
    result.edges_through_max = s.max_edges_through;
    result.edges_through_frames = s.frames_with_edges_through;
    result.body_self_crossing_frames = s.frames_with_body_self_crossing;
    result.body_self_crossing_max = s.max_body_self_crossing_faces;
  }
  for (double ms : r.step_ms) result.step_ms_mean += ms / r.step_ms.size();
  result.residual_measured = in.measure_residual;
  result.own_start_frames = r.own_start_frames;
  result.residual_mm_median = median_residual_mm(r.reports);
  for (const EnergyReport& report : r.reports) {
    result.residual_mm_mean += report.residual_mm / r.reports.size();
    result.residual_mm_max = std::max(result.residual_mm_max, report.residual_mm);
  }
  result.minimum = summarize_minimum(r.reports);
  if (scene.outputs.plot && scene.outputs.energies_csv && writer.num_frames() > 1)
    plot_energies(out_dir + "/energies.csv", out_dir + "/energies.png", &result.files);
  if (scene.outputs.preview && writer.num_frames() > 0) {
    const std::string png = out_dir + "/preview.png";
    const std::string title = fs::path(scene_path).filename().string() + ": " +
                              (model ? method_name(model->config) : std::string("reference solver")) +
                              (r.diverged ? ", diverged at frame " + std::to_string(r.diverged_at_frame) : "");
    if (write_preview(png, preview_frames(writer.num_frames()), writer.garment_frames(), setup.garment.F,
                      writer.body_frames(), body_written ? setup.body_faces : Eigen::MatrixXi(), title))
      result.files.push_back(png);
  }
  return result;
}

}  // namespace pb4u
