#include "pb4u/train/trainer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <mutex>

#include "pb4u/model/checkpoint.h"
#include "pb4u/physics/physics_term.h"
#include "pb4u/train/group_start.h"
#include "pb4u/train/init_weights.h"
#include "pb4u/train/metrics_log.h"
#include "pb4u/train/run_directory.h"
#include "pb4u/util/device.h"
#include "pb4u/util/error.h"
#include "pb4u/util/progress.h"

namespace pb4u {

namespace {

// run.device; with CUDA, rank R of a group takes GPU R mod (GPUs on this machine), so ranks
// started in order on one machine use one GPU each.
torch::Device training_device(const std::string& name, const DistributedGroup* group) {
  torch::Device device = resolve_device(name, "run.device");
  if (device.is_cuda() && group && group->world_size() > 1)
    device = torch::Device(torch::kCUDA, static_cast<c10::DeviceIndex>(group->rank() % torch::cuda::device_count()));
  return device;
}

}  // namespace

Trainer::Trainer(TrainConfig config, std::string config_yaml, TrainingData data, bool resume,
                 std::shared_ptr<DistributedGroup> group)
    : config_(std::move(config)), config_yaml_(std::move(config_yaml)), data_(std::move(data)),
      device_(training_device(config_.run.device, group.get())), group_(std::move(group)) {
  if (data_.garments.empty()) throw Error(config_.data.dataset + ": no garments at the training levels");
  if (data_.motions.empty()) throw Error(config_.data.dataset + ": no training motions");
  {
    // The initial weights come from torch's process-wide generator: trainers built at once in
    // one process (ranks as threads, in tests) must not interleave their draws.
    static std::mutex init_mutex;
    std::lock_guard<std::mutex> lock(init_mutex);
    torch::manual_seed(static_cast<uint64_t>(config_.run.seed));
    model_ = Pb4uNet(config_.model);
  }
  model_->to(device_);
  // Calibrate K on the training resolution: the mean edge length over the training garments.
  // Every garment at every data.scales factor: topology_ and cloth_ are indexed by
  // variant(garment, scale); the calibration uses the garments as generated.
  // (The config checks the factors: data.scales, scale_factors.)
  const auto& scales = config_.data.scales;
  double lbar = 0;
  for (int gi = 0; gi < int(data_.garments.size()); ++gi) {
    const Garment& g = data_.garments[gi];
    for (double c : scales) {
      auto mesh = g.mesh;
      mesh.V *= c;
      topology_.push_back(garment_topology_to(
          build_garment_topology(mesh, g.name, config_.model.graph_options().geodesic_anchors), device_));
      cloth_.push_back(make_cloth_geometry(mesh, torch::kFloat32, device_, false, config_.physics.degenerate_area));
      if (config_.replay.refine_iterations > 0)
        refine_cloth_.push_back(
            make_cloth_geometry(mesh, torch::kFloat64, torch::kCPU, false, config_.physics.degenerate_area));
    }
    lbar += topology_[variant(gi, 0)].mean_edge_length / scales[0];
  }
  model_->calibrate(lbar / data_.garments.size());
  optimizer_ = std::make_unique<torch::optim::Adam>(model_->parameters(),
                                                    torch::optim::AdamOptions(config_.optim.lr));
  Effects every_effect;
  every_effect.gravity = every_effect.collision = every_effect.friction = every_effect.self_collision = true;
  term_names_ = term_names(build_terms(every_effect, config_.physics));
  start_group(resume);
}

// Rank 0 owns the run directory: it checks it, resumes from it and writes the config. The
// other ranks get its verdict, its checkpoint and its weights, so the group starts as one.
void Trainer::start_group(bool resume) {
  const bool distributed = group_ && group_->world_size() > 1;
  std::string problem, checkpoint_bytes;
  auto load = [this](const std::string& path) {
    CheckpointMeta meta = load_checkpoint(path, *model_, optimizer_.get(), device_);
    step_ = meta.step;
    skipped_steps_ = meta.skipped_steps;
    elapsed_seconds_ = meta.elapsed_seconds;
  };
  if (is_root()) {
    try {
      const std::string latest = checkpoint_to_resume(config_.run.out, resume);
      if (resume) {
        load(latest);
        if (distributed) checkpoint_bytes = read_binary_file(latest);
        spdlog::info("resumed {} at step {}", latest, step_);
      } else if (!config_.run.init_from.empty()) {
        // Weights and normaliser statistics only: step, optimiser and schedule start afresh.
        int64_t from_step = 0;
        try {
          from_step = init_weights_from(config_.run.init_from, *model_, device_);
        } catch (const Error& e) {
          throw Error(std::string("run.init_from: ") + e.what());
        }
        spdlog::info("initialised from {} (trained {} steps)", config_.run.init_from, from_step);
      }
    } catch (const Error& e) {
      if (!distributed) throw;
      problem = e.what();
    }
  }
  if (distributed) {
    agree_to_start(*group_, problem, config_yaml_, resume);
    if (resume) share_checkpoint(*group_, checkpoint_bytes, load);
    broadcast_module_state(*group_, *model_);
  }
  // The run directory is written once the whole group has agreed to start.
  if (is_root()) write_run_directory(config_.run.out, config_yaml_);
}

void Trainer::save(bool final_checkpoint) {
  CheckpointMeta meta;
  meta.step = step_;
  meta.config_yaml = config_yaml_;
  meta.host_rng_state = "";  // samples are seeded by (seed, step, sample): nothing to keep
  meta.elapsed_seconds = elapsed_seconds_;
  meta.skipped_steps = skipped_steps_;
  save_run_checkpoint(config_.run.out, *model_, optimizer_.get(), meta, config_.run.keep_checkpoints,
                      final_checkpoint);
}

void Trainer::run(int64_t stop_at) {
  const int64_t end = stop_at >= 0 ? std::min<int64_t>(stop_at, config_.run.steps) : config_.run.steps;
  if (!is_root()) {  // rank 0 writes the metrics and checkpoints of the group
    while (step_ < end) train_step();
    return;
  }
  MetricsLog metrics(config_.run.out + "/metrics.jsonl", step_);
  Progress bar("train", end - step_, "step");
  while (step_ < end) {
    StepResult s = train_step();
    std::vector<std::pair<std::string, double>> row{
        {"loss", s.loss}, {"lr", s.lr}, {"seconds", elapsed_seconds_}, {"step_seconds", s.seconds},
        {"rollout", double(s.rollout)}, {"K", double(s.K)}, {"age", double(s.age)},
        {"collision_weight", s.collision_weight}, {"skipped_steps", double(skipped_steps_)},
        {"samples", double(s.samples)}};
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
