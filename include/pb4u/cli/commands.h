#pragma once
// Each subcommand lives in its own file and registers itself on the app.
namespace CLI {
class App;
}

namespace pb4u {

struct GlobalOptions {
  int threads = 0;  // 0 = all cores
  int verbose = 0;  // -v: debug logging; -vv: also the solver's every iteration (trace)
  bool quiet = false;
};

// Applies -v/-q/--threads: logging level, progress bars, torch threads, runtime log line.
void apply_global_options(const GlobalOptions& options);

void add_inspect_command(CLI::App& app, const GlobalOptions& global);
void add_generate_command(CLI::App& app, const GlobalOptions& global);
void add_train_command(CLI::App& app, const GlobalOptions& global);
void add_evaluate_command(CLI::App& app, const GlobalOptions& global);
void add_simulate_command(CLI::App& app, const GlobalOptions& global);
void add_export_command(CLI::App& app, const GlobalOptions& global);
void add_bench_command(CLI::App& app, const GlobalOptions& global);
void add_score_command(CLI::App& app, const GlobalOptions& global);

// Builds the app, parses, runs the chosen subcommand; returns the exit status. Every
// failure is one line on stderr: "pb4u: error: <file or key>: <reason>".
int run_cli(int argc, char** argv);

}  // namespace pb4u
