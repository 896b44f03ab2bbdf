// `pb4u export --checkpoint P [--checkpoint Q ...] [--weights a,b,...] --out F`: the portable
// model file (HDF5), of one model or of a weight average of several (eval/model_average.h).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "pb4u/cli/commands.h"
#include "pb4u/eval/model_average.h"
#include "pb4u/model/model_file.h"

namespace pb4u {

void add_export_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "export",
      "Write a portable model file: HDF5 with one dataset per parameter and buffer (normaliser\n"
      "statistics, calibration), the model config, D and Lbar_base and a format version as root\n"
      "attributes. Readable by h5ls/h5py; evaluate and simulate load it like a checkpoint.\n"
      "Several --checkpoint: the file holds their weight average (the tail of a run, or a\n"
      "fine-tune interpolated with its base), with the first file's config and buffers.");
  struct Args {
    std::vector<std::string> checkpoints;
    std::string out;
    std::vector<std::string> sets;
    std::vector<double> weights;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--checkpoint", args->checkpoints,
                  "Training checkpoint (.pt) or an export; repeat it to export the weight average of\n"
                  "several models of one architecture and the same normaliser statistics")
      ->required();
  cmd->add_option("--weights", args->weights,
                  "One weight per --checkpoint, summing to 1 (default: equal), e.g. --weights 0.5,0.5")
      ->delimiter(',');
  cmd->add_option("--out,-o", args->out, "Output file (.h5)")->required();
  cmd->add_option("--set", args->sets,
                  "Change an inference-time switch of the stored model config, e.g. --set\n"
                  "update_scaling=detail or --set strain_limit=0.1 (update_scaling, smooth_distance,\n"
                  "propagation_control, contact_projection, strain_limit, refine_iterations,\n"
                  "refine_tolerance_mm, refine_contact, refine_strain_limit only)");
  cmd->callback([args, &global] {
    apply_global_options(global);
    std::vector<ModelFile> models;
    for (const auto& path : args->checkpoints) models.push_back(load_model_file(path));
    ModelFile model = models.size() == 1 && args->weights.empty() ? models.front()
                                                                   : average_models(models, args->weights);
    set_inference_switches(model, args->sets);
    export_model_file(model, args->out);
    spdlog::info("exported {} ({}, step {}, {} parameters) to {}", model.path, method_name(model.config),
                 model.step, parameter_count(*model.model), args->out);
  });
}

}  // namespace pb4u
