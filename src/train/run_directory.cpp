#include "pb4u/train/run_directory.h"

#include "pb4u/config/config_io.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

std::string checkpoints_dir(const std::string& run_out) { return run_out + "/checkpoints"; }

std::string checkpoint_to_resume(const std::string& run_out, bool resume) {
  const std::string dir = checkpoints_dir(run_out);
  const std::string latest = latest_checkpoint(dir);
  if (resume && latest.empty()) throw Error(dir + ": --resume given but there is no checkpoint");
  if (!resume && !latest.empty())
    throw Error(run_out + ": already holds checkpoints; use --resume to continue it, or a new run.out");
  return resume ? latest : "";
}

void write_run_directory(const std::string& run_out, const std::string& config_yaml) {
  ensure_output_dir(checkpoints_dir(run_out));
  write_text_file(run_out + "/config.yaml", config_yaml);
}

void save_run_checkpoint(const std::string& run_out, const torch::nn::Module& model,
                         const torch::optim::Optimizer* optimizer, const CheckpointMeta& meta, int keep,
                         bool final_checkpoint) {
  const std::string dir = checkpoints_dir(run_out);
  save_checkpoint(checkpoint_path(dir, meta.step), model, optimizer, meta);
  prune_checkpoints(dir, keep);
  if (final_checkpoint) save_checkpoint(run_out + "/final.pt", model, nullptr, meta);
}

}  // namespace pb4u
