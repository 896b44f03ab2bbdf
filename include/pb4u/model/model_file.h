#pragma once
// A trained model from either file kind `--checkpoint` accepts: a training checkpoint
// (<run>/final.pt, checkpoints/step_*.pt) or a portable export (`pb4u export`, HDF5 with one
// dataset per parameter/buffer). Both rebuild the network from the model config they carry.
#include <torch/torch.h>

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "pb4u/model/model_config.h"
#include "pb4u/model/pb4u_net.h"

namespace pb4u {

// Name and version written into every export; a file with another format or a newer version
// is refused.
inline constexpr const char* kExportFormat = "pb4u-model";
inline constexpr int64_t kExportFormatVersion = 1;

struct ModelFile {
  Pb4uNet model{nullptr};   // in eval mode (normalisers frozen), CPU, float32
  ModelConfig config;
  std::string config_yaml;  // the `model` section as YAML
  std::string path;
  std::string source;       // "training checkpoint" | "export"
  int64_t step = 0;         // training step the weights come from
};

// Loads `path` (a training checkpoint or an export). Throws a one-line pb4u::Error naming
// the file when it is missing, corrupt, of another format/version, or does not match its
// own config.
ModelFile load_model_file(const std::string& path);

// Changes switches that alter what the network computes but not its weights: `key=value` with
// key update_scaling, smooth_distance or propagation_control (an optional "model." prefix is
// accepted). Any other key, or a bad value, is a pb4u::Error naming the key.
void set_inference_switches(ModelFile& model, const std::vector<std::string>& assignments);

// True when `path` is an HDF5 file carrying the export's format attribute (never throws).
bool is_model_export(const std::string& path);

// Writes the portable export of `model` to `out` atomically: root attributes format,
// format_version, model_config (YAML), lbar_base and propagation_distance (m), k_base,
// step, parameter_count; one dataset per parameter and buffer.
void export_model_file(const ModelFile& model, const std::string& out);

// The method's name for tables, from its config: "Pb4U", "MGN", "HOOD", "Pb4U w/o PC",
// "Pb4U w/o US" or "Pb4U w/o both", with " + projection" when it projects out of the body and
// " + strain limit" when it limits edge strain, and its refinement (refine_label) after.
std::string method_name(const ModelConfig& config);

// " + N it", " + to T mm" or " + N it + to T mm": a refinement by the reference solver in a
// method's name (N iterations, then on to T mm; rollout/refined_step.h).
std::string refine_label(int iterations, double tolerance_mm);

// Number of scalar learned parameters (buffers excluded).
int64_t parameter_count(const torch::nn::Module& module);

// What `pb4u inspect` prints for a checkpoint or export: source, step, method, parameter
// count, calibration (Lbar_base, D, K_base) and the model config.
void print_model_summary(std::ostream& out, const ModelFile& model);

}  // namespace pb4u
