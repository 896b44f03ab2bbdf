// `pb4u evaluate --checkpoint A [--checkpoint B ...] [--config C] [--format table|csv|json]`:
// Table 1 of the paper on a dataset's held-out motions.
#include <CLI/CLI.hpp>
#include <spdlog/fmt/fmt.h>
#include <iostream>

#include "pb4u/cli/commands.h"
#include "pb4u/eval/evaluate.h"
#include "pb4u/model/pass_variants.h"
#include "pb4u/util/device.h"
#include "pb4u/util/error.h"

namespace pb4u {

void add_evaluate_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "evaluate",
      "Roll every model out on the dataset's motions of the config's split (default: test) from\n"
      "their LBS-initialised first frame, at each level, and print the physics terms per frame\n"
      "(Table 1 layout); with a body also the share of garment vertices inside it and the deepest\n"
      "penetration. Without a body (effects [gravity, pins]) each garment hangs from rest, pinned by\n"
      "pins.top_band. A rollout that goes non-finite, or whose positive energy exceeds\n"
      "divergence.energy_ratio x frame 1's, is reported as diverged at frame N; averages use the\n"
      "frames measured. --format json also lists every sequence. --start settled starts every method\n"
      "from the first frame the reference solver reaches from the bind pose instead.");
  struct Args {
    std::string device = "cpu";
    std::vector<std::string> checkpoints, names, methods, sets;
    std::string config, format = "table", preview, frames_dir, start;
    int refine = -1;
    double refine_tolerance = -1;
    int minimum_every = -1;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--checkpoint", args->checkpoints, "Training checkpoint or export (repeatable)");
  cmd->add_option("--name", args->names, "Column name for the n-th run: each --checkpoint once per entry of the config's passes (repeatable)");
  cmd->add_option("--method", args->methods,
                  "Extra method column (repeatable): reference (the SPEC 8 solver with the config's "
                  "physics.solver.contact: by default barrier, intersection-free with SPEC 3.3's penalty kept beside "
                  "it) | penalty (the solver with the penalty term alone, the reference before pb4u 0.2)")
      ->check(CLI::IsMember({"reference", "penalty", "net"}));
  cmd->add_option("--config,-c", args->config, "Evaluation config (configs/eval/*.yaml)");
  cmd->add_option("--refine", args->refine,
                  "Refine each network step by N iterations of the reference solver (physics.solver; config key "
                  "refine.iterations); the network columns are named '+ N it'")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--refine-tolerance", args->refine_tolerance,
                  "Refine each network step until the solver's step is below MM millimetres; with --refine N, "
                  "at most N iterations first (fewer where the step is below MM already), then on until below MM "
                  "(refine.tolerance_mm)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--start", args->start,
                  "How frame 0 is reached (config key start): skinned (the garment skinned to the start pose and "
                  "pushed out of the body, as in training) | settled (carried there by the reference solver from "
                  "the bind pose in settle_steps steps, free of the body; once per sequence, for every method)")
      ->check(CLI::IsMember({"skinned", "settled"}));
  cmd->add_option("--set", args->sets, "Override a config key, e.g. --set max_frames=10 (repeatable)");
  cmd->add_option("--format", args->format, "table | csv | json")->check(CLI::IsMember({"table", "csv", "json"}));
  cmd->add_option("--preview", args->preview,
                  "Write a contact sheet (PNG) of the first network's worst sequence (largest mean positive energy)");
  cmd->add_option("--frames-dir", args->frames_dir,
                  "Write every rollout's frames as CSV (energy terms, positive energy, residual, penetration) to "
                  "DIR/lv<level>/<method>/<garment>_<motion>_<body>.csv, replacing files of those names "
                  "(config key frames_dir)");
  cmd->add_option("--minimum-every", args->minimum_every,
                  "Every N-th frame of every rollout, solve the frame's step on to the energy's minimum (to 0.001 mm) "
                  "and report the distance and energy gap to it (JSON distance_to_minimum, the table's To min. rows, "
                  "--frames-dir columns): what the residual estimates, measured; a reference solve per sampled "
                  "frame; 0: off (config key minimum_every)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--device", args->device, "Where the network runs: cpu | cuda | cuda:N (metrics stay on the CPU)");
  cmd->callback([args, &global] {
    apply_global_options(global);
    std::vector<std::string> sets = args->sets;
    if (!args->preview.empty()) sets.push_back("preview=" + args->preview);
    if (!args->frames_dir.empty()) sets.push_back("frames_dir=" + args->frames_dir);
    if (!args->start.empty()) sets.push_back("start=" + args->start);
    if (args->refine >= 0) sets.push_back("refine.iterations=" + std::to_string(args->refine));
    if (args->minimum_every >= 0) sets.push_back("minimum_every=" + std::to_string(args->minimum_every));
    if (args->refine_tolerance >= 0) sets.push_back(fmt::format("refine.tolerance_mm={}", args->refine_tolerance));
    const EvalConfig config = load_config<EvalConfig>(args->config, sets);
    std::vector<ModelFile> files;
    const torch::Device device = resolve_device(args->device, "--device");
    for (const auto& path : args->checkpoints) files.push_back(load_model_file(path));
    for (auto& m : files) m.model->to(device);
    std::vector<ModelFile> models = pass_variants(files, config.passes);
    if (args->names.size() > models.size()) throw Error("--name: more names than --checkpoint runs (with passes)");
    auto names = method_names(models, args->names);
    if (config.refine.enabled())
      for (auto& name : names)
        name += refine_label(config.refine.iterations, config.refine.tolerance_mm);
    std::vector<EvalMethod> methods;
    for (size_t i = 0; i < models.size(); ++i) methods.push_back({names[i], &models[i], ""});
    for (const auto& m : args->methods)
      if (m == "reference") methods.push_back({"Reference", nullptr, ""});
      else if (m == "penalty") methods.push_back({"Penalty solver", nullptr, "penalty"});
    const auto results = evaluate(config, methods);
    if (args->format == "json") std::cout << format_json(results);
    else if (args->format == "csv") std::cout << format_csv(results);
    else std::cout << format_table(results);
  });
}

}  // namespace pb4u
