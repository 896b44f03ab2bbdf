// `pb4u bench --config C [--out DIR]`: accuracy vs time (Table 3 / Figure 5).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "pb4u/cli/commands.h"
#include "pb4u/eval/bench.h"
#include "pb4u/eval/bench_writers.h"
#include "pb4u/util/atomic_file.h"
#include "pb4u/util/plot_script.h"
#include "pb4u/util/error.h"

namespace pb4u {
namespace fs = std::filesystem;

namespace {

void write_text(const std::string& path, const std::string& text) {
  AtomicFile f(path);
  f.stream() << text;
  f.commit();
}

}  // namespace

void add_bench_command(CLI::App& app, const GlobalOptions& global) {
  auto* cmd = app.add_subcommand(
      "bench",
      "Accuracy vs time: roll one garment out on one held-out motion at each level with every\n"
      "method (networks with their own K, Pb4U at fixed K, ablations, the reference solver at\n"
      "several iteration budgets, and without a body) and report the physics loss and the\n"
      "per-frame latency, plus a per-stage breakdown. Writes to DIR: bench.csv (SPEC 7),\n"
      "bench_details.csv, stages.csv, table.txt, bench_config.yaml and the plots\n"
      "loss_vs_k.png, loss_vs_latency.png, latency_vs_vertices.png. Timings use --threads.");
  struct Args {
    std::string config, out = "runs/bench";
    std::vector<std::string> sets;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("--config,-c", args->config, "Bench config (configs/bench/*.yaml)")->required();
  cmd->add_option("--out,-o", args->out, "Output directory (files in it are replaced)")->capture_default_str();
  cmd->add_option("--set", args->sets, "Override a config key, e.g. --set frames=10 (repeatable)");
  cmd->callback([args, &global] {
    apply_global_options(global);
    const BenchConfig config = load_config<BenchConfig>(args->config, args->sets);
    ensure_output_dir(args->out);
    const fs::path out(args->out);
    auto write_all = [&](const BenchResult& result) {
      write_text((out / "bench.csv").string(), format_bench_csv(result));
      write_text((out / "bench_details.csv").string(), format_bench_details_csv(result));
      write_text((out / "stages.csv").string(), format_stages_csv(result));
      write_text((out / "table.txt").string(), format_bench_table(result));
      save_config(config, (out / "bench_config.yaml").string());
    };
    const BenchResult result = run_bench(config, write_all);
    run_plot_script("plot_bench.py", {args->out});  // the three figures
    std::cout << format_bench_table(result);
    spdlog::info("wrote bench.csv, bench_details.csv, stages.csv, table.txt and plots to {}", args->out);
  });
}

}  // namespace pb4u
