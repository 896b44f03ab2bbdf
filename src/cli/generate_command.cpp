// `pb4u generate --config C --out DIR`: the HDF5 dataset of bodies, motions and garments.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>

#include "pb4u/cli/commands.h"
#include "pb4u/data/generate.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/error.h"

namespace pb4u {

void add_generate_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "generate",
      "Build a dataset: mannequin bodies, procedural and BVH motions, garment templates and\n"
      "garment files remeshed to every resolution level, with skinning weights, into HDF5\n"
      "(schema: docs/data.md). Writes <out>/<file> and the effective config <out>/config.yaml.");
  struct Options {
    std::string config, out;
    std::vector<std::string> sets;
    bool force = false;
  };
  auto opt = std::make_shared<Options>();
  cmd->add_option("--config,-c", opt->config, "Data config (YAML), e.g. configs/data/quick.yaml")->required();
  cmd->add_option("--out,-o", opt->out, "Output directory")->required();
  cmd->add_option("--set", opt->sets, "Override a config key: a.b=value (repeatable)");
  cmd->add_flag("--force", opt->force, "Overwrite an existing dataset file");
  cmd->callback([opt, &global] {
    apply_global_options(global);
    GenerateConfig config = load_config<GenerateConfig>(opt->config, opt->sets);
    validate_generate_config(config, opt->config);
    const std::string target = (std::filesystem::path(opt->out) / config.file).string();
    if (std::filesystem::exists(target) && !opt->force)
      fail_file(target, "exists; pass --force to overwrite it");
    ensure_output_dir(opt->out);
    const auto start = std::chrono::steady_clock::now();
    const std::string base = std::filesystem::path(opt->config).parent_path().string();
    Dataset data = generate_dataset(config, base);
    write_dataset(target, data);
    save_config(config, (std::filesystem::path(opt->out) / "config.yaml").string());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    int garments = 0;
    for (const auto& b : data.bodies) garments += static_cast<int>(b.garments.size());
    spdlog::info("wrote {} ({} bodies, {} garments x {} levels, {} motions) in {:.1f} s", target,
                 data.bodies.size(), garments, data.level_triangles.size(), data.motions.size(),
                 seconds);
  });
}

}  // namespace pb4u
