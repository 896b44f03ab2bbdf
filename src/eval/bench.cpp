#include "pb4u/eval/bench.h"

#include <spdlog/spdlog.h>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include "pb4u/data/dataset.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/eval/rollout.h"
#include "pb4u/eval/score.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/graph/world_edges.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/physics/cloth_geometry.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/util/error.h"
#include "pb4u/util/number_format.h"
#include "pb4u/util/progress.h"
#include "pb4u/util/remove_tree.h"
#include "pb4u/util/runtime.h"
#include "pb4u/util/stopwatch.h"

namespace pb4u {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "nan";
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", v);
  return s;
}

// Dense float matmul of an m x k by k x n product, timed one product at a time.
class DenseMatmul {
 public:
  explicit DenseMatmul(const std::vector<int>& size) {
    if (size.size() != 3 || size[0] < 1 || size[1] < 1 || size[2] < 1)
      throw Error("matmul_size: expected three positive sizes [m, k, n]");
    c10::InferenceMode guard;
    a_ = torch::randn({size[0], size[1]});
    b_ = torch::randn({size[1], size[2]});
    c_ = torch::mm(a_, b_);  // warm-up: BLAS buffers, page faults
    flops_ = 2.0 * double(size[0]) * double(size[1]) * double(size[2]);
  }
  // GFLOP/s of one product.
  double gflops() {
    c10::InferenceMode guard;
    auto t0 = Clock::now();
    torch::mm_out(c_, a_, b_);
    return flops_ / (ms_since(t0) * 1e6);
  }
  double median_gflops(int repeats) {
    std::vector<double> g;
    for (int r = 0; r < repeats; ++r) g.push_back(gflops());
    return median(g);
  }

 private:
  torch::Tensor a_, b_, c_;
  double flops_ = 0;
};

