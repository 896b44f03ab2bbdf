// `pb4u export --checkpoint P --out F`: the portable model file (HDF5).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>

#include "pb4u/cli/commands.h"
#include "pb4u/eval/model_file.h"

namespace pb4u {

void add_export_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "export",
      "Write a portable model file: HDF5 with one dataset per parameter and buffer (normaliser\n"
      "statistics, calibration), the model config, D and Lbar_base and a format version as root\n"
      "attributes. Readable by h5ls/h5py; evaluate and simulate load it like a checkpoint.");
  struct Args {
    std::string checkpoint, out;
    std::vector<std::string> sets;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--checkpoint", args->checkpoint, "Training checkpoint (.pt) or an export")->required();
  cmd->add_option("--out,-o", args->out, "Output file (.h5)")->required();
  cmd->add_option("--set", args->sets,
                  "Change an inference-time switch of the stored model config, e.g. --set\n"
                  "update_scaling=detail or --set contact_projection=0 (update_scaling, smooth_distance,\n"
                  "propagation_control, contact_projection only)");
  cmd->callback([args, &global] {
    apply_global_options(global);
    ModelFile model = load_model_file(args->checkpoint);
    set_inference_switches(model, args->sets);
    export_model_file(model, args->out);
    spdlog::info("exported {} ({}, step {}, {} parameters) to {}", args->checkpoint,
                 method_name(model.config), model.step, parameter_count(*model.model), args->out);
  });
}

}  // namespace pb4u
