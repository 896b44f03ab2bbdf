#include "pb4u/train/trainer.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "pb4u/data/lbs_frame.h"
#include "pb4u/graph/build_graph.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/model/euler_step.h"
#include "pb4u/model/propagation_control.h"
#include "pb4u/physics/body_queries.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/train/checkpoint.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "pb4u/util/progress.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

bool gradients_finite(const std::vector<torch::Tensor>& params) {
  for (const auto& p : params)
    if (p.grad().defined() && !torch::isfinite(p.grad()).all().item<bool>()) return false;
  return true;
}

std::string checkpoints_dir(const TrainConfig& c) { return c.run.out + "/checkpoints"; }

}  // namespace

Trainer::Trainer(TrainConfig config, std::string config_yaml, TrainingData data, bool resume)
    : config_(std::move(config)), config_yaml_(std::move(config_yaml)), data_(std::move(data)),
      device_(config_.run.device == "cuda" ? torch::kCUDA : torch::kCPU),
      rng_(static_cast<uint64_t>(config_.run.seed)) {
  if (device_.is_cuda() && !torch::cuda::is_available())
    throw Error("run.device: cuda requested but this build or machine has no CUDA device");
  if (data_.garments.empty()) throw Error(config_.data.dataset + ": no garments at the training levels");
  if (data_.motions.empty()) throw Error(config_.data.dataset + ": no training motions");
  torch::manual_seed(static_cast<uint64_t>(config_.run.seed));

  model_ = Pb4uNet(config_.model);
  model_->to(device_);
  // Calibrate K on the training resolution: the mean edge length over the training garments.
  double lbar = 0;
  for (const auto& g : data_.garments) {
    topology_.push_back(build_garment_topology(g.mesh, g.name));
    topology_.back().faces = topology_.back().faces.to(device_);
    cloth_.push_back(make_cloth_geometry(g.mesh, torch::kFloat32, device_, false,
                                         config_.physics.degenerate_area));
    lbar += topology_.back().mean_edge_length;
  }
  model_->calibrate(lbar / data_.garments.size());
  optimizer_ = std::make_unique<torch::optim::Adam>(model_->parameters(),
                                                    torch::optim::AdamOptions(config_.optim.lr));

  const std::string ckpt_dir = checkpoints_dir(config_);
  const std::string latest = latest_checkpoint(ckpt_dir);
  if (resume) {
    if (latest.empty()) throw Error(ckpt_dir + ": --resume given but there is no checkpoint");
    CheckpointMeta meta = load_checkpoint(latest, *model_, optimizer_.get());
    step_ = meta.step;
    skipped_steps_ = meta.skipped_steps;
    elapsed_seconds_ = meta.elapsed_seconds;
    std::istringstream(meta.host_rng_state) >> rng_;
    spdlog::info("resumed {} at step {}", latest, step_);
  } else if (!latest.empty()) {
    throw Error(config_.run.out + ": already holds checkpoints; use --resume to continue it, or a new run.out");
  }
  ensure_output_dir(ckpt_dir);
  write_text_file(config_.run.out + "/config.yaml", config_yaml_);
}

std::string Trainer::host_rng_state() const {
  std::ostringstream s;
  s << rng_;
  return s.str();
}

