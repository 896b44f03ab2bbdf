// `pb4u train --config C [--set k=v ...] [--resume] [--world-size N --rank R --master H:P]`:
// self-supervised training, alone or as one rank of a data-parallel group.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cstdio>

#include "pb4u/cli/commands.h"
#include "pb4u/config/config_io.h"
#include "pb4u/train/distributed.h"
#include "pb4u/train/train_config.h"
#include "pb4u/train/trainer.h"
#include "pb4u/train/training_data.h"
#include "pb4u/util/runtime.h"

namespace pb4u {

void add_train_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "train",
      "Train a model self-supervised with the physics terms on LBS-initialised frames.\n"
      "Writes <run.out>/config.yaml, metrics.jsonl, checkpoints/step_*.pt and final.pt.\n"
      "Data-parallel: start one process per rank with the same config and --world-size,\n"
      "--master, and --rank 0..N-1 (scripts/train_ddp.sh starts N local ranks); rank 0 writes.");
  struct Args {
    std::string config;
    std::vector<std::string> sets;
    bool resume = false;
    bool profile = false;
    std::string out;
    DistributedOptions distributed;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--config,-c", args->config, "Training config (configs/train/*.yaml)")->required();
  cmd->add_option("--set", args->sets, "Override a config key, e.g. --set run.steps=100 (repeatable)");
  cmd->add_option("--out", args->out, "Run directory (overrides run.out)");
  cmd->add_flag("--resume", args->resume, "Continue the run from its newest checkpoint");
  cmd->add_flag("--profile", args->profile,
                "Time every step's stages (sampling, graph build, forward stages, each physics term, "
                "backward, optimiser) and print a table of median and mean ms per step at the end");
  cmd->add_option("--world-size", args->distributed.world_size,
                  "Number of data-parallel ranks (processes); each trains run.batch samples a step")
      ->default_val(1);
  cmd->add_option("--rank", args->distributed.rank, "This process's rank, 0..world-size-1")->default_val(0);
  cmd->add_option("--master", args->distributed.master,
                  "HOST:PORT where rank 0 meets the others (rank 0 listens on PORT)")
      ->default_val("127.0.0.1:29500");
  cmd->add_option("--timeout", args->distributed.timeout_seconds,
                  "Seconds to wait for the other ranks (joining, or any step) before failing")
      ->default_val(300);
  cmd->callback([args, &global] {
    apply_global_options(global);
    std::vector<std::string> sets = args->sets;
    if (!args->out.empty()) sets.push_back("run.out=" + args->out);
    TrainConfig config = load_config<TrainConfig>(args->config, sets);
    if (global.threads == 0 && config.run.threads > 0) configure_threads(config.run.threads);
    TrainingData data = load_training_data(config.data);
    std::shared_ptr<DistributedGroup> group;
    if (args->distributed.world_size != 1 || args->distributed.rank != 0) {
      group = std::make_shared<DistributedGroup>(args->distributed);
      spdlog::info("rank {} of {} joined the group at {}", group->rank(), group->world_size(),
                   args->distributed.master);
    }
    Trainer trainer(config, config_to_yaml(config), std::move(data), args->resume, group);
    StepProfile profile;
    if (args->profile) trainer.set_profile(&profile);
    trainer.run();
    if (args->profile && profile.steps() > 0)
      std::printf("Training step profile (%s, %d threads):\n%s", config.run.device.c_str(),
                  torch::get_num_threads(), profile.table().c_str());
  });
}

}  // namespace pb4u
