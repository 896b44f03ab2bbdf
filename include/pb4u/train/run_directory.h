#pragma once
// A training run's directory (SPEC 7): <run.out>/config.yaml, checkpoints/step_N.pt (atomic,
// the newest `keep` kept), final.pt and metrics.jsonl. Whether a run starts afresh or resumes
// is decided here, from what the directory holds.
#include <torch/torch.h>

#include <string>

#include "pb4u/model/checkpoint.h"

namespace pb4u {

// <run_out>/checkpoints.
std::string checkpoints_dir(const std::string& run_out);

// The checkpoint a run continues from: with resume, the newest in <run_out>/checkpoints (a
// pb4u::Error if there is none); without, "" (a pb4u::Error if the directory already holds
// checkpoints, which a fresh run would mix with its own).
std::string checkpoint_to_resume(const std::string& run_out, bool resume);

// Creates <run_out>/checkpoints and writes <run_out>/config.yaml (the effective config).
void write_run_directory(const std::string& run_out, const std::string& config_yaml);

// checkpoints/step_<meta.step>.pt with the optimiser, pruned to the newest `keep`; with
// final_checkpoint also <run_out>/final.pt (weights only).
void save_run_checkpoint(const std::string& run_out, const torch::nn::Module& model,
                         const torch::optim::Optimizer* optimizer, const CheckpointMeta& meta, int keep,
                         bool final_checkpoint);

}  // namespace pb4u