// Matmul FLOPs of propagation + update + blocks as the split-first-layer code computes them
// (model/mlp.cpp): node terms once per node, edge terms per edge, then the remaining layers.
double message_passing_flops(const ModelConfig& c, int64_t nodes, int64_t mesh_edges,
                             int64_t world_edges, int64_t K) {
  const double H = c.latent, L = c.mlp_hidden_layers, n = double(nodes);
  auto finish = [&](double rows) { return 2.0 * rows * H * H * L; };  // (L - 1) hidden + output
  auto edge_mlp = [&](double edges, bool edge_term) {
    return 2.0 * n * H * 2.0 * H + (edge_term ? 2.0 * edges * H * H : 0.0) + finish(edges);
  };
  double flops = 0;
  if (c.is_pb4u()) {
    flops += 2.0 * double(mesh_edges) * H * H;  // edge term, once for the K steps
    flops += double(K) * edge_mlp(double(mesh_edges), false);
    flops += 2.0 * n * H * H * 2.0 + finish(n);  // update f_u(v, h^K)
  }
  for (int b = 0; b < c.num_blocks; ++b) {
    flops += edge_mlp(double(mesh_edges), true);
    if (world_edges > 0) flops += edge_mlp(double(world_edges), true);
    flops += 2.0 * n * H * H * 3.0 + finish(n);
  }
  return flops;
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
      row.message_passing_gflops =
          message_passing_flops(net->config, g.num_nodes(), row.mesh_edges, row.world_edges, K);
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

// A method run at one level.
struct Run {
  std::string method, family;
  const ModelFile* model = nullptr;  // null: the reference solver
  int64_t k_override = -1;           // fixed K, or -1 for the model's own
  int iterations = 0;
  bool with_body = true;
};

BenchRow run_one(const Run& run, const RolloutInput& body_input, const RolloutInput& free_input,
                 const GarmentTopology& topology, const BenchConfig& config) {
  const RolloutInput& in = run.with_body ? body_input : free_input;
  PhysicsConfig physics = config.physics;
  StepFunction step;
  BenchRow row;
  row.method = run.method;
  row.family = run.family;
  row.iterations = run.iterations;
  if (run.model) {
    step = network_stepper(*run.model, topology, run.k_override);
    row.K = run.k_override >= 0 ? run.k_override : run.model->model->propagation_steps_for(topology.mean_edge_length);
  } else {
    physics.solver.max_iterations = run.iterations;
    step = reference_stepper(physics.solver);
  }
  RolloutResult r = run_rollout(in, step, physics);
  row.frames = int(r.reports.size());
  row.diverged = r.diverged;
  row.diverged_at_frame = r.diverged_at_frame;
  std::vector<double> latency;
  const size_t skip = r.step_ms.size() > size_t(config.warmup_frames) ? size_t(config.warmup_frames) : 0;
  for (size_t i = skip; i < r.step_ms.size(); ++i)
    latency.push_back(r.step_ms[i] + (run.model ? 0.0 : r.contact_ms[i]));  // the solver needs contact
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
  for (int k : config.k_values)
    if (k < 0) throw Error("k_values: K must be non-negative");

  std::vector<ModelFile> models;
  for (const auto& path : config.checkpoints) models.push_back(load_model_file(path));
  if (config.names.size() > models.size()) throw Error("names: more names than checkpoints");
  const std::vector<std::string> names = method_names(models, config.names);
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
    const GarmentTopology topology = build_garment_topology(g.mesh, g.name);
    RolloutInput body_input = lbs_rollout_input(record->body, g, motion.motion, config.start_frame, steps, effects,
                                                config.material, config.push_out_gap);
    RolloutInput free_input = lbs_rollout_input(record->body, g, motion.motion, config.start_frame, steps,
                                                free_effects, config.material, config.push_out_gap);
    body_input.divergence = free_input.divergence = config.divergence;
    std::vector<Run> runs;
    for (size_t i = 0; i < models.size(); ++i) runs.push_back({names[i], "network", &models[i]});
    for (int k : config.k_values) runs.push_back({method_name(pb4u->config) + " (fixed K)", "fixed_k", pb4u, k});
    for (const auto& m : ablated) runs.push_back({method_name(m.config) + " (same weights)", "ablation", &m});
    for (int it : config.reference_iterations)
      runs.push_back({"Reference (" + std::to_string(it) + " it)", "reference", nullptr, -1, it});
    if (config.no_body_variant && effects.needs_body() && !models.empty()) {
      runs.push_back({names[0] + " (no body)", "no_body", &models[0], -1, 0, false});
      if (!config.reference_iterations.empty())
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

std::string format_bench_csv(const BenchResult& result) {
  std::ostringstream out;
  out << "level,triangles,vertices,method,K,threads,latency_ms_median,latency_ms_min,physics_loss\n";
  for (const auto& r : result.rows)
    out << r.level << ',' << r.triangles << ',' << r.vertices << ',' << csv_field(r.method) << ',' << r.K << ','
        << r.threads << ',' << number(r.latency_ms_median) << ',' << number(r.latency_ms_min) << ','
        << number(r.physics_loss) << '\n';
  return out.str();
}

std::string format_bench_details_csv(const BenchResult& result) {
  static const char* kTerms[] = {"stretch", "bending", "collision", "inertia", "gravity", "friction"};
  std::ostringstream out;
  out << "level,triangles,vertices,method,family,K,iterations,threads,latency_ms_median,latency_ms_min,"
         "physics_loss,positive_loss";
  for (const char* t : kTerms) out << ',' << t;
  out << ",frames,diverged,diverged_at_frame,penetrating_fraction,max_penetrating_fraction,max_penetration_mm\n";
  for (const auto& r : result.rows) {
    out << r.level << ',' << r.triangles << ',' << r.vertices << ',' << csv_field(r.method) << ',' << r.family
        << ',' << r.K << ',' << r.iterations << ',' << r.threads << ',' << number(r.latency_ms_median) << ','
        << number(r.latency_ms_min) << ',' << number(r.physics_loss) << ',' << number(r.positive_loss);
    for (const char* t : kTerms) {
      double v = NAN;
      for (const auto& [name, value] : r.terms)
        if (name == t) v = value;
      out << ',' << (std::isnan(v) ? std::string() : number(v));
    }
    out << ',' << r.frames << ',' << (r.diverged ? "true" : "false") << ',' << r.diverged_at_frame;
    for (double PenetrationSummary::*field : {&PenetrationSummary::penetrating_fraction,
                                             &PenetrationSummary::max_penetrating_fraction,
                                             &PenetrationSummary::max_penetration_mm})
      out << ',' << (r.penetration ? number((*r.penetration).*field) : std::string());
    out << '\n';
  }
  return out.str();
}

std::string format_stages_csv(const BenchResult& result) {
  std::ostringstream out;
  out << "level,vertices,mesh_edges,world_edges,method,body,K,graph_build_ms,world_edge_query_ms,encode_ms,"
         "propagate_ms,blocks_ms,decode_ms,euler_ms,contact_query_ms,physics_terms_ms,message_passing_gflops,"
         "matmul_gflops\n";
  for (const auto& s : result.stages)
    out << s.level << ',' << s.vertices << ',' << s.mesh_edges << ',' << s.world_edges << ','
        << csv_field(s.method) << ',' << (s.with_body ? "true" : "false") << ',' << s.K << ','
        << number(s.graph_build) << ',' << number(s.world_edge_query) << ',' << number(s.encode) << ','
        << number(s.propagate) << ',' << number(s.blocks) << ',' << number(s.decode) << ','
        << number(s.euler) << ',' << number(s.contact_query) << ',' << number(s.physics_terms) << ','
        << number(s.message_passing_gflops) << ',' << number(s.matmul_gflops) << '\n';
  return out.str();
}

const BenchRow* cheapest_at_equal_loss(const std::vector<BenchRow>& rows, const BenchRow& net,
                                       const std::string& family) {
  const BenchRow* best = nullptr;
  for (const auto& r : rows)
    if (r.level == net.level && r.family == family && !r.diverged && std::isfinite(r.physics_loss) &&
        r.physics_loss <= net.physics_loss && (!best || r.latency_ms_median < best->latency_ms_median))
      best = &r;
  return best;
}

double latency_exponent(const std::vector<BenchRow>& rows, const std::string& method) {
  std::vector<double> x, y;
  for (const auto& r : rows)
    if (r.method == method && r.vertices > 0 && r.latency_ms_median > 0 && std::isfinite(r.latency_ms_median)) {
      x.push_back(std::log(double(r.vertices)));
      y.push_back(std::log(r.latency_ms_median));
    }
  if (x.size() < 2) return NAN;
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= double(x.size());
  my /= double(y.size());
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
  return sxx > 0 ? sxy / sxx : NAN;
}

std::string format_bench_table(const BenchResult& result) {
  std::ostringstream out;
  out << "Accuracy vs time (" << result.device << ", " << result.threads << " torch threads, BLAS "
      << result.blas_core << "); latency per frame after warm-up, loss = mean physics energy per frame (J)\n";
  std::vector<int> levels;
  for (const auto& r : result.rows)
    if (std::find(levels.begin(), levels.end(), r.level) == levels.end()) levels.push_back(r.level);
  std::vector<std::string> methods;
  for (const auto& r : result.rows)
    if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
  size_t w = 8;
  for (const auto& m : methods) w = std::max(w, m.size());
  char line[256];
  for (int level : levels) {
    const BenchRow* first = nullptr;
    for (const auto& r : result.rows)
      if (r.level == level) {
        first = first ? first : &r;
      }
    out << "\nLv." << level << "  (" << first->triangles << " triangles, " << first->vertices << " vertices)\n";
    std::snprintf(line, sizeof line, "  %-*s %4s %12s %12s %12s %12s\n", int(w), "method", "K", "median ms",
                  "min ms", "total J", "positive J");
    out << line;
    for (const auto& r : result.rows) {
      if (r.level != level) continue;
      std::string note = r.diverged ? "  diverged at frame " + std::to_string(r.diverged_at_frame) : "";
      std::snprintf(line, sizeof line, "  %-*s %4lld %12s %12s %12s %12s%s\n", int(w), r.method.c_str(),
                    static_cast<long long>(r.K), fixed(r.latency_ms_median, 1).c_str(),
                    fixed(r.latency_ms_min, 1).c_str(), scientific(r.physics_loss, 3).c_str(),
                    scientific(r.positive_loss, 3).c_str(),
                    note.c_str());
      out << line;
    }
  }

  if (!result.stages.empty()) {
    out << "\nPer-stage time of one frame (ms, median); MP = message passing (propagation + update + "
           "blocks) FLOP rate\n";
    std::snprintf(line, sizeof line, "  %-3s %-*s %3s %6s %6s %6s %6s %6s %6s %6s %6s %7s %7s %8s\n", "Lv.",
                  int(w), "method", "K", "graph", "world", "enc", "prop", "blocks", "dec", "euler", "total",
                  "contact", "terms", "MP GF/s");
    out << line;
    for (const auto& s : result.stages) {
      const double total = s.graph_build + s.world_edge_query + s.encode + s.propagate + s.blocks + s.decode + s.euler;
      std::snprintf(line, sizeof line,
                    "  %-3d %-*s %3lld %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %6.1f %7.1f %7.1f %8.1f\n",
                    s.level, int(w), s.method.c_str(), static_cast<long long>(s.K), s.graph_build,
                    s.world_edge_query, s.encode, s.propagate, s.blocks, s.decode, s.euler, total,
                    s.contact_query, s.physics_terms, s.message_passing_gflops);
      out << line;
    }
    out << "  dense matmul (same threads, at start): " << fixed(result.matmul_gflops, 1) << " GFLOP/s\n";
    for (const auto& s : result.stages)
      if (s.with_body)
        out << "  Lv." << s.level << " " << s.method << ": message passing " << fixed(s.message_passing_gflops, 1)
            << " GFLOP/s = " << fixed(100.0 * s.message_passing_gflops / s.matmul_gflops, 0)
            << "% of the dense matmul's " << fixed(s.matmul_gflops, 1) << " GFLOP/s timed alongside\n";
  }

  // Speed-up over the reference solver (and Blender) at equal loss: the cheapest run that ran to
  // the end with a loss not above the network's.
  auto equal_loss = [&](const std::string& family, const std::string& who, const std::string& budget) {
    const bool any = std::any_of(result.rows.begin(), result.rows.end(), [&](const BenchRow& r) { return r.family == family; });
    if (!any) return;
    out << "\nNetworks vs " << who << " at equal loss\n";
    for (int level : levels) {
      for (const auto& net : result.rows) {
        if (net.level != level || net.family != "network" || !std::isfinite(net.physics_loss)) continue;
        const BenchRow* best = cheapest_at_equal_loss(result.rows, net, family);
        const BenchRow* most = nullptr;
        for (const auto& ref : result.rows)
          if (ref.level == level && ref.family == family && (!most || ref.iterations > most->iterations)) most = &ref;
        if (!most) continue;
        out << "  Lv." << level << " " << net.method << ": ";
        if (best)
          out << best->method << " reaches its loss in " << fixed(best->latency_ms_median, 1) << " ms: "
              << fixed(best->latency_ms_median / net.latency_ms_median, 1) << "x the network's "
              << fixed(net.latency_ms_median, 1) << " ms\n";
        else
          out << "no " << budget << " reaches its loss (up to " << most->method << ", "
              << fixed(most->latency_ms_median, 1) << " ms = "
              << fixed(most->latency_ms_median / net.latency_ms_median, 1) << "x the network's "
              << fixed(net.latency_ms_median, 1) << " ms, loss " << fixed(most->physics_loss, 3) << " J)\n";
      }
    }
  };
  equal_loss("reference", "the reference solver", "reference budget");
  equal_loss("blender", "Blender's cloth", "Blender quality");
  if (levels.size() >= 2) {
    out << "\nLatency growth exponent in vertex count (least squares over levels, log-log)\n";
    for (const auto& m : methods) {
      const bool one_row_per_level =
          std::count_if(result.rows.begin(), result.rows.end(), [&](const BenchRow& r) { return r.method == m; }) ==
          std::ptrdiff_t(levels.size());
      if (!one_row_per_level) continue;  // fixed-K sweeps: several K per level
      const double e = latency_exponent(result.rows, m);
      if (std::isfinite(e)) out << "  " << m << ": " << fixed(e, 2) << "\n";
    }
  }
  return out.str();
}

}  // namespace pb4u