StepResult Trainer::train_step() {
  auto t0 = std::chrono::steady_clock::now();
  model_->train();
  StepResult result;
  result.step = step_ + 1;
  result.rollout = rollout_length(config_.curriculum, step_);
  result.lr = learning_rate(config_.optim, step_, config_.run.steps);
  result.collision_weight = collision_weight(config_.physics.collision, step_);
  for (auto& group : optimizer_->param_groups())
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(result.lr);

  // The sample: garment, motion of its body, start frame, material, effects, K.
  const int gi = std::uniform_int_distribution<int>(0, int(data_.garments.size()) - 1)(rng_);
  const int bi = data_.garment_body[gi];
  std::vector<int> motions;
  for (int m = 0; m < int(data_.motions.size()); ++m)
    if (data_.motion_body[m] == bi) motions.push_back(m);
  if (motions.empty()) throw Error(config_.data.dataset + ": no training motion for body " + data_.bodies[bi].name);
  const Motion& motion = data_.motions[motions[std::uniform_int_distribution<size_t>(0, motions.size() - 1)(rng_)]];
  const int r = std::min(result.rollout, std::max(1, motion.num_frames() - 2));
  const int t = std::uniform_int_distribution<int>(1, std::max(1, motion.num_frames() - 1 - r))(rng_);
  Material material = sample_material(config_.materials, Material{}, rng_);
  Effects effects = sample_effects(config_.effects, rng_);
  result.K = sample_propagation_steps(config_.model, rng_);
  result.rollout = r;

  const Body& body = data_.bodies[bi];
  const Garment& garment = data_.garments[gi];
  LbsFrame frame = lbs_frame(body, garment, motion, t, config_.data.push_out_gap);
  FrameState state;
  state.x = matrix_to_tensor(frame.garment, torch::kFloat32, device_);
  state.x_prev = matrix_to_tensor(frame.garment_prev, torch::kFloat32, device_);
  state.effects = effects;
  state.material = material;
  const torch::Tensor body_faces = index_matrix_to_tensor(body.mesh.F, device_);
  Eigen::MatrixXd body_now = frame.body, body_next = frame.body_next;

  TermList terms = build_terms(effects, config_.physics, result.collision_weight);
  optimizer_->zero_grad();
  torch::Tensor loss_sum = torch::zeros({}, torch::TensorOptions().device(device_));
  std::vector<double> term_sums(terms.size(), 0.0);
  for (int i = 0; i < r; ++i) {
    if (effects.needs_body()) {
      state.body.vertices = matrix_to_tensor(body_now, torch::kFloat32, device_);
      state.body.next_vertices = matrix_to_tensor(body_next, torch::kFloat32, device_);
      state.body.faces = body_faces;
    } else {
      state.body = BodyFrame{};
    }
    GraphBatch graph = build_graph(state, topology_[gi], config_.model.graph_options());
    torch::Tensor accel = model_->forward(graph, result.K);
    torch::Tensor x_next = euler_step(state, accel);
    std::optional<BodyContact> contact = body_contact_for(state, config_.physics);
    auto energies = term_energies(terms, x_next, state, cloth_[gi], contact ? &*contact : nullptr);
    torch::Tensor step_loss = torch::zeros({}, x_next.options());
    for (size_t k = 0; k < energies.size(); ++k) {
      step_loss = step_loss + energies[k].second;
      term_sums[k] += energies[k].second.item<double>();
    }
    loss_sum = loss_sum + step_loss.detach();
    step_loss.backward();  // gradients accumulate; the next step starts from a detached state
    state.x_prev = state.x;
    state.x = x_next.detach();
    if (i + 1 < r) {
      body_now = body_next;
      body_next = pose_body(body, motion.frames[std::min(t + i + 2, motion.num_frames() - 1)]);
    }
  }
  result.loss = loss_sum.item<double>() / r;
  for (size_t k = 0; k < terms.size(); ++k) result.terms.emplace_back(terms[k]->name(), term_sums[k] / r);

  auto params = model_->parameters();
  if (!std::isfinite(result.loss) || !gradients_finite(params)) {
    result.skipped = true;
    ++skipped_steps_;
    optimizer_->zero_grad();
  } else {
    torch::nn::utils::clip_grad_norm_(params, config_.optim.grad_clip);
    optimizer_->step();
  }
  ++step_;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  elapsed_seconds_ += result.seconds;
  return result;
}

void Trainer::save(bool final_checkpoint) {
  CheckpointMeta meta;
  meta.step = step_;
  meta.config_yaml = config_yaml_;
  meta.host_rng_state = host_rng_state();
  meta.elapsed_seconds = elapsed_seconds_;
  meta.skipped_steps = skipped_steps_;
  save_checkpoint(checkpoint_path(checkpoints_dir(config_), step_), *model_, optimizer_.get(), meta);
  prune_checkpoints(checkpoints_dir(config_), config_.run.keep_checkpoints);
  if (final_checkpoint) save_checkpoint(config_.run.out + "/final.pt", *model_, nullptr, meta);
}

void Trainer::run(int64_t stop_at) {
  const int64_t end = stop_at >= 0 ? std::min<int64_t>(stop_at, config_.run.steps) : config_.run.steps;
  MetricsLog metrics(config_.run.out + "/metrics.jsonl", step_);
  Progress bar("train", end - step_, "step");
  while (step_ < end) {
    StepResult s = train_step();
    std::vector<std::pair<std::string, double>> row{
        {"loss", s.loss}, {"lr", s.lr}, {"seconds", elapsed_seconds_}, {"step_seconds", s.seconds},
        {"rollout", double(s.rollout)}, {"K", double(s.K)},
        {"collision_weight", s.collision_weight}, {"skipped_steps", double(skipped_steps_)}};
    row.insert(row.end(), s.terms.begin(), s.terms.end());
    metrics.write(s.step, row);
    char status[96];
    std::snprintf(status, sizeof status, "loss %.3e r %d K %lld%s", s.loss, s.rollout,
                  static_cast<long long>(s.K), s.skipped ? " (skipped)" : "");
    bar.step(1, status);
    if (step_ % config_.run.checkpoint_every == 0 || step_ == config_.run.steps)
      save(step_ == config_.run.steps);
  }
  bar.finish();
  if (step_ < config_.run.steps) return;
  spdlog::info("trained {} steps in {:.1f} s ({} skipped); final model {}/final.pt", step_,
               elapsed_seconds_, skipped_steps_, config_.run.out);
}

}  // namespace pb4u
