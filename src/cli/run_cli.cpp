#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <c10/util/Exception.h>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "pb4u/cli/commands.h"
#include "pb4u/util/error.h"
#include "pb4u/util/progress.h"
#include "pb4u/util/runtime.h"

namespace pb4u {
namespace {

// Torch and yaml messages span several lines; the CLI promises one.
std::string one_line(std::string s) {
  auto end = s.find_last_not_of(" \n\r\t");
  s.erase(end == std::string::npos ? 0 : end + 1);
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  return s;
}

int report(const std::string& message) {
  std::fflush(stdout);
  std::fprintf(stderr, "pb4u: error: %s\n", one_line(message).c_str());
  return 1;
}

}  // namespace

void apply_global_options(const GlobalOptions& options) {
  spdlog::set_level(options.verbose > 1   ? spdlog::level::trace
                    : options.verbose == 1 ? spdlog::level::debug
                    : options.quiet        ? spdlog::level::warn
                                           : spdlog::level::info);
  Progress::set_quiet(options.quiet);
  configure_threads(options.threads);
  log_runtime_info();
}

int run_cli(int argc, char** argv) {
  auto logger = spdlog::stderr_color_mt("pb4u");
  logger->set_pattern("[%H:%M:%S %^%l%$] %v");
  spdlog::set_default_logger(logger);

  CLI::App app{
      "pb4u: resolution-adaptive neural garment simulation (Pb4U-GNet).\n"
      "Trains a graph network on physics losses at a coarse mesh resolution and runs it\n"
      "stably at finer ones. Run 'pb4u <command> --help' for a command's options.",
      "pb4u"};
  app.set_version_flag("--version", std::string("pb4u ") + PB4U_VERSION);
  app.require_subcommand(1);
  GlobalOptions global;
  app.add_option("--threads", global.threads, "Worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("-v,--verbose", global.verbose,
               "Debug logging (each solve's summary line); -vv also each solver iteration: its step, the "
               "part CCD and the line search let it take, the energy's decrease, the closest pair");
  app.add_flag("-q,--quiet", global.quiet, "Warnings and errors only; no progress bars");

  add_inspect_command(app, global);
  add_generate_command(app, global);
  add_train_command(app, global);
  add_evaluate_command(app, global);
  add_simulate_command(app, global);
  add_export_command(app, global);
  add_bench_command(app, global);
  add_score_command(app, global);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const Error& e) {
    return report(e.what());
  } catch (const c10::Error& e) {
    return report(e.what_without_backtrace());
  } catch (const std::exception& e) {
    return report(e.what());
  } catch (...) {
    return report("unexpected failure");
  }
  return 0;
}

}  // namespace pb4u
