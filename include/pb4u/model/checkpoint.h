#pragma once
// Training checkpoints: model parameters and buffers (normaliser statistics included),
// optimiser state, step, RNG states and the effective config in one file, written
// atomically (temporary + fsync + rename) so a killed run always leaves loadable files.
#include <torch/torch.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pb4u {

struct CheckpointMeta {
  int64_t step = 0;
  std::string config_yaml;     // the effective config of the run
  std::string host_rng_state;  // serialised std::mt19937_64 (or any host RNG) state
  double elapsed_seconds = 0;  // training wall time so far, s
  int64_t skipped_steps = 0;   // steps skipped for a non-finite loss or gradient
  std::string kind = "pb4u-train-checkpoint";
  int64_t format_version = 1;
};

// Writes `path` atomically. `optimizer` may be null (e.g. for a final model).
void save_checkpoint(const std::string& path, const torch::nn::Module& model,
                     const torch::optim::Optimizer* optimizer, const CheckpointMeta& meta);

// Reads meta only (cheap: no module needed). Throws pb4u::Error naming `path` if it is
// missing, corrupt or not a pb4u checkpoint.
CheckpointMeta read_checkpoint_meta(const std::string& path);

// Restores parameters/buffers into `model` (and the optimiser if given) and returns the
// meta. A missing or differently shaped parameter is a pb4u::Error naming the file and
// the parameter. Tensors are read onto `device` whatever device saved them: pass the one the
// model and optimiser are on (a parameter on another device would be moved to `device`).
CheckpointMeta load_checkpoint(const std::string& path, torch::nn::Module& model,
                               torch::optim::Optimizer* optimizer, torch::Device device = torch::kCPU);

// "<dir>/step_00001234.pt"
std::string checkpoint_path(const std::string& dir, int64_t step);
// Checkpoint files in `dir`, oldest step first; temporaries are ignored.
std::vector<std::string> list_checkpoints(const std::string& dir);
// The newest checkpoint in `dir`, or "" if none.
std::string latest_checkpoint(const std::string& dir);
// Deletes all but the newest `keep` checkpoints in `dir`.
void prune_checkpoints(const std::string& dir, int keep);

}  // namespace pb4u
