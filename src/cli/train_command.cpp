// `pb4u train --config C [--set k=v ...] [--resume]`: self-supervised training.
#include <CLI/CLI.hpp>

#include "pb4u/cli/commands.h"
#include "pb4u/config/config_io.h"
#include "pb4u/train/train_config.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/runtime.h"

namespace pb4u {

void add_train_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "train",
      "Train a model self-supervised with the physics terms on LBS-initialised frames.\n"
      "Writes <run.out>/config.yaml, metrics.jsonl, checkpoints/step_*.pt and final.pt.");
  struct Args {
    std::string config;
    std::vector<std::string> sets;
    bool resume = false;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--config,-c", args->config, "Training config (configs/train/*.yaml)")->required();
  cmd->add_option("--set", args->sets, "Override a config key, e.g. --set run.steps=100 (repeatable)");
  cmd->add_option("--out", args->out, "Run directory (overrides run.out)");
  cmd->add_flag("--resume", args->resume, "Continue the run from its newest checkpoint");
  cmd->callback([args, &global] {
    apply_global_options(global);
    std::vector<std::string> sets = args->sets;
    if (!args->out.empty()) sets.push_back("run.out=" + args->out);
    TrainConfig config = load_config<TrainConfig>(args->config, sets);
    if (global.threads == 0 && config.run.threads > 0) configure_threads(config.run.threads);
    TrainingData data = load_training_data(config.data);
    Trainer trainer(config, config_to_yaml(config), std::move(data), args->resume);
    trainer.run();
  });
}

}  // namespace pb4u
